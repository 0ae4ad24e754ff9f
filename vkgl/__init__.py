"""vkgl: the VKG language and its compiler.

    import vkgl
    program = vkgl.compile("examples/tasks/b_stick_push.vkg")
    plan = vkgl.solve(program)
    print(plan.text())

The functions here are the driver's (`vkgl.api`); docs/api.md shows them all.
Heavy back ends (DART, NLopt) are imported inside them, so `import vkgl` is fast.
"""

from typing import TYPE_CHECKING as _TYPE_CHECKING

from vkgl.api import compile, compile_source, execute, explore, infer, learn, solve
from vkgl.errors import CompileError, InputError, VkgError

if _TYPE_CHECKING:
    from vkgl.lang.ir.program import Program

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
    if name == "__version__":  # importlib.metadata costs 30 ms of every `vkgc` start; only --version wants it
        return _version()
    raise AttributeError(f"module 'vkgl' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)


def _version() -> str:
    from importlib import metadata

    try:
        return metadata.version("vkgl")
    except metadata.PackageNotFoundError:  # a source checkout that is not installed
        return "0+unknown"
