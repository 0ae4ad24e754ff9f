"""The Hook held at its shaft's end (`Hook.wield_2`, stdlib): the hand 3.5 cm nearer the robot for the same contact,
so a far pull that starts just beyond the arm's reach with the hook held at its handle is within it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import extend, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.task_space.reach.workspace import unreachable

TASK = """
use stdlib.robots.panda
use stdlib.affordances.block
use stdlib.affordances.hook
use stdlib.tools

scene far {
    table size (1.6, 1.4) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (1.08, 0.0) m yaw 0deg
    hook : Hook on table at (0.4, -0.35) m yaw 0deg
}

task pull_back { scene far  goal block at (0.8, 0.0) m within 1 cm }
"""


def _hands(tmp_path: Path) -> tuple[Problem, dict[str, np.ndarray]]:
    """The problem, and the hand's pose where the hook, held by each of its grasps, first touches the Block's far
    face (the Block at rest)."""
    (tmp_path / "task.vkg").write_text(TASK, encoding="utf-8")
    program = compile_file(str(tmp_path / "task.vkg"))
    problem = build_problem(program, program.task())
    hands: dict[str, np.ndarray] = {}
    root = start_sequence(problem)
    for grasp in successors(problem, root.graphs[-1], root.last):
        if grasp.engagement.body != "hook" or not grasp.engagement.affordance.startswith("wield"):
            continue
        held, _ = extend(problem, root, grasp)
        for pull in successors(problem, held.graphs[-1], held.last):
            e = pull.engagement
            if e.body == "block" and e.affordance == "push_center_nx" and e.effector == "hook.tip":
                _, hand = extend(problem, held, pull)
                assert hand is not None
                hands[grasp.engagement.affordance] = hand
    return problem, hands


def test_held_at_its_end_the_hook_pulls_from_where_the_handle_is_out_of_reach(tmp_path: Path) -> None:
    problem, hands = _hands(tmp_path)
    assert set(hands) == {"wield", "wield_2"}
    # the same contact: the hand 3.5 cm farther back along the shaft, toward the arm
    assert np.linalg.norm(hands["wield"][:3, 3] - hands["wield_2"][:3, 3]) == pytest.approx(0.035, abs=1e-6)
    assert np.allclose(hands["wield"][:3, :3], hands["wield_2"][:3, :3])
    # the Block's far face 1.13 m out: held at the handle the hand is just beyond the reach, at the end within it
    out = unreachable(problem, hands["wield"])
    assert out is not None and 0.0 < out.excess < 0.035, out
    assert unreachable(problem, hands["wield_2"]) is None
