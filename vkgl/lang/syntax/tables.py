"""The grammar's LALR tables, kept between processes in the cache folder.

Lark builds the tables of grammar/vkg.lark in about a tenth of a second, as
long as the rest of `vkgc check`; it loads them saved in a few milliseconds.
The saved parser (`Lark.save`) is kept in the cache folder
(`vkgl.resources.cache_folder`) in a file whose name and first line are the
hash of everything the tables depend on: the grammar's text, the parser's
options, Lark's and Python's versions. A file whose first line differs, or
that Lark cannot load, is ignored and written again; files are written to a
temporary name and renamed, so a process never reads another's half-written
file (a saved parser is not the same bytes from one process to the next).
"""

from __future__ import annotations

import hashlib
import io
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import lark
from lark import Lark

from vkgl.atomic import write_bytes
from vkgl.resources import cache_folder

_FORMAT = "vkg-lark-tables/1"  # part of the key: a new way of saving forgets the old files


def load_or_build(grammar: str, options: Mapping[str, Any], build: Callable[[], Lark]) -> Lark:
    """The parser `build()` makes of `grammar` with `options` (no callbacks), loaded from the cache when kept."""
    key = _key(grammar, options)
    path = _file(key)
    if path is not None:
        loaded = _load(path, key)
        if loaded is not None:
            return loaded
    parser = build()
    if path is not None:
        _store(path, key, parser)
    return parser


def _key(grammar: str, options: Mapping[str, Any]) -> str:
    described = [_FORMAT, lark.__version__, repr(sys.version_info[:2]), repr(sorted(options.items())), grammar]
    return hashlib.sha256("\0".join(described).encode("utf-8")).hexdigest()


def _file(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / f"grammar-{key[:32]}.lark-tables"


def _load(path: Path, key: str) -> Lark | None:
    try:
        with path.open("rb") as stream:
            if stream.readline().rstrip(b"\n") != key.encode("ascii"):
                return None
            return Lark.load(stream)
    except Exception:  # missing, unreadable, torn or from another Lark: build the tables instead
        return None


def _store(path: Path, key: str, parser: Lark) -> None:
    """Keep `parser` at `path` (by the one atomic writer: no process reads another's half-written file; a
    failure only means building again next time)."""
    buffer = io.BytesIO()
    try:
        buffer.write(key.encode("ascii") + b"\n")
        parser.save(buffer)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_bytes(path, buffer.getvalue())
    except Exception:  # a read-only or full disk, or a parser Lark cannot save
        pass
