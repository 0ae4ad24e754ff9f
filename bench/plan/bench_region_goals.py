"""Region goals against the pose goal at the region's centre: contacts (robot-object transitions) and solve time.

Run on demand: `PYTHONPATH=. python bench/plan/bench_region_goals.py`. For each case, the task of
examples/scenes/tabletop.vkg is solved twice: `goal block in region R [yaw Q]` and `goal block at C [yaw Q]`
with C the centre of R (the same tolerances). Prints one table: the contacts (ADD steps) and depth of each
plan, and the solve time (one run each; the search is deterministic). The issue's claim is that a region goal
never needs more contacts than the pose goal at its centre, and fewer on some example.
"""

from __future__ import annotations

import time
from pathlib import Path

from vkgl.api import solve
from vkgl.lang.compiler import compile_source

REPO = Path(__file__).resolve().parents[2]
HEADER = """use "examples/scenes/tabletop.vkg"
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.affordances.hook
use stdlib.tools
"""

# (name, region corners (x0, y0, x1, y1) m, heading or None); the block starts at (0.45, 0) m, yaw 0, 10 x 20 cm
CASES = [
    ("k: off-centre tray, square", (0.55, -0.16, 0.75, 0.12), "0deg"),
    ("ahead, heading free", (0.55, -0.16, 0.75, 0.12), None),
    ("wide strip ahead", (0.58, -0.3, 0.7, 0.3), None),
    ("tray ahead and left", (0.56, -0.05, 0.8, 0.2), None),
    ("centred tray", (0.60, -0.12, 0.72, 0.12), "0deg"),
]


def _run(goal: str) -> tuple[int | None, int | None, float]:
    search = "search { max_depth 6  timeout 60 s }"
    text = HEADER + f"task t {{\n    scene tabletop\n    goal {goal} within 1 cm, 3deg\n    {search}\n}}\n"
    program = compile_source(text, "bench.vkg", base_dir=REPO)
    started = time.perf_counter()
    plan = solve(program)
    elapsed = time.perf_counter() - started
    if plan.status != "solved":
        return None, None, elapsed
    return sum(1 for s in plan.steps if s.op == "add"), plan.depth, elapsed


def main() -> None:
    print("| case | region goal: contacts (depth) | time s | pose goal at centre: contacts (depth) | time s |")
    print("|---|---|---|---|---|")
    for name, (x0, y0, x1, y1), yaw in CASES:
        heading = f" yaw {yaw}" if yaw else ""
        region = _run(f"block in region ({x0}, {y0}) to ({x1}, {y1}) m{heading}")
        centre = _run(f"block at ({(x0 + x1) / 2:.4f}, {(y0 + y1) / 2:.4f}) m{heading}")
        shown = [f"{c} ({d})" if c is not None else "no plan" for c, d, _ in (region, centre)]
        print(f"| {name} | {shown[0]} | {region[2]:.2f} | {shown[1]} | {centre[2]:.2f} |")


if __name__ == "__main__":
    main()
