"""How to get the affordances of a body that a goal names but nothing can move (W601's note).

The stdlib's module when it has one (`use stdlib.affordances.block`); otherwise the `vkgc learn` command
for the body's own file, since suggesting a stdlib module that does not exist sends the reader to E501.
"""

from __future__ import annotations

import os
import re
import shlex
from functools import cache

from vkgl.lang.ir import nodes as ir
from vkgl.resources import stdlib_dir


def affordance_hint(body: ir.Body) -> str:
    """W601's note for `body`: the stdlib module that holds its affordances, else how to learn them."""
    module = stdlib_affordance_module(body.name)
    if module is not None:
        return f"add `use {module}` or learn one with `vkgc learn`"
    command = "vkgc learn" + (f" {shlex.quote(_shown(body.span.file))}" if body.span is not None else "")
    return f"the stdlib has none for `{body.name}`: learn them with `{command}` and `use` the module it writes"


def stdlib_affordance_module(body: str) -> str | None:
    """The dotted name of the stdlib module that declares `affordances BODY`, or None when none does."""
    return _affordance_modules().get(body)


@cache
def _affordance_modules() -> dict[str, str]:
    """Body name -> `stdlib.affordances.NAME`, read from the installed stdlib's modules."""
    found: dict[str, str] = {}
    folder = stdlib_dir() / "affordances"
    for path in sorted(folder.glob("*.vkg")) if folder.is_dir() else []:
        text = path.read_text(encoding="utf-8", errors="replace")
        for name in re.findall(r"^affordances\s+([A-Za-z_][A-Za-z0-9_]*)", text, flags=re.MULTILINE):
            found.setdefault(name, f"stdlib.affordances.{path.stem}")
    return found


def _shown(path: str) -> str:
    """`path` relative to the working directory when inside it, else as it is."""
    try:
        relative = os.path.relpath(path)
    except ValueError:  # another drive on Windows
        return path
    return path if relative.startswith("..") else relative
