"""`vkg-hull-cache/1`: the convex hulls of the bodies' shapes, as Qhull finds them, kept between processes.

The planner's hulls (a body's outline, the footprint a goal region must hold)
are SciPy's `ConvexHull`, and importing `scipy.spatial` costs about a quarter
of a second, half of what `vkgc solve` may take on a simple task. A hull
depends only on its points and on Qhull, and a task has a few bodies whose
shapes rarely change, so the vertices Qhull found are kept in the cache folder
(`vkgl.resources.cache_folder`), one small JSON file per hull:

    {"format": "vkg-hull-cache/1", "key": "<sha256>", "vertices": [0, 1, 3, ...]}

`key` is the hash of the points' bytes and shape and of the Qhull library file
(its path, size and time, found without importing SciPy), so a hull read back
is exactly `ConvexHull(points).vertices` of the same Qhull; a file whose key
or format differs, or that cannot be read, is ignored and written again. Only
hulls that exist are kept: points Qhull finds flat raise as `ConvexHull` does.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
import stat
from pathlib import Path

import numpy as np

from vkgl.atomic import write_text
from vkgl.errors import InputError
from vkgl.resources import cache_folder

CACHE_FORMAT = "vkg-hull-cache/1"
MAX_BYTES = 1024 * 1024
"""The largest cache file read (a hull of 10,000 vertices is about 60 kB)."""


def hull_vertices(points: np.ndarray) -> np.ndarray:
    """`scipy.spatial.ConvexHull(points).vertices`: the indices of the points (n x 3) that are the hull's
    vertices, in input order. Raises as `ConvexHull` does (QhullError, ValueError) for flat or too few points."""
    points = np.ascontiguousarray(points, dtype=float)
    key = _key(points)
    if key is not None:
        kept = _load(key, len(points))
        if kept is not None:
            return kept
    from scipy.spatial import ConvexHull  # only for a hull this machine has not computed yet

    vertices = ConvexHull(points).vertices
    if key is not None:
        _store(key, vertices)
    return vertices


def hull_corner_points(points: np.ndarray) -> np.ndarray:
    """The points (k x 3) of `points` that are vertices of their convex hull; all of them when Qhull finds
    them flat or degenerate (every point then counts)."""
    try:
        return points[hull_vertices(points)]
    except ValueError:
        return points
    except RuntimeError as exc:  # QhullError is a RuntimeError; SciPy is imported already when it is raised
        from scipy.spatial import QhullError

        if isinstance(exc, QhullError):
            return points
        raise


def _key(points: np.ndarray) -> str | None:
    qhull = _qhull_identity()
    if qhull is None:
        return None
    digest = hashlib.sha256()
    for part in (CACHE_FORMAT, qhull, repr(points.shape)):
        digest.update(part.encode("utf-8") + b"\0")
    digest.update(points.tobytes())
    return digest.hexdigest()


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


def _load(key: str, count: int) -> np.ndarray | None:
    """The vertices kept for `key`, or None (no file, another key or format, or not indices of `count` points)."""
    path = _file(key)
    if path is None:
        return None
    try:
        if not stat.S_ISREG(os.stat(path).st_mode) or os.stat(path).st_size > MAX_BYTES:
            return None
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return None
    if not isinstance(data, dict) or data.get("format") != CACHE_FORMAT or data.get("key") != key:
        return None
    vertices = data.get("vertices")
    if not isinstance(vertices, list) or not vertices:
        return None
    if not all(type(v) is int and 0 <= v < count for v in vertices):
        return None
    return np.array(vertices, dtype=np.int32)


def _store(key: str, vertices: np.ndarray) -> None:
    """Keep the vertices for `key` (by the one atomic writer; a failure only means computing them again)."""
    path = _file(key)
    if path is None:
        return
    text = json.dumps({"format": CACHE_FORMAT, "key": key, "vertices": [int(v) for v in vertices]})
    with contextlib.suppress(OSError, InputError):
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text(path, text + "\n")


__all__ = ["hull_corner_points", "hull_vertices"]
