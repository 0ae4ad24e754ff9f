"""Goals that turn a body farther than any of its written turns: an arc member whose offset the task space chooses.

For the stdlib Block and every generated type (tests/support/task_makers/generated_tasks.py, their learned fixtures
`tests/bench/learned/`), alone on the tabletop at (0.45, 0) m, four goals that turn it 35 to 50 deg while
moving it 10 to 20 cm, some of them aside (`GOALS`). A written turn of these bodies makes 18 to 31 deg in one
contact, so without an arc such a goal takes two turns and a push (depth 6); an arc member turns it as far as
its open slide lets it, and its offset, a variable of the task-space optimisation (`vkgl.plan.graphs.members`),
fits its arc to wherever an earlier contact left the body. Each goal is solved (`vkgl.solve`, 20 s) and, with
`--execute`, carried out open loop in DART (`vkgl.execute`). Prints per body the depths, how many of the plans
end with an arc member at an offset other than the one the problem offered (the offset moved in the task
space), how many reached their goal in DART, the CPU time of the solves, and the median depth over the solved.

    PYTHONPATH=$PWD .venv/bin/python bench/physical/bench_arc_offsets.py [--execute]

`VKG_REPO` names another checkout whose fixtures and code to use (the main branch, with the same goals:
`VKG_REPO=/path/to/main PYTHONPATH=/path/to/main python bench/physical/bench_arc_offsets.py`).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

REPO = Path(os.environ.get("VKG_REPO", Path(__file__).resolve().parents[2]))
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from task_makers.lone_goals import each_body_solved  # noqa: E402

import vkgl  # noqa: E402
from vkgl.lang.ir.nodes import PrismaticC  # noqa: E402
from vkgl.plan.problem.problem import build_problem  # noqa: E402

GOALS = ((0.15, 0.03, -45.0), (0.20, 0.0, -50.0), (0.10, 0.05, 35.0), (0.12, -0.04, 40.0))
"""(dx, dy in m, heading change in deg) of each goal from the body's rest at (0.45, 0) m."""


def moved_arc(program: vkgl.Program, name: str) -> bool:
    """Whether `name` (a plan step's affordance, without the body type) is a member of a slide's arc family that
    the problem did not offer the goal body (`vkgl.plan.problem.arcs`): its offset moved in the task space."""
    problem = build_problem(program, program.tasks["turn_far"])
    base = name.split("@", 1)[0]
    offered = {a.name for a in problem.bodies["it"].affordances}
    return "@" in name and name not in offered and isinstance(problem.affordance("it", base).motion, PrismaticC)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--execute", action="store_true", help="carry each plan out in DART")
    args = parser.parse_args(argv)
    depths: list[int] = []
    print(f"{'body':7} {'solved':>6} {'depths':>9} {'moved':>5} {'clean in DART':>13} {'CPU s':>6}")
    for name, solves in each_body_solved("turn_far", GOALS):
        solved, found, moved, clean = 0, [], 0, 0
        for one in solves:
            if one.plan.status != "solved":
                found.append("-")
                continue
            solved += 1
            found.append(str(one.plan.depth))
            depths.append(int(one.plan.depth))  # type: ignore[arg-type]
            last = one.plan.steps[-1].affordance.split(".", 1)[1] if one.plan.steps else ""
            moved += moved_arc(one.program, last)
            if args.execute:
                clean += vkgl.execute(one.program, "turn_far", one.plan).status == "reached"
        shown = f"{clean}/{solved}" if args.execute else "-"
        cpu = sum(one.cpu_s for one in solves)
        print(f"{name:7} {solved:>4}/{len(GOALS)} {' '.join(found):>9} {moved:>5} {shown:>13} {cpu:6.1f}", flush=True)
    median = statistics.median(depths) if depths else float("nan")
    print(f"\nsolved {len(depths)}; median depth {median:g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
