"""The parses of module files, kept between processes in the cache folder, as Python keeps its bytecode.

`vkgc check` and `vkgc solve` of a task parse every module it uses, most of
them the same files every time (the standard library, a scene): importing Lark,
loading its tables and parsing take about a sixth of a `vkgc check`. A file's
parse (its IR module, comments and diagnostics) depends only on its text, the
path it is shown as, and the front end's code, so the parse of each module
file read from disk (`vkgl.lang.resolve`: its IR module and diagnostics; a
compilation needs no comments) is kept in the cache folder
(`vkgl.resources.cache_folder`) and read back while none of them changed:

- one file per shown path (`parse-<hash>.pickle`), so editing a module, or
  the front end's code, replaces its parse rather than adding one: the folder
  holds at most one parse per module file checked;
- its first line is the hash of everything the parse depends on: the text,
  the shown path, the code (every module of `vkgl/lang` with
  `vkgl/errors.py`, `vkgl/rotations.py` and the grammar, by path, size and
  time, as Python checks its bytecode) and the versions of Python, pydantic
  and Lark; a file whose first line differs, or that cannot be read back, is
  ignored and written again;
- the rest is the parse, pickled, as Lark keeps its tables in the same folder
  (the cache folder is the user's own: what is in it is trusted as much).

Texts sent by an editor are never kept (only files read from disk are), nor
texts over `MAX_CHARS`. The cache is only a speed-up: a file that cannot be
read or written is ignored, never an error.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import pickle
import sys
from functools import lru_cache
from pathlib import Path
from typing import Any

from vkgl.atomic import write_bytes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.syntax.parse_cache import ParseCache
from vkgl.resources import cache_folder, grammar_path, read_cache_file

_FORMAT = "vkg-parse-cache/1"  # part of the key: a new way of keeping parses forgets the old files
MAX_CHARS = 200_000
"""The largest text whose parse is kept (a parse pickles to a few bytes per character of source)."""
MAX_BYTES = 64 * 1024 * 1024
"""The largest cache file read."""

_PACKAGE = Path(__file__).resolve().parent.parent  # vkgl/

_Parsed = tuple[ir.Module | None, tuple[Diagnostic, ...]]


def parse_file_text(text: str, path: str) -> tuple[ir.Module | None, list[Diagnostic]]:
    """The module and diagnostics of `parse_collecting(text, path)` for the text of a module file: read back
    in this process or from the cache folder, else parsed (the parser, and Lark with it, is imported only
    then) and kept."""
    found = _read_back.get((text, path))
    if found is None and len(text) <= MAX_CHARS:
        found = _load(text, path)
        if found is not None:
            _read_back.put((text, path), found)
    if found is None:
        from vkgl.lang.syntax.parser import parse_collecting

        module, _, diagnostics = parse_collecting(text, path)
        if len(text) <= MAX_CHARS:
            _store(text, path, (module, tuple(diagnostics)))
        return module, diagnostics
    module, kept = found
    return module, list(kept)


_read_back: ParseCache[_Parsed] = ParseCache(4 * MAX_CHARS)  # parses read back, by (text, path)


def forget_read_back() -> None:
    """Forget the parses read back in this process (benchmarks that time parsing call it)."""
    _read_back.clear()


def _load(text: str, path: str) -> _Parsed | None:
    entry = _entry(path)
    if entry is None:
        return None
    raw = read_cache_file(entry, MAX_BYTES)
    if raw is None:
        return None
    first, _, payload = raw.partition(b"\n")
    if first != _key(text, path).encode("ascii"):
        return None
    try:
        parsed = pickle.loads(payload)
    except Exception:  # torn, or pickled by another pydantic: parse instead
        return None
    return parsed if _is_parse(parsed) else None


def _is_parse(value: Any) -> bool:
    if not isinstance(value, tuple) or len(value) != 2:
        return False
    module, diagnostics = value
    return (
        (module is None or isinstance(module, ir.Module))
        and isinstance(diagnostics, tuple)
        and all(isinstance(d, Diagnostic) for d in diagnostics)
    )


def _store(text: str, path: str, parsed: _Parsed) -> None:
    """Keep `parsed` (by the one atomic writer: no process reads another's half-written file; a failure only
    means parsing again next time)."""
    entry = _entry(path)
    if entry is None:
        return
    with contextlib.suppress(Exception):  # a read-only or full disk, or a parse that cannot be pickled
        payload = _key(text, path).encode("ascii") + b"\n" + pickle.dumps(parsed, protocol=pickle.HIGHEST_PROTOCOL)
        entry.parent.mkdir(parents=True, exist_ok=True)
        write_bytes(entry, payload)


def _entry(path: str) -> Path | None:
    folder = cache_folder()
    if folder is None:
        return None
    name = hashlib.sha256(f"{_FORMAT}\0{path}".encode("utf-8", "surrogatepass")).hexdigest()[:32]
    return folder / f"parse-{name}.pickle"


def _key(text: str, path: str) -> str:
    digest = hashlib.sha256()
    for part in (_FORMAT, code_identity(), path):
        digest.update(part.encode("utf-8", "surrogatepass") + b"\0")
    digest.update(text.encode("utf-8", "surrogatepass"))
    return digest.hexdigest()


@lru_cache(maxsize=1)
def code_identity() -> str:
    """What a parse depends on besides its text and path: the front end's code files (path, size, time), the
    grammar, and the versions of Python, pydantic and Lark (Lark's found without importing it)."""
    import pydantic

    files = [*_python_files(_PACKAGE / "lang"), _PACKAGE / "errors.py", _PACKAGE / "rotations.py", grammar_path()]
    parts = [repr(sys.version_info), pydantic.VERSION, _origin_identity("lark")]
    for file in files:
        try:
            found = os.stat(file)
        except OSError:
            parts.append(f"{file}:missing")
            continue
        parts.append(f"{file}:{found.st_size}:{found.st_mtime_ns}")
    return hashlib.sha256("\0".join(parts).encode("utf-8", "surrogatepass")).hexdigest()


def _python_files(folder: Path) -> list[Path]:
    found: list[Path] = []
    with contextlib.suppress(OSError):
        for item in sorted(os.scandir(folder), key=lambda e: e.name):
            if item.is_dir() and item.name != "__pycache__":
                found += _python_files(Path(item.path))
            elif item.name.endswith(".py"):
                found.append(Path(item.path))
    return found


def _origin_identity(package: str) -> str:
    try:
        spec = importlib.util.find_spec(package)
        origin = spec.origin if spec is not None else None
        if origin is None:
            return f"{package}:none"
        found = os.stat(origin)
    except (ImportError, ValueError, OSError):
        return f"{package}:none"
    return f"{origin}:{found.st_size}:{found.st_mtime_ns}"


__all__ = ["MAX_CHARS", "code_identity", "forget_read_back", "parse_file_text"]
