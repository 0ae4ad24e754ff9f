"""Benchmark: what the search does, in counts and CPU time, on the example tasks and generated ones.

    python bench/plan/bench_search_counts.py [--seed 1 --tasks 1 5 7] [--timeout 20]

For each task: the status, the plan's depth, the graphs expanded, the sequences made, the task-space checks,
the optimiser's runs and the CPU seconds of the search (`time.process_time`). Every deadline of the search runs
on the process's CPU time (`time.perf_counter` is replaced by `time.process_time` in this process), so a
timeout means `--timeout` CPU seconds of work whatever else runs on the machine: on a shared machine wall-clock
timeouts stop the search at a different point each run, and the counts would be meaningless. Compare two
checkouts by running this file from each (`PYTHONPATH=<checkout>`). Without `--seed`, the example tasks only.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]


def tasks(seed: int | None, indices: list[int], scratch: Path) -> list[tuple[str, Path]]:
    """(name, task file) of the examples, or of the generated tasks `indices` of `seed`."""
    if seed is None:
        return [(f.stem, f) for f in sorted((REPO / "examples" / "tasks").glob("*.vkg"))]
    from task_makers import generated_tasks

    library = generated_tasks.fixture_library()
    out = []
    for index in indices:
        spec = generated_tasks.task_spec(seed, index)
        out.append((spec.name, generated_tasks.write_task(spec, scratch / spec.name, library)))
    return out


def row(name: str, path: Path, timeout: float) -> str:
    """One table row: the search of the file's first task, its deadline `timeout` CPU seconds away."""
    from vkgl.lang.compiler import compile_file
    from vkgl.plan.problem.problem import build_problem
    from vkgl.plan.search.search import search

    program = compile_file(str(path))
    problem = build_problem(program, program.task(), timeout=timeout)
    started = time.process_time()
    result = search(problem, deadline=time.perf_counter() + timeout)
    cpu = time.process_time() - started
    stats = result.stats
    depth = result.sequence.depth if result.sequence is not None else "-"
    return (
        f"| {name} | {result.status} | {depth} | {stats.graphs_expanded} | {stats.sequences} | "
        f"{stats.task_space_checks} | {stats.work.optimisations} | {cpu:.2f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seed", type=int, help="generated tasks of this seed instead of the examples")
    parser.add_argument("--tasks", type=int, nargs="*", default=list(range(50)), help="their indices")
    parser.add_argument("--timeout", type=float, default=20.0, help="per task, CPU seconds (default 20)")
    args = parser.parse_args()
    time.perf_counter = time.process_time  # every deadline in CPU seconds (see the module's docstring)
    print("| task | status | depth | graphs expanded | sequences | task-space checks | optimisations | CPU s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as scratch:
        for name, path in tasks(args.seed, args.tasks, Path(scratch)):
            print(row(name, path, args.timeout), flush=True)


if __name__ == "__main__":
    main()
