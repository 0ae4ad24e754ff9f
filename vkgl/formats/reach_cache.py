"""`vkg-reach-cache/1`: an arm's reachable radii per height, kept between processes (its only reader and writer).

Computing an arm's reach at a new height takes ten constrained optimisations
and IK all around the base (`vkgl.robot.reach`), 0.05 to 0.1 s each; a
planner process needs a few heights, and every `vkgc solve` is a new process.
The results are kept in one JSON file per arm model in the user's cache
folder, so a height is computed once per machine, not once per process:

    {"format": "vkg-reach-cache/1", "key": "<sha256>", "reach": {"0.025": [0.094, 0.8], ...}}

`key` names everything the values depend on (the URDF's bytes, the effector
link and offset, the version of the code that computed them); a file whose key
or format differs is ignored and replaced. Heights are written to the mm, as
the planner rounds them. Floats round-trip exactly through JSON, so a value
read back is the value computed: a cached run plans exactly as a cold one.

The folder is `$VKGL_CACHE_DIR`, else `$XDG_CACHE_HOME/vkgl`, else
`~/.cache/vkgl`; `VKGL_CACHE_DIR=off` turns the cache off. The cache is only
a speed-up, and is not trusted: only a regular file of at most `MAX_BYTES` is
read (a FIFO, a device or a link to `/dev/zero` in its place is never opened
for long, nor read without bound); a file that cannot be read or parsed
(deep nesting included) is ignored, never an error; an entry whose interval
is implausible (not finite, negative, or r_min > r_max) is dropped, so that
height is computed again. Only finite heights and plausible intervals are
written.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

from vkgl.atomic import Way, decide, write_text
from vkgl.errors import InputError
from vkgl.resources import CACHE_ENV as ENV_DIR
from vkgl.resources import CACHE_OFF as OFF
from vkgl.resources import (  # the one cache folder of vkgl (the grammar's tables are kept there too)
    cache_folder,
    read_cache_file,
)

CACHE_FORMAT = "vkg-reach-cache/1"

MAX_BYTES = 1024 * 1024
"""The largest cache file read: one height per mm over 2 m is about 80 kB."""

Entries = dict[float, tuple[float, float]]


def _file(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / f"reach-{key[:32]}.json"


def load(key: str) -> Entries:
    """The heights (m, to the mm) and (r_min, r_max) kept for `key`; {} when none are (or the file is unusable)."""
    path = _file(key)
    if path is None:
        return {}
    text = _read_bounded(path)
    if text is None:
        return {}
    try:
        data = json.loads(text)
        if not isinstance(data, dict) or data.get("format") != CACHE_FORMAT or data.get("key") != key:
            return {}
        reach = data["reach"]
        if not isinstance(reach, dict):
            return {}
    except (ValueError, RecursionError, KeyError):  # RecursionError: `[[[[...` nested deeper than json can go
        return {}
    entries: Entries = {}
    for height_text, pair in reach.items():
        height, interval = _height(height_text), _interval(pair)
        if height is not None and interval is not None:
            entries[height] = interval
    return entries


def store(key: str, height: float, interval: tuple[float, float]) -> None:
    """Add one height's interval to `key`'s file (atomically; entries other processes added are kept).

    A height that is not finite or an implausible interval is not kept.
    """
    path = _file(key)
    if path is None or not math.isfinite(height) or not _plausible(*interval):
        return
    entries = load(key)
    entries[round(height, 3)] = (float(interval[0]), float(interval[1]))
    data = {
        "format": CACHE_FORMAT,
        "key": key,
        "reach": {f"{h:.3f}": [r_min, r_max] for h, (r_min, r_max) in sorted(entries.items())},
    }
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if os.path.islink(path) or decide(path)[0] is not Way.REPLACE:
            return  # a link, a FIFO or a device in the cache's place: never written through
        write_text(path, json.dumps(data, indent=0, allow_nan=False) + "\n")
    except (OSError, ValueError, InputError):
        pass  # a read-only or full disk, or something not a file in the cache's place: computed, only not kept


def _read_bounded(path: Path) -> str | None:
    """The text of `path` if it is a regular file of at most MAX_BYTES, else None. Never blocks, never reads more."""
    data = read_cache_file(path, MAX_BYTES)
    try:
        return None if data is None else data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def _height(text: str) -> float | None:
    try:
        height = round(float(text), 3)
    except (TypeError, ValueError, OverflowError):
        return None
    return height if math.isfinite(height) else None


def _interval(pair: object) -> tuple[float, float] | None:
    if not isinstance(pair, list) or len(pair) != 2:
        return None
    if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in pair):
        return None
    r_min, r_max = float(pair[0]), float(pair[1])
    return (r_min, r_max) if _plausible(r_min, r_max) else None


def _plausible(r_min: float, r_max: float) -> bool:
    """Radii an arm can have: finite, not negative, the inner one not beyond the outer one."""
    return math.isfinite(r_min) and math.isfinite(r_max) and 0.0 <= r_min <= r_max


__all__ = ["CACHE_FORMAT", "ENV_DIR", "MAX_BYTES", "OFF", "cache_folder", "load", "store"]
