"""Benchmark: the physical bench's timed-out tasks, in CPU seconds and checks per CPU second.

    python bench/plan/bench_timeouts.py [--tasks gen1_018 gen6_004 ...] [--timeout 20] [--checks N] [--against DIR]
                                   [--jobs 1]

Each task is generated as `bench/physical/bench_physical.py` generates it (the bodies' affordances from its cache,
`bench/.cache/physical/`, learned there when missing) and searched once with a deadline of `--timeout` CPU
seconds: every deadline of the search runs on the process's CPU time (`time.perf_counter` is replaced by
`time.process_time` in each worker, as in `bench_search_counts.py`), so where a search stops does not depend
on what else runs on the machine (its CPU seconds still grow somewhat with the load: compare runs made side by
side). Per task: the status, the plan's depth, the sequences made, the task-space checks, the
optimiser's runs, the IK calls, the CPU seconds, and the task-space checks per CPU second (the throughput a
cheaper check raises: a search that times out does more of the same work in the same time). Compare two
checkouts with `--against <other checkout>`: each task is searched with both codes (a process per search) and
the table says whether they did the same work and what it cost each; with `--checks N` every search stops after
its N-th task-space check instead, the same work on both when the checks give the same answers (the counts must
agree), so the CPU seconds compare the checks' cost alone. The default tasks are those that timed out at 20 s on
the idle physical bench of seeds 1, 6 and 7 (docs/bench/physical_bench_final_seed{1,6,7}.json), then of seeds 1 and 9
(docs/bench/physical_bench_1127_seed{1,9}.json).

    python bench/plan/bench_timeouts.py --checks 500 --against /path/to/main --jobs 2
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

TIMED_OUT = [
    "gen1_016",
    "gen1_018",
    "gen1_021",
    "gen1_024",
    "gen1_026",
    "gen1_033",
    "gen1_038",
    "gen1_039",
    "gen1_040",
    "gen6_001",
    "gen6_004",
    "gen6_008",
    "gen6_011",
    "gen6_017",
    "gen6_026",
    "gen6_028",
    "gen6_036",
    "gen6_038",
    "gen6_049",
    "gen7_018",
    "gen7_028",
    "gen7_032",
    "gen7_038",
    "gen7_046",
    "gen1_005",
    "gen1_046",
    "gen9_008",
    "gen9_018",
    "gen9_021",
    "gen9_025",
    "gen9_036",
    "gen9_046",
]
"""The tasks that timed out at 20 s on the idle physical bench (seeds 1, 6, 7, default max depth 6; then those of
seeds 1 and 9 on 2026-11-27 not already named, docs/bench/physical_bench_1127_seed{1,9}.json)."""

COMPARED = "| task | status | same work | sequences | task-space checks | CPU s | CPU change |"

HEAD = "| task | status | depth | sequences | task-space checks | optimisations | IK calls | CPU s | checks / CPU s |"


def write_tasks(names: list[str], out: Path) -> list[tuple[str, Path]]:
    """(name, task file) of each generated task `genS_III`, written as the physical bench writes it."""
    from task_makers import generated_tasks

    cache = REPO / "bench" / ".cache" / "physical"
    specs = [generated_tasks.task_spec(int(n[3:].split("_")[0]), int(n.split("_")[1])) for n in names]
    types = sorted({t for s in specs for t in s.generated_types()}, key=lambda t: t.name)
    library = generated_tasks.learned_affordances(types, cache, jobs=1)
    return [(s.name, generated_tasks.write_task(s, out / s.name, library)) for s in specs]


def measure(job: tuple[str, str, float, int | None, str | None]) -> tuple[str, str, str, int, int, int, int, float]:
    """The search of one task file, its deadline `timeout` CPU seconds away, or, with `checks`, after that many
    task-space checks; with `checkout`, that checkout's code (each job runs in a process of its own): (name,
    status, depth, sequences, task-space checks, optimisations, IK calls, CPU s)."""
    name, path, timeout, checks, checkout = job
    if checkout is not None:
        sys.path.insert(0, checkout)
    from vkgl.lang.compiler import compile_file
    from vkgl.plan.problem.problem import build_problem
    from vkgl.plan.search import search as module

    deadline = float(timeout)
    if checks is None:
        time.perf_counter = time.process_time  # every deadline in CPU seconds (see the module's docstring)
    else:
        time.perf_counter = _count_checks(_checking(module))  # the deadline in checks: the same work on any checkout
        deadline = float(checks)
    program = compile_file(path)
    problem = build_problem(program, program.task(), timeout=timeout)
    started = time.process_time()
    result = module.search(problem, deadline=time.perf_counter() + deadline)
    cpu = time.process_time() - started
    stats = result.stats
    depth = str(result.sequence.depth) if result.sequence is not None else "-"
    work = stats.work
    return name, result.status, depth, stats.sequences, stats.task_space_checks, work.optimisations, work.ik_calls, cpu


def row(found: tuple[str, str, str, int, int, int, int, float]) -> str:
    """One row of the single checkout's table."""
    name, status, depth, sequences, checks, optimisations, ik_calls, cpu = found
    return (
        f"| {name} | {status} | {depth} | {sequences} | {checks} | {optimisations} | {ik_calls} | {cpu:.2f} | "
        f"{checks / cpu:.0f} |"
    )


