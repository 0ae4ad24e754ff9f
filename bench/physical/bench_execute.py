"""Benchmark: execute every example task's plan in DART, open loop and closed loop.

    python bench/physical/bench_execute.py [--gif DIR] [--disturb DY,DYAW] [TASK.vkg ...]

For each task: solve it with the planner, replay the plan open loop
(the plan as planned) and closed loop (re-solving when a body strays by more
than half the tolerance), and print one Markdown table with the goal errors,
the number of replans, the simulated duration and the wall time of the
replay, and the grip on a held tool (its peak load, the tool's largest slip
in the hand). `wall/sim` is the cost of the open-loop replay per simulated second
(the target is < 5 on 2 cores); re-solving time is reported apart.

A second table does the same with a disturbed start: the block really lies
DY metres to the side and DYAW degrees turned from where the planner was told
(default 0.005,1), so the open-loop plan goes wrong and the closed loop has to
re-solve from what it observes. In the tasks on drawers and doors (a joint
goal, no block) the goal body's joint starts elsewhere instead: a slide DQ
centimetres further open, a hinge DQ' degrees nearer its lower limit (or
further open when it starts there), `--disturb-joint DQ,DQ'` (default 3,10).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


def _errors(report) -> str:
    joints = [g.opening for g in report.goals if g.opening is not None]
    if joints:  # a joint goal: how far off its coordinate is
        return ", ".join(
            f"{abs(o.error) * 100:.2f} cm" if o.joint == "prismatic" else f"{np.degrees(abs(o.error)):.2f} deg"
            for o in joints
        )
    pos = max((g.position_error or 0.0) for g in report.goals) * 100
    yaw = max(abs(np.degrees(g.yaw_error or 0.0)) for g in report.goals)
    return f"{pos:5.2f} cm {yaw:5.2f} deg"


def _grip(report) -> str:
    """The largest load on the grip of a held tool (the fraction of what the fingers' friction carries) and the
    largest slip of the tool in the hand, over the steps; `-` without a tool."""
    grips = [s.grip for s in report.steps if s.grip is not None]
    if not grips:
        return "-"
    slip = max(g.slip for g in grips) * 1000
    broke = " (broke)" if any(g.broke for g in grips) else ""
    return f"{max(g.peak_load for g in grips) * 100:.0f} %, {slip:.2f} mm{broke}"


def _plan(program, task: str):
    """The planner's plan as a vkg-plan/1 document (`vkgl.formats.plan.PlanDocument`)."""
    from vkgl.plan.solve import solve

    return solve(program, program.task(task)).document()


def _disturbed(program, task_name: str, dy: float, dyaw_deg: float, joint: tuple[float, float] = (3.0, 10.0)):
    """The program with the block `dy` m to the side and `dyaw_deg` turned (the world the robot really meets);
    in a task with a joint goal, its body's joint moved by `joint` (cm for a slide, deg for a hinge)."""
    from scipy.spatial.transform import Rotation

    from vkgl.lang.ir.geometry import joint_pose, scene_body_anchor, scene_body_pose

    task = program.task(task_name)
    scene = program.scenes[task.scene.name]
    jointed = next((g.body.name for g in task.goals if g.opening is not None), None)
    if jointed is not None:
        placed = next(b for b in scene.bodies if b.name == jointed)
        kind = program.bodies[placed.type.name]
        start = placed.start_opening()
        if kind.joint.type == "prismatic":
            value = start + joint[0] / 100
        else:
            value = start - np.radians(joint[1]) if start > kind.joint.lower.value else start + np.radians(joint[1])
        return program.with_start_poses(
            task, {jointed: joint_pose(kind.joint, scene_body_anchor(scene, placed, kind), value)}
        )
    block = next(b for b in scene.bodies if b.name == "block")
    pose = scene_body_pose(scene, block, program.bodies[block.type.name])
    error = np.eye(4)  # in the block's own frame: sideways along its y, turned about its centre
    error[:3, :3] = Rotation.from_euler("z", dyaw_deg, degrees=True).as_matrix()
    error[:3, 3] = [0.0, dy, 0.0]
    return program.with_start_poses(task, {"block": pose @ error})


def bench_task(
    path: Path, gif_dir: Path | None, disturb: tuple[float, float], joint: tuple[float, float] = (3.0, 10.0)
) -> tuple[list[str], list[str]]:
    """Two table rows (nominal start, disturbed start): solve, then execute open and closed loop."""
    from vkgl.api import resolver
    from vkgl.execute.closed_loop import execute
    from vkgl.lang.compiler import compile_file

    program = compile_file(str(path))
    task = program.task()
    started = time.perf_counter()
    plan = _plan(program, task.name)
    solve_s = time.perf_counter() - started
    if not plan.solved:
        return [task.name, plan.status] + [""] * 9, [task.name, plan.status] + [""] * 9
    rows = []
    for kind, world in (("", program), ("_disturbed", _disturbed(program, task.name, *disturb, joint))):
        opened = execute(world, task.name, plan, record=gif_dir is not None)
        closed = execute(world, task.name, plan, replan=True, record=gif_dir is not None, resolve=resolver)
        if gif_dir is not None:
            from vkgl.execute.animate import animate

            animate(opened, gif_dir / f"{task.name}{kind}_open.gif")
            animate(closed, gif_dir / f"{task.name}{kind}_closed.gif")
        rows.append(
            [
                task.name,
                f"{len(plan.steps)} ({solve_s:.1f} s)",
                f"{opened.status} {_errors(opened)}",
                f"{opened.sim_time:.1f}",
                f"{opened.wall_time:.1f}",
                f"{opened.wall_time / max(opened.sim_time, 1e-9):.2f}",
                f"{closed.status} {_errors(closed)}",
                str(closed.replans),
                f"{closed.sim_time:.1f}",
                f"{closed.wall_time - closed.solve_time:.1f} + {closed.solve_time:.1f}",
                _grip(opened),
            ]
        )
    return rows[0], rows[1]


def _table(title: str, rows: list[list[str]]) -> None:
    header = [
        "task",
        "steps (solve)",
        "open loop: status, goal error",
        "sim s",
        "wall s",
        "wall/sim",
        "closed loop: status, goal error",
        "replans",
        "sim s",
        "wall s (+ solve s)",
        "open loop: grip peak load, slip",
    ]
    print(f"\n{title}\n")
    print("| " + " | ".join(header) + " |")
    print("|" + "|".join("---" for _ in header) + "|")
    for row in rows:
        print("| " + " | ".join(row) + " |")


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the tables; exit 1 if a closed-loop run from the nominal start misses."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tasks", nargs="*", type=Path, help="task files (default: examples/tasks/*.vkg)")
    parser.add_argument("--gif", type=Path, metavar="DIR", help="also write open- and closed-loop animations")
    parser.add_argument(
        "--disturb",
        default="0.005,1",
        metavar="DY,DYAW",
        help="block start error for the second table: metres sideways, degrees (default 0.005,1)",
    )
    parser.add_argument(
        "--disturb-joint",
        default="3,10",
        metavar="DQ,DQ'",
        help="start error of a joint goal's body for the second table: cm on a slide, deg on a hinge (default 3,10)",
    )
    args = parser.parse_args(argv)
    disturb = tuple(float(v) for v in args.disturb.split(","))
    joint = tuple(float(v) for v in args.disturb_joint.split(","))
    tasks = args.tasks or sorted((REPO / "examples" / "tasks").glob("*.vkg"))
    if args.gif is not None:
        args.gif.mkdir(parents=True, exist_ok=True)
    nominal, disturbed = [], []
    for path in tasks:
        row, row_disturbed = bench_task(path, args.gif, disturb, joint)  # type: ignore[arg-type]
        nominal.append(row)
        disturbed.append(row_disturbed)
        print(
            f"{row[0]}: {row[2]} | {row[6]};  disturbed: {row_disturbed[2]} | {row_disturbed[6]}",
            file=sys.stderr,
            flush=True,
        )
    _table("Nominal start (the world is what the planner was told)", nominal)
    _table(
        f"Disturbed start (block {disturb[0] * 100:g} cm sideways, {disturb[1]:g} deg turned; a drawer "
        f"{joint[0]:g} cm further open, a door {joint[1]:g} deg)",
        disturbed,
    )
    return 1 if any(not row[6].startswith("reached") for row in nominal) else 0


if __name__ == "__main__":
    sys.path[:0] = [str(REPO), str(REPO / "tests" / "support")]  # plan_script: the test suite's scripted plans
    sys.exit(main())
