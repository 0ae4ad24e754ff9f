"""A simple validity function for transit tests and benchmarks: the Panda as balls against boxes and the table.

Not the project's collision checker (that one uses the links' real shapes):
points every 4 cm along the segments joining the Panda's joint origins (from
Franka's published modified-DH table, in numpy: DART's per-body transforms
cost 20 us each from Python) and the effector, each a ball of `RADIUS`,
against axis-aligned boxes and the table's top (z = 0, the arm's base on it).
The arm's base is its world pose `arm.base`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from panda_fixtures import DH  # Franka's modified-DH table, one copy for the tests

from vkgl.robot import Arm

RADIUS = 0.06
"""m: the arm's links as balls of this radius around points on their axes."""

SPACING = 0.04
"""m: the points' spacing along each link."""

FLANGE_TO_EFFECTOR = 0.103 + 0.0  # m along the flange's z axis: the hand (0) and the fingertip (10.3 cm)


def origins(q: np.ndarray, base: np.ndarray) -> np.ndarray:
    """The world positions of the joint frames 1..7, the flange and the effector point at joints `q`.

    Plain floats, not numpy: 3 x 3 numpy products cost more than their arithmetic.
    """
    r = [list(map(float, row)) for row in base[:3, :3]]
    p = [float(v) for v in base[:3, 3]]
    points = []
    for i, (a, d, alpha) in enumerate(DH):
        theta = float(q[i]) if i < 7 else 0.0
        ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
        step = ((ct, -st, 0.0), (st * ca, ct * ca, -sa), (st * sa, ct * sa, ca))
        offset = (a, -d * sa, d * ca)
        p = [p[k] + r[k][0] * offset[0] + r[k][1] * offset[1] + r[k][2] * offset[2] for k in range(3)]
        r = [[r[k][0] * step[0][j] + r[k][1] * step[1][j] + r[k][2] * step[2][j] for j in range(3)] for k in range(3)]
        points.append(p)
    points.append([p[k] + r[k][2] * FLANGE_TO_EFFECTOR for k in range(3)])
    return np.array(points)


class BoxWorld:
    """Boxes (centre, half-size) and the table; `is_valid(q)` says whether the arm at `q` touches none."""

    def __init__(self, arm: Arm, boxes: Sequence[tuple[Sequence[float], Sequence[float]]]) -> None:
        self.base = arm.base.copy()
        self.centres = np.array([c for c, _ in boxes], dtype=float).reshape(-1, 3)
        self.halves = np.array([h for _, h in boxes], dtype=float).reshape(-1, 3) + RADIUS
        self.weights = self._weights(origins(arm.home, self.base))
        self.calls = 0

    @staticmethod
    def _weights(anchors: np.ndarray) -> np.ndarray:
        """The points as fixed combinations of the origins (the links are rigid: their lengths never change)."""
        rows = [np.eye(len(anchors))[1]]  # from the shoulder (joint 2's origin) on: joint 1's is the base
        for i in range(1, len(anchors) - 1):
            count = max(1, math.ceil(np.linalg.norm(anchors[i + 1] - anchors[i]) / SPACING))
            for k in range(1, count + 1):
                row = np.zeros(len(anchors))
                row[i], row[i + 1] = 1 - k / count, k / count
                rows.append(row)
        return np.array(rows)

    def points(self, q: np.ndarray) -> np.ndarray:
        """Points on the arm's axis at `q` (world), from the shoulder to the effector."""
        return self.weights @ origins(q, self.base)

    def is_valid(self, q: np.ndarray) -> bool:
        """Whether the arm at `q` keeps `RADIUS` from every box and the table."""
        self.calls += 1
        points = self.points(q)
        if (points[1:, 2] < RADIUS).any():
            return False
        if not len(self.centres):
            return True
        inside = (np.abs(points[:, None, :] - self.centres[None]) < self.halves[None]).all(axis=2)
        return not bool(inside.any())
