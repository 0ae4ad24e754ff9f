"""Footprints of the generated tasks' bodies on the tabletop: unions of oriented rectangles (every body is a box or
a union of boxes), tested for overlap by separating axes."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import ConvexHull
from task_makers.generated_bodies import BodyType

TABLE_MIN = np.array([-0.3, -0.6])
TABLE_MAX = np.array([1.3, 0.6])
TABLE_MARGIN = 0.03  # m: footprints keep this far inside the table's edge


def polygons(body: BodyType, x: float, y: float, yaw_deg: float) -> list[np.ndarray]:
    """The footprint of a body at a planar pose: one (4, 2) array of corners per rectangle."""
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    rotation = np.array([[c, -s], [s, c]])
    out = []
    for cx, cy, sx, sy in body.rects():
        corners = np.array([[-sx, -sy], [sx, -sy], [sx, sy], [-sx, sy]]) / 2 + [cx, cy]
        out.append(corners @ rotation.T + [x, y])
    return out


def _separated(a: np.ndarray, b: np.ndarray, gap: float) -> bool:
    """Whether two convex polygons are at least `gap` apart along some edge normal (separating axes)."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        for ex, ey in edges:
            norm = math.hypot(ex, ey)
            if norm < 1e-12:
                continue
            axis = np.array([-ey, ex]) / norm
            pa, pb = a @ axis, b @ axis
            if pa.max() + gap <= pb.min() or pb.max() + gap <= pa.min():
                return True
    return False


def overlaps(a: list[np.ndarray], b: list[np.ndarray], gap: float = 0.0) -> bool:
    """Whether two footprints (lists of convex polygons) come closer than `gap` (conservative near corners)."""
    return any(_near(p, q, gap) and not _separated(p, q, gap) for p in a for q in b)


def _near(a: np.ndarray, b: np.ndarray, gap: float) -> bool:
    """Whether the polygons' bounding circles come closer than `gap` (a cheap test before the exact one)."""
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    ra, rb = np.max(np.hypot(*(a - ca).T)), np.max(np.hypot(*(b - cb).T))
    return bool(np.hypot(*(ca - cb)) < ra + rb + gap)


def hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2-d points, counter-clockwise."""
    return points[ConvexHull(points).vertices]


def on_table(polygons: list[np.ndarray]) -> bool:
    """Whether every corner lies `TABLE_MARGIN` inside the table's edge."""
    points = np.vstack(polygons)
    return bool(np.all(points >= TABLE_MIN + TABLE_MARGIN) and np.all(points <= TABLE_MAX - TABLE_MARGIN))
