"""Regions of the table's plane: an axis-aligned box or a convex polygon, and what lies inside one.

`region (0.6, -0.1) to (0.8, 0.1) m` is a box given by its lower-left and
upper-right corners; `region sink = polygon (x, y), (x, y), ... m` in a scene
a convex polygon given by its vertices in order (either sense). A region is
a set of half-planes `n . p <= d` (`Region.halfplanes`); a body's footprint
is inside when every point of it is (`excess` <= 0). The region goals of
tasks (`goal B in R`) and the keep-out regions (`keep out R`) use them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

from pydantic import Field

from vkgl.lang.ir.values import Node, Ref, Span, Vector

if TYPE_CHECKING:  # numpy is imported where a region is computed with: `vkgc fmt` and scene-less checks need none
    import numpy as np

MIN_SIDE = 1e-3
"""m: a region narrower than a millimetre along some side is degenerate."""

FAR = 1000.0
"""m: a region's corners lie within a kilometre of the origin (the scene checks' bound on positions)."""


class Region(Node):
    """A region of the table's plane. `corners`: a box's two corners (lower-left, upper-right) or a polygon's
    vertices in order, each an (x, y) vector in SI. `name` is the scene's name for it ("" when written in place).
    """

    kind: Literal["box", "polygon"] = "box"
    corners: list[Vector]
    name: str = ""
    name_span: Span | None = Field(default=None, exclude=True, repr=False)

    def points(self) -> np.ndarray:
        """The region's vertices (k x 2, m), counterclockwise."""
        import numpy as np

        corners = np.array([c.values[:2] for c in self.corners], dtype=float).reshape(-1, 2)
        if self.kind == "box":
            (x0, y0), (x1, y1) = corners[0], corners[-1]
            return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
        return corners[::-1].copy() if _signed_area(corners) < 0 else corners

    def halfplanes(self) -> np.ndarray:
        """Rows `(nx, ny, d)` with unit outward normals: a point `p` is inside when `n . p <= d` for every row."""
        import numpy as np

        points = self.points()
        edges = np.roll(points, -1, axis=0) - points
        normals = np.c_[edges[:, 1], -edges[:, 0]]
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        return np.c_[normals, np.sum(normals * points, axis=1)]

    def centre(self) -> np.ndarray:
        """The centroid of the region (m)."""
        import numpy as np

        points = self.points()
        area = _signed_area(points)
        if abs(area) < 1e-12:
            return points.mean(axis=0)
        nxt = np.roll(points, -1, axis=0)
        cross = points[:, 0] * nxt[:, 1] - nxt[:, 0] * points[:, 1]
        return np.array([np.sum((points[:, 0] + nxt[:, 0]) * cross), np.sum((points[:, 1] + nxt[:, 1]) * cross)]) / (
            6 * area
        )

    def words(self) -> str:
        """`region tray` for a named region, else `region (0.6, -0.1) to (0.8, 0.1) m` in metres."""
        if self.name:
            return f"region {self.name}"
        pts = ", ".join(f"({_m(c.values[0])}, {_m(c.values[1])})" for c in self.corners)
        joiner = pts.replace("), (", ") to (", 1) if self.kind == "box" else "polygon " + pts
        return f"region {joiner} m"


class KeepOut(Node):
    """`keep out R` (every body) or `keep B out of R` (`body` set): no such body's sweep enters region R.

    `region_ref` keeps a scene region's name as written; the checker copies the region into `region`.
    """

    body: Ref | None = None
    region: Region | None = None
    region_ref: Ref | None = None

    def applies_to(self, name: str) -> bool:
        """Whether the region keeps out the scene body `name`."""
        return self.body is None or self.body.name == name


def region_problem(region: Region) -> str | None:
    """What makes `region` no region, or None: "swapped" corners, "flat", "few" vertices, "repeated" (two
    vertices in a row closer than `MIN_SIDE`), "concave", "far" (a corner beyond `FAR`), or "reported" (a
    corner that is not two finite numbers: E204, E201, E208 say why)."""
    import numpy as np

    if any(len(c.values) != 2 for c in region.corners):
        return "reported"
    corners = np.array([c.values for c in region.corners], dtype=float).reshape(-1, 2)
    if not np.all(np.isfinite(corners)):
        return "reported"
    if np.any(np.abs(corners) > FAR):
        return "far"
    if region.kind == "box":
        if len(corners) != 2:
            return None
        (x0, y0), (x1, y1) = corners
        swapped = [axis for axis, lo, hi in (("x", x0, x1), ("y", y0, y1)) if lo > hi]
        if swapped:
            return "swapped"
        if min(x1 - x0, y1 - y0) < MIN_SIDE:
            return "flat"
        return None
    if len(corners) < 3:
        return "few"
    if np.any(np.hypot(*(np.roll(corners, -1, axis=0) - corners).T) < MIN_SIDE):
        return "repeated"  # an edge of no length has no outward normal: its half-plane would be NaN
    if abs(_signed_area(corners)) < MIN_SIDE**2:
        return "flat"
    points = corners if _signed_area(corners) > 0 else corners[::-1]
    edges = np.roll(points, -1, axis=0) - points
    turns = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    return "concave" if np.any(turns < -1e-12) else None


def excess(halfplanes: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Per half-plane, how far the farthest of `points` (n x 2) lies outside it (m; <= 0 when all are inside)."""
    import numpy as np

    return np.max(points @ halfplanes[:, :2].T - halfplanes[:, 2], axis=0)


def footprint(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """The (x, y) of body-frame `points` (n x 3) at world `pose` (4 x 4)."""
    return points @ pose[:2, :3].T + pose[:2, 3]


def _signed_area(points: np.ndarray) -> float:
    import numpy as np

    nxt = np.roll(points, -1, axis=0)
    return float(np.sum(points[:, 0] * nxt[:, 1] - nxt[:, 0] * points[:, 1]) / 2)


def _m(value: float) -> str:
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def overlap_depth(region: np.ndarray, points: np.ndarray) -> float:
    """How deep the convex hull of `points` (n x 2) and the convex polygon `region` (k x 2, counterclockwise)
    overlap: the shortest push that separates them (m; <= 0 when they are apart, by the gap's width).

    Separating axes: the edge normals of both polygons (exact for convex polygons)."""
    import numpy as np

    hull = convex_hull(points)
    axes = [_edge_normals(region), _edge_normals(hull)] if len(hull) > 2 else [_edge_normals(region)]
    normals = np.vstack(axes)
    a, b = region @ normals.T, points @ normals.T
    overlap = np.minimum(a.max(axis=0), b.max(axis=0)) - np.maximum(a.min(axis=0), b.min(axis=0))
    return float(overlap.min())


def _edge_normals(polygon: np.ndarray) -> np.ndarray:
    import numpy as np

    edges = np.roll(polygon, -1, axis=0) - polygon
    normals = np.c_[edges[:, 1], -edges[:, 0]]
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals[lengths[:, 0] > 1e-12] / lengths[lengths[:, 0] > 1e-12]


def convex_hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2-d `points`, counterclockwise, without collinear points (Andrew's monotone chain: here
    rather than SciPy's Qhull, which `vkgc check` does not import)."""
    import numpy as np

    ordered = sorted(set(map(tuple, np.round(points, 12))))
    if len(ordered) <= 2:
        return np.array(ordered, dtype=float).reshape(-1, 2)

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2 and _cross(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(ordered), half(ordered[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=float)


def _cross(o: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


__all__ = ["KeepOut", "Region", "convex_hull", "excess", "footprint", "overlap_depth", "region_problem"]
