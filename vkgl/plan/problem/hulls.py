"""`vkg-hull-cache/2`: the convex hulls of the bodies' shapes, as Qhull finds them, kept between processes (and
the held tools' widths across the grip, `kept_width`).

The planner's hulls (a body's outline, the footprint a goal region must hold)
are SciPy's `ConvexHull`, and importing `scipy.spatial` costs about a quarter
of a second, half of what `vkgc solve` may take on a simple task. A hull
depends only on its points and on Qhull, and a task has a few bodies whose
shapes rarely change, so what Qhull found is kept in the cache folder
(`vkgl.resources.cache_folder`), one small JSON file per hull: the indices of
the hull's vertices among the points (`hull_vertices`), or, for an outline
(`outline_corners`, whose points are first made unique with numpy's
`unique`, which imports numpy's masked arrays), the corners themselves:

    {"format": "vkg-hull-cache/2", "key": "<sha256>", "vertices": [0, 1, 3, ...]}
    {"format": "vkg-hull-cache/2", "key": "<sha256>", "corners": [[0.1, -0.05, 0.0], ...]}
    {"format": "vkg-hull-cache/2", "key": "<sha256>", "width": 0.02}

`key` is the hash of which of the two it is, of the points' bytes and shape,
and of the Qhull library file (its path, size and time, found without
importing SciPy), so a hull read back is exactly the one computed with the
same Qhull (floats round-trip exactly through JSON); a file whose key or
format differs, or that cannot be read, is ignored and written again. Only
hulls that exist are kept: points Qhull finds flat raise as `ConvexHull` does
(an outline is then all of its points, computed each time).
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.atomic import write_text
from vkgl.errors import InputError
from vkgl.resources import cache_folder, read_cache_file

CACHE_FORMAT = "vkg-hull-cache/2"
MAX_BYTES = 1024 * 1024
"""The largest cache file read (a hull of 10,000 vertices is about 60 kB)."""


def hull_vertices(points: np.ndarray) -> np.ndarray:
    """`scipy.spatial.ConvexHull(points).vertices`: the indices of the points (n x 3) that are the hull's
    vertices, in input order. Raises as `ConvexHull` does (QhullError, ValueError) for flat or too few points."""
    points = np.ascontiguousarray(points, dtype=float)

    def compute() -> list[int]:
        from scipy.spatial import ConvexHull  # only for a hull this machine has not computed yet

        return [int(v) for v in ConvexHull(points).vertices]

    vertices = _kept("vertices", points, compute, lambda kept: _indices(kept, len(points)))
    return np.array(vertices, dtype=np.int32)  # ConvexHull's own type


def outline_corners(vertices: np.ndarray) -> np.ndarray:
    """The corners (k x 3) of the convex hull of `vertices` made unique (`np.unique(vertices, axis=0)`, in its
    order); all of the unique points when Qhull finds them flat or too few (every point then counts)."""
    vertices = np.ascontiguousarray(vertices, dtype=float)

    def compute() -> list[list[float]]:
        from scipy.spatial import ConvexHull, QhullError  # only for a hull this machine has not computed yet

        unique = np.unique(vertices, axis=0)
        try:
            corners = unique[ConvexHull(unique).vertices]
        except (QhullError, ValueError):
            raise _Flat(unique) from None
        return [[float(x) for x in row] for row in corners]

    try:
        corners = _kept("corners", vertices, compute, _points)
    except _Flat as flat:
        return flat.points
    return np.array(corners, dtype=float).reshape(-1, 3)


class _Flat(Exception):
    """Points Qhull refuses: the outline is all of them, computed each time (only hulls that exist are kept)."""

    def __init__(self, points: np.ndarray) -> None:
        super().__init__("flat")
        self.points = points


def _kept(kind: str, points: np.ndarray, compute: Callable[[], Any], valid: Callable[[Any], bool]) -> Any:
    """What `compute()` gives for `points`, read back from the cache folder when kept (and `valid`), else
    computed and kept."""
    key = _key(kind, points)
    if key is not None:
        kept = _load(key, kind)
        if kept is not None and valid(kept):
            return kept
    value = compute()
    if key is not None:
        _store(key, kind, value)
    return value


def _indices(value: Any, count: int) -> bool:
    return isinstance(value, list) and bool(value) and all(type(v) is int and 0 <= v < count for v in value)


def _points(value: Any) -> bool:
    return (
        isinstance(value, list)
        and bool(value)
        and all(isinstance(row, list) and len(row) == 3 and all(type(x) is float for x in row) for row in value)
    )


def _key(kind: str, points: np.ndarray) -> str | None:
    qhull = _qhull_identity()
    if qhull is None:
        return None
    digest = hashlib.sha256()
    for part in (CACHE_FORMAT, kind, qhull, repr(points.shape)):
        digest.update(part.encode("utf-8") + b"\0")
    digest.update(points.tobytes())
    return digest.hexdigest()


@lru_cache(maxsize=1)
def _qhull_identity() -> str | None:
    """Which Qhull would compute the hull (found without importing SciPy): its library file, size and time."""
    try:
        spec = importlib.util.find_spec("scipy")
    except (ImportError, ValueError):
        return None
    if spec is None or spec.origin is None:
        return None
    folder = Path(spec.origin).parent / "spatial"
    try:
        libraries = sorted(p for p in folder.iterdir() if p.name.startswith("_qhull.") and p.suffix in (".so", ".pyd"))
        if not libraries:
            return None
        found = os.stat(libraries[0])
    except OSError:
        return None
    return f"{libraries[0]}:{found.st_size}:{found.st_mtime_ns}"


def _file(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / f"hull-{key[:32]}.json"


def _load(key: str, kind: str) -> Any:
    """The `kind` kept for `key`, or None (no file, or another key or format)."""
    path = _file(key)
    if path is None:
        return None
    raw = read_cache_file(path, MAX_BYTES)
    if raw is None:
        return None
    try:
        data = json.loads(raw.decode("utf-8"))
    except (ValueError, RecursionError):  # UnicodeDecodeError is a ValueError
        return None
    if not isinstance(data, dict) or data.get("format") != CACHE_FORMAT or data.get("key") != key:
        return None
    return data.get(kind)


def _store(key: str, kind: str, value: Any) -> None:
    """Keep `value` for `key` (by the one atomic writer; a failure only means computing it again)."""
    path = _file(key)
    if path is None:
        return
    text = json.dumps({"format": CACHE_FORMAT, "key": key, kind: value})
    with contextlib.suppress(OSError, InputError):
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text(path, text + "\n")


def kept_width(points: np.ndarray, compute: Callable[[], float]) -> float:
    """`compute()`, a tool's width across the grip (m) that `points` determine (its shape's vertices and the grasp,
    flattened), kept in the cache folder like a hull: measuring it slices the tool's mesh, which imports trimesh
    and SciPy (`vkgl.robot.grip.width_across_grip`), more than a simple solve takes otherwise."""
    points = np.ascontiguousarray(points, dtype=float)
    return float(_kept("width", points, lambda: float(compute()), lambda kept: type(kept) is float))


def kept_centre(points: np.ndarray, compute: Callable[[], np.ndarray]) -> np.ndarray:
    """`compute()`, a body's centre of mass (its frame, m) that `points` determine (its shape's parts' vertices,
    flattened), kept in the cache folder like a hull: it is measured on the body's mesh (trimesh), which a solve
    that reads it back need not import."""
    points = np.ascontiguousarray(points, dtype=float)
    kept = _kept("centre", points, lambda: [float(x) for x in compute()], lambda value: _points([value]))
    return np.asarray(kept, dtype=float)


__all__ = ["hull_vertices", "kept_centre", "kept_width", "outline_corners"]
