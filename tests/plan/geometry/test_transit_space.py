"""The spaces a held tool's transits are planned in (`GeometryCheck.transit_space`): the body the transit leads
to keeps `TARGET_CLEARANCE` less the touch tolerance from the tool, not only the tolerance of a touch."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLES

import vkgl
from vkgl.motion.arm_collision import Held
from vkgl.motion.collision import TOUCH_TOL
from vkgl.plan.geometry.bodies import TARGET_CLEARANCE, GeometryCheck
from vkgl.plan.problem.problem import build_problem


@pytest.fixture(scope="module")
def geometry() -> GeometryCheck:
    program = vkgl.compile(EXAMPLES / "tasks" / "c_hook_pull.vkg")
    return GeometryCheck(build_problem(program, next(iter(program.tasks.values()))))


def _hook_beside_the_block(geometry: GeometryCheck, gap: float) -> tuple[np.ndarray, Held, dict[str, np.ndarray]]:
    """The arm at its ready pose holding the hook in free space, the block `gap` (m; < 0: overlapping) beside the
    +x face of the hook's first part, turned with it."""
    problem = geometry.problem
    home = np.asarray(problem.arm.home, dtype=float)
    hook = np.eye(4)
    hook[:3, 3] = (0.45, 0.35, 0.25)
    held = Held("hook", np.linalg.inv(problem.arm.fk(home)) @ hook)
    part, half = geometry.scene.part_boxes_local("hook")[0]
    (block_part, block_half), *_ = geometry.scene.part_boxes_local("block")
    face = hook @ part
    block = np.eye(4)
    block[:3, :3] = face[:3, :3]
    block[:3, 3] = face[:3, 3] + face[:3, 0] * (half[0] + block_half[0] + gap)
    block = block @ np.linalg.inv(block_part)
    poses = {name: body.rest for name, body in problem.bodies.items()} | {"hook": hook, "block": block}
    return home, held, poses


@pytest.mark.parametrize(
    ("gap", "free"), [(-0.0005, False), (0.0002, False), (TARGET_CLEARANCE - TOUCH_TOL + 5e-4, True)]
)
def test_a_held_tool_keeps_a_millimetre_from_the_body_its_transit_leads_to(geometry, gap, free) -> None:
    """0.5 mm into the block passed as a touch (the block's exact shape, 1 mm tolerance): a hook whose stand-off
    lay 0.06 mm inside a crate it was to pull ended its transit touching it in DART."""
    home, held, poses = _hook_beside_the_block(geometry, gap)
    exact = geometry.arm_collision
    exact.scene.place(poses)
    assert exact.free(home, held=held) == (gap > -TOUCH_TOL)  # the real shapes: a touch within the tolerance
    space = geometry.transit_space(held, "block")
    space.scene.place(poses)
    assert space.free(home, held=held) is free
