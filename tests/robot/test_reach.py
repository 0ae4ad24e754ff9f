"""The reachable workspace: what is inside and outside the reach, and what it depends on."""

from __future__ import annotations

import math

import numpy as np
import pytest
from panda_fixtures import (
    arm_fixture,  # noqa: F401 (the `arm` fixture)
    hand_down,
    panda_robot,
    transform,
)

from vkgl.robot import Arm


def test_reach_at_table_height_is_the_pandas(arm: Arm) -> None:
    r_min, r_max = arm.reach(0.03)
    # Franka quotes 855 mm of reach, measured from joint 2's axis (0.333 m high)
    assert math.hypot(r_max, 0.333 - 0.03) == pytest.approx(0.855, abs=0.02)
    assert 0.05 < r_min < 0.2
    assert arm.reach(0.0302) == (r_min, r_max)  # cached to the mm


def test_reach_interval_is_what_ik_reaches(arm: Arm) -> None:
    height = 0.03
    r_min, r_max = arm.reach(height)
    rng = np.random.default_rng(5)
    for _ in range(20):
        radius, azimuth = rng.uniform(r_min, r_max), rng.uniform(-math.pi, math.pi)
        target = hand_down(radius * math.cos(azimuth), radius * math.sin(azimuth), height)
        assert arm.ik(target, yaw_free=True) is not None
    for azimuth in (0.0, 2.0, math.pi, -1.0):
        for radius in (r_max + 0.01, r_min - 0.01):
            point = (radius * math.cos(azimuth), radius * math.sin(azimuth), height)
            assert arm.ik(hand_down(*point), yaw_free=True) is None
    # the bisection along one azimuth agrees with the optimised extremes (IK's 1 mm tolerance aside)
    bisected = arm.radial_interval(height, 0.5)
    assert bisected is not None
    assert bisected[0] == pytest.approx(r_min, abs=0.005) and bisected[1] == pytest.approx(r_max, abs=0.005)


def test_reachable_uses_the_reach_around_the_base() -> None:
    base = transform(translation=(0.2, 0.1, 0.0))
    moved = Arm.load(panda_robot(), "fingertip", base)
    assert moved.reachable((0.2 + 0.5, 0.1, 0.03))
    assert moved.reachable((0.2, 0.1 - 0.6, 0.03))
    assert not moved.reachable((0.2 + 0.9, 0.1, 0.03))
    assert not moved.reachable((0.2 + 0.02, 0.1, 0.03))
    assert not moved.reachable((0.2, 0.1, 1.5))
    assert moved.reach(1.5) == (0.0, 0.0)


def test_reach_depends_on_the_effector_offset(arm: Arm) -> None:
    longer = Arm.load(panda_robot(offset=0.2), "fingertip", np.eye(4))
    # hand down, an effector 9.7 cm further along the approach axis holds the hand 9.7 cm higher:
    # its reach at table height is the fingertip's 9.7 cm above it (not the cached fingertip's)
    np.testing.assert_allclose(longer.reach(0.03), arm.reach(0.03 + 0.097), atol=0.003)
    assert abs(longer.reach(0.03)[0] - arm.reach(0.03)[0]) > 0.01
