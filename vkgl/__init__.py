"""vkgl: the VKG language and its compiler.

    import vkgl
    program = vkgl.compile("examples/tasks/b_stick_push.vkg")
    plan = vkgl.solve("examples/tasks/b_stick_push.vkg")

Heavy back ends (DART, NLopt) are imported lazily so that `vkgc --help` is fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

if TYPE_CHECKING:
    from vkgl.lang.program import Program


def compile(path: str) -> Program:
    """Parse, resolve and check a `.vkg` file and everything it uses; raise CompileError on errors."""
    from vkgl.lang.compiler import compile_file

    return compile_file(path)


def solve(task: Any, **options: Any) -> Any:
    """Plan for a task (a path, a Program or a Task IR); return a Plan. See `vkgl.plan.solve`."""
    from vkgl.plan.solve import solve as _solve

    return _solve(task, **options)
