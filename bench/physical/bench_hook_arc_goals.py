"""The hook pulling bodies along arcs to goals with a heading: where DART puts them against where the plan says.

The arcs (a slide's `arc` family, docs/language.md "Arcs") were learned from exploration's point fingertip; the
Hook pulls with its flat 16 cm cross-piece. For the stdlib Block and generated types (their learned fixtures,
`tests/bench/learned/`), alone on the table at (0.88, 0.05) m (beyond the fingertip's reach from the far face, so
that only the hook pulls it toward the base), goals pulled 12 to 20 cm toward the base and turned 10 to 25 deg
either way (within 1 cm and 3 deg: the planner offers the one arc member that ends nearest, `vkgl.plan.problem.arcs`).
Each goal is solved (`vkgl.solve`, 20 s) and, when the plan is a hook pull along an arc, carried out open loop in
DART (`vkgl.execute`). Printed per goal: the member (its offset), the planned turn, and how far the body ended from
the plan's final pose in DART (cm, deg); then the largest and median errors.

    PYTHONPATH=$PWD .venv/bin/python bench/physical/bench_hook_arc_goals.py [--bodies Block,CubeM] [--no-execute]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]

from task_makers import generated_tasks  # noqa: E402

import vkgl  # noqa: E402

START = (0.88, 0.05)
"""m: where each body rests (yaw 0): its +x face out of the fingertip's reach."""

GOALS = ((-0.12, 10.0), (-0.12, -10.0), (-0.10, 20.0), (-0.10, -20.0), (-0.15, 35.0), (-0.15, -35.0))
"""(slide along x in m, heading change in deg) of each goal."""


def task_text(body: str, uses: str, dx: float, dyaw: float) -> str:
    """A task with `body` at `START`, the Hook and the Stick on the table, its goal slid `dx` and turned `dyaw`."""
    return (
        "use stdlib.robots.panda\nuse stdlib.bodies.stick\nuse stdlib.bodies.hook\n"
        "use stdlib.affordances.stick\nuse stdlib.affordances.hook\nuse stdlib.tools\n"
        f"{uses}\n"
        "scene alone {\n"
        "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n"
        "    robot arm : Panda at (0, 0, 0) m\n"
        f"    it : {body} on table at ({START[0]}, {START[1]}) m yaw 0deg\n"
        "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"
        "    hook : Hook on table at (0.3, 0.4) m yaw 0deg\n"
        "}\n\n"
        "task hook_arc {\n"
        "    scene alone\n"
        f"    goal it at ({START[0] + dx:.3f}, {START[1]}) m yaw {dyaw:g}deg within 1 cm, 3deg\n"
        "    search { max_depth 6  timeout 20 s }\n"
        "}\n"
    )


def _yaw(pose: np.ndarray) -> float:
    return math.degrees(math.atan2(pose[1, 0], pose[0, 0]))


def _hook_arc(plan: vkgl.Plan) -> str | None:
    """The affordance of the plan's hook pull along an arc (`NAME@+S.SScm`), or None if it has none."""
    for step in plan.to_json()["steps"]:
        if step["effector"] == "hook.tip" and "@" in step["affordance"] and "/straight" not in step["affordance"]:
            return str(step["affordance"])
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", default="Block,CubeS,CubeM,SlabN", help="comma-separated body types")
    parser.add_argument("--no-execute", action="store_true", help="solve only")
    args = parser.parse_args(argv)
    errors: list[tuple[float, float]] = []
    print(f"{'body':6} {'goal':>13} {'plan':>44} {'turn':>7} {'DART off':>16} {'status':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.bodies.split(","):
            folder = Path(tmp) / name
            folder.mkdir()
            uses = generated_tasks.body_uses(name, folder)
            for dx, dyaw in GOALS if uses is not None else ():
                task = folder / "task.vkg"
                task.write_text(task_text(name, uses, dx, dyaw), encoding="utf-8")  # type: ignore[arg-type]
                program = vkgl.compile(task)
                plan = vkgl.solve(program, "hook_arc")
                goal = f"{dx * 100:+.0f}cm {dyaw:+.0f}deg"
                arc = _hook_arc(plan) if plan.status == "solved" else None
                if arc is None:
                    shown = plan.status if plan.status != "solved" else f"no hook arc (depth {plan.depth})"
                    print(f"{name:6} {goal:>13} {shown:>44}", flush=True)
                    continue
                turn = _yaw(plan.final["it"]) - _yaw(plan.start["it"])
                if args.no_execute:
                    print(f"{name:6} {goal:>13} {arc:>44} {turn:+6.1f}d", flush=True)
                    continue
                report = vkgl.execute(program, "hook_arc", plan)
                real, planned = report.final["it"], plan.final["it"]
                off = float(np.linalg.norm(real[:2, 3] - planned[:2, 3])) * 100
                dturn = abs(math.remainder(math.radians(_yaw(real) - _yaw(planned)), math.tau))
                errors.append((off, math.degrees(dturn)))
                print(
                    f"{name:6} {goal:>13} {arc:>44} {turn:+6.1f}d {off:6.2f} cm {math.degrees(dturn):5.2f} d "
                    f"{report.status:>9}",
                    flush=True,
                )
    if errors:
        offs, turns = zip(*errors, strict=True)
        print(
            f"\n{len(errors)} hook arcs in DART: off the plan by median {statistics.median(offs):.2f} cm, "
            f"{statistics.median(turns):.2f} deg; at most {max(offs):.2f} cm, {max(turns):.2f} deg"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
