"""The front end's entry points: compile a file into a checked Program, or check many files.

`compile_file` is what `vkgl.compile(path)` and every back end call;
`check_files` is `vkgc check`: it reports and never raises for bad input.
"""

from __future__ import annotations

from pathlib import Path

from vkgl.errors import CompileError
from vkgl.lang.checks import check_program
from vkgl.lang.diagnostics import Diagnostic
from vkgl.lang.program import Program
from vkgl.lang.resolve import load_program


def compile_file(path: str | Path) -> Program:
    """Parse, resolve and check `path` and its imports.

    Raises CompileError carrying every error, sorted by position; warnings are
    kept in `Program.warnings`.
    """
    program, diagnostics = _compile(str(path))
    errors = [d for d in diagnostics if d.is_error]
    if errors or program is None:
        raise CompileError(errors or diagnostics)
    program.warnings = [d for d in diagnostics if not d.is_error]
    return program


def check_files(paths: list[str]) -> tuple[list[Diagnostic], dict[str, str]]:
    """Every diagnostic of every file (each compiled as a root), and the sources by path, for rendering."""
    diagnostics: list[Diagnostic] = []
    sources: dict[str, str] = {}
    seen: set[str] = set()
    for path in paths:
        program, found = _compile(path)
        if program is not None:
            sources.update(program.sources)
        for diag in found:
            key = diag.headline()
            if key not in seen:  # a module used by several checked files reports its problems once
                seen.add(key)
                diagnostics.append(diag)
    return sorted(diagnostics, key=Diagnostic.sort_key), sources


def _compile(path: str) -> tuple[Program | None, list[Diagnostic]]:
    loaded = load_program(path)
    if loaded.root not in loaded.modules:
        return _empty(loaded.root, loaded.sources), sorted(loaded.diagnostics, key=Diagnostic.sort_key)
    program, diagnostics = check_program(loaded.modules, loaded.root, loaded.sources)
    return program, sorted(loaded.diagnostics + diagnostics, key=Diagnostic.sort_key)


def _empty(root: str, sources: dict[str, str]) -> Program:
    from vkgl.lang.ir import Module

    return Program(root=Module(path=root), sources=dict(sources))
