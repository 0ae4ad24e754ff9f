"""Benchmark: where a task with a body in the way spends its time, search by search.

    python bench/plan/bench_blocked.py TASK_DIR [TASK_DIR ...] [--timeout 20] [--max-depth N] [--unlimited UNITS]

Each `TASK_DIR` holds a `task.vkg` as `bench/physical/bench_physical.py --out DIR` writes it (`DIR/gen1_018`).
Every task
is solved in this process with its deadlines counted in CPU seconds of the process (`time.perf_counter` is
`time.process_time` here: the numbers are what load does not inflate), and every search the solve runs is
recorded: the main search, each sub-search that clears a blocker to one side (`vkgl.plan.search.clutter.clear_first`),
and each search of the goals after a clearing plan. Prints one Markdown table row per search (CPU s, status,
graphs expanded, task-space checks, optimisations, the level reached, the most frequent rejections) and one per
task (outcome, depth, CPU s, the plan's words).

`--unlimited UNITS` lifts clearing's limits: every search `clear_first` runs (each side of each blocker, each search
of the goals after a clearing plan) gets `UNITS` of work and no deadline, and the walk goes on over every blocker
and side until it has tried them all (the search before keeps its share of the timeout). It tells a search cut by
its share from one that has no plan within its depth: a "then ... (free)" row that ends "infeasible" proves that no
plan of at most its `max_depth` graphs starts with that clearing plan's sequence, whatever the budget
(docs/planning.md, "Clear first, then solve").
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO)]


NO_DEADLINE = 3600.0
"""What `--unlimited` gives each search instead of its deadline (CPU s): an hour, as good as none."""


def _recording(rows: list[dict[str, Any]], original: Any, where: str, unlimited: float | None = None) -> Any:
    """`original` (a `search` function) wrapped to append one row per call to `rows`; given `unlimited`, each call
    gets that budget (work units) and no deadline."""

    def wrapped(problem: Any, *, deadline: float, progress: bool = False, root: Any = None, **more: Any) -> Any:
        started = time.process_time()
        if unlimited is not None:
            more["budget"], deadline = unlimited, time.perf_counter() + NO_DEADLINE
        budget = more.get("budget")
        result = original(problem, deadline=deadline, progress=progress, root=root, **more)
        goal = problem.goals[0]
        what = f"clear {goal.body} {goal.region_words}" if goal.region is not None else where
        if where == "then" and goal.region is None:
            what = f"then goals from {root.depth} graphs ({'its values pinned' if problem.pinned else 'free'})"
        stats = result.stats
        top = ", ".join(f"{n} {k}" for k, n in stats.rejections.most_common(3))
        rows.append(
            {
                "what": what,
                "status": result.status,
                "cpu": time.process_time() - started,
                "expanded": stats.graphs_expanded,
                "ts": stats.task_space_checks,
                "opt": stats.work.optimisations,
                "ik": stats.work.ik_calls,
                "arm": stats.arm_path_checks,
                "transits": stats.transits,
                "geometry": stats.geometry_checks,
                "level": stats.level,
                "max_depth": problem.max_depth,
                "budget": budget,
                "units": stats.work_done() if hasattr(stats, "work_done") else 0.0,
                "rejections": top,
            }
        )
        return result

    return wrapped


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tasks", nargs="+", type=Path, help="task folders (each with a task.vkg)")
    parser.add_argument("--timeout", type=float, default=20.0)
    parser.add_argument("--max-depth", type=int)
    parser.add_argument(
        "--unlimited",
        type=float,
        metavar="UNITS",
        help="every search of the clearing gets UNITS of work and no deadline, and every blocker and side is tried",
    )
    args = parser.parse_args()
    time.perf_counter = time.process_time  # every deadline in CPU seconds of this process
    import vkgl
    import vkgl.plan.search.clutter.clear_first as clear_first
    import vkgl.plan.search.clutter.still as still

    rows: list[dict[str, Any]] = []
    still.search = _recording(rows, still.search, "main")  # type: ignore[attr-defined]
    clear_first.search = _recording(rows, clear_first.search, "then", args.unlimited)  # type: ignore[attr-defined]
    if args.unlimited is not None:
        clear_first._Walk.spent = lambda self: False  # type: ignore[method-assign]  # every blocker and side tried
    print(
        "| task | search | status | CPU s | work units (budget) | expanded | task-space checks | optimisations | IK | "
        "arm paths | transits | level/max | rejections |"
    )
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|")
    summaries = []
    for folder in args.tasks:
        rows.clear()
        program = vkgl.compile(str(folder / "task.vkg"))
        name = folder.name
        started = time.process_time()
        plan = vkgl.solve(program, name, timeout=args.timeout, max_depth=args.max_depth)
        cpu = time.process_time() - started
        for row in rows:
            budget = "-" if row["budget"] is None else f"{row['budget']:.0f}"
            print(
                f"| {name} | {row['what']} | {row['status']} | {row['cpu']:.2f} | {row['units']:.0f} ({budget}) | "
                f"{row['expanded']} | {row['ts']} | {row['opt']} | {row['ik']} | {row['arm']} | {row['transits']} | "
                f"{row['level']:g}/{row['max_depth']} | {row['rejections']} |"
            )
        words = (plan.reason or "").splitlines()
        summaries.append((name, plan.status, len(plan.graphs), cpu, words[-1] if words else ""))
        sys.stdout.flush()
    print("\n| task | outcome | graphs | CPU s | words |\n|---|---|---:|---:|---|")
    for name, status, depth, cpu, words in summaries:
        print(f"| {name} | {status} | {depth} | {cpu:.1f} | {words[:300]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
