"""vkgl: the VKG language and its compiler.

    import vkgl
    program = vkgl.compile("examples/tasks/b_stick_push.vkg")
    plan = vkgl.solve(program)
    print(plan.text())

The functions here are the driver's (`vkgl.api`); docs/api.md shows them all.
Heavy back ends (DART, NLopt) are imported inside them, so `import vkgl` is fast.
"""

from importlib import metadata as _metadata
from typing import TYPE_CHECKING as _TYPE_CHECKING

from vkgl.api import compile, compile_source, execute, explore, infer, learn, solve
from vkgl.errors import CompileError, InputError, VkgError

if _TYPE_CHECKING:
    from vkgl.lang.ir.program import Program

try:
    __version__ = _metadata.version("vkgl")
except _metadata.PackageNotFoundError:  # a source checkout that is not installed
    __version__ = "0+unknown"

__all__ = [
    "CompileError",
    "InputError",
    "Program",
    "VkgError",
    "__version__",
    "compile",
    "compile_source",
    "execute",
    "explore",
    "infer",
    "learn",
    "solve",
]


def __getattr__(name: str) -> object:
    # `vkgl.Program` without importing the front end (pydantic, lark) when only the CLI's help is wanted.
    if name == "Program":
        from vkgl.lang.ir.program import Program

        return Program
    raise AttributeError(f"module 'vkgl' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
