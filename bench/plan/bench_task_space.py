"""Benchmark: what each sequence the search checks costs, on generated tasks of the physical bench.

    python bench/plan/bench_task_space.py [--seed 6] [--tasks 1,4,5] [--timeout 20]

Each task (`tests/support/task_makers/generated_tasks.py`, the bodies' learned affordances from the tests' fixtures) is
solved in this process with its deadline counted in CPU seconds of the process (`time.process_time`), not in
wall-clock seconds: on a shared machine a 20 s timeout then means the same work whatever the load, and a task
that times out here times out idle too. Prints a Markdown table per task: the outcome, CPU seconds, and the
counts that explain them (sequences checked in task space, NLopt runs, and how many sequences the closed form
rejected before any optimisation versus the optimiser after its starts failed).

The default tasks are seed 6's timeouts and slow "no plan" answers at 20 s on main before the closed form
judged goals that leave the heading free (docs/planning.md, "What a sequence costs").
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

DEFAULT_TASKS = "1,3,4,5,8,11,13,15,17"


def main(argv: list[str] | None = None) -> int:
    """Solve the tasks and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=6)
    parser.add_argument("--tasks", default=DEFAULT_TASKS, help=f"task indices (default {DEFAULT_TASKS})")
    parser.add_argument("--timeout", type=float, default=20.0, help="per task, CPU s (default 20)")
    args = parser.parse_args(argv)
    from task_makers import generated_tasks

    import vkgl

    time.perf_counter = time.process_time  # the planner's deadlines in CPU seconds (see the docstring)
    library = generated_tasks.fixture_library()
    print(f"## bench_task_space: seed {args.seed}, {args.timeout:g} CPU s per task\n")
    print(
        "| task | goal | outcome | CPU s | depth | task-space checks | NLopt runs | closed form rejected | "
        "optimiser rejected |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as scratch:
        for index in (int(i) for i in args.tasks.split(",")):
            spec = generated_tasks.task_spec(args.seed, index)
            path = generated_tasks.write_task(spec, Path(scratch) / spec.name, library)
            program = vkgl.compile(path)
            started = time.process_time()
            plan = vkgl.solve(program, spec.name, timeout=args.timeout)
            cpu = time.process_time() - started
            details = plan.details or {}
            rejections = details.get("rejections") or {}
            goal = plan.problem.goals[0] if plan.problem is not None else None
            heading = "position, heading" if goal is not None and goal.yaw is not None else "position"
            closed = sum(rejections.get(k, 0) for k in ("position", "yaw"))
            print(
                f"| {spec.name} | {heading} | {plan.status} | {cpu:.1f} | {plan.depth or '-'} "
                f"| {plan.stats.get('task_space_checks', 0)} "
                f"| {details.get('optimisations', 0)} | {closed} | {rejections.get('goal', 0)} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
