"""An arc member's offset along its face as a task-space variable (vkgl/plan/graphs/members.py, `ArcSeed`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import vkgl
from vkgl.lang.ir.families import find_member, member_name
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.motions import member_motions, motion_matrix
from vkgl.plan.graphs.rollout import bounds, extend, start_sequence
from vkgl.plan.problem.problem import build_problem


def _task(dx: float, dy: float, dyaw: float) -> str:
    """The Block at (0.45, 0) m and a goal (`dx`, `dy`) m from there, turned by `dyaw` deg."""
    return (
        "use stdlib.robots.panda\nuse stdlib.bodies.block\nuse stdlib.affordances.block\n\n"
        "scene alone {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
        "    it : Block on table at (0.45, 0) m yaw 0deg\n}\n\n"
        f"task turn_far {{\n    scene alone\n"
        f"    goal it at ({0.45 + dx:.3f}, {dy:g}) m yaw {dyaw:g}deg within 1 cm, 3deg\n"
        "    search { max_depth 6  timeout 20 s }\n}\n"
    )


@pytest.fixture(scope="module")
def program(tmp_path_factory: pytest.TempPathFactory) -> vkgl.Program:
    task = tmp_path_factory.mktemp("arc_offsets") / "task.vkg"
    task.write_text(_task(0.20, 0.0, -50.0), encoding="utf-8")  # beyond the Block's written turns (<= 30.6 deg)
    return vkgl.compile(task)


def test_the_rollout_moves_a_members_contact_and_pivot_as_the_executor_resolves_the_name(program) -> None:
    problem = build_problem(program, program.task())
    seeds = [a.name for a in problem.bodies["it"].affordances if "@" in a.name and a.name.startswith("push_center_px")]
    assert seeds, "a heading beyond every written turn is offered an arc member"
    seed = seeds[0]
    e = Engagement(problem.robot_effector.name, "it", seed)
    seq, _ = extend(problem, start_sequence(problem), Action("add", e))
    lower, upper = bounds(problem, seq, offsets=True)
    assert lower[-1] < 0.0 < upper[-1]  # the offset may move both ways from the member's own
    own = float(seed.split("@")[1].removesuffix("cm")) / 100.0
    for change in np.linspace(lower[-1], upper[-1], 5):
        name = member_name("push_center_px", own + change)
        resolved = find_member(problem.bodies["it"].affordances, name)  # what the executor reads from the plan
        assert resolved is not None
        at = float(name.split("@")[1].removesuffix("cm")) / 100.0 - own  # the change the name keeps
        planned = member_motions(problem, e, at, np.array([math.radians(30.0)]))[0]
        assert np.allclose(planned, motion_matrix(resolved.motion, math.radians(30.0)), atol=1e-9)


def test_a_turn_beyond_every_written_one_is_an_arc_whose_offset_the_task_space_chose(program) -> None:
    """Without arc members the goal takes two turns and a push (depth 6). The plan's last contact is an arc
    member at an offset the problem did not offer: the body was moved first, and the offset fits the arc to where
    it lies then. (CPU: about 1.5 s.)"""
    problem = build_problem(program, program.task())
    offered = {a.name for a in problem.bodies["it"].affordances if "@" in a.name}
    plan = vkgl.solve(program, "turn_far")
    assert plan.status == "solved" and plan.depth == 4, plan.reason
    last = plan.steps[-1].affordance.removeprefix("Block.")
    assert "@" in last and last not in offered, (last, offered)
    final = np.asarray(plan.final["it"])
    assert np.linalg.norm(final[:2, 3] - (0.65, 0.0)) <= 0.01
    assert abs(math.remainder(math.atan2(final[1, 0], final[0, 0]) - math.radians(-50.0), math.tau)) <= math.radians(3)
