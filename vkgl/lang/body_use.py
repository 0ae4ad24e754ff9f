"""Whether the module `vkgc infer` writes will find its body: the `use` it is given (or its default) is looked up
from where the module goes, before anything is inferred (`vkgl.api.infer(check_from=)`). Here, in the front end,
because only the front end compiles: the lookup is the compiler's own.

The trials name only their body type (`Crate`); the generated module imports
the module that declares it, by default `stdlib.bodies.<body>`. For a body of
one's own that module does not exist, and the module was written anyway: the
first `vkgc check` of it said E501 and E301. Now `vkgc infer` stops first
(exit 1, nothing written), saying which module it looked for, from where, and
which `--use` to pass: the path, relative to the output's folder, of a body
file near it that declares the body (`../bodies/crate.vkg` in the stdlib's
layout, `bodies/crate.vkg`, or `crate.vkg` beside it), else the two forms
`--use` takes.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from vkgl.errors import CompileError, InputError

__all__ = ["check_body_use"]


def check_body_use(use: str, body: str, module_path: str | os.PathLike[str], *, given: bool) -> None:
    """Raise InputError unless a module at `module_path` that says `use` (a dotted name, or a path ending in
    `.vkg`) finds a module that declares the body type `body`. `given`: whether the user named `use` (`--use`),
    else it is the default."""
    from vkgl.lang.compiler import compile_source
    from vkgl.lang.diagnostics.codes import MISSING_MODULE

    destination = Path(module_path)
    line = f'use "{use}"' if use.endswith(".vkg") else f"use {use}"
    which = f"`--use {use}`" if given else f"the default `--use {use}`"
    of = f"the trials are of `{body}`"
    try:
        program = compile_source(line + "\n", str(destination), base_dir=destination.parent)
    except CompileError as exc:
        missing = next((d for d in exc.diagnostics if d.code == MISSING_MODULE.code), None)
        first = missing or exc.diagnostics[0]
        problem = "names no module" if missing is not None else "names a module with errors"
        said = "; ".join((first.message, *first.notes))
        raise InputError(
            f"{of}, and {which} {problem} ({said}), so the module written to {destination} would not "
            f"compile; {_what_to_pass(body, destination)}"
        ) from None
    if body not in program.bodies:
        known = ", ".join(f"`{name}`" for name in sorted(program.bodies)) or "none"
        raise InputError(
            f"{of}, and {which} declares no body `{body}` (its bodies: {known}), so the module written to "
            f"{destination} would not compile; {_what_to_pass(body, destination)}"
        )


def _what_to_pass(body: str, destination: Path) -> str:
    """The `--use` to pass: a body file near the output that declares `body`, or the two forms `--use` takes."""
    folder = destination.parent
    stem = body.lower()
    declares = re.compile(rf"^\s*body\s+{re.escape(body)}\b", re.M)
    for candidate in (
        folder.parent / "bodies" / f"{stem}.vkg",
        folder / "bodies" / f"{stem}.vkg",
        folder / f"{stem}.vkg",
    ):
        try:
            if (
                candidate != destination
                and candidate.is_file()
                and declares.search(candidate.read_text(encoding="utf-8", errors="replace"))
            ):
                relative = Path(os.path.relpath(candidate, folder)).as_posix()
                return f"`{candidate}` declares it: pass `--use {relative}` (its path from the output's folder)"
        except OSError:
            continue
    return (
        f"pass `--use` the module that declares `body {body}`, as the output will find it: its path from the "
        f"output's folder (`--use ../bodies/{stem}.vkg`), or its dotted name from that folder or a `VKG_PATH` "
        f"folder (`--use mylib.bodies.{stem}`)"
    )
