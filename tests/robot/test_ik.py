"""Inverse kinematics, checked by what it promises: round trips, limits, paths without jumps, determinism."""

from __future__ import annotations

import math
import time

import numpy as np
from panda_fixtures import (
    LOWER,
    UPPER,
    arm_fixture,  # noqa: F401 (the `arm` fixture)
    hand_down,
    panda_robot,
    pose_error,
    transform,
)
from scipy.spatial.transform import Rotation

from vkgl.robot import Arm, clear_caches


def test_ik_round_trips_random_reachable_targets_within_the_limits(arm: Arm) -> None:
    rng = np.random.default_rng(11)
    for q in rng.uniform(LOWER, UPPER, (25, 7)):
        target = arm.fk(q)
        found = arm.ik(target)
        assert found is not None, f"no IK for the FK of {q}"
        assert np.all(arm.lower <= found) and np.all(found <= arm.upper)
        position, angle = pose_error(arm.fk(found), target)
        assert position < 1e-3 and angle < math.radians(0.5)


def test_ik_solves_hand_down_pushes_all_over_the_table(arm: Arm) -> None:
    # (how fast: bench/robot/bench_robot.py)
    rng = np.random.default_rng(3)
    for _ in range(40):
        radius, azimuth, yaw = rng.uniform(0.3, 0.75), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi)
        target = hand_down(radius * math.cos(azimuth), radius * math.sin(azimuth), 0.025, yaw)
        found = arm.ik(target)
        assert found is not None
        position, angle = pose_error(arm.fk(found), target)
        assert position < 1e-3 and angle < math.radians(0.5)


def test_ik_warm_started_follows_a_path_without_jumps(arm: Arm) -> None:
    q = arm.ik(hand_down(0.45, 0.0, 0.03))
    for step in range(1, 21):
        nxt = arm.ik(hand_down(0.45 + 0.01 * step, 0.0, 0.03), q0=q)
        assert nxt is not None
        assert np.max(np.abs(nxt - q)) < 0.2  # 1 cm of motion: a small joint step, not another branch
        q = nxt


def test_ik_near_tracks_a_straight_path_in_small_steps_as_tightly_as_ik(arm: Arm) -> None:
    rng = np.random.default_rng(5)
    for yaw_free in (False, True):
        q = arm.home.copy()
        start = arm.fk(q)
        for _ in range(15):
            start = start.copy()
            start[:3, 3] += rng.uniform(-0.01, 0.01, 3)
            nxt = arm.ik_near(start, q, yaw_free=yaw_free)
            assert nxt is not None
            assert np.all(arm.lower <= nxt) and np.all(nxt <= arm.upper)
            pose = arm.fk(nxt)
            assert np.linalg.norm(pose[:3, 3] - start[:3, 3]) < 1.5e-4
            axis_error = math.acos(min(1.0, float(pose[:3, 2] @ start[:3, 2])))
            assert axis_error < 1.5e-3
            if not yaw_free:
                assert pose_error(pose, start)[1] < 1.5e-3
            assert np.max(np.abs(nxt - q)) < 0.2  # the small step stays on its branch
            q = nxt


def test_ik_near_falls_back_to_ik_for_a_far_target(arm: Arm) -> None:
    near = arm.ik(hand_down(0.4, -0.3, 0.05))
    far = hand_down(0.5, 0.35, 0.2)  # 67 cm away: Gauss-Newton steps from `near` are no answer, NLopt's seeds are
    found = arm.ik_near(far, near)
    assert found is not None
    position, angle = pose_error(arm.fk(found), far)
    assert position < 1e-3 and angle < math.radians(0.5)


def test_ik_with_yaw_free_matches_position_and_z_axis_only(arm: Arm) -> None:
    tilted = transform(Rotation.from_euler("xz", [20, 70], degrees=True).as_matrix(), (0.5, 0.15, 0.1))
    found = arm.ik(tilted, yaw_free=True)
    assert found is not None
    pose = arm.fk(found)
    assert np.linalg.norm(pose[:3, 3] - tilted[:3, 3]) < 1e-3
    assert math.acos(min(1.0, pose[:3, 2] @ tilted[:3, 2])) < math.radians(0.5)
    # a hand-down target at any yaw is the same problem when the yaw is free
    for yaw in (0.0, 1.0, 2.5, -2.0):
        found = arm.ik(hand_down(0.55, -0.1, 0.03, yaw), yaw_free=True)
        assert found is not None
        assert arm.fk(found)[2, 2] > math.cos(math.radians(0.5))


def test_ik_of_an_unreachable_target_is_none_and_quick(arm: Arm) -> None:
    start = time.perf_counter()
    assert arm.ik(hand_down(2.0, 0.0, 0.03)) is None
    assert time.perf_counter() - start < 0.05  # rejected by its distance, without optimising (which takes ~0.1 s)
    # within the chain's length but beyond a hand-down pose's reach: the optimiser must say no
    start = time.perf_counter()
    assert arm.ik(hand_down(0.95, 0.0, 0.03), yaw_free=True) is None
    assert time.perf_counter() - start < 1.0


def test_ik_is_deterministic() -> None:
    one = Arm.load(panda_robot(), "fingertip", np.eye(4))
    clear_caches()  # compute the ready pose again, not from the cache
    two = Arm.load(panda_robot(), "fingertip", np.eye(4))
    target = hand_down(0.6, -0.2, 0.05, 0.7)
    np.testing.assert_array_equal(one.home, two.home)
    np.testing.assert_array_equal(one.ik(target), two.ik(target))


def test_ik_answers_are_remembered_as_a_new_run_gives_them_and_each_caller_gets_its_own(monkeypatch) -> None:
    arm = Arm.load(panda_robot(), "fingertip", np.eye(4))
    fresh = Arm.load(panda_robot(), "fingertip", np.eye(4))  # nothing remembered yet
    target = hand_down(0.55, 0.1, 0.04, 0.3)
    near = target.copy()
    near[0, 3] += 0.005
    first = arm.ik(target, arm.home)
    assert first is not None
    step = arm.ik_near(near, first)
    assert step is not None
    first[:] = 0.0  # the caller's own array: the remembered answer stays as it was
    runs = []
    monkeypatch.setattr(arm._ik, "solve", lambda *a, **k: runs.append(a))
    monkeypatch.setattr(arm._ik, "track", lambda *a, **k: runs.append(a))
    again = arm.ik(target, arm.home)
    np.testing.assert_array_equal(again, fresh.ik(target, fresh.home))
    np.testing.assert_array_equal(arm.ik_near(near, again), fresh.ik_near(near, again))
    assert arm.ik(hand_down(2.0, 0.0, 0.03)) is None and fresh.ik(hand_down(2.0, 0.0, 0.03)) is None
    assert arm.ik(hand_down(2.0, 0.0, 0.03)) is None  # a failure is remembered too
    assert len(runs) == 1  # only the first unreachable target ran IK: the rest were remembered
    assert arm.ik(target, arm.home, yaw_free=True) is None and len(runs) == 2  # other inputs: IK runs again
