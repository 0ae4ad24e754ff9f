"""Far tasks whose goal leaves the heading free, off the straight push's line: the arc member through the goal.

The physical bench's class "pushed out, heading free, the goal off the push line" (docs/planning.md, "Far tasks
with a clear path that end with no plan"): gen1_005, gen1_017, gen6_017, gen6_025, gen6_037, gen6_049, gen7_005.
For each, the goal body's learned arc families (`vkgl.plan.problem.arcs`): how far the straight push misses the
goal, the member offered (the arc through the goal), its turn to the goal and the contact's travel, and the CPU
time of choosing it (`time.process_time`, the mean of 200 calls). With --solve, each task is solved (`vkgl.solve`,
its own 20 s timeout) and the outcome, depth and the step that uses a member are printed.

    PYTHONPATH=$PWD:tests/support .venv/bin/python bench/physical/bench_arc_free.py [--solve]

The bodies are learned as bench_physical learns them (cached in bench/.cache/physical/).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from task_makers import generated_tasks  # noqa: E402

import vkgl  # noqa: E402
from vkgl.lang.ir.arcs import arc_lever_arm  # noqa: E402
from vkgl.lang.ir.families import member_offset  # noqa: E402
from vkgl.plan.problem.arcs import arc_members  # noqa: E402
from vkgl.plan.problem.problem import build_problem  # noqa: E402

TASKS = ((1, 5), (1, 17), (6, 17), (6, 25), (6, 37), (6, 49), (7, 5))
"""(seed, index) of the class's tasks."""

CALLS = 200


def _straight_miss(rest: np.ndarray, goal: np.ndarray, affordances: tuple) -> float:
    """How far the nearest straight push (a written slide of a face, any length) leaves the goal (m)."""
    misses = [math.inf]
    for a in affordances:
        if a.family is None or a.family.arc is None:
            continue
        push = (rest[:3, :3] @ a.motion.axis.array())[:2]
        push = push / np.linalg.norm(push)
        ahead = max(float(np.dot(goal - rest[:2, 3], push)), 0.0)
        misses.append(float(np.linalg.norm(rest[:2, 3] + ahead * push - goal)))
    return min(misses)


def _row(task_file: Path, solve: bool) -> str:
    program = vkgl.compile(task_file)
    task = next(iter(program.tasks.values()))
    problem = build_problem(program, task)
    goal = problem.goals[0]
    assert goal.position is not None and goal.yaw is None
    body = problem.bodies[goal.body]
    written = tuple(a for a in body.affordances if "@" not in a.name)
    target = goal.position[:2]
    tolerances = (goal.tol_position, goal.tol_yaw)
    members = arc_members(written, body.rest, target, None, tolerances)
    started = time.process_time()
    for _ in range(CALLS):
        arc_members(written, body.rest, target, None, tolerances)
    cpu_ms = (time.process_time() - started) / CALLS * 1e3
    words = []
    for m in members:
        name, offset = member_offset(m.name)
        slide = next(a for a in written if a.name == name)
        assert slide.family is not None and slide.family.arc is not None
        lever = arc_lever_arm(slide.family.arc, offset)
        pivot = m.motion.center.array()  # type: ignore[union-attr]
        world = (body.rest @ np.append(pivot, 1.0))[:2]
        start, end = body.rest[:2, 3] - world, target - world
        turn = abs(math.remainder(math.atan2(end[1], end[0]) - math.atan2(start[1], start[0]), math.tau))
        words.append(f"{m.name} turn {math.degrees(turn):.0f} deg travel {turn * lever * 100:.0f} cm")
    miss = _straight_miss(body.rest, target, written)
    row = (
        f"{task.name:9s} {body.type.name:7s} straight push misses {miss * 100:5.1f} cm"
        f" | {'; '.join(words) or 'no member'} | {cpu_ms:.2f} ms CPU"
    )
    if solve:
        plan = vkgl.solve(program, task.name)
        used = [s.affordance for s in plan.steps if "@" in s.affordance]
        row += f" | {plan.status}" + (f" depth {plan.depth} ({', '.join(used) or 'no member'})" if plan.depth else "")
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--solve", action="store_true", help="also solve each task (20 s each)")
    args = parser.parse_args(argv)
    specs = [generated_tasks.task_spec(seed, index) for seed, index in TASKS]
    types = sorted({t for s in specs for t in s.generated_types()}, key=lambda t: t.name)
    library = generated_tasks.learned_affordances(types, REPO / "bench" / ".cache" / "physical", jobs=1)
    with tempfile.TemporaryDirectory() as scratch:
        for spec in specs:
            print(_row(generated_tasks.write_task(spec, Path(scratch) / spec.name, library), args.solve), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
