"""Benchmark: transit planning time for random start/goal pairs of the Panda around 1 to 3 boxes.

    PYTHONPATH=. python bench/robot/bench_transit.py [--pairs N] [--seed S] [--time-limit T]

Each scene has 1 to 3 boxes on the table in front of the arm (random sizes
and places); start and goal are hand-down effector poses between 8 and 35 cm
above the table (IK, the way pre-contact poses are), both clear of the boxes.
The validity function is the tests' `box_world.BoxWorld` (balls along the
links against the boxes and the table), not the project's collision checker:
`checks` (calls of it) is the machine- and checker-independent work measure;
`us/check` says what one call cost here.

Two runs over the same pairs: `plan_transit` as it is (straight joint-space
line first, OMPL only when it is blocked) and with `straight_first=False`
(OMPL's RRTConnect for every pair). Prints one Markdown table: wall and CPU
time per plan (median, p90), checks per plan, and the checks per stage.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


def _scenes(arm, pairs: int, seed: int):
    """`pairs` (world, start, goal) triples: boxes, and two valid hand-down configurations."""
    from task_makers.box_world import BoxWorld

    rng = np.random.default_rng(seed)
    made = []
    while len(made) < pairs:
        boxes = []
        for _ in range(int(rng.integers(1, 4))):
            radius, azimuth = rng.uniform(0.35, 0.65), rng.uniform(-1.2, 1.2)
            half = (rng.uniform(0.03, 0.08), rng.uniform(0.03, 0.08), rng.uniform(0.05, 0.2))
            centre = (radius * np.cos(azimuth), radius * np.sin(azimuth), half[2])
            boxes.append((centre, half))
        world = BoxWorld(arm, boxes)
        ends = []
        for _ in range(40):
            radius, azimuth, height = rng.uniform(0.35, 0.7), rng.uniform(-1.4, 1.4), rng.uniform(0.08, 0.35)
            pose = np.eye(4)
            yaw = azimuth + rng.uniform(-0.5, 0.5)
            pose[:3, :3] = [[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]]
            pose[:3, 3] = (radius * np.cos(azimuth), radius * np.sin(azimuth), height)
            q = arm.ik(pose)
            if q is not None and world.is_valid(q):
                ends.append(q)
            if len(ends) == 2:
                made.append((world, ends[0], ends[1]))
                break
    return made


def _percentiles(values: list[float]) -> str:
    return f"{np.median(values):8.1f} | {np.percentile(values, 90):8.1f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=40)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--time-limit", type=float, default=2.0)
    args = parser.parse_args()
    sys.path.insert(0, str(REPO))
    sys.path.insert(0, str(REPO / "tests"))
    sys.path.insert(0, str(REPO / "tests" / "support"))
    from robot.test_arm import panda_robot

    from vkgl.motion.density import DEFAULT_RESOLUTION
    from vkgl.motion.transit import TransitPath, plan_transit
    from vkgl.robot import Arm

    arm = Arm.load(panda_robot(), "fingertip", np.eye(4))
    scenes = _scenes(arm, args.pairs, args.seed)
    world = scenes[0][0]
    began = time.process_time()
    for _ in range(2000):
        world.is_valid(arm.home)
    per_check = (time.process_time() - began) / 2000 * 1e6

    print(
        f"{len(scenes)} pairs, 1-3 boxes, resolution {DEFAULT_RESOLUTION} rad, time limit {args.time_limit} s, "
        f"{per_check:.0f} us/check (CPU)\n"
    )
    print(
        "| run | pairs | solved | straight | wall ms median | p90 | CPU ms median | p90 | checks median | p90 |"
        " checks per stage (mean) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for label, straight_first, subset in (
        ("fast path first", True, None),
        ("OMPL always", False, None),
        ("fast path first, blocked pairs only", True, "blocked"),
    ):
        walls, cpus, checks, solved, straight = [], [], [], 0, 0
        stages: dict[str, list[int]] = {}
        for index, (scene, start, goal) in enumerate(scenes):
            wall0, cpu0 = time.perf_counter(), time.process_time()
            result = plan_transit(
                start, goal, scene.is_valid, arm.lower, arm.upper,
                seed=index, time_limit=args.time_limit, straight_first=straight_first,
            )  # fmt: skip
            wall, cpu = (time.perf_counter() - wall0) * 1e3, (time.process_time() - cpu0) * 1e3
            is_straight = isinstance(result, TransitPath) and result.method == "straight"
            if subset == "blocked" and is_straight:
                continue
            walls.append(wall)
            cpus.append(cpu)
            checks.append(result.checks)
            solved += isinstance(result, TransitPath)
            straight += is_straight
            for name, count in result.stages.items():
                stages.setdefault(name, []).append(count)
        if not walls:
            continue
        split = ", ".join(f"{name} {np.mean(counts):.0f}" for name, counts in stages.items())
        print(
            f"| {label} | {len(walls)} | {solved} | {straight} | {_percentiles(walls)} | {_percentiles(cpus)} | "
            f"{np.median(checks):.0f} | {np.percentile(checks, 90):.0f} | {split} |"
        )


if __name__ == "__main__":
    main()
