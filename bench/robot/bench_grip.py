"""Benchmark: can DART hold a tool between two pressed fingers, and how much grip do the tasks' tools use?

    python bench/robot/bench_grip.py [--fingers | --tasks-only] [TASK.vkg ...]

`--fingers` (the measurement behind `vkgl.execute.grip.model`): a hand driven
kinematically like the execution's arm, with two 15 g fingers on prismatic
joints pressed by their joints' force, grasps the stdlib Stick at its handle
on the table, lifts it 10 cm, holds it 1 s and carries it 20 cm sideways. For
each time step, finger force, pad friction and contact solver it prints how
far the fingers sink into the stick (per side), how much the opening jitters
while held, how far the stick slides and turns in the grip, and the wall time.

The tasks (default: the paper's tool tasks b, c, e, f): the planner's plan of
each task carried out in DART, open loop; for every step with a tool in hand
the grip's peak load (the fraction of what the fingers' friction carries) and
the tool's slip in the hand.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
TOOL_TASKS = ["b_stick_push", "c_hook_pull", "e_rotate_stick_push", "f_rotate_hook_pull"]
PAD = (0.02, 0.018, 0.023)  # m: a finger pad box along the hand's x, y (thickness), z
CASES = [  # time step (s), finger force (N), pad friction, solver
    (0.001, 20.0, 1.0, "nsgs"),
    (0.001, 70.0, 1.0, "nsgs"),
    (0.001, 5.0, 1.0, "nsgs"),
    (0.00025, 20.0, 1.0, "nsgs"),
    (0.001, 20.0, 1.0, "dantzig"),
    (0.00025, 20.0, 1.0, "dantzig"),
]


def _hand(world, hand_pose: np.ndarray, mu: float):
    import dartpy as dart

    from vkgl.shapes import isometry

    skeleton = dart.dynamics.Skeleton("hand")
    root, hand = skeleton.createFreeJointAndBodyNodePair()
    inertia = dart.dynamics.Inertia()
    inertia.setMass(0.7)
    inertia.setMoment(1e-3 * np.eye(3))
    hand.setInertia(inertia)
    root.setPositions(dart.dynamics.FreeJoint.convertToPositions(isometry(hand_pose)))
    root.setActuatorType(dart.dynamics.ActuatorType.VELOCITY)
    skeleton.setGravity(np.zeros(3))
    fingers = []
    for sign in (1.0, -1.0):
        joint, finger = hand.createPrismaticJointAndBodyNodePair()
        joint.setAxis(np.array([0.0, sign, 0.0]))
        joint.setLimitEnforcement(True)
        joint.setPositionLowerLimit(0, 0.0)
        joint.setPositionUpperLimit(0, 0.04)
        offset = np.eye(4)
        offset[1, 3] = sign * PAD[1] / 2  # closed (0), the pads' inner faces meet on y = 0
        shape = finger.createShapeNode(dart.dynamics.BoxShape(np.array(PAD)))
        shape.setRelativeTransform(isometry(offset))
        shape.createCollisionAspect()
        shape.createDynamicsAspect().setFrictionCoeff(mu)
        finger_inertia = dart.dynamics.Inertia()
        finger_inertia.setMass(0.015)
        finger_inertia.setMoment(1e-6 * np.eye(3))
        finger.setInertia(finger_inertia)
        joint.setActuatorType(dart.dynamics.ActuatorType.FORCE)
        joint.setPosition(0, 0.02)
        fingers.append(joint)
    world.addSkeleton(skeleton)
    return skeleton, hand, fingers


def hold_stick(dt: float, force: float, mu: float, solver: str) -> dict[str, float]:
    """Grasp, lift, hold and carry the stdlib Stick with force-driven fingers; what DART did."""
    from scipy.spatial.transform import Rotation

    from vkgl.execute.world_arm import drive_body
    from vkgl.lang.compiler import compile_file
    from vkgl.sim import world as sim_world

    stick = compile_file(str(REPO / "examples" / "tasks" / "b_stick_push.vkg")).bodies["Stick"]
    # the friction cone (NSGS) of every simulated scene, or the boxed LCP (Dantzig) of the grasp trials
    world = sim_world.new_world(dt) if solver == "nsgs" else sim_world.new_grasp_world(dt)
    sim_world.add_table(world)
    stick_pose = np.eye(4)
    stick_pose[2, 3] = 0.01
    _, node = sim_world.add_body(world, "stick", stick, stick_pose)
    effector = stick_pose.copy()
    effector[0, 3] = -0.15  # its handle; the hand points down (the effector frame's z up)
    flip = np.eye(4)
    flip[:3, :3] = Rotation.from_euler("x", np.pi).as_matrix()
    skeleton, hand, fingers = _hand(world, effector @ flip, mu)

    def step() -> None:
        for finger in fingers:
            finger.setCommand(0, -force)
        world.step(False)

    for _ in range(round(0.3 / dt)):  # close
        step()
    grasp = np.linalg.inv(node.getWorldTransform().matrix()) @ hand.getWorldTransform().matrix()
    gaps: list[float] = []
    slips: list[float] = []
    turns: list[float] = []

    def record() -> None:
        gaps.append(fingers[0].getPosition(0) + fingers[1].getPosition(0))
        now = np.linalg.inv(node.getWorldTransform().matrix()) @ hand.getWorldTransform().matrix()
        slips.append(float(np.linalg.norm(now[:3, 3] - grasp[:3, 3])))
        turns.append(float(np.degrees(Rotation.from_matrix(now[:3, :3] @ grasp[:3, :3].T).magnitude())))

    def move(shift: np.ndarray, speed: float) -> None:
        start = hand.getWorldTransform().matrix()
        periods = max(1, int(np.ceil(np.linalg.norm(shift) / speed / 0.02)))
        for k in range(1, periods + 1):
            s = k / periods
            target = start.copy()
            target[:3, 3] += shift * (3 * s * s - 2 * s**3)
            drive_body(skeleton, hand, target, 0.02)
            for _ in range(round(0.02 / dt)):
                step()
                record()
        skeleton.getRootJoint().setCommands(np.zeros(6))

    started = time.perf_counter()
    move(np.array([0.0, 0.0, 0.10]), 0.1)
    held_from = len(gaps)
    for _ in range(round(1.0 / dt)):
        step()
        record()
    held = np.array(gaps[held_from:])
    move(np.array([0.2, 0.0, 0.0]), 0.3)
    width = 0.02  # the stick's
    return {
        "sink_mm": (width - min(gaps)) * 500,
        "jitter_mm": float(held.max() - held.min()) * 1000,
        "slip_mm": max(slips) * 1000,
        "turn_deg": max(turns),
        "wall_s": time.perf_counter() - started,
    }


def fingers_table() -> None:
    """The finger-grip measurement, one row per case."""
    print("| time step | finger force | pads' mu | solver | sink per side | opening jitter | slip | turn | wall |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dt, force, mu, solver in CASES:
        r = hold_stick(dt, force, mu, solver)
        print(
            f"| {dt * 1000:g} ms | {force:g} N | {mu:g} | {solver} | {r['sink_mm']:.1f} mm | {r['jitter_mm']:.1f} mm "
            f"| {r['slip_mm']:.1f} mm | {r['turn_deg']:.1f} deg | {r['wall_s']:.1f} s |",
            flush=True,
        )


def tasks_table(paths: list[Path]) -> None:
    """The grip of every step with a tool in hand, in the planner's plan of each task, open loop."""
    from vkgl.execute.closed_loop import execute
    from vkgl.lang.compiler import compile_file
    from vkgl.plan.solve import solve

    print("| task | status | step | tool | peak load | slip | broke |")
    print("|---|---|---|---|---|---|---|")
    for path in paths:
        program = compile_file(str(path))
        task = program.task()
        plan = solve(program, task)
        if plan.status != "solved":
            print(f"| {task.name} | {plan.status} | | | | | |")
            continue
        report = execute(program, task.name, plan.document())
        for step in report.steps:
            g = step.grip
            if g is None:
                continue
            print(
                f"| {task.name} | {report.status} | {step.index}: {step.title} | {g.tool} | {g.peak_load * 100:.0f} % "
                f"| {g.slip * 1000:.2f} mm, {np.degrees(g.slip_angle):.2f} deg | {g.broke or '-'} |",
                flush=True,
            )


def main(argv: list[str] | None = None) -> int:
    """Print the tables asked for (both by default)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("tasks", nargs="*", type=Path, help="task files for --tasks (default: b, c, e, f)")
    parser.add_argument("--fingers", action="store_true", help="only the finger-grip measurement")
    parser.add_argument("--tasks-only", dest="tasks_only", action="store_true", help="only the tasks' grip")
    args = parser.parse_args(argv)
    if not args.tasks_only:
        fingers_table()
    if not args.fingers:
        print()
        tasks_table(args.tasks or [REPO / "examples" / "tasks" / f"{name}.vkg" for name in TOOL_TASKS])
    return 0


if __name__ == "__main__":
    sys.path[:0] = [str(REPO)]
    sys.exit(main())
