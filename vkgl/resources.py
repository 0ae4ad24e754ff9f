"""Where the shipped data lives (the grammar and the standard library), and where vkgl keeps what it computes once.

In a wheel they are inside the package (`vkgl/grammar`, `vkgl/stdlib`); in a
source checkout (editable install, tests) they are at the repository root.

The cache folder holds what is worth computing once per machine rather than
once per process: the arm's reach (`vkgl.formats.reach_cache`), the grammar's
LALR tables (`vkgl.lang.syntax.tables`) and the URDFs DART has loaded
(`vkgl.lang.checks.urdf`), so that `vkgc check` starts fast, and the bodies'
convex hulls (`vkgl.plan.problem.hulls`), so that `vkgc solve` needs no SciPy. It is
`$VKGL_CACHE_DIR`, else `$XDG_CACHE_HOME/vkgl`, else `~/.cache/vkgl`;
`VKGL_CACHE_DIR=off` turns it off. The cache is only a speed-up: a file that cannot be read or written is
ignored, never an error, and every file names what it was computed from.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

CACHE_ENV = "VKGL_CACHE_DIR"
CACHE_OFF = "off"
"""`VKGL_CACHE_DIR=off`: compute everything in the process, keep nothing on disk."""

_PACKAGE = Path(__file__).resolve().parent


def _find(name: str) -> Path:
    inside = _PACKAGE / name
    if inside.is_dir():
        return inside
    return _PACKAGE.parent / name


def grammar_path() -> Path:
    """The path of `vkg.lark`."""
    return _find("grammar") / "vkg.lark"


def stdlib_dir() -> Path:
    """The directory `stdlib/` (its parent is an import root)."""
    return _find("stdlib")


def cache_folder() -> Path | None:
    """The folder of the cache (it may not exist yet), or None when the cache is off."""
    chosen = os.environ.get(CACHE_ENV)
    if chosen:
        return None if chosen == CACHE_OFF else Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "vkgl"


def read_cache_file(path: Path, limit: int) -> bytes | None:
    """The bytes of the cache file `path` if it is a regular file of at most `limit` bytes, else None (missing,
    unreadable, too large, or not a regular file: a FIFO or a device in its place). Never blocks, never reads
    more than `limit` + 1 bytes."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)  # non-blocking: opening a FIFO does not wait for a writer
    except OSError:
        return None
    try:
        info = os.fstat(fd)  # of what was opened, not of what the name pointed to a moment before
        if not stat.S_ISREG(info.st_mode) or info.st_size > limit:
            return None
        chunks: list[bytes] = []
        size = 0
        while size <= limit:
            chunk = os.read(fd, limit + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        return b"".join(chunks) if size <= limit else None
    except OSError:
        return None
    finally:
        os.close(fd)
