"""`shape_vertices` gives the meshes' vertices without making meshes, and planning never imports trimesh.

The planner reads boxes' and unions' vertices (resting heights, bounding balls) through `shape_vertices`,
which computes them as trimesh does; these tests hold it to trimesh's numbers, bit for bit, so that plans
do not change with the shortcut.
"""

from __future__ import annotations

import subprocess
import sys
from functools import cache
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.lang.ir.geometry import shape_mesh, shape_vertices
from vkgl.lang.ir.nodes import BoxShape, CylinderShape, Pose, Quantity, ShapePart, UnionShape, Vector

REPO = Path(__file__).resolve().parents[3]


def _part(shape: BoxShape | CylinderShape, position: tuple[float, float, float], **turn: object) -> ShapePart:
    return ShapePart(shape=shape, pose=Pose(position=Vector(values=position), **turn))  # type: ignore[arg-type]


def _box(x: float, y: float, z: float) -> BoxShape:
    return BoxShape(size=Vector(values=(x, y, z)))


@cache
def _shapes() -> list[object]:
    stdlib = [
        body.shape
        for path in sorted((REPO / "stdlib" / "bodies").glob("*.vkg"))
        for body in vkgl.compile(path).bodies.values()
    ]
    rng = np.random.default_rng(5)
    unions = []
    for _ in range(40):
        parts = []
        for _ in range(int(rng.integers(1, 4))):
            size = tuple(float(v) for v in rng.uniform(0.005, 0.3, 3).round(3))
            at = tuple(float(v) for v in rng.uniform(-0.2, 0.2, 3).round(3))
            turn: dict[str, object] = {}
            if rng.random() < 0.5:
                turn["yaw"] = Quantity(value=float(rng.uniform(-np.pi, np.pi)))
            elif rng.random() < 0.5:
                turn["rpy"] = Vector(values=tuple(float(v) for v in rng.uniform(-1.5, 1.5, 3)))
            parts.append(_part(_box(*size), at, **turn))
        unions.append(UnionShape(parts=parts))
    return [*stdlib, _box(0.1, 0.2, 0.05), *unions]


@pytest.mark.parametrize("index", range(len(_shapes())))
def test_the_vertices_are_the_meshes_bit_for_bit(index: int) -> None:
    shape = _shapes()[index]
    assert np.array_equal(shape_vertices(shape), shape_mesh(shape).vertices)  # type: ignore[arg-type]


def test_other_shapes_take_the_meshes_vertices() -> None:
    can = CylinderShape(radius=Quantity(value=0.04), height=Quantity(value=0.12))
    union = UnionShape(parts=[_part(_box(0.1, 0.1, 0.1), (0.0, 0.0, 0.0)), _part(can, (0.0, 0.0, 0.1))])
    for shape in (can, union):
        assert np.array_equal(shape_vertices(shape), shape_mesh(shape).vertices)
        assert not shape_vertices(shape).flags.writeable


def test_solving_an_example_imports_no_trimesh_once_its_tools_widths_are_kept() -> None:
    """trimesh (with networkx and SciPy's image module) is a third of a second of `vkgc solve`'s start. The
    first solve with a held tool measures the tool's width across the grip on its mesh and keeps it in the cache
    folder (`vkgl.plan.problem.hulls.kept_width`); from the second on, trimesh is not imported."""
    code = (
        "import sys, vkgl; plan = vkgl.solve(sys.argv[1]); "
        "print(plan.status, 'trimesh' in sys.modules, 'networkx' in sys.modules)"
    )
    task = str(REPO / "examples" / "tasks" / "c_hook_pull.vkg")
    for _ in range(2):
        result = subprocess.run(
            [sys.executable, "-c", code, task], capture_output=True, text=True, cwd=REPO, timeout=300
        )
    assert result.stdout.split() == ["solved", "False", "False"], result.stdout + result.stderr[-2000:]