def compared_row(
    before: tuple[str, str, str, int, int, int, int, float], after: tuple[str, str, str, int, int, int, int, float]
) -> str:
    """One row of the comparison: whether the two searches did the same work, and what it cost each."""
    name, cpu_before, cpu_after = before[0], before[7], after[7]
    same = "yes" if before[1:7] == after[1:7] else "no"
    return (
        f"| {name} | {before[1]} -> {after[1]} | {same} | {before[3]} -> {after[3]} | {before[4]} -> {after[4]} | "
        f"{cpu_before:.2f} -> {cpu_after:.2f} | {100 * (cpu_after - cpu_before) / cpu_before:+.0f} % |"
    )


def _checking(module: Any) -> Any:
    """The module whose sequence check calls `task_space`: `vkgl.plan.search.check`, or the search module itself
    on a checkout older than that split."""
    try:
        from vkgl.plan.search import check
    except ImportError:
        return module
    return check


def _count_checks(module: Any) -> Callable[[], float]:
    """A clock that reads the search's task-space checks so far (`module.task_space` counted): a deadline of N
    stops the search after its N-th check, at the same sequence whatever the checks cost."""
    real, count = module.task_space, [0]

    def counted(*args: Any, **kwargs: Any) -> Any:
        count[0] += 1
        return real(*args, **kwargs)

    module.task_space = counted
    return lambda: float(count[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="*", default=list(TIMED_OUT), help="generated tasks, by name")
    parser.add_argument("--timeout", type=float, default=20.0, help="per task, CPU seconds (default 20)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    parser.add_argument(
        "--checks",
        type=int,
        help="stop each search after this many task-space checks instead (the same work on any checkout: "
        "the CPU seconds then compare the checks' cost, the counts must agree)",
    )
    parser.add_argument(
        "--against",
        type=Path,
        help="another checkout (its root): each task searched with its code too, and the two compared "
        "(the counts agree when the work is the same: with --checks)",
    )
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        tasks = write_tasks(args.tasks, Path(scratch))
        jobs = [(name, str(path), args.timeout, args.checks, None) for name, path in tasks]
        with ProcessPoolExecutor(max_workers=args.jobs, mp_context=get_context("spawn"), max_tasks_per_child=1) as pool:
            if args.against is None:
                print(HEAD)
                print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
                for found in pool.map(measure, jobs):
                    print(row(found), flush=True)
                return
            print(f"before: {args.against}; after: {REPO}")
            print(COMPARED)
            print("|---|---|---|---:|---:|---:|---:|")
            other = [(*job[:4], str(args.against.resolve())) for job in jobs]
            totals = [0.0, 0.0]
            for before, after in zip(pool.map(measure, other), pool.map(measure, jobs), strict=True):
                totals[0], totals[1] = totals[0] + before[7], totals[1] + after[7]
                print(compared_row(before, after), flush=True)
            change = 100 * (totals[1] - totals[0]) / totals[0]
            print(f"| all | | | | | {totals[0]:.1f} -> {totals[1]:.1f} | {change:+.0f} % |")


if __name__ == "__main__":
    main()
