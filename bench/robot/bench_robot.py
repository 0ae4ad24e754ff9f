"""Benchmark: the stdlib Panda's forward/inverse kinematics and reach.

    python bench/robot/bench_robot.py [--samples N]

Prints one Markdown table of timings (load, FK, Jacobian, IK on several kinds
of target, reach) and one of the reach intervals at table heights. Targets:
FK tens of microseconds, one IK typically < 5 ms, reach(height) < 0.2 s on
its first call. All targets are drawn from a fixed seed.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

REPO = Path(__file__).resolve().parents[2]


def _panda():
    from vkgl.lang.ir.nodes import Effector, Pose, Robot, Vector

    return Robot(
        name="Panda",
        urdf="panda.urdf",
        urdf_resolved=str(REPO / "stdlib" / "robots" / "panda.urdf"),
        effectors=[Effector(name="fingertip", link="panda_hand", offset=Pose(position=Vector(values=(0, 0, 0.103))))],
    )


def _hand_down(radius: float, azimuth: float, height: float, yaw: float) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_euler("z", yaw).as_matrix()
    pose[:3, 3] = (radius * math.cos(azimuth), radius * math.sin(azimuth), height)
    return pose


def _timed(calls: list[Callable[[], object]]) -> tuple[list[float], list[object]]:
    times, results = [], []
    for call in calls:
        start = time.perf_counter()
        results.append(call())
        times.append(time.perf_counter() - start)
    return times, results


def _row(name: str, times: list[float], unit: str, failures: str = "") -> str:
    scale = {"us": 1e6, "ms": 1e3, "s": 1.0}[unit]
    quantiles = np.percentile(times, [50, 95]) * scale
    return (
        f"| {name} | {len(times)} | {statistics.fmean(times) * scale:.2f} {unit} | {quantiles[0]:.2f} {unit} | "
        f"{quantiles[1]:.2f} {unit} | {max(times) * scale:.2f} {unit} | {failures} |"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200, help="targets per IK row (default 200)")
    args = parser.parse_args(argv)

    from vkgl.robot import Arm
    from vkgl.robot.reach import clear_reach_cache

    rng = np.random.default_rng(0)
    rows = ["| what | n | mean | median | p95 | max | failures |", "|---|---|---|---|---|---|---|"]

    load_times, arms = _timed([lambda: Arm.load(_panda(), "fingertip", np.eye(4)) for _ in range(3)])
    arm = arms[0]
    rows.append(_row("Arm.load (first: DART parse + ready pose)", load_times[:1], "ms"))
    rows.append(_row("Arm.load (URDF cached)", load_times[1:], "ms"))

    qs = rng.uniform(arm.lower, arm.upper, (2000, 7))
    rows.append(_row("fk(q)", _timed([lambda q=q: arm.fk(q) for q in qs])[0], "us"))
    rows.append(_row("jacobian(q)", _timed([lambda q=q: arm.jacobian(q) for q in qs])[0], "us"))

    def ik_row(name: str, targets: list[np.ndarray], **options: object) -> None:
        times, results = _timed([lambda t=t: arm.ik(t, **options) for t in targets])
        failed = sum(r is None for r in results)
        rows.append(_row(name, times, "ms", f"{failed}/{len(targets)}"))

    n = args.samples
    ik_row("ik, FK of random q (full pose)", [arm.fk(q) for q in qs[:n]])
    table = [
        _hand_down(rng.uniform(0.3, 0.75), rng.uniform(-1.5, 1.5), rng.uniform(0.0, 0.05), rng.uniform(-3.1, 3.1))
        for _ in range(n)
    ]
    ik_row("ik, hand down over the table, given yaw", table)
    ik_row("ik, hand down over the table, yaw_free", table, yaw_free=True)

    # 1 mm steps along a straight push, each IK warm-started at the last: what execution does
    start_pose = _hand_down(0.35, 0.2, 0.025, 0.3)
    q = arm.ik(start_pose)
    steps = []
    for i in range(1, n + 1):
        target = start_pose.copy()
        target[:3, 3] += 0.001 * i * np.array([math.cos(0.2), math.sin(0.2), 0.0])
        steps.append(target)
    times = []
    for target in steps:
        start = time.perf_counter()
        q = arm.ik(target, q0=q) if q is not None else arm.ik(target)
        times.append(time.perf_counter() - start)
    rows.append(_row("ik, warm-started 1 mm steps", times, "ms"))
    ik_row("ik, unreachable: 2 m away", [_hand_down(2.0, a, 0.03, 0.0) for a in rng.uniform(-3, 3, 20)])
    ik_row("ik, unreachable: 0.95 m, table height", [_hand_down(0.95, a, 0.03, 0.0) for a in rng.uniform(-3, 3, 20)])

    heights = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05]
    clear_reach_cache()
    reach_times, intervals = _timed([lambda h=h: arm.reach(h) for h in heights])
    rows.append(_row("reach(height), first call", reach_times, "s"))
    rows.append(_row("reach(height), cached", _timed([lambda h=h: arm.reach(h) for h in heights])[0], "us"))

    print("\n".join(rows))
    print()
    print("| table height z | r_min | r_max | distance of r_max from joint 2's axis |")
    print("|---|---|---|---|")
    for h, (r_min, r_max) in zip(heights, intervals):
        print(f"| {h:.2f} m | {r_min:.4f} m | {r_max:.4f} m | {math.hypot(r_max, 0.333 - h):.4f} m |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
