"""The one exception family of vkgl.

The front end collects `Diagnostic`s and raises a single `CompileError` carrying
all of them; the back ends raise the other subclasses with a message that says
what to change. The CLI turns them into one-line errors and exit codes.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any


class VkgError(Exception):
    """Base of every error vkgl raises on purpose. `exit_code` is what `vkgc` exits with."""

    exit_code = 4


class InputError(VkgError):
    """The user's input (a file, an option, a dataset) is wrong; the message says where and what to change."""

    exit_code = 1


class CompileError(InputError):
    """A `.vkg` program has errors; `diagnostics` holds all of them, sorted by position.

    They are `vkgl.lang.diagnostics.diagnostic.Diagnostic`s; typed loosely here because this module is the
    bottom layer, which imports nothing of vkgl (not even for type checking).
    """

    def __init__(self, diagnostics: list[Any]) -> None:
        self.diagnostics = diagnostics
        first = diagnostics[0].headline() if diagnostics else "compilation failed"
        more = f" (and {len(diagnostics) - 1} more)" if len(diagnostics) > 1 else ""
        super().__init__(first + more)


class PlanFormatError(InputError):
    """A `vkg-plan/8` document is malformed; `path` is the JSON path of the bad field (e.g. `steps[2].value`)."""

    def __init__(self, path: str, problem: str) -> None:
        self.path = path
        self.problem = problem
        super().__init__(f"{path}: {problem}" if path else problem)


class SimulationError(VkgError):
    """The simulator could not run what was asked (e.g. DART rejected a mesh)."""

    exit_code = 1


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """` (did you mean `X`?)`-style help for a misspelled name: "did you mean `X`?", or "" when none is close.

    Every message that names something a user typed (a keyword, an option, a task, a module) suggests the
    closest known name with this one rule, so a typo is always answered the same way.
    """
    import difflib

    match = difflib.get_close_matches(name, sorted(set(candidates)), n=1, cutoff=0.6)
    return f"did you mean `{match[0]}`?" if match else ""
