"""Transit planning: the straight fast path, OMPL's RRTConnect around an obstacle, seeding, failures, quiet output.

The validity functions are the tests' own: a box in front of the Panda
against balls along its links (`box_world.BoxWorld`), and joint-space regions
(cheap, for the tests that only need the planner's behaviour).
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from conftest import REPO
from panda_fixtures import panda_robot
from task_makers.box_world import BoxWorld

from vkgl.motion.density import DEFAULT_RESOLUTION, densify, edge_resolution, link_reach, segment_is_valid
from vkgl.motion.transit import TransitFailure, TransitPath, plan_transit
from vkgl.robot import Arm

LOWER = -2.0 * np.ones(7)
UPPER = 2.0 * np.ones(7)


@pytest.fixture(scope="module")
def arm() -> Arm:
    return Arm.load(panda_robot(), "fingertip", np.eye(4))


@pytest.fixture(scope="module")
def box_case(arm: Arm) -> tuple[BoxWorld, np.ndarray, np.ndarray, TransitPath | TransitFailure]:
    """A box in front of the arm; the hand swings from its left to its right at home height."""
    world = BoxWorld(arm, [((0.55, 0.0, 0.3), (0.1, 0.1, 0.3))])
    start, goal = arm.home.copy(), arm.home.copy()
    start[0], goal[0] = 1.0, -1.0
    return world, start, goal, plan_transit(start, goal, world.is_valid, arm.lower, arm.upper, seed=0, time_limit=5.0)


def wall(q: np.ndarray) -> bool:
    """A joint-space wall across joint 1 with a gap at joint 2 > 0.8."""
    return not (abs(q[0]) < 0.3 and q[1] < 0.8)


def test_resolution_bounds_link_motion(arm: Arm) -> None:
    reach = link_reach(arm)
    assert reach[0] > 0.9 and reach[-1] < reach[0]  # the shoulder moves the most
    # the default keeps every point within 1 cm per step, with a tool up to 12 cm
    assert edge_resolution(arm, 0.01, tool_reach=0.12) >= DEFAULT_RESOLUTION
    assert edge_resolution(arm, 0.01, tool_reach=0.3) < DEFAULT_RESOLUTION
    # an effector point never moves more than the bound between samples
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = rng.uniform(arm.lower, arm.upper)
        direction = rng.normal(size=7)
        step = direction / np.linalg.norm(direction) * DEFAULT_RESOLUTION
        assert np.linalg.norm(arm.fk(q + step)[:3, 3] - arm.fk(q)[:3, 3]) <= np.linalg.norm(reach) * DEFAULT_RESOLUTION


def test_clear_transit_takes_the_straight_line_without_ompl(arm: Arm) -> None:
    world = BoxWorld(arm, [])
    start, goal = arm.home.copy(), arm.home.copy()
    goal[0] = 0.8
    result = plan_transit(start, goal, world.is_valid, arm.lower, arm.upper, seed=0)
    assert isinstance(result, TransitPath)
    assert result.method == "straight"
    assert np.array_equal(result.waypoints, np.vstack([start, goal]))
    assert "search" not in result.stages


def test_blocked_transit_goes_around_the_box(box_case) -> None:
    world, start, goal, result = box_case
    assert not segment_is_valid(start, goal, world.is_valid, DEFAULT_RESOLUTION)  # the straight line hits the box
    assert isinstance(result, TransitPath), result
    assert result.method == "rrtconnect"
    assert np.array_equal(result.waypoints[0], start) and np.array_equal(result.waypoints[-1], goal)
    dense = densify(result.waypoints, DEFAULT_RESOLUTION)
    steps = np.linalg.norm(np.diff(dense, axis=0), axis=1)
    assert steps.max() <= DEFAULT_RESOLUTION + 1e-12
    assert all(world.is_valid(q) for q in dense)


def test_same_seed_same_path() -> None:
    start, goal = np.zeros(7), np.zeros(7)
    start[0], goal[0] = -1.0, 1.0
    first = plan_transit(start, goal, wall, LOWER, UPPER, seed=7, time_limit=5.0)
    second = plan_transit(start, goal, wall, LOWER, UPPER, seed=7, time_limit=5.0)
    other = plan_transit(start, goal, wall, LOWER, UPPER, seed=8, time_limit=5.0)
    assert isinstance(first, TransitPath) and isinstance(second, TransitPath) and isinstance(other, TransitPath)
    assert first.method == "rrtconnect"
    assert np.array_equal(first.waypoints, second.waypoints)
    assert not np.array_equal(first.waypoints, other.waypoints)
    assert all(wall(q) for q in densify(first.waypoints, DEFAULT_RESOLUTION))


def test_threads_planning_at_once_get_their_seeded_paths() -> None:
    start, goal = np.zeros(7), np.zeros(7)
    start[0], goal[0] = -1.0, 1.0
    alone = plan_transit(start, goal, wall, LOWER, UPPER, seed=11, time_limit=5.0)
    with ThreadPoolExecutor(3) as pool:
        together = list(
            pool.map(lambda _: plan_transit(start, goal, wall, LOWER, UPPER, seed=11, time_limit=5.0), [0, 1, 2])
        )
    assert isinstance(alone, TransitPath)
    assert all(isinstance(r, TransitPath) and np.array_equal(r.waypoints, alone.waypoints) for r in together)


def test_invalid_goal_fails_at_once() -> None:
    start, goal = -np.ones(7), np.zeros(7)
    result = plan_transit(start, goal, wall, LOWER, UPPER, seed=0)
    assert isinstance(result, TransitFailure)
    assert "goal configuration is invalid" in result.reason
    assert result.planning_time < 0.1
    outside = plan_transit(start, 3 * np.ones(7), wall, LOWER, UPPER, seed=0)
    assert isinstance(outside, TransitFailure) and "outside the joint limits" in outside.reason


def test_enclosed_goal_fails_within_the_time_limit() -> None:
    start, goal = np.zeros(7), np.zeros(7)
    start[0], goal[0] = -1.0, 1.0

    def enclosed(q: np.ndarray) -> bool:  # the goal sits in a hollow shell
        return not 0.1 < np.abs(q - goal).max() < 0.3

    began = time.perf_counter()
    result = plan_transit(start, goal, enclosed, LOWER, UPPER, seed=0, time_limit=0.2)
    elapsed = time.perf_counter() - began
    assert isinstance(result, TransitFailure)
    assert "no path found" in result.reason and "0.2" in result.reason
    assert elapsed < 0.2 + 0.15


def test_exception_of_the_validity_function_propagates() -> None:
    start, goal = np.zeros(7), np.zeros(7)
    start[0], goal[0] = -1.0, 1.0

    def broken(q: np.ndarray) -> bool:
        if q[1] > 0.5:
            raise RuntimeError("checker broke")
        return wall(q)

    with pytest.raises(RuntimeError, match="checker broke"):
        plan_transit(start, goal, broken, LOWER, UPPER, seed=0, time_limit=0.5)


def test_ompl_prints_nothing(tmp_path) -> None:
    """No OMPL log and no nanobind leak warning at exit, after a found path, a failure and an exception;
    and the path found in a fresh process is the one found here (bit for bit: both on this machine, so
    CPU differences cannot enter)."""
    script = tmp_path / "quiet.py"
    script.write_text(
        textwrap.dedent(
            """
            import numpy as np
            from vkgl.motion.transit import plan_transit, TransitPath, TransitFailure

            def wall(q):
                return not (abs(q[0]) < 0.3 and q[1] < 0.8)

            def broken(q):
                raise ValueError("no")

            low, high = -2 * np.ones(7), 2 * np.ones(7)
            a, b = np.zeros(7), np.zeros(7)
            a[0], b[0] = -1.0, 1.0
            found = plan_transit(a, b, wall, low, high, seed=3)
            shell = lambda q: not 0.1 < np.abs(q - b).max() < 0.3
            lost = plan_transit(a, b, shell, low, high, seed=3, time_limit=0.1)
            try:
                plan_transit(a, b, lambda q: broken(q) if q[1] > 0.5 else wall(q), low, high, seed=3)
            except ValueError:
                pass
            print(type(found).__name__, found.method, type(lost).__name__)
            print(found.waypoints.tobytes().hex())
            """
        )
    )
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, cwd=REPO, env={"PYTHONPATH": str(REPO)}
    )
    assert done.returncode == 0, done.stderr
    summary, digest = done.stdout.strip().splitlines()
    assert summary == "TransitPath rrtconnect TransitFailure"
    assert done.stderr == ""
    # the same path in this process, after other plans: the seed alone decides it
    start, goal = np.zeros(7), np.zeros(7)
    start[0], goal[0] = -1.0, 1.0
    here = plan_transit(start, goal, wall, LOWER, UPPER, seed=3)
    assert isinstance(here, TransitPath) and here.waypoints.tobytes().hex() == digest
