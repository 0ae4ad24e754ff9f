"""The front end's entry points: compile a file (or a string) into a checked Program, or check many files.

`compile_file` is what `vkgl.compile(path)` and every back end call;
`compile_source` compiles text held in memory (tests, notebooks, generated problems);
`check_files` is `vkgc check`: it reports and never raises for bad input.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from vkgl.errors import CompileError
from vkgl.lang.checks.checker import check_program
from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.program import Program
from vkgl.lang.resolve import LoadedProgram, load_program, load_source


def compile_file(path: str | Path) -> Program:
    """Parse, resolve and check `path` and its imports.

    Raises CompileError carrying every error, sorted by position; warnings are
    kept in `Program.warnings`.
    """
    return _raise_or_program(*_compile(str(path)))


def compile_source(text: str, name: str = "<string>", *, base_dir: str | Path | None = None) -> Program:
    """Parse, resolve and check the module `text`, as `compile_file` does a file.

    Diagnostics show `name` as its path. `use` lines and relative mesh and URDF
    paths of the text start from `base_dir` (the working directory when None).
    Raises CompileError carrying every error; warnings are kept in `Program.warnings`.
    """
    return _raise_or_program(*_check_loaded(load_source(text, name, base_dir)))


def _raise_or_program(program: Program | None, diagnostics: list[Diagnostic]) -> Program:
    errors = [d for d in diagnostics if d.is_error]
    if errors or program is None:
        raise CompileError(errors or diagnostics)
    program.warnings = [d for d in diagnostics if not d.is_error]
    return program


def check_files(paths: list[str]) -> tuple[list[Diagnostic], dict[str, str]]:
    """Every diagnostic of every file (each compiled as a root), and the sources by path, for rendering."""
    found: list[Diagnostic] = []
    sources: dict[str, str] = {}
    for path in paths:
        program, diagnostics = _compile(path)
        if program is not None:
            sources.update(program.sources)
        found.extend(diagnostics)
    return _unique(found), sources


def check_file(path: str | Path) -> tuple[Program | None, list[Diagnostic]]:
    """One compilation of `path`: the (possibly partial) program and exactly `check_files([path])`'s diagnostics."""
    program, diagnostics = _compile(str(path))
    return program, _unique(diagnostics)


def _unique(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """Sorted, each headline once (a module used by several checked files reports its problems once)."""
    seen: set[str] = set()
    kept: list[Diagnostic] = []
    for diag in diagnostics:
        key = diag.headline()
        if key not in seen:
            seen.add(key)
            kept.append(diag)
    return sorted(kept, key=Diagnostic.sort_key)


def _compile(path: str) -> tuple[Program | None, list[Diagnostic]]:
    return _check_loaded(load_program(path))


def _check_loaded(loaded: LoadedProgram) -> tuple[Program | None, list[Diagnostic]]:
    if loaded.root not in loaded.modules:
        return _empty(loaded.root, loaded.sources), sorted(loaded.diagnostics, key=Diagnostic.sort_key)
    program, diagnostics = check_program(loaded.modules, loaded.root, loaded.sources, loaded.folders)
    if any(d.code in _UNLOADED for d in loaded.diagnostics):
        diagnostics = [_maybe_in_unloaded_module(d) for d in diagnostics]
    return program, sorted(loaded.diagnostics + diagnostics, key=Diagnostic.sort_key)


# A module that could not be found, read or parsed, or that closes a cycle: its names are missing.
_UNLOADED = {
    c.code
    for c in (
        codes.MISSING_MODULE,
        codes.IMPORT_CYCLE,
        codes.SOURCE_UNREADABLE,
        codes.UNEXPECTED_TOKEN,
        codes.UNEXPECTED_CHARACTER,
        codes.UNEXPECTED_END,
        codes.NESTING_TOO_DEEP,
        codes.TOO_MANY_TOKENS,
        codes.UNKNOWN_UNIT,
    )
}


def _maybe_in_unloaded_module(diag: Diagnostic) -> Diagnostic:
    """An unknown name may be declared in a module that failed to load: say so, so the user fixes that first."""
    if diag.code != codes.UNKNOWN_NAME.code:
        return diag
    note = "a module of this compilation could not be loaded (see its error); the name may be declared there"
    return replace(diag, notes=(*diag.notes, note))


def _empty(root: str, sources: dict[str, str]) -> Program:
    from vkgl.lang.ir.nodes import Module

    return Program(root=Module(path=root), sources=dict(sources))
