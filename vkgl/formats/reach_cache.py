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
a speed-up: a file that cannot be read or written is ignored, never an error.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from vkgl.formats.atomic import write_text
from vkgl.resources import CACHE_ENV as ENV_DIR
from vkgl.resources import CACHE_OFF as OFF
from vkgl.resources import cache_folder  # the one cache folder of vkgl (the grammar's tables are kept there too)

CACHE_FORMAT = "vkg-reach-cache/1"

Entries = dict[float, tuple[float, float]]


def _file(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / f"reach-{key[:32]}.json"


def load(key: str) -> Entries:
    """The heights (m, to the mm) and (r_min, r_max) kept for `key`; {} when none are (or the file is unusable)."""
    path = _file(key)
    if path is None:
        return {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("format") != CACHE_FORMAT or data.get("key") != key:
            return {}
        return {_height(text): _interval(pair) for text, pair in data["reach"].items()}
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}


def store(key: str, height: float, interval: tuple[float, float]) -> None:
    """Add one height's interval to `key`'s file (atomically; entries other processes added are kept)."""
    path = _file(key)
    if path is None:
        return
    entries = load(key)
    entries[round(height, 3)] = interval
    data = {
        "format": CACHE_FORMAT,
        "key": key,
        "reach": {f"{h:.3f}": [r_min, r_max] for h, (r_min, r_max) in sorted(entries.items())},
    }
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text(path, json.dumps(data, indent=0) + "\n")
    except OSError:
        pass  # a read-only or full disk: the reach is still computed, only not kept


def _height(text: str) -> float:
    return round(float(text), 3)


def _interval(pair: object) -> tuple[float, float]:
    if not isinstance(pair, list) or len(pair) != 2:
        raise ValueError("not an interval")
    r_min, r_max = float(pair[0]), float(pair[1])
    if not (math.isfinite(r_min) and math.isfinite(r_max)):
        raise ValueError("not finite")
    return r_min, r_max


__all__ = ["CACHE_FORMAT", "ENV_DIR", "OFF", "cache_folder", "load", "store"]
