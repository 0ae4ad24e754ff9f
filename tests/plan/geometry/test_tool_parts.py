"""A tool's parts beside its contact stand clear of the body it acts on (`vkgl.plan.geometry.tool_parts`): the
hook's shaft beside the Block it pulls, at the contact gen8_027's arc member put 1.05 cm toward the shaft."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.geometry.tool_parts import BESIDE_CLEARANCE
from vkgl.plan.graphs.graph import Engagement, KGraph
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem, build_problem

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


@pytest.fixture(scope="module")
def problem() -> Problem:
    program = vkgl.compile(EXAMPLES / "tasks" / "c_hook_pull.vkg")
    return build_problem(program, program.task("c_hook_pull"))


def _pull_poses(problem: Problem, offset: float) -> dict[str, np.ndarray]:
    """The bodies at rest, the hook's tip on the Block's +x face `offset` (m) from its centre along the face's
    +y (toward the hook's shaft: the tip sits 12 cm off it, on the -y side of the contact)."""
    poses = {name: body.rest.copy() for name, body in problem.bodies.items()}
    contact = problem.action("block", "push_center_nx").copy()
    contact[:3, 3] += offset * np.array([0.0, 1.0, 0.0])  # the Block's y axis, along its +x face
    tip = problem.effector("hook.tip").frame
    poses["hook"] = poses["block"] @ contact @ np.linalg.inv(tip)
    return poses


def _why(problem: Problem, offset: float) -> str | None:
    graph = KGraph((Engagement("arm.fingertip", "hook", "wield"), Engagement("hook.tip", "block", "push_center_nx")))
    poses = _pull_poses(problem, offset)
    rejection = GeometryCheck(problem).bodies([graph], [ModeTrace(poses, poses, [], False, {})])
    return None if rejection is None else rejection.why


def test_the_shaft_alongside_the_block_it_pulls_is_refused_as_gen8_027s_arc_member_put_it(problem: Problem) -> None:
    # the Block is 20 cm wide and the shaft (2 cm thick) 12 cm beside the tip: 1.05 cm toward it, the shaft lies
    # 0.05 cm inside the Block's side, which the thickness test let pass and DART's hook touched
    why = _why(problem, 0.0105)
    assert why is not None and "hook, acting on block with hook.tip, would stand 0.05 cm inside block" in why, why
    assert "beside its contact" in why


def test_the_shaft_clear_of_the_block_by_the_clearance_is_kept(problem: Problem) -> None:
    assert _why(problem, 0.0) is None  # task c's pull: the shaft 1 cm clear
    assert _why(problem, -0.0105) is None  # away from the shaft
    edge = 0.01 - BESIDE_CLEARANCE  # the shaft exactly the clearance from the Block's side
    assert _why(problem, edge - 0.0005) is None
    why = _why(problem, edge + 0.0005)
    assert why is not None and "only 0.45 cm from block" in why, why


def test_a_tool_of_one_part_has_nothing_beside_its_contact(problem: Problem) -> None:
    from vkgl.plan.geometry.tool_parts import BesideParts

    poses = {name: body.rest.copy() for name, body in problem.bodies.items()}
    assert BesideParts(problem).overlap(problem.effector("stick.tip"), "block", poses) is None
