"""The reach of a tilted hand (`vkgl.plan.task_space.reach.workspace.hand_down_point`): counted at the point its
wrist stands above, as inverse kinematics finds it (the hand-down reach alone gave every tilt the same reach)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from panda_fixtures import DH, FINGERTIP, arm_fixture, transform  # noqa: F401 (the `arm` fixture)
from scipy.spatial.transform import Rotation

from vkgl.plan.task_space.reach.workspace import (
    hand_down_point,
    hand_down_points,
    hand_reach_violation,
    reach_violation,
    unreachable,
)
from vkgl.robot import Arm

HEIGHT = 0.125
AZIMUTH = math.radians(-24.0)


def _tilted(arm: Arm, radius: float, degrees: float, about: str) -> np.ndarray:
    """A hand at `radius` from the base along `AZIMUTH`, its z axis tilted `degrees` about the line out from the
    base (`about="out"`: sideways) or across it (`"across"`: positive leans its top toward the base)."""
    out = np.array([math.cos(AZIMUTH), math.sin(AZIMUTH), 0.0])
    axis = out if about == "out" else np.cross(np.array([0.0, 0.0, 1.0]), out)
    rotation = Rotation.from_rotvec(-math.radians(degrees) * axis).as_matrix()
    return transform(rotation, tuple(arm.base[:3, 3] + radius * out + np.array([0.0, 0.0, HEIGHT])))


def test_the_wrist_lever_is_the_flange_and_the_fingertip(arm: Arm) -> None:
    # panda_link7's origin lies on the hand's axis: the flange's 0.107 m (DH) and the fingertip's offset above it
    assert arm.wrist_lever == pytest.approx(DH[-1][1] + FINGERTIP, abs=1e-3)


def test_an_upright_hand_is_its_own_point(arm: Arm) -> None:
    problem = SimpleNamespace(arm=arm)
    hand = _tilted(arm, 0.7, 0.0, "across")
    assert np.allclose(hand_down_point(problem, hand), hand[:3, 3])  # type: ignore[arg-type]
    assert hand_reach_violation(problem, hand) == reach_violation(problem, hand[:3, 3])  # type: ignore[arg-type]


def test_a_hand_leaning_toward_the_base_reaches_farther_as_ik_finds(arm: Arm) -> None:
    problem = SimpleNamespace(arm=arm)
    far = arm.reach(HEIGHT)[1] + 0.04  # 4 cm beyond the hand-down reach
    hand = _tilted(arm, far, 20.0, "across")
    assert reach_violation(problem, hand[:3, 3]) > 0  # type: ignore[arg-type]
    assert hand_reach_violation(problem, hand) < 0  # type: ignore[arg-type]
    assert unreachable(problem, hand) is None  # type: ignore[arg-type]
    assert arm.ik(hand, yaw_free=True) is not None


def test_a_hand_leaning_away_reaches_less_far_as_ik_finds(arm: Arm) -> None:
    problem = SimpleNamespace(arm=arm)
    near = arm.reach(HEIGHT)[1] - 0.03  # 3 cm inside the hand-down reach
    hand = _tilted(arm, near, -20.0, "across")
    assert reach_violation(problem, hand[:3, 3]) < 0  # type: ignore[arg-type]
    found = unreachable(problem, hand)  # type: ignore[arg-type]
    assert found is not None and "tilted 20 deg" in found.why
    assert arm.ik(hand, yaw_free=True) is None


def test_a_sideways_tilt_keeps_the_radius(arm: Arm) -> None:
    problem = SimpleNamespace(arm=arm)
    hand = _tilted(arm, 0.75, 35.0, "out")
    point = hand_down_point(problem, hand)  # type: ignore[arg-type]
    assert math.hypot(*point[:2]) == pytest.approx(0.75, abs=1e-9)


def test_many_hands_at_once_are_each_hands_point(arm: Arm) -> None:
    problem = SimpleNamespace(arm=arm)
    hands = np.array(
        [
            _tilted(arm, r, d, a)
            for r, d, a in ((0.6, 0.0, "out"), (0.8, 30.0, "across"), (0.7, -15.0, "across"), (0.75, 20.0, "out"))
        ]
    )
    each = np.array([hand_down_point(problem, h) for h in hands])  # type: ignore[arg-type]
    assert np.allclose(hand_down_points(problem, hands), each)  # type: ignore[arg-type]
