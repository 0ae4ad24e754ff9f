"""A lower bound on the arm's distance to the bodies and the table: spheres around its links, boxes around the rest.

Transit checks use it for conservative advancement (`vkgl.motion.density.
segment_is_valid`): where the bound `d` at a configuration is positive, no
point of the arm touches anything there, and a straight joint-space move on
which no arm point travels `d` or more cannot reach anything either (a point
beyond joint i moves at most `r_i |dq_i|` summed over the joints, `r` from
`density.link_reach`). So the open stretches of a transit need a handful of
bound evaluations instead of a collision check every centimetre of motion.

Why spheres and boxes, not distance queries: dartpy exposes no distance
between two collision groups, and a sphere-to-box distance for every pair is
one small NumPy computation. The bound is conservative by construction:
every sphere contains its part of a link's collision shape (a box or a
cylinder cut into pieces along its longest side), every box contains its body
part (boxes as they are, cylinders in their bounding boxes, meshes and
other shapes in the bounding box of their hull), so the distance between a
sphere and a box is at most the distance between what they contain.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from vkgl.motion.collision import TABLE, CollisionScene

SAFETY = 0.002
"""m taken off every bound: round-off and the pad's caps (a cylinder stands in for the capsule) never count."""

Clearance = Callable[[np.ndarray], float]
"""A lower bound (m) on the distance from the arm at a configuration to everything it is checked against."""


def cover_box(size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Spheres (centres k x 3 in the box's frame, radii k) that together contain a box of side lengths `size`."""
    size = np.asarray(size, dtype=float)
    long = int(np.argmax(size))
    across = max(float(np.delete(size, long).max()), 1e-6)
    count = max(1, math.ceil(size[long] / across))
    piece = size.copy()
    piece[long] = size[long] / count
    radius = float(np.linalg.norm(piece)) / 2
    centres = np.zeros((count, 3))
    centres[:, long] = (np.arange(count) + 0.5) * piece[long] - size[long] / 2
    return centres, np.full(count, radius)


def cover_cylinder(radius: float, height: float) -> tuple[np.ndarray, np.ndarray]:
    """Spheres that together contain a cylinder along its frame's z (DART's convention)."""
    count = max(1, math.ceil(height / (2 * radius)))
    half = height / count / 2
    centres = np.zeros((count, 3))
    centres[:, 2] = (np.arange(count) + 0.5) * 2 * half - height / 2
    return centres, np.full(count, math.hypot(radius, half))


def cover_shape(shape: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """Spheres containing a DART box or cylinder shape (its own frame); None for other shapes."""
    kind = shape.getType()
    if kind == "BoxShape":
        return cover_box(np.asarray(shape.getSize(), dtype=float))
    if kind == "CylinderShape":
        return cover_cylinder(float(shape.getRadius()), float(shape.getHeight()))
    return None


def scene_boxes(scene: CollisionScene, names: Iterable[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World boxes (rotations M x 3 x 3, centres M x 3, half sides M x 3) containing the parts of `names` where
    the scene has placed them (the table: its slab)."""
    rotations, centres, halves = [], [], []
    for name in names:
        if name == TABLE:
            if scene.table_box is not None:
                low, high = scene.table_box
                rotations.append(np.eye(3))
                centres.append((low + high) / 2)
                halves.append((high - low) / 2)
            continue
        for pose, half in scene.part_boxes(name):
            rotations.append(pose[:3, :3])
            centres.append(pose[:3, 3])
            halves.append(half)
    if not rotations:
        return np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros((0, 3))
    return np.array(rotations), np.array(centres), np.array(halves)


def spheres_to_boxes(centres: np.ndarray, radii: np.ndarray, boxes: tuple[np.ndarray, np.ndarray, np.ndarray]) -> float:
    """The least distance (m) between any of the spheres and any of the boxes (negative where they overlap)."""
    rotations, box_centres, halves = boxes
    if len(box_centres) == 0 or len(centres) == 0:
        return math.inf
    # each sphere centre in each box's frame: (N, M, 3)
    local = np.einsum("nmj,mji->nmi", centres[:, None, :] - box_centres[None, :, :], rotations)
    outside = np.maximum(np.abs(local) - halves[None, :, :], 0.0)
    return float((np.sqrt(np.einsum("nmi,nmi->nm", outside, outside)) - radii[:, None]).min())


__all__ = ["SAFETY", "Clearance", "cover_box", "cover_cylinder", "cover_shape", "scene_boxes", "spheres_to_boxes"]
