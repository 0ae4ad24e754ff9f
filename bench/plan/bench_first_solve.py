"""Benchmark: the paper's six tasks solved in fresh processes, as `vkgc solve` meets them.

    python bench/plan/bench_first_solve.py [--runs 5] [--alone] [--calls]

Each run is a new Python process that imports vkgl, compiles the six example
tasks and solves each once, in the paper's order (a to f), with the collision
checks on: the first solve of each task pays what a process computes once and
keeps (the arm loaded from its URDF, its ready pose, its reach at each new
height, the arm's collision skeleton). `--alone` also solves each task in a
process of its own (each then pays all of that itself).

The arm's reach at each height is kept between processes in the user's
cache folder (`vkgl.formats.reach_cache`): every `vkgc solve` after the first
on a machine reads it. Each measurement is therefore made twice: "cached", in
processes sharing a cache folder that one untimed run filled, as users meet
it; "cold", each process with an empty cache folder of its own, as the very
first run on a machine (or `VKGL_CACHE_DIR=off`) meets it.

Prints Markdown tables of the medians over `--runs` runs: wall time
(`time.perf_counter`) and CPU time of the process (`time.process_time`) per
phase. On a shared machine wall time grows with the load and CPU time much
less: both are printed, with the load average before and after.

`--calls` counts instead of timing: one cached and one cold process solve the
six tasks each under `cProfile` (hash seed 0), and the Python function calls
of each first solve are printed. The counts do not depend on the machine or
its load (the same code and libraries give the same counts), so two commits
are compared by them where CPU seconds, which vary by 15 % and more from run
to run on a shared machine, cannot tell a small change from noise; a callback
from native code (NLopt's objective, say) is a Python call and is counted.

Targets (issue 12): the six first solves together at most 0.5 s; the
transits, planned after the search (`vkgl.plan.arm.paths`: the search's
candidate, the search going on when one fails), are reported separately
(issue 13), and so are the straight moves planned inside the search.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[2]
TASKS = ["a_push", "b_stick_push", "c_hook_pull", "d_rotate_push", "e_rotate_stick_push", "f_rotate_hook_pull"]


def _clock() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


def _since(start: tuple[float, float]) -> list[float]:
    wall, cpu = _clock()
    return [wall - start[0], cpu - start[1]]


def _solve_counted(solve: Any, program: Any) -> tuple[Any, int]:
    """`solve(program)` under `cProfile`: the plan and how many Python function calls it made."""
    profile = cProfile.Profile()
    plan = profile.runcall(solve, program)
    return plan, int(pstats.Stats(profile).total_calls)  # type: ignore[attr-defined]


def child(tasks: list[str], counted: bool = False) -> dict[str, object]:
    """Run in a fresh process: import, compile, first solves; every phase as [wall, cpu] seconds."""
    started = _clock()
    sys.path.insert(0, str(REPO))
    import vkgl.plan.solve  # noqa: F401 - the planner's imports (DART, NLopt, SciPy, trimesh)
    from vkgl.api import solve
    from vkgl.lang.compiler import compile_file

    out: dict[str, object] = {"import": _since(started)}
    started = _clock()
    programs = {name: compile_file(str(REPO / "examples" / "tasks" / f"{name}.vkg")) for name in tasks}
    out["compile"] = _since(started)
    first, arm_paths, transits, calls = {}, {}, {}, {}
    for name in tasks:
        started = _clock()
        if counted:
            plan, calls[name] = _solve_counted(solve, programs[name])
        else:
            plan = solve(programs[name])
        first[name] = _since(started)
        arm_paths[name] = float(plan.details.get("arm_path_time_s", 0.0))
        transits[name] = float(plan.details.get("transit_time_s", 0.0))
        if plan.status != "solved":
            raise SystemExit(f"{name}: {plan.status}: {plan.reason}")
    out["first"] = first
    out["arm_paths"] = arm_paths
    out["transits"] = transits
    out["calls"] = calls
    return out


def _run(tasks: list[str], cache: str | None = None, counted: bool = False) -> dict[str, object]:
    """One fresh process solving `tasks` with the reach cache folder `cache` (None: an empty one); its phases
    (`counted`: under `cProfile`, with hash seed 0, each solve's Python function calls too)."""
    flag = "--child-counted" if counted else "--child"
    seed = {"PYTHONHASHSEED": "0"} if counted else {}
    with tempfile.TemporaryDirectory(prefix="vkgl-bench-cache-") as empty:
        result = subprocess.run(
            [sys.executable, __file__, flag, *tasks],
            capture_output=True,
            text=True,
            check=True,
            cwd=REPO,
            env={**os.environ, "VKGL_CACHE_DIR": cache or empty, **seed},
        )
    return json.loads(result.stdout.strip().splitlines()[-1])  # type: ignore[no-any-return]


def _median(values: list[list[float]]) -> tuple[float, float]:
    return statistics.median(v[0] for v in values), statistics.median(v[1] for v in values)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5, help="fresh processes per measurement (medians reported)")
    parser.add_argument("--alone", action="store_true", help="also solve each task in a process of its own")
    parser.add_argument("--calls", action="store_true", help="count each first solve's Python calls (no timing)")
    parser.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    parser.add_argument("--child-counted", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child or args.child_counted:
        print(json.dumps(child(args.child or args.child_counted, counted=bool(args.child_counted))))
        return 0
    if args.calls:
        _print_calls()
        return 0
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="vkgl-bench-cache-") as shared:
        _run(TASKS, shared)  # fills the cache, untimed
        cached = [_run(TASKS, shared) for _ in range(args.runs)]
        alone = {name: [_run([name], shared) for _ in range(args.runs)] for name in TASKS} if args.alone else {}
    cold = [_run(TASKS) for _ in range(args.runs)]
    load_after = os.getloadavg()[0]
    print(
        f"## Six tasks in one fresh process ({args.runs} runs, medians; {os.cpu_count()} cores, "
        f"load average {load_before:.1f} before, {load_after:.1f} after)\n"
    )
    _phase_table(cached, cold, alone)
    for title, runs in (("cached reach", cached), ("cold: reach computed in the process", cold)):
        total = statistics.median(sum(r["first"][n][0] for n in TASKS) for r in runs)  # type: ignore[index]
        arm = statistics.median(sum(r["arm_paths"].values()) for r in runs)  # type: ignore[attr-defined]
        transit = statistics.median(sum(r["transits"].values()) for r in runs)  # type: ignore[attr-defined]
        print(
            f"\n{title}: of the first solves' {total:.3f} s wall time, the search took {total - transit:.3f} s "
            f"(of which the arm's straight moves and contact chains, by IK, with their checks: {arm:.3f} s, "
            f"`details['arm_path_time_s']`), and the transits planned after it {transit:.3f} s "
            f"(`details['transit_time_s']`)."
        )
    return 0


