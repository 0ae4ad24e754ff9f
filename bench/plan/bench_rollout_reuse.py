"""Benchmark: the task-space optimiser's rollouts, full (`rollout`) or reusing unchanged modes (`Rollouts`).

    python bench/plan/bench_rollout_reuse.py [--tasks gen1_018 gen1_021 ...] [--checks 100] [--repeat 5]

Each task is generated as `bench/physical/bench_physical.py` generates it and searched until its `--checks`-th
task-space check; every point at which the optimiser's evaluator rolled a sequence out is recorded (the
points of its runs and of their finite-difference steps, per sequence, in order). The recorded points are
then rolled out again, per sequence, with `rollout` and with a fresh `Rollouts`, `--repeat` times each,
alternately; the least CPU time of each (`time.process_time`) is kept per sequence and summed, so that the
load of a shared machine counts as little as it can. Printed per task: the rollouts, the modes they hold and
how many `Rollouts` computed (the rest it reused), and the CPU seconds of each.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support"), str(REPO / "bench" / "plan")]

DEFAULT_TASKS = ["gen1_018", "gen1_021", "gen1_026", "gen8_001", "gen8_021"]
"""Tasks that time out at 20 s on the idle physical bench (seeds 1 and 8): blocked, and far pushes."""


def recorded_points(name: str, path: Path, checks: int) -> list[tuple[object, list[object]]]:
    """(evaluator, the points it rolled out) of each sequence the search optimised in its first `checks`
    task-space checks."""
    import bench_timeouts

    from vkgl.plan.task_space import feasible

    points: dict[int, list[object]] = defaultdict(list)
    evaluators: dict[int, object] = {}
    original = feasible._Evaluator._compute

    def recording(self, x):  # type: ignore[no-untyped-def]
        evaluators[id(self)] = self
        points[id(self)].append(x.copy())
        return original(self, x)

    feasible._Evaluator._compute = recording  # type: ignore[method-assign]
    try:
        bench_timeouts.measure((name, str(path), 20.0, checks, None))
    finally:
        feasible._Evaluator._compute = original  # type: ignore[method-assign]
    return [(evaluators[key], xs) for key, xs in points.items()]


def least_cpu(recorded: list[tuple[object, list[object]]], repeat: int) -> tuple[float, float, int, int]:
    """(full CPU s, reusing CPU s, modes, modes computed by `Rollouts`) over every recorded sequence."""
    from vkgl.plan.graphs.reuse import Rollouts
    from vkgl.plan.graphs.rollout import rollout
    from vkgl.plan.task_space.feasible import TASK_SAMPLES

    full_total = reuse_total = 0.0
    modes = rolled = 0
    for evaluator, xs in recorded:
        problem, seq = evaluator.problem, evaluator.seq  # type: ignore[attr-defined]
        best_full = best_reuse = float("inf")
        for _ in range(repeat):
            started = time.process_time()
            for x in xs:
                rollout(problem, seq, x, TASK_SAMPLES)
            best_full = min(best_full, time.process_time() - started)
            rollouts = Rollouts(problem, seq, TASK_SAMPLES)
            started = time.process_time()
            for x in xs:
                rollouts.rollout(x)
            best_reuse = min(best_reuse, time.process_time() - started)
        full_total += best_full
        reuse_total += best_reuse
        modes += len(xs) * seq.depth
        rolled += rollouts.modes_rolled
    return full_total, reuse_total, modes, rolled


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="*", default=DEFAULT_TASKS, help="generated tasks, by name")
    parser.add_argument("--checks", type=int, default=100, help="task-space checks recorded per task")
    parser.add_argument("--repeat", type=int, default=5, help="replays of each sequence's points (least kept)")
    args = parser.parse_args()
    import bench_timeouts

    print("| task | rollouts | modes | modes computed | CPU s, full | CPU s, reusing | change |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as scratch:
        for name, path in bench_timeouts.write_tasks(args.tasks, Path(scratch)):
            recorded = recorded_points(name, path, args.checks)
            full, reuse, modes, rolled = least_cpu(recorded, args.repeat)
            count = sum(len(xs) for _, xs in recorded)
            print(
                f"| {name} | {count} | {modes} | {rolled} ({100 * rolled / max(modes, 1):.0f} %) | {full:.3f} | "
                f"{reuse:.3f} | {100 * (reuse - full) / full:+.0f} % |",
                flush=True,
            )


if __name__ == "__main__":
    main()
