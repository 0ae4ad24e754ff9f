"""IR shapes as DART shapes, and numpy poses as DART transforms.

Shared by the simulator (`vkgl.sim.world`: exploration and execution worlds)
and the planner's collision checks (`vkgl.motion.collision`), so that both see
the same bodies: boxes and cylinders as DART primitives, a mesh as DART loads
it, a union as one shape per part.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import dartpy as dart
import numpy as np

from vkgl.errors import InputError, SimulationError
from vkgl.lang.ir.nodes import BoxShape, CylinderShape, MeshShape, Shape, UnionShape


def isometry(matrix: np.ndarray) -> Any:
    """A 4x4 numpy pose as a dartpy Isometry3."""
    iso = dart.math.Isometry3()
    iso.set_matrix(np.asarray(matrix, dtype=float))
    return iso


def translation(p: np.ndarray) -> np.ndarray:
    """The 4x4 pose that translates by `p`."""
    m = np.eye(4)
    m[:3, 3] = p
    return m


def dart_shapes(shape: Shape, pose: np.ndarray | None = None) -> list[tuple[Any, np.ndarray]]:
    """The DART shapes of an IR shape, each with its 4x4 pose in the body frame."""
    pose = np.eye(4) if pose is None else pose
    if isinstance(shape, BoxShape):
        return [(dart.dynamics.BoxShape(shape.size.array()), pose)]
    if isinstance(shape, CylinderShape):
        return [(dart.dynamics.CylinderShape(shape.radius.value, shape.height.value), pose)]
    if isinstance(shape, MeshShape):
        return [(load_mesh_shape(shape), pose)]
    if isinstance(shape, UnionShape):
        return [item for part in shape.parts for item in dart_shapes(part.shape, pose @ part.pose.matrix())]
    raise TypeError(f"unknown shape {shape!r}")


def load_mesh_shape(shape: MeshShape) -> Any:
    """DART's MeshShape of a mesh file (through DART's own loader, assimp).

    dartpy cannot build a MeshShape from vertices, so the file is loaded the
    way DART loads URDF meshes. A file DART cannot read is a SimulationError
    that names it.
    """
    from xml.sax.saxutils import quoteattr  # with urllib.request, http and ssl: only for meshes

    path = Path(shape.resolved or shape.path).resolve()
    if not path.is_file():
        raise InputError(f"{path}: no such mesh file")
    scale = f"{shape.scale!r} {shape.scale!r} {shape.scale!r}"
    uri = dart.common.Uri.createFromPath(str(path)).toString()
    urdf = (
        '<robot name="mesh"><link name="mesh"><collision><geometry>'
        f"<mesh filename={quoteattr(uri)} scale={quoteattr(scale)}/>"
        "</geometry></collision></link></robot>"
    )
    skeleton = dart.utils.DartLoader().parseSkeletonString(urdf, dart.common.Uri.createFromPath(str(path.parent) + "/"))
    node = skeleton.getBodyNode(0) if skeleton is not None and skeleton.getNumBodyNodes() else None
    if node is None or node.getNumShapeNodes() == 0:
        raise SimulationError(
            f"{path}: DART cannot load this mesh (its mesh importer rejected the file); "
            "export it as a binary STL or OBJ and point the body's `mesh` at that file"
        )
    mesh_shape = node.getShapeNode(0).getShape()
    extents = np.asarray(mesh_shape.getBoundingBox().computeFullExtents(), dtype=float)
    if not np.all(np.isfinite(extents)) or float(extents.max()) <= 0.0:
        raise SimulationError(f"{path}: DART loaded this mesh but it has no extent (degenerate triangles?)")
    return mesh_shape
