"""Benchmark: how often does a plan that `vkgc solve` calls solved work in physics, on generated tasks?

    python bench/physical/bench_physical.py [--seed 1] [--count 50] [--jobs 2] [--timeout 20] [--short-pushes]
                                   [--carry] [--json results.json] [--max-depth N] [--only 1,3,16-18]
                                   [--cpu-clock] [--two-faces]

Generates `--count` tasks with `tests/support/task_makers/generated_tasks.py` (bodies,
scenes and goals nobody tuned the planner for; the generated bodies'
affordances are learned once with `vkgl.learn` and cached by body source
hash under `bench/.cache/physical/`; `--short-pushes` explores them with their
short push grid only, without the long `explore slides` pushes; they are
explored on all four side faces, +x, -x, +y and -y, so that a blocker can be
pushed sideways, since 2026-11-27; `--two-faces` explores them on +x and -x
only, as before),
then for each task, in a process pool of
`--jobs` workers: solve it (`vkgl.solve`, `--timeout` s), check a solved plan's
geometry independently (`tests/support/checkers/plan_geometry.py`: bodies pushed
through bodies or the table), carry it out open loop in DART and classify it:

- `solved`: the planner returned a plan;
- `reached`: carried out in DART, every goal held (`report.status`);
- `clean`: reached, and no body the plan leaves still moved by more than 1 cm;
- `disturbed`: a body the plan leaves still ended more than 1 cm from where
  the plan leaves it (report.final against the plan's final poses);
- `colliding`: the geometry check found an overlap deeper than 2 mm;
- `no plan`: the planner said no plan exists (honest infeasible);
- `timeout`, `error`: the solve ran out of time, or something raised;
- `missed`: "no plan", yet a plan exists: solved again with `max_depth` + 4
  (at most 12) and ten times the timeout, a plan is found (`--no-missed`
  skips these re-solves, for speed; a re-solve that times out counts as
  unsettled, listed under the tables).

`--carry` runs the carry family instead (`tests/support/task_makers/carry_tasks.py`): a
body 4 to 8 cm wide that the hand can grasp, 1 to 3 Blocks lying across its
way to a goal 22 to 40 cm off; its size classes are the body's width in cm.

`--max-depth N` solves every task with that max_depth; `--only` solves the
tasks of those indices (all are generated); `--cpu-clock` counts the
timeouts in CPU seconds of the solving worker (`time.process_time`), so that a
loaded machine does not turn slow solves into timeouts. The totals report the
solves' CPU seconds, graphs expanded and optimisations.

Prints one line per task as it finishes (stderr), then Markdown tables by
target kind, size class, clutter count, reach and path, and the totals.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import signal
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from checkers import plan_geometry  # noqa: E402
from task_makers import (  # noqa: E402
    carry_tasks,
    generated_tasks,
)

DISTURBED_M = 0.01
COLUMNS = ("solved", "reached", "clean", "disturbed", "colliding", "no plan", "timeout", "missed", "error")
MISSED_DEPTH = 4
"""The re-solve of a "no plan" searches this many graphs deeper (up to the limit of 12) ..."""
MISSED_TIME = 10.0
"""... with this many times the timeout."""


def execute_plan(program: Any, task_name: str, plan: Any) -> Any:
    """Carry `plan` out open loop in DART."""
    import vkgl

    return vkgl.execute(program, task_name, plan)


def run_task(job: dict[str, Any]) -> dict[str, Any]:
    """Solve, check and execute one generated task; return its metadata and outcome (never raises)."""
    import vkgl

    result: dict[str, Any] = {**job["meta"], "outcome": "error", "reason": "", "findings": []}
    if job.get("cpu_clock"):
        # every deadline of the solve (`time.perf_counter() > deadline`) then counts this worker's CPU seconds:
        # on a loaded machine a wall-clock timeout would cut a search short by however many others share the cores
        time.perf_counter = time.process_time
    try:
        program = vkgl.compile(job["task_file"])
        started, cpu = time.perf_counter(), time.process_time()
        plan = vkgl.solve(program, job["name"], timeout=job["timeout"], max_depth=job.get("max_depth"))
        result["solve_s"] = round(time.perf_counter() - started, 3)
        result["solve_cpu_s"] = round(time.process_time() - cpu, 3)  # what load does not inflate
        result["outcome"] = {"solved": "solved", "infeasible": "no plan", "timeout": "timeout"}[plan.status]
        result["reason"] = (plan.reason or "").splitlines()[0] if plan.reason else ""
        result["arm_path_s"] = plan.details.get("arm_path_time_s")
        result["transit_s"] = plan.details.get("transit_time_s")
        result["search"] = {
            "expanded": plan.stats.get("graphs_expanded"),
            "sequences": plan.details.get("sequences"),
            "pruned_by_bound": plan.details.get("pruned_by_bound"),
            "task_space_checks": plan.stats.get("task_space_checks"),
            "optimisations": plan.details.get("optimisations"),
            "max_depth": plan.details.get("max_depth"),
        }
        if plan.status == "infeasible" and job.get("missed", True):
            result["missed"] = _resolved_deeper(program, job, plan.problem.max_depth)
        if plan.status != "solved":
            return result
        plan_json = plan.to_json()
        result["steps"] = [_step_text(s) for s in plan_json["steps"]]
        result["findings"] = [f.text for f in plan_geometry.check_plan(program, job["name"], plan_json)]
        started = time.perf_counter()
        report = execute_plan(program, job["name"], plan)
        result["execute_s"] = round(time.perf_counter() - started, 1)
        result["execution"] = report.status
        result["reason"] = (report.reason or "").splitlines()[0] if report.reason else ""
        result["disturbed"] = _disturbed(plan_json, report.final)
        result["slip_mm"] = _slip_mm(report)
        result["goal_off"] = _goal_off(report)
    except Exception as exc:  # a benchmark reports every failure and goes on
        result["outcome"] = "error"
        result["reason"] = f"{type(exc).__name__}: {exc}".splitlines()[0]
    return result


def _goal_off(report: Any) -> list[list[float | None]]:
    """How far each goal body ended from its goal in DART: [cm, deg] per goal (None where the goal leaves it
    free), so that plans that end near their tolerance show."""
    return [
        [
            None if g.position_error is None else round(100.0 * g.position_error, 2),
            None if g.yaw_error is None else round(math.degrees(abs(g.yaw_error)), 2),
        ]
        for g in report.goals
    ]


def _slip_mm(report: Any) -> float | None:
    """The largest slip of a held body in the hand over the plan's steps (mm), when the executor measures it
    (a step's `grip`, vkg-execution/5); None otherwise (an executor that welds what it holds)."""
    slips = [step.grip.slip for step in report.steps if getattr(step, "grip", None) is not None]
    return round(1000.0 * max(slips), 2) if slips else None


def _resolved_deeper(program: Any, job: dict[str, Any], depth: int) -> dict[str, Any]:
    """A "no plan" solved again, `MISSED_DEPTH` graphs deeper and with `MISSED_TIME` times the timeout."""
    import vkgl

    deeper = min(12, depth + MISSED_DEPTH)
    started = time.perf_counter()
    plan = vkgl.solve(program, job["name"], timeout=job["timeout"] * MISSED_TIME, max_depth=deeper)
    return {
        "status": plan.status,
        "max_depth": deeper,
        "depth": plan.depth if plan.status == "solved" else None,
        "solve_s": round(time.perf_counter() - started, 2),
    }


def _step_text(step: dict[str, Any]) -> str:
    value = step.get("value", 0.0)
    amount = f" {np.degrees(value):.0f}deg" if step["motion"] == "revolute" else f" {value * 100:.0f}cm"
    amount = "" if step["motion"] == "free" else amount
    return f"{step['op']} {step['affordance']} on {step['body']} with {step['effector']}{amount}"


def _disturbed(plan_json: dict[str, Any], real: dict[str, np.ndarray]) -> dict[str, float]:
    """Bodies the plan leaves where they start but that really ended more than 1 cm away: name -> distance (m)."""
    start = plan_json["steps"][0]["poses_start"]
    final = {**plan_json["steps"][-1]["poses_end"], **(plan_json.get("final") or {})}
    out = {}
    for name, pose in start.items():
        planned = np.asarray(final.get(name, pose))
        if name not in real or not np.allclose(planned, np.asarray(pose), atol=1e-6):
            continue
        moved = float(np.linalg.norm(np.asarray(real[name])[:3, 3] - planned[:3, 3]))
        if moved > DISTURBED_M:
            out[name] = round(moved, 3)
    return out


def flags(result: dict[str, Any]) -> dict[str, bool]:
    """The table's columns for one task."""
    solved = result["outcome"] == "solved"
    # the executor's own "disturbed" is a reached goal with a bystander moved (vkg-execution's status)
    reached = solved and result.get("execution") in ("reached", "disturbed")
    disturbed = solved and (bool(result.get("disturbed")) or result.get("execution") == "disturbed")
    return {
        "solved": solved,
        "reached": reached,
        "clean": reached and not disturbed,
        "disturbed": disturbed,
        "colliding": solved and bool(result["findings"]),
        "no plan": result["outcome"] == "no plan",
        "timeout": result["outcome"] == "timeout",
        "missed": (result.get("missed") or {}).get("status") == "solved",
        "error": result["outcome"] == "error",
    }


def table(results: list[dict[str, Any]], title: str, key: Callable[[dict[str, Any]], str]) -> str:
    """A Markdown table of the columns, one row per value of `key`, and a total row."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for r in results:
        groups.setdefault(key(r), []).append(r)
    head = f"| {title} | tasks | " + " | ".join(COLUMNS) + " | median solve s |"
    lines = [head, "|" + "---|" * (len(COLUMNS) + 3)]
    for name in sorted(groups):
        lines.append(_row(name, groups[name]))
    lines.append(_row("**all**", results))
    return "\n".join(lines)


def _row(name: str, rows: list[dict[str, Any]]) -> str:
    counts = {c: sum(flags(r)[c] for r in rows) for c in COLUMNS}
    times = [r["solve_s"] for r in rows if "solve_s" in r and r["outcome"] == "solved"]
    median = f"{statistics.median(times):.2f}" if times else "-"
    return f"| {name} | {len(rows)} | " + " | ".join(str(counts[c]) for c in COLUMNS) + f" | {median} |"


def report_text(results: list[dict[str, Any]]) -> str:
    """All the tables: by kind, size class, clutter count, reach, path; then the rates."""
    results = sorted(results, key=lambda r: r["index"])
    parts = [
        table(results, "target kind", lambda r: r["kind"]),
        table(results, "size class", lambda r: f"{r['size_class']}"),
        table(results, "clutter", lambda r: str(r["clutter"])),
        table(results, "reach", lambda r: r["reach"]),
        table(results, "straight path", lambda r: "blocked" if r["in_path"] else "clear"),
    ]
    n = len(results)
    total = {c: sum(flags(r)[c] for r in results) for c in COLUMNS}
    solved = max(total["solved"], 1)
    parts.append(
        f"{n} tasks: {total['solved']} solved ({100 * total['solved'] / n:.0f} %); of the solved, "
        f"{total['reached']} reached in physics ({100 * total['reached'] / solved:.0f} %), "
        f"{total['clean']} reached without disturbing another body ({100 * total['clean'] / solved:.0f} %), "
        f"{total['colliding']} colliding plans ({100 * total['colliding'] / solved:.0f} %)."
    )
    cpu = [r["solve_cpu_s"] for r in results if r.get("solve_cpu_s") is not None]
    if cpu:
        searched = [r["search"] for r in results if r.get("search")]
        parts.append(
            f"Search effort over all tasks: {sum(cpu):.1f} s of CPU in the solves (`time.process_time`, not inflated "
            f"by load; median {statistics.median(cpu):.2f} s), {sum(s['expanded'] or 0 for s in searched)} graphs "
            f"expanded, {sum(s.get('optimisations') or 0 for s in searched)} optimisations."
        )
    arm = [1000 * r["arm_path_s"] for r in results if r["outcome"] == "solved" and r.get("arm_path_s") is not None]
    if arm:
        parts.append(
            f"The arm's straight moves and contact chains, planned in the search: median {statistics.median(arm):.0f} "
            f"ms per solved task (max {max(arm):.0f} ms; every candidate the search checked, not only the plan's)."
        )
    transit = [1000 * r["transit_s"] for r in results if r["outcome"] == "solved" and r.get("transit_s") is not None]
    if transit:
        parts.append(
            f"Transit planning, after the search (the candidates it found): median "
            f"{statistics.median(transit):.0f} ms per solved task (max {max(transit):.0f} ms)."
        )
    slips = [r["slip_mm"] for r in results if r.get("slip_mm") is not None]
    if slips:
        parts.append(
            f"Grasp slip (the largest of a held body in the hand, per task, {len(slips)} tasks measured): median "
            f"{statistics.median(slips):.2f} mm, max {max(slips):.2f} mm."
        )
    again = [r for r in results if r.get("missed")]
    if again:
        unsettled = [r["name"] for r in again if r["missed"]["status"] == "timeout"]
        found = [f"{r['name']} (depth {r['missed']['depth']})" for r in again if r["missed"]["status"] == "solved"]
        parts.append(
            f'Each "no plan" solved again {MISSED_DEPTH} graphs deeper with {MISSED_TIME:g} times the timeout: '
            f"{len(again)} re-solved, {len(found)} missed plans"
            + (f" ({', '.join(found)})" if found else "")
            + f", {len(unsettled)} unsettled (the re-solve timed out)"
            + (f": {', '.join(unsettled)}" if unsettled else "")
            + "."
        )
    return "\n\n".join(parts)


def progress_line(r: dict[str, Any]) -> str:
    """One line per finished task."""
    what = f"{r['name']}  {r['kind']:5s} {r['size_class']:4s} clutter {r['clutter']} {r['reach']:8s}"
    what += " blocked" if r["in_path"] else " clear  "
    outcome = r["outcome"]
    if outcome == "solved":
        outcome = f"solved {r.get('solve_s', 0):.1f}s ({r.get('solve_cpu_s', 0):.1f}s CPU) -> {r.get('execution', '?')}"
        if r.get("disturbed"):
            outcome += " disturbed " + ",".join(r["disturbed"])
        if r["findings"]:
            outcome += f" | {len(r['findings'])} overlaps: {r['findings'][0]}"
        if r.get("slip_mm") is not None:
            outcome += f" slip {r['slip_mm']:.2f} mm"
        for cm, deg in r.get("goal_off") or ():
            outcome += (
                " off" + (f" {cm:.2f} cm" if cm is not None else "") + (f" {deg:.2f} deg" if deg is not None else "")
            )
    elif r.get("solve_cpu_s") is not None:
        outcome += f" ({r['solve_cpu_s']:.1f}s CPU, {(r.get('search') or {}).get('expanded')} expanded)"
    if r.get("missed"):
        outcome += f" [deeper: {r['missed']['status']} in {r['missed']['solve_s']}s]"
    if r.get("reason") and r.get("execution") != "reached":
        outcome += f" | {r['reason'][:140]}"
    return f"{what}  {outcome}"


def _indices(text: str) -> set[int]:
    """`1,3,16-18` as {1, 3, 16, 17, 18}."""
    out: set[int] = set()
    for part in text.split(","):
        first, _, last = part.partition("-")
        out.update(range(int(first), int(last or first) + 1))
    return out


def _end_workers_on_sigterm() -> None:
    """A SIGTERM (`timeout`, a killed shell) ends the solving workers too, not only this process."""

    def end(signum: int, frame: Any) -> None:
        children = multiprocessing.active_children()
        for child in children:
            child.terminate()
        for child in children:
            child.join(1.0)
            if child.is_alive():
                child.kill()
        os._exit(128 + signum)

    signal.signal(signal.SIGTERM, end)


def main(argv: list[str] | None = None) -> int:
    """Generate, run, print."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1, help="the generator's seed (default 1)")
    parser.add_argument("--count", type=int, default=50, help="how many tasks (default 50)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--timeout", type=float, default=20.0, help="solve timeout per task, s (default 20)")
    parser.add_argument("--max-depth", type=int, help="max_depth for every task (default: the task's own, else vkgl's)")
    parser.add_argument(
        "--cpu-clock",
        action="store_true",
        help="time the solves' timeouts in CPU seconds of their worker (a fair count on a loaded machine)",
    )
    parser.add_argument(
        "--only", type=_indices, help="solve only these tasks, by index (e.g. 1,3,16-18); all are generated"
    )
    parser.add_argument("--out", type=Path, help="folder for the generated tasks (default: a temporary one)")
    parser.add_argument(
        "--cache", type=Path, default=REPO / "bench" / ".cache" / "physical", help="learned affordances"
    )
    parser.add_argument(
        "--short-pushes",
        action="store_true",
        help="explore the generated bodies with their short push grid only (no long `explore slides` block)",
    )
    parser.add_argument(
        "--two-faces",
        action="store_true",
        help="explore the generated bodies on +x and -x only (a blocker slides along its own x), not on all four",
    )
    parser.add_argument("--four-faces", action="store_true", help="the default (kept for old command lines)")
    parser.add_argument(
        "--no-missed", action="store_true", help='do not solve each "no plan" again deeper and longer (faster)'
    )
    parser.add_argument("--carry", action="store_true", help="the carry family: graspable bodies, Blocks in their way")
    parser.add_argument("--json", type=Path, help="also write every task's result here")
    parser.add_argument("--from-json", type=Path, help="print the tables of a --json file again; run nothing")
    args = parser.parse_args(argv)
    _end_workers_on_sigterm()
    if args.from_json:
        print(report_text(json.loads(args.from_json.read_text())))
        return 0
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or Path(scratch)
        started = time.perf_counter()
        if args.carry:
            specs = [carry_tasks.carry_spec(args.seed, i) for i in range(args.count)]
            generated = [(carry_tasks.write_carry_task(spec, out), spec.name, spec.metadata()) for spec in specs]
        else:
            tasks = generated_tasks.generate_tasks(
                args.seed,
                args.count,
                out,
                cache=args.cache,
                jobs=args.jobs,
                long_slides=not args.short_pushes,
                faces=generated_tasks.TWO_FACES if args.two_faces else generated_tasks.FOUR_FACES,
            )
            generated = [(t.task_file, t.name, t.spec.metadata()) for t in tasks]
        print(f"generated {len(generated)} tasks in {time.perf_counter() - started:.0f} s", file=sys.stderr)
        jobs = [
            {
                "task_file": str(path),
                "name": name,
                "timeout": args.timeout,
                "max_depth": args.max_depth,
                "cpu_clock": args.cpu_clock,
                "missed": not args.no_missed,
                "meta": meta,
            }
            for path, name, meta in generated
            if args.only is None or meta["index"] in args.only
        ]
        results: list[dict[str, Any]] = []
        with ProcessPoolExecutor(max_workers=args.jobs, mp_context=get_context("spawn")) as pool:
            futures = [pool.submit(run_task, job) for job in jobs]
            for future in as_completed(futures):
                result = future.result()
                results.append(result)
                print(f"[{len(results):3d}/{len(jobs)}] {progress_line(result)}", file=sys.stderr, flush=True)
        wall = time.perf_counter() - started
    if args.json:
        args.json.write_text(json.dumps(sorted(results, key=lambda r: r["index"]), indent=1) + "\n")
    explored = ", the carry family" if args.carry else ", short push grid only" if args.short_pushes else ""
    explored += ", two faces" if args.two_faces and not args.carry else ""
    depth = f", max_depth {args.max_depth}" if args.max_depth else ""
    depth += ", timeouts in CPU s" if args.cpu_clock else ""
    print(
        f"## bench_physical: seed {args.seed}, {len(jobs)} of {args.count} tasks{explored}{depth}, {args.jobs} jobs, "
        f"{wall:.0f} s wall\n"
    )
    print(report_text(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
