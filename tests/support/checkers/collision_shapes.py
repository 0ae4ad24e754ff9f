"""Shapes and poses shared by the collision tests (a module, not a conftest.py: see plan_programs.py)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.nodes import BoxShape, CylinderShape, Pose, ShapePart, UnionShape, Vector


def box(x: float, y: float, z: float) -> BoxShape:
    """A box of sides x, y, z (m)."""
    return BoxShape(size=Vector(values=(x, y, z)))


def cylinder(radius: float, height: float) -> CylinderShape:
    """A cylinder along z."""
    from vkgl.lang.ir.nodes import Quantity

    return CylinderShape(radius=Quantity(value=radius), height=Quantity(value=height))


def hook() -> UnionShape:
    """The stdlib Hook: a 40 cm shaft along x and a 16 cm cross-piece at its +x end, toward +y."""
    return UnionShape(
        parts=[
            ShapePart(shape=box(0.40, 0.02, 0.02), pose=Pose(position=Vector(values=(0.0, 0.0, 0.0)))),
            ShapePart(shape=box(0.02, 0.16, 0.02), pose=Pose(position=Vector(values=(0.19, 0.07, 0.0)))),
        ]
    )


def pose(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """A 4x4 pose at (x, y, z) turned by `yaw` about z."""
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("z", yaw).as_matrix()
    m[:3, 3] = (x, y, z)
    return m
