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

    def body(self, name: str | None = None) -> Body:
        """The body called `name` (any in scope), or the only body the root module declares.

        Raises InputError (saying what there is) when there is no such body, or
        when `name` is None and the root module declares none or several.
        """
        from vkgl.errors import InputError

        where = self.root.path
        if name is not None:
            if name not in self.bodies:
                known = ", ".join(sorted(self.bodies)) or "none"
                raise InputError(f"{where}: no body named `{name}` (bodies in scope: {known})")
            return self.bodies[name]
        own = [d for d in self.root.decls if isinstance(d, Body)]
        if not own:
            raise InputError(f"{where}: declares no body; give a file with a `body NAME {{ ... }}` declaration")
        if len(own) > 1:
            names = ", ".join(b.name for b in own)
            raise InputError(f"{where}: declares {len(own)} bodies ({names}); say which with --body NAME")
        return own[0]

    def task(self, name: str | None = None) -> Task:
        """The task called `name`, or the only/first task of the root module."""
        if name is not None:
            return self.tasks[name]
        for decl in self.root.decls:
            if isinstance(decl, Task):
                return decl
        raise KeyError("the program declares no task")
