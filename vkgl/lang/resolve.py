"""Import resolution: load a root module and everything it `use`s, once each.

Dotted names (`use mylib.bodies.crate`) are looked up under, in order: the
importing file's directory, each directory of `VKG_PATH`, and the directory
that holds the installed `stdlib/`. `stdlib.*` names are the exception: one
stdlib per compilation, the installed one (the `stdlib/` of the vkgl that
runs), so that no module of a compilation reads another copy of it. A local
`stdlib/` folder is never read for them; when it holds a module that differs
from the installed one, W603 says so. String paths are relative to the
importing file. Modules are identified by their resolved absolute path; a
cycle is an error that prints the cycle.
"""

from __future__ import annotations

import difflib
import os
from dataclasses import dataclass, field
from pathlib import Path

from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.module_cache import parse_file_text
from vkgl.lang.syntax.sources import foreign_link, read_source
from vkgl.resources import stdlib_dir


@dataclass
class LoadedProgram:
    """Every module of one compilation, dependencies before the modules that use them."""

    root: str
    modules: dict[str, ir.Module] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # The directory each module's relative paths (meshes, URDFs, `use "..."`) start from.
    folders: dict[str, Path] = field(default_factory=dict)


def import_roots(importing_file: str, dotted: str = "") -> list[Path]:
    """Where the dotted `use` of `dotted` from `importing_file` is looked up, in order.

    `stdlib.*` names are looked up in the installed stdlib only (one stdlib per compilation).
    """
    installed = stdlib_dir().resolve().parent
    if _is_stdlib(dotted):
        return [installed]
    return [*_local_roots(importing_file), installed]


def _local_roots(importing_file: str) -> list[Path]:
    """The importing file's directory and each `VKG_PATH` directory, in order."""
    roots = [_real(Path(importing_file)).parent]
    for entry in os.environ.get("VKG_PATH", "").split(os.pathsep):
        if entry.strip():
            roots.append(_real(Path(entry).expanduser()))
    return roots


def _is_stdlib(dotted: str) -> bool:
    return dotted == "stdlib" or dotted.startswith("stdlib.")


def _real(path: Path) -> Path:
    """`path` resolved through symbolic links; absolute but unresolved when it is a link loop."""
    try:
        return path.resolve()
    except (OSError, RuntimeError):  # RuntimeError: Python 3.11's "Symlink loop"
        return Path(os.path.abspath(path))


def load_program(path: str) -> LoadedProgram:
    """Read, parse and resolve `path` and its imports; problems become diagnostics."""
    loaded = LoadedProgram(root=_display_path(Path(path)))
    _Loader(loaded).load(Path(path), via=None, stack=[])
    return loaded


def load_source(text: str, name: str, base_dir: str | Path | None = None) -> LoadedProgram:
    """Parse `text` as the root module shown as `name`, and resolve its imports like `load_program`.

    `use` lines and relative file paths of the text start from `base_dir` (the
    working directory when None), as if the text were a file there.
    """
    folder = Path(base_dir if base_dir is not None else Path.cwd()).resolve()
    loaded = LoadedProgram(root=name)
    _Loader(loaded).load_text(text, name, folder / "<source>.vkg")
    return loaded


def _parse(text: str, path: str) -> tuple[ir.Module | None, list[Diagnostic]]:
    from vkgl.lang.syntax.parser import parse_collecting  # Lark: only when a text is parsed

    module, _, diagnostics = parse_collecting(text, path)
    return module, diagnostics


class _Loader:
    def __init__(self, loaded: LoadedProgram) -> None:
        self.out = loaded
        self.by_real: dict[Path, str] = {}

    def load(self, path: Path, via: ir.Use | None, stack: list[Path]) -> str | None:
        """Load `path` (if not yet loaded) and its imports; return its key in `modules`."""
        real = _real(path)
        if real in stack:
            self._report_cycle(stack[stack.index(real) :] + [real], via)
            return None
        if real in self.by_real:
            return self.by_real[real]
        shown = _display_path(path)
        # `x.vkg` (used, or named on the command line) links to /etc/passwd: not a module, never read nor quoted.
        foreign = foreign_link(path, _display_link(path), via.span if via is not None else None)
        if foreign is not None:
            self.out.diagnostics.append(foreign)
            return None
        source = self._read(path, shown, via)
        if source is None:
            return None
        return self.load_text(source, shown, real, stack, from_file=True)

    def load_text(
        self, source: str, shown: str, real: Path, stack: list[Path] | None = None, *, from_file: bool = False
    ) -> str | None:
        """Parse `source` as the module `shown` found at `real` (which need not exist) and load its imports.

        The parse of a file's text (`from_file`) may be read back from the cache folder (vkgl.lang.module_cache).
        """
        stack = stack or []
        module, diagnostics = parse_file_text(source, shown) if from_file else _parse(source, shown)
        self.out.sources[shown] = source
        self.out.diagnostics.extend(diagnostics)
        if module is None:
            return None
        self.by_real[real] = shown
        self.out.folders[shown] = real.parent
        uses = [self._resolve_use(use, real, stack + [real]) for use in module.uses]
        self.out.modules[shown] = module.model_copy(update={"uses": uses})
        return shown

    def _read(self, path: Path, shown: str, via: ir.Use | None) -> str | None:
        """The file's text; None after a diagnostic (at the `use`, or naming the file given on the command line)."""
        source = read_source(path, shown, via.span if via is not None else None)
        if isinstance(source, str):
            return source
        self.out.diagnostics.append(source)
        return None

    def _resolve_use(self, use: ir.Use, importer: Path, stack: list[Path]) -> ir.Use:
        if use.by_path and not use.target.endswith(".vkg"):
            # Never read (nor later quote) a file that is not a module: `use "/etc/passwd"`.
            self.out.diagnostics.append(
                codes.USE_NOT_VKG.diagnostic(
                    f'`use "{use.target}"` does not name a .vkg module; it is not read',
                    use.span,
                    'only .vkg modules can be used: `use "path/module.vkg"` or `use dotted.name`',
                )
            )
            return use
        target = _find_module(use, importer)
        if target is None:
            self.out.diagnostics.append(_missing_module(use, importer))
            return use
        unread = _unread_local_stdlib(use, importer, target)
        if unread is not None:
            self.out.diagnostics.append(unread)
        self.load(target, use, stack)
        return use.model_copy(update={"resolved": str(_real(target))})

    def _report_cycle(self, cycle: list[Path], via: ir.Use | None) -> None:
        chain = " -> ".join(_display_path(p) for p in cycle)
        self.out.diagnostics.append(
            codes.IMPORT_CYCLE.diagnostic(
                f"import cycle: {chain}", via.span if via else None, "remove one of these `use` lines"
            )
        )


