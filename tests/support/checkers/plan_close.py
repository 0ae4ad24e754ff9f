"""Comparing two `vkg-plan/8` documents (parsed JSON) as a planner's results, not as text.

Two kinds of numbers are in a plan, and another CPU changes them differently (measured on the example
tasks, this machine's plans against golden files written on another one):

- What the planner decides in task space (body poses, motion values, the robot's base and offset): closed
  form arithmetic. These are compared as numbers within `json_close.REL` / `json_close.ABS` (1e-7
  relative, 1e-8 absolute); measured: identical to the bit.
- The arm's joint positions (`q_start`, `q_end`, `contact`, `path[].joints`) and the path's `times`
  come from iterative solvers: IK stops at the first seeded run whose effector is within 1 mm and 0.5 deg
  of the target (vkgl/robot/pose_error.py), and the Panda is redundant (7 joints for at most 6
  constraints), so an optimiser that takes a slightly different step lands elsewhere on the same
  target. Measured: joints apart by up to 1e-5 rad in most tasks and 0.031 rad in task (e), where the
  effector poses still agree within 0.1 mm and 0.07 deg. No tolerance on joint values separates that
  from a change. What a configuration means is where it puts the effector, so each one is compared by
  its effector pose (FK): within `FK_POSITION` and `FK_ANGLE`, twice IK's acceptance, because both are
  accepted solutions for one target. A joint change that moves the effector by less than that is
  indistinguishable from another CPU's answer; the meaning of joint values is checked elsewhere (the
  independent replay of tests/plan/test_examples.py, execution in DART).
- `times` follow from the joint path (the arm's speed limits): within `TIMES_ABS` (measured: 0.027 s
  apart in task (e), where its joints are 0.03 rad apart).

Everything else (names, types, counts, keys and their order, list lengths, phases) must be equal.
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np

from checkers.json_close import REL, floats_close, json_differences
from vkgl.robot.arm import Arm
from vkgl.robot.pose_error import ANGLE_TOL, POSITION_TOL

FK_POSITION = 2 * POSITION_TOL
"""Metres: two IK solutions for one target, each within POSITION_TOL (1 mm) of it."""
FK_ANGLE = 2 * ANGLE_TOL
"""Radians: two IK solutions for one target, each within ANGLE_TOL (0.5 deg) of it."""
TIMES_ABS = 0.1
"""Seconds: a path's times follow its joints (measured 0.027 s apart where joints are 0.03 rad apart)."""


@cache
def _panda() -> Arm:
    """The stdlib Panda's fingertip chain (the examples' robot); its base does not change FK differences."""
    from panda_fixtures import panda_robot

    return Arm.load(panda_robot(), "fingertip", np.eye(4))


def _effector_pose_difference(actual: list[float], expected: list[float]) -> tuple[float, float]:
    a, e = _panda().fk(np.asarray(actual)), _panda().fk(np.asarray(expected))
    turn = a[:3, :3].T @ e[:3, :3]
    angle = math.acos(max(-1.0, min(1.0, (float(np.trace(turn)) - 1.0) / 2.0)))
    return float(np.linalg.norm(a[:3, 3] - e[:3, 3])), angle


def _configuration(actual: Any, expected: Any, path: str) -> list[str]:
    """One joint configuration, compared by the effector pose it gives."""
    if not isinstance(actual, list) or len(actual) != len(expected) or not all(isinstance(x, float) for x in actual):
        return [f"{path}: {actual!r} where a configuration of {len(expected)} joint positions was expected"]
    moved, turned = _effector_pose_difference(actual, expected)
    if moved <= FK_POSITION and turned <= FK_ANGLE:
        return []
    return [
        f"{path}: the effector is {1000 * moved:.2f} mm and {math.degrees(turned):.3f} deg from the expected "
        f"configuration's (allowed {1000 * FK_POSITION:.0f} mm, {math.degrees(FK_ANGLE):.1f} deg)"
    ]


def _configurations(actual: Any, expected: Any, path: str) -> list[str]:
    """A list of joint configurations, one by one."""
    if not isinstance(actual, list) or len(actual) != len(expected):
        count = len(actual) if isinstance(actual, list) else actual
        return [f"{path}: {count!r} configurations where {len(expected)} were expected"]
    return [
        line
        for k, (a, e) in enumerate(zip(actual, expected, strict=True))
        for line in _configuration(a, e, f"{path}[{k}]")
    ]


def _times(actual: Any, expected: Any, path: str) -> list[str]:
    """A path's times, each within `TIMES_ABS`."""
    if not isinstance(actual, list) or len(actual) != len(expected):
        return [f"{path}: {actual!r} where {len(expected)} times were expected"]
    return [
        f"{path}[{k}]: {a!r} s where {e!r} s was expected (allowed {TIMES_ABS} s)"
        for k, (a, e) in enumerate(zip(actual, expected, strict=True))
        if not (isinstance(a, float) and floats_close(a, e, rel=REL, abs_=TIMES_ABS))
    ]


BY_PATH = {
    "steps[].q_start": _configuration,
    "steps[].q_end": _configuration,
    "steps[].contact": _configurations,
    "steps[].path[].joints": _configurations,
    "steps[].path[].times": _times,
}


def plan_differences(actual: dict[str, Any], expected: dict[str, Any], limit: int = 20) -> list[str]:
    """Where two parsed plans differ as results (see the module's docstring), one line each."""
    return json_differences(actual, expected, by_path=BY_PATH, limit=limit)


def assert_plans_close(actual: dict[str, Any], expected: dict[str, Any], what: str = "the plan") -> None:
    """Fail, listing the differences, unless the two parsed plans agree as `plan_differences` says."""
    differences = plan_differences(actual, expected)
    if differences:
        raise AssertionError(f"{what} differs:\n  " + "\n  ".join(differences))
