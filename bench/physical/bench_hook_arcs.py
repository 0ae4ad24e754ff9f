"""Hook pulls along a slide's arc against DART: does the hook's cross-piece carry a body along the point's arc?

A slide's arc family (`family ... arc lever L bias B ahead A`) was fitted on exploration's point pushes; the planner
lets the hook pull such a member (`NAME@+S.SScm`), whose cross-piece lies flat along the face, 16 cm of it. Here
the generated SlabW and CrateM lie alone with the stdlib tools at (0.85, BEARING) m, and the goal (heading free) is
where the member of the far face's slide (`push_center_nx`) at offset S, turned T deg, leaves the body, by the law.
Each is solved (`vkgl.solve`, depth 3: wield, pull) and carried out open loop in DART (`vkgl.execute`). Printed
per pull: the member the planner chose, its turn, where the plan ends against the law's point (cm), and where
DART's body ends against the plan (cm, deg).

    PYTHONPATH=$PWD:tests/support .venv/bin/python bench/physical/bench_hook_arcs.py [--offsets 6,9,12] [--turn 40]
        [--bodies SlabW,CrateM]
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

from task_makers import generated_tasks as g  # noqa: E402

import vkgl  # noqa: E402


def yaw_of(pose: np.ndarray) -> float:
    """The heading (deg) of a world pose."""
    return math.degrees(math.atan2(pose[1, 0], pose[0, 0]))


def pull(body: str, offset: float, turn: float, folder: Path) -> str:
    """Solve and carry out one hook pull along the member at `offset` (m) turned `turn` (deg); one line."""
    from vkgl.lang.ir.families import at_offset
    from vkgl.plan.graphs.rollout import motion_matrix
    from vkgl.plan.problem.problem import build_problem

    tools = tuple(g.Placement(n, t.name, x, y, a) for n, t, x, y, a in g.TOOLS)
    target = g.Placement("target", body, 0.85, 0.0, 0.0)
    library = g.fixture_library((body,))
    probe = g.TaskSpec("probe", 0, 0, (target, *tools), (0.85, 0.0, None), "far-pull", False, 0.0)
    program = vkgl.compile(g.write_task(probe, folder / "probe", library))
    problem = build_problem(program, program.tasks["probe"])
    rest = problem.bodies["target"].rest
    law = rest @ motion_matrix(
        at_offset(problem.affordance("target", "push_center_nx"), offset).motion, math.radians(turn)
    )
    goal = (round(float(law[0, 3]), 4), round(float(law[1, 3]), 4), None)
    spec = g.TaskSpec("arc", 0, 0, (target, *tools), goal, "far-pull", False, 0.0)
    program = vkgl.compile(g.write_task(spec, folder / "arc", library))
    plan = vkgl.solve(program, "arc", max_depth=3)
    if plan.status != "solved":
        return f"{plan.status}: {plan.reason.splitlines()[0][:120] if plan.reason else ''}"
    step = plan.steps[-1]
    planned = step.poses_end["target"]
    report = vkgl.execute(program, "arc", plan)
    real = report.final["target"]
    off_cm = float(np.linalg.norm(planned[:2, 3] - real[:2, 3])) * 100
    off_deg = abs((yaw_of(planned) - yaw_of(real) + 180) % 360 - 180)
    from_law = float(np.linalg.norm(planned[:2, 3] - law[:2, 3])) * 100
    turned = step.motion == "revolute"
    moved = f"turned {math.degrees(step.value):.1f} deg" if turned else f"slid {step.value * 100:.1f} cm"
    return (
        f"{step.affordance} {moved} (plan {from_law:.2f} cm from the law's point); "
        f"DART {report.status}, {off_cm:.2f} cm and {off_deg:.2f} deg from the plan"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--offsets", default="6,9,12", help="cm along the face toward the hook's shaft")
    parser.add_argument("--turn", type=float, default=40.0, help="deg")
    parser.add_argument("--bodies", default="SlabW,CrateM")
    args = parser.parse_args(argv)
    cpu = time.process_time()
    with tempfile.TemporaryDirectory() as tmp:
        for body in args.bodies.split(","):
            for offset in (float(s) / 100 for s in args.offsets.split(",")):
                line = pull(body, offset, args.turn, Path(tmp) / f"{body}{offset}")
                print(f"{body} at +{offset * 100:.2f} cm, {args.turn:.0f} deg: {line}", flush=True)
    print(f"{time.process_time() - cpu:.0f} s of CPU in this process")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
