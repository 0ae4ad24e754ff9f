"""Goals that change a body's heading by 10 to 20 deg while sliding it 10 to 15 cm: depth, and clean in DART.

For the stdlib Block and every generated type (tests/support/generated_tasks.py, their learned fixtures
`tests/bench/learned/`), alone on the tabletop at (0.45, 0) m, four goals: slid 10 or 15 cm along +x and turned
by -10, +15 or -20 deg (a seeded choice). Each is solved (`vkgl.solve`, 20 s) and, when solved, carried out open
loop in DART (`vkgl.execute`). Prints per body the goals solved, the depths, how many reached their goal in DART,
and the median depth over the solved ones.

    PYTHONPATH=$PWD .venv/bin/python bench/bench_heading.py [--execute]

`VKG_REPO` names another checkout whose fixtures and code to use (to measure the main branch with the same
goals: `VKG_REPO=/path/to/main PYTHONPATH=/path/to/main python bench/bench_heading.py`).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

REPO = Path(os.environ.get("VKG_REPO", Path(__file__).resolve().parents[1]))
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

import generated_tasks  # noqa: E402

import vkgl  # noqa: E402

GOALS = ((0.10, -10.0), (0.12, 15.0), (0.15, -20.0), (0.13, 12.0))
"""(slide along +x in m, heading change in deg) of each goal."""


def task_text(body: str, affordances: str, dx: float, dyaw: float) -> str:
    """A one-body task: `body` at (0.45, 0) m, goal slid `dx` and turned `dyaw`."""
    return (
        "use stdlib.robots.panda\n"
        f"{affordances}\n"
        "scene alone {\n"
        "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n"
        "    robot arm : Panda at (0, 0, 0) m\n"
        f"    it : {body} on table at (0.45, 0) m yaw 0deg\n"
        "}\n\n"
        "task turn_and_slide {\n"
        "    scene alone\n"
        f"    goal it at ({0.45 + dx:.3f}, 0) m yaw {dyaw:g}deg within 1 cm, 3deg\n"
        "    search { max_depth 6  timeout 20 s }\n"
        "}\n"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--execute", action="store_true", help="carry each plan out in DART")
    args = parser.parse_args(argv)
    names = ["Block", *(t.name for t in generated_tasks.GENERATED_TYPES)]
    depths: list[int] = []
    print(f"{'body':7} {'goals solved':>12} {'depths':>14} {'clean in DART':>13}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            folder = Path(tmp) / name
            folder.mkdir()
            uses = generated_tasks.body_uses(name, folder)
            solved, found, clean = 0, [], 0
            for dx, dyaw in GOALS if uses is not None else ():
                task = folder / "task.vkg"
                task.write_text(task_text(name, uses, dx, dyaw), encoding="utf-8")  # type: ignore[arg-type]
                program = vkgl.compile(task)
                plan = vkgl.solve(program, "turn_and_slide")
                if plan.status != "solved":
                    found.append("-")
                    continue
                solved += 1
                found.append(str(plan.depth))
                depths.append(int(plan.depth))  # type: ignore[arg-type]
                if args.execute:
                    clean += vkgl.execute(program, "turn_and_slide", plan).status == "reached"
            shown = f"{clean}/{solved}" if args.execute else "-"
            print(f"{name:7} {solved:>9}/{len(GOALS)} {' '.join(found) or 'no affordance':>14} {shown:>13}", flush=True)
    median = statistics.median(depths) if depths else float("nan")
    print(f"\nsolved {len(depths)}; median depth {median:g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
