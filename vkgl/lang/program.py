"""A compiled program: every module of one compilation, resolved into one flat namespace.

This is what `vkgl.compile(path)` returns and what the back ends consume.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vkgl.lang.diagnostics import Diagnostic
from vkgl.lang.ir import (
    Affordance,
    Body,
    Correspondence,
    Module,
    Robot,
    Scene,
    Task,
)


@dataclass
class Program:
    """The checked IR of a root module and everything it (transitively) uses.

    `affordances` maps a body type name to its affordances, in declaration order,
    merged over every `affordances BODY { ... }` block of the compilation.
    `warnings` holds the non-fatal diagnostics of the compilation.
    """

    root: Module
    modules: dict[str, Module] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    robots: dict[str, Robot] = field(default_factory=dict)
    affordances: dict[str, list[Affordance]] = field(default_factory=dict)
    correspondences: list[Correspondence] = field(default_factory=list)
    scenes: dict[str, Scene] = field(default_factory=dict)
    tasks: dict[str, Task] = field(default_factory=dict)
    warnings: list[Diagnostic] = field(default_factory=list)
    sources: dict[str, str] = field(default_factory=dict)

    def task(self, name: str | None = None) -> Task:
        """The task called `name`, or the only/first task of the root module."""
        if name is not None:
            return self.tasks[name]
        for decl in self.root.decls:
            if isinstance(decl, Task):
                return decl
        raise KeyError("the program declares no task")
