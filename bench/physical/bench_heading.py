"""Goals that change a body's heading by 10 to 20 deg while sliding it 10 to 15 cm: depth, and clean in DART.

For the stdlib Block and every generated type (tests/support/task_makers/generated_tasks.py, their learned fixtures
`tests/bench/learned/`), alone on the tabletop at (0.45, 0) m, four goals: slid 10 or 15 cm along +x and turned
by -10, +15 or -20 deg (a seeded choice). Each is solved (`vkgl.solve`, 20 s) and, when solved, carried out open
loop in DART (`vkgl.execute`). Prints per body the goals solved, the depths, how many reached their goal in DART,
and the median depth over the solved ones.

    PYTHONPATH=$PWD .venv/bin/python bench/physical/bench_heading.py [--execute]

`VKG_REPO` names another checkout whose fixtures and code to use (to measure the main branch with the same
goals: `VKG_REPO=/path/to/main PYTHONPATH=/path/to/main python bench/physical/bench_heading.py`).
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

GOALS = ((0.10, 0.0, -10.0), (0.12, 0.0, 15.0), (0.15, 0.0, -20.0), (0.13, 0.0, 12.0))
"""(slide along +x in m, aside in m, heading change in deg) of each goal."""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--execute", action="store_true", help="carry each plan out in DART")
    args = parser.parse_args(argv)
    depths: list[int] = []
    print(f"{'body':7} {'goals solved':>12} {'depths':>14} {'clean in DART':>13}")
    for name, solves in each_body_solved("turn_and_slide", GOALS):
        solved, found, clean = 0, [], 0
        for one in solves:
            if one.plan.status != "solved":
                found.append("-")
                continue
            solved += 1
            found.append(str(one.plan.depth))
            depths.append(int(one.plan.depth))  # type: ignore[arg-type]
            if args.execute:
                clean += vkgl.execute(one.program, "turn_and_slide", one.plan).status == "reached"
        shown = f"{clean}/{solved}" if args.execute else "-"
        print(f"{name:7} {solved:>9}/{len(GOALS)} {' '.join(found) or 'no affordance':>14} {shown:>13}", flush=True)
    median = statistics.median(depths) if depths else float("nan")
    print(f"\nsolved {len(depths)}; median depth {median:g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
