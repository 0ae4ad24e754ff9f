"""What makes a mesh file usable beyond being readable: its size (E511) and a volume (E503).

The size limits are what the checks, the simulator and the planner agree to hold in memory.

A mesh costs memory per triangle in every stage (trimesh, its convex pieces,
DART's collision shape): 1.3 million triangles took 2.2 GB and 22 s to check.
`file_too_large` looks only at the file's size and, for a binary STL, at the
triangle count in its header, so a mesh past the limit is refused before it is
read; `too_many_faces` is the check after loading (other formats).
`flat_problem` says why loaded vertices bound no volume (a one-triangle STL).
"""

from __future__ import annotations

import os
import stat
import struct
from typing import Any

MAX_MESH_FACES = 500_000
"""The most triangles a mesh may have (about 0.2 GB and 10 s to check at the limit; bench/lang/bench_limits.py)."""
MAX_MESH_BYTES = 128 * 1024 * 1024
"""The largest mesh file read: an ASCII STL of MAX_MESH_FACES triangles is about 130 MB."""

_STL_HEADER = 80  # bytes of free text, then the triangle count (uint32, little-endian), then 50 bytes per triangle


def file_too_large(path: str) -> str | None:
    """Why the mesh file `path` is past the limits, found without reading it (a binary STL's header aside)."""
    try:
        info = os.stat(path)
    except OSError:
        return None  # missing or unreadable: reported as such where it is loaded
    if not stat.S_ISREG(info.st_mode):
        return None
    if info.st_size > MAX_MESH_BYTES:
        return f"the file is {info.st_size / 2**20:.0f} MiB; a mesh file is at most {MAX_MESH_BYTES // 2**20} MiB"
    if path.lower().endswith(".stl") and info.st_size >= _STL_HEADER + 4:
        with open(path, "rb") as stream:
            head = stream.read(_STL_HEADER + 4)
        (count,) = struct.unpack("<I", head[_STL_HEADER:])
        if info.st_size == _STL_HEADER + 4 + 50 * count:  # a binary STL (an ASCII one never matches exactly)
            return too_many_faces(count)
    return None


def too_many_faces(count: int) -> str | None:
    """Why a mesh of `count` triangles is past the limit, or None."""
    if count > MAX_MESH_FACES:
        return f"it has {count:,} triangles; a mesh has at most {MAX_MESH_FACES:,}"
    return None


def flat_problem(vertices: Any) -> str | None:
    """Why the mesh `vertices` (an n x 3 array) bound no volume (too few, or all on one plane), or None."""
    import numpy as np  # only once a mesh was loaded (trimesh has imported it)

    points = np.asarray(vertices, dtype=float)
    if len(points) < 4 or not np.all(np.isfinite(points)):
        return f"it is degenerate: {len(points)} vertices bound no volume (a solid needs 4 not on one plane)"
    spread = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
    if spread[2] <= 1e-9 * spread[0]:
        return "it is flat: all its vertices lie on one plane, so it bounds no volume (a solid body needs one)"
    return None
