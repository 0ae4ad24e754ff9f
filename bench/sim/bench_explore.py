"""Benchmark: explore the stdlib bodies in DART and report the speed.

    python bench/sim/bench_explore.py [--jobs N ...] [--repeat R]

Prints one Markdown table: per body and job count, the trials, the simulated
seconds, the wall time (best of R runs, including process start-up) and
simulated seconds per wall second. The target: the full Block grid (2 faces x
9 points, 2 s each = 36 simulated s) in under 20 s wall on 2 cores.

Bodies come from stdlib/bodies/*.vkg through the front end; until the front
end exists, from the test suite's handmade twins (tests/sim/sim_bodies.py).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
BODIES = ["Block", "Drawer", "Door", "Stick", "Hook"]


def load_body(name: str):
    """The stdlib body `name`, compiled from its file."""
    from vkgl.lang.compiler import compile_file

    return compile_file(str(REPO / "stdlib" / "bodies" / f"{name.lower()}.vkg")).bodies[name]


def simulated_seconds(trials) -> float:
    """Total simulated time of a dataset (the last sample time of each trial)."""
    import numpy as np

    return float(sum(np.nanmax(trials.t[i]) for i in range(len(trials))))


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, nargs="+", default=[1, 2], help="job counts to try (default 1 2)")
    parser.add_argument("--repeat", type=int, default=2, help="runs per cell; the best is reported (default 2)")
    args = parser.parse_args(argv)

    from vkgl.sim.explore import explore

    print("| body | trials | failed | jobs | simulated s | wall s | sim s / wall s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in BODIES:
        body = load_body(name)
        if body is None:
            continue
        for jobs in args.jobs:
            best = float("inf")
            for _ in range(args.repeat):
                started = time.perf_counter()
                trials = explore(body, jobs=jobs)
                best = min(best, time.perf_counter() - started)
            sim = simulated_seconds(trials)
            failed = int((~trials.ok).sum())
            print(
                f"| {name} | {len(trials)} | {failed} | {jobs} | {sim:.1f} | {best:.2f} | {sim / best:.1f} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