def _print_calls() -> None:
    """One cached and one cold process under `cProfile`: each first solve's Python function calls."""
    with tempfile.TemporaryDirectory(prefix="vkgl-bench-cache-") as shared:
        _run(TASKS, shared)  # fills the cache, uncounted
        cached = _run(TASKS, shared, counted=True)["calls"]
    cold = _run(TASKS, counted=True)["calls"]
    print("| first solve | cached: Python calls | cold: Python calls |\n|---|---:|---:|")
    for name in TASKS:
        print(f"| {name} | {cached[name]:,} | {cold[name]:,} |")  # type: ignore[index]
    totals = [sum(calls[n] for n in TASKS) for calls in (cached, cold)]  # type: ignore[index]
    print(f"| **six first solves** | **{totals[0]:,}** | **{totals[1]:,}** |")


def _phase_table(cached: list[dict[str, object]], cold: list[dict[str, object]], alone: dict[str, Any]) -> None:
    head = "| phase | cached: wall (s) | cached: CPU (s) | cold: wall (s) | cold: CPU (s) |"
    print(head + (" alone: wall (s) | alone: CPU (s) |" if alone else ""))
    print("|---|---:|---:|---:|---:|" + ("---:|---:|" if alone else ""))
    for phase in ("import", "compile"):
        cells = [_median([r[phase] for r in runs]) for runs in (cached, cold)]  # type: ignore[misc]
        print(f"| {phase} (six tasks) | " + " | ".join(f"{w:.3f} | {c:.3f}" for w, c in cells) + " |")
    for name in TASKS:
        cells = [_median([r["first"][name] for r in runs]) for runs in (cached, cold)]  # type: ignore[index]
        row = f"| first solve {name} | " + " | ".join(f"{w:.3f} | {c:.3f}" for w, c in cells) + " |"
        if alone:
            a_wall, a_cpu = _median([r["first"][name] for r in alone[name]])
            row += f" {a_wall:.3f} | {a_cpu:.3f} |"
        print(row)
    totals = [
        _median([[sum(r["first"][n][k] for n in TASKS) for k in (0, 1)] for r in runs])  # type: ignore[index]
        for runs in (cached, cold)
    ]
    row = "| **first solves, total** | " + " | ".join(f"**{w:.3f}** | **{c:.3f}**" for w, c in totals) + " |"
    if alone:
        alone_totals = [sum(statistics.median(r["first"][n][k] for r in alone[n]) for n in TASKS) for k in (0, 1)]
        row += f" {alone_totals[0]:.3f} | {alone_totals[1]:.3f} |"
    print(row)


if __name__ == "__main__":
    sys.exit(main())
