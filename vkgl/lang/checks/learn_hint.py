"""Where the stdlib declares what a program lacks: notes for W601 and E301.

W601 (a goal body nothing can move): the stdlib's affordance module when it has one (`use
stdlib.affordances.block`); otherwise the `vkgc learn` command for the body's own file, since suggesting a
stdlib module that does not exist sends the reader to E501. E301 (an unknown body or robot): the stdlib
module that declares it, or one with a close name, when nothing in scope is close (a forgotten `use`).
"""

from __future__ import annotations

import difflib
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


def stdlib_use_hint(name: str, kind: str) -> str:
    """E301's note for an unknown body or robot `name`: the `use` of the stdlib module that declares it (or a
    name close to it); '' when the stdlib has nothing close."""
    declared = _declarations().get(kind, {})
    if name in declared:
        return f"the stdlib declares {kind} `{name}`: add `use {declared[name]}`"
    match = difflib.get_close_matches(name, sorted(declared), n=1, cutoff=0.6)
    if match:
        return f"did you mean `{match[0]}`? the stdlib declares it: add `use {declared[match[0]]}`"
    return ""


@cache
def _declarations() -> dict[str, dict[str, str]]:
    """Kind (`body`, `robot`) -> name -> dotted module, for every declaration of the installed stdlib."""
    found: dict[str, dict[str, str]] = {"body": {}, "robot": {}}
    root = stdlib_dir()
    for path in sorted(root.rglob("*.vkg")):
        text = path.read_text(encoding="utf-8", errors="replace")
        module = ".".join(("stdlib", *path.relative_to(root).with_suffix("").parts))
        for kind, name in re.findall(r"^(body|robot)\s+([A-Za-z_][A-Za-z0-9_]*)", text, flags=re.MULTILINE):
            found[kind].setdefault(name, module)
    return found


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
