"""The grip estimate counts the held tool's weight alone as well as the doubled push, with the margin measured in
DART (`vkgl.plan.geometry.grip_load`, bench/physical/bench_grip_margin.py)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pytest

from vkgl.lang.compiler import compile_file
from vkgl.plan.geometry.grip_load import GRIP_MARGIN, push_usage
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.problem.problem import Problem, build_problem

TASK = Path(__file__).resolve().parents[3] / "examples" / "tasks" / "b_stick_push.vkg"
TIP_PUSH = Engagement("stick.tip", "block", "push_center_px")


@dataclass
class _HandAt:
    """An arm whose effector is where the grasp puts it on the tool (what joint space solves for)."""

    pose: np.ndarray

    def fk(self, q: np.ndarray) -> np.ndarray:
        return self.pose


@pytest.fixture(scope="module")
def problem() -> Problem:
    program = compile_file(str(TASK))
    return build_problem(program, program.task())


def _usages(problem: Problem, grasp: str) -> tuple[float, float]:
    """(the tool's weight alone, the push counted twice) for the Stick held by `grasp` pushing the Block 10 cm
    along +x, level at the block's height."""
    start = np.eye(4)
    start[:3, 3] = (0.4, 0.0, 0.025)
    end = start.copy()
    end[0, 3] += 0.1
    held = replace(problem, arm=_HandAt(start @ problem.action("stick", grasp)))
    loads = [push_usage(held, grasp, TIP_PUSH, start, end, np.zeros(7), f) for f in (0.0, 2.0)]
    assert loads[0] is not None and loads[1] is not None
    return loads[0][0], loads[1][0]


def test_a_stick_held_at_its_handle_by_20_n_cannot_carry_its_own_weight(problem):
    """gen9_026: the push's moment takes some of the weight's off, but DART's contact comes and goes, and the
    weight alone broke the grip in every such push (bench_grip_margin cases 8-11: peak 1.06)."""
    weight, twice = _usages(problem, "grasp_top_y_handle")
    assert weight == pytest.approx(1.06, abs=0.01)
    assert twice < weight  # counting the push alone would have let it through
    assert max(weight, twice) * GRIP_MARGIN > 1.0


def test_the_wielded_stick_keeps_within_the_margin(problem):
    weight, twice = _usages(problem, "wield")
    assert max(weight, twice) * GRIP_MARGIN < 1.0
