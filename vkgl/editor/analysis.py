"""Compile what the editor shows: `vkgc check`'s diagnostics and the program, for unsaved buffers too.

`analyze(path, overlay)` compiles `path` the way `vkgc check path` does, except
that a module whose resolved path is a key of `overlay` is read from there (an
open editor buffer) instead of from disk. The diagnostics are exactly those of
`vkgl.lang.compiler.check_files([path])` (one compilation, by `check_file`).
A buffer larger than the CLI's source limit is refused as a file would be (E507).

The one seam: the import resolver reads files in `vkgl.lang.resolve._Loader._read`.
While an analysis runs, `resolve._Loader` is a subclass that looks in the
overlay first (under a lock; the language server handles one request at a
time anyway). When the front end grows a `read=` hook in `load_program`, this
module should use it instead.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from vkgl.lang import compiler, resolve
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.nodes import Module, Span, Use
from vkgl.lang.ir.program import Program
from vkgl.lang.syntax.sources import oversized_text

_LOCK = threading.Lock()


@dataclass
class Analysis:
    """What one compilation of a root file found.

    `diagnostics` is `vkgc check`'s list (sorted, de-duplicated); `program` the
    checked program (partial when there are errors; without modules when the
    root did not parse); `sources` every module's text by display path; `files` the resolved
    paths of every module of the compilation.
    """

    root: Path
    diagnostics: list[Diagnostic]
    program: Program
    sources: dict[str, str] = field(default_factory=dict)
    files: set[Path] = field(default_factory=set)

    def diagnostics_by_file(self) -> dict[Path, list[Diagnostic]]:
        """The diagnostics grouped by the resolved path of their file (no span: the root)."""
        grouped: dict[Path, list[Diagnostic]] = {self.root: []}
        for diag in self.diagnostics:
            where = resolved(diag.span.file) if diag.span is not None else self.root
            grouped.setdefault(where, []).append(diag)
        return grouped


def resolved(display_path: str) -> Path:
    """The absolute path of a span's file (display paths are relative to the working directory)."""
    return Path(display_path).resolve()


def span_path(span: Span) -> Path:
    """The absolute path of the file a span is in."""
    return resolved(span.file)


def analyze(path: str | Path, overlay: dict[Path, str] | None = None) -> Analysis:
    """Compile `path` (buffers in `overlay`, by resolved path, take the place of files) and report."""
    root = Path(path).resolve()
    with _reading(overlay or {}):
        compiled, diagnostics = compiler.check_file(path)
    program = compiled if compiled is not None else Program(root=Module(path=str(path)))
    sources = dict(program.sources)
    files = {resolved(shown) for shown in sources} | {root}
    files |= {resolved(key) for key in program.modules}
    return Analysis(
        root=root,
        diagnostics=diagnostics,
        program=program,
        sources=sources,
        files=files,
    )


@contextmanager
def _reading(overlay: dict[Path, str]) -> Iterator[None]:
    """While active, the import resolver reads `overlay`'s buffers instead of those files."""
    base = resolve._Loader

    class _OverlayLoader(base):  # type: ignore[valid-type, misc]
        def _read(self, path: Path, shown: str, via: Use | None) -> str | None:
            text = overlay.get(path.resolve())
            if text is None:
                return super()._read(path, shown, via)
            refused = oversized_text(text, shown, via.span if via is not None else None)
            if refused is not None:
                self.out.diagnostics.append(refused)
                return None
            return text

    with _LOCK:
        resolve._Loader = _OverlayLoader  # type: ignore[misc]
        try:
            yield
        finally:
            resolve._Loader = base  # type: ignore[misc]