def _find_module(use: ir.Use, importer: Path) -> Path | None:
    """The file a `use` names, if something is there (whether it can be read is `read_source`'s business)."""
    if use.by_path:
        candidate = importer.parent / use.target
        return candidate if os.path.lexists(candidate) else None
    relative = Path(*use.target.split(".")).with_suffix(".vkg")
    for root in import_roots(str(importer), use.target):
        candidate = root / relative
        if os.path.lexists(candidate):
            return candidate
    return None


def _unread_local_stdlib(use: ir.Use, importer: Path, installed: Path) -> Diagnostic | None:
    """W603 when `use stdlib.X` has a local `stdlib/X.vkg` (beside the file or in `VKG_PATH`) that differs from the
    installed module it reads: the user may believe their copy is used. An identical copy (a source checkout's
    `stdlib/` after `pip install .`) is no news."""
    if use.by_path or not _is_stdlib(use.target):
        return None
    relative = Path(*use.target.split(".")).with_suffix(".vkg")
    for root in _local_roots(str(importer)):
        local = root / relative
        if local.is_file() and _real(local) != _real(installed) and not _same_bytes(local, installed):
            return codes.SHADOWED_STDLIB.diagnostic(
                f"`use {use.target}` reads the installed stdlib's `{_display_path(installed)}`, not "
                f"`{_display_path(local)}`, which differs from it",
                use.span,
                "a compilation uses one stdlib, the installed one; to use your module, give it a name outside "
                "`stdlib` (e.g. move it to `mylib/`) or install your changed stdlib (`pip install -e .`)",
            )
    return None


def _same_bytes(a: Path, b: Path) -> bool:
    try:
        return a.stat().st_size == b.stat().st_size and a.read_bytes() == b.read_bytes()
    except OSError:
        return False


def _missing_module(use: ir.Use, importer: Path) -> Diagnostic:
    if use.by_path:
        message = f"no file `{use.target}` (relative to {_display_path(importer.parent)})"
        suggestion = _close_file(importer.parent / use.target)
    else:
        roots = import_roots(str(importer), use.target)
        message = f"cannot find module `{use.target}`; looked in: " + ", ".join(_described_roots(importer, use.target))
        suggestion = _close_module(use.target, roots)
    notes = (f"did you mean `{suggestion}`?",) if suggestion else ()
    return codes.MISSING_MODULE.diagnostic(message, use.span, *notes)


def _described_roots(importer: Path, dotted: str) -> list[str]:
    """The import roots of `dotted` from `importer`, each with why it is searched (for E501)."""
    roots = import_roots(str(importer), dotted)
    if _is_stdlib(dotted):
        return [f"{_display_folder(roots[0])} (the installed stdlib's parent: one stdlib per compilation)"]
    why = ["this file's directory"] + ["VKG_PATH"] * (len(roots) - 2) + ["the installed stdlib's parent"]
    return [f"{_display_folder(root)} ({reason})" for root, reason in zip(roots, why)]


def _display_folder(path: Path) -> str:
    shown = _display_path(path)
    return "./" if shown == "." else shown.rstrip("/") + "/"


def _close_module(dotted: str, roots: list[Path]) -> str | None:
    """A module name one typo away from `dotted`, found among the files beside where it was looked for."""
    parts = dotted.split(".")
    names: set[str] = set()
    for root in roots:
        folder = root.joinpath(*parts[:-1])
        if folder.is_dir():
            names.update(p.stem for p in folder.glob("*.vkg"))
    match = difflib.get_close_matches(parts[-1], sorted(names), n=1, cutoff=0.6)
    return ".".join(parts[:-1] + match) if match else None


def _close_file(target: Path) -> str | None:
    if not target.parent.is_dir():
        return None
    names = sorted(p.name for p in target.parent.glob("*.vkg"))
    match = difflib.get_close_matches(target.name, names, n=1, cutoff=0.6)
    return match[0] if match else None


def _display_path(path: Path) -> str:
    """A path as users like to read it: relative to the working directory when inside it."""
    real = _real(path)
    try:
        relative = os.path.relpath(real)
    except ValueError:  # another drive on Windows
        return str(real)
    return str(real) if relative.startswith("..") else relative


def _display_link(path: Path) -> str:
    """A path as written (a symbolic link not followed), relative to the working directory when inside it."""
    absolute = os.path.abspath(path)
    try:
        relative = os.path.relpath(absolute)
    except ValueError:  # another drive on Windows
        return absolute
    return absolute if relative.startswith("..") else relative
