"""Write a `vkg-plan/8` plan from a script of steps, by kinematics alone (no search).

    from plan_script import scripted_plan
    plan = scripted_plan(program, "a_push", ["add Block.push_center_px block arm.fingertip 0.15"])
    # a vkgl.formats.plan.PlanDocument; vkgl.formats.plan.to_json(plan) is its vkg-plan/8 JSON

The planner (`vkgl.plan.solve`) finds the steps; this module only carries out
given ones on paper: each pushed body moves by its affordance's motion
(prismatic: along the axis; revolute: about the axis through the centre), a
held tool moves rigidly with the effector, and the arm's joints come from its
IK. It exists so that execution can be checked (and deliberately wrong plans
written) independently of the search, the way another tool would write them:
through `vkgl.formats.plan`, the one definition of the format.

A script step is `OP AFFORDANCE BODY EFFECTOR [VALUE]` (value in metres or
radians; a tuple of the same five items works too), e.g.
`add Stick.wield stick arm.fingertip`, `add Block.push_center_px block stick.tip 0.25`,
`remove Block.push_center_px block stick.tip`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.errors import InputError
from vkgl.formats.plan import PlanDocument, PlanRobot, PlanStats, PlanStepRecord
from vkgl.lang.ir.geometry import resting_height, scene_body_pose, table_top
from vkgl.lang.ir.nodes import Affordance, FixedC, FreeC, PrismaticC, RevoluteC, Task
from vkgl.lang.ir.program import Program

EXAMPLE_SCRIPTS: dict[str, list[str]] = {
    # The plans of the paper's six tasks (examples/tasks/) as scripts over the stdlib affordances: execution
    # is checked with them when the planner is absent. The turns and the
    # pushes after them are the planner's values (tests/formats/golden), rounded: where a turn about the
    # learned pivot leaves the block decides how far the push must go.
    "a_push": ["add Block.push_center_px block arm.fingertip 0.15"],
    "b_stick_push": ["add Stick.wield stick arm.fingertip", "add Block.push_center_px block stick.tip 0.25"],
    "c_hook_pull": ["add Hook.wield hook arm.fingertip", "add Block.push_center_nx block hook.tip 0.30"],
    "d_rotate_push": [
        "add Block.turn_px_left block arm.fingertip 0.3655",  # 20.9 deg
        "remove Block.turn_px_left block arm.fingertip",
        "add Block.push_center_px block arm.fingertip 0.0882",
    ],
    "e_rotate_stick_push": [
        "add Block.turn_px_left block arm.fingertip 0.3671",  # 21.0 deg
        "remove Block.turn_px_left block arm.fingertip",
        "add Stick.wield stick arm.fingertip",
        "add Block.push_center_px block stick.tip 0.4369",
    ],
    "f_rotate_hook_pull": [
        "add Hook.wield hook arm.fingertip",
        "add Block.turn_nx_left block hook.tip 0.3746",  # 21.5 deg
        "remove Block.turn_nx_left block hook.tip",
        "add Block.push_center_nx block hook.tip 0.2377",
    ],
}


@dataclass
class _State:
    """The kinematic state the script walks through."""

    poses: dict[str, np.ndarray]
    q: np.ndarray
    held: str | None = None
    grasp: np.ndarray | None = None  # effector frame in the held tool's frame
    edges: dict[str, tuple[str, str]] = field(default_factory=dict)  # body -> (effector, motion type) while attached


def _parse_step(raw: str | tuple) -> tuple[str, str, str, str, float]:
    items = raw.split() if isinstance(raw, str) else list(raw)
    if len(items) not in (4, 5) or items[0] not in ("add", "remove"):
        raise InputError(f"script step {raw!r}: expected `add|remove AFFORDANCE BODY EFFECTOR [VALUE]`")
    value = float(items[4]) if len(items) == 5 else 0.0
    return items[0], items[1], items[2], items[3], value


def _affordance(program: Program, name: str) -> Affordance:
    type_name, _, aff_name = name.partition(".")
    for aff in program.affordances.get(type_name, []):
        if aff.name == aff_name:
            return aff
    raise InputError(f"script step: the program has no affordance {name}")


def affordance_motion(aff: Affordance, body_start: np.ndarray, value: float) -> np.ndarray:
    """The body's end pose after its affordance's motion by `value` (m or rad) from `body_start`."""
    motion = aff.motion
    local = np.eye(4)
    if isinstance(motion, PrismaticC):
        axis = motion.axis.array() / np.linalg.norm(motion.axis.array())
        local[:3, 3] = value * axis
    elif isinstance(motion, RevoluteC):
        axis = motion.axis.array() / np.linalg.norm(motion.axis.array())
        centre = motion.center.array()
        rotation = Rotation.from_rotvec(value * axis).as_matrix()
        local[:3, :3] = rotation
        local[:3, 3] = centre - rotation @ centre
    elif not isinstance(motion, (FixedC, FreeC)):
        raise InputError(f"affordance {aff.name}: cannot script a {motion.type} motion")
    return body_start @ local


def scripted_plan(program: Program, task: str | Task | None, script: list[str | tuple]) -> PlanDocument:
    """A solved `vkg-plan/8` document for `task` made of the scripted steps (see the module docstring).

    Raises InputError for an unknown affordance, body or effector, or when the
    arm has no IK solution for a step's effector pose.
    """
    from vkgl.robot import Arm

    task = task if isinstance(task, Task) else program.task(task)
    scene = program.scenes[task.scene.name]
    scene_robot = scene.robots[0]
    robot = program.robots[scene_robot.type.name]
    effector = robot.effectors[0]
    base = scene_robot.pose.matrix()
    arm = Arm.load(robot, effector.name, base)
    types = {sb.name: program.bodies[sb.type.name] for sb in scene.bodies}
    poses = {sb.name: scene_body_pose(scene, sb, types[sb.name]) for sb in scene.bodies}
    state = _State(poses, np.asarray(arm.home, dtype=float))
    own = f"{scene_robot.name}.{effector.name}"
    steps, graphs = [], [_graph(scene_robot.name, poses, state)]
    for raw in script:
        op, aff_name, body, eff, value = _parse_step(raw)
        if body not in poses:
            raise InputError(f"script step {raw!r}: no body `{body}` in scene {scene.name}")
        aff = _affordance(program, aff_name)
        start = {n: p.copy() for n, p in state.poses.items()}
        q_start = state.q.copy()
        if op == "add":
            q_start, tool_start = _add(state, arm, types, aff, body, eff, own, value, raw)
            start.update(tool_start)  # a held tool starts the step where it touches the body
            state.edges[body] = (eff, aff.motion.type)
        else:
            _remove(state, aff, body, scene, types)
            state.edges.pop(body, None)
        steps.append(
            PlanStepRecord(
                op=op,
                affordance=aff_name,
                body=body,
                effector=eff,
                motion=aff.motion.type,
                value=abs(value),
                poses_start={n: p.copy() for n, p in start.items()},
                poses_end={n: p.copy() for n, p in state.poses.items()},
                q_start=q_start.copy(),
                q_end=state.q.copy(),
            )
        )
        graphs.append(_graph(scene_robot.name, state.poses, state))
    steps = _with_arm_paths(program, task, steps)
    return PlanDocument(
        task=task.name,
        status="solved",
        depth=len(graphs),
        stats=PlanStats(solve_time_s=0.0, graphs_expanded=0, task_space_checks=0, joint_space_checks=0),
        robot=PlanRobot(
            name=scene_robot.name,
            urdf=robot.urdf_resolved or robot.urdf,
            base=base,
            effector=effector.name,
            effector_link=effector.link,
            effector_offset=np.asarray(arm.link_offset, dtype=float),  # FK(q) = base @ link(q) @ effector_offset
            joints=tuple(arm.joint_names),
        ),
        graphs=tuple(graphs),
        steps=tuple(steps),
        final={n: p.copy() for n, p in state.poses.items()},
    )


def _with_arm_paths(program: Program, task: Task, steps: list[PlanStepRecord]) -> list[PlanStepRecord]:
    """The steps with the arm's paths between contacts, planned as the planner plans them (vkg-plan/8)."""
    from vkgl.plan.arm.paths import ArmPathPlanner
    from vkgl.plan.geometry.bodies import GeometryCheck
    from vkgl.plan.problem.problem import build_problem
    from vkgl.plan.problem.rejection import Rejection

    problem = build_problem(program, task)
    planned = ArmPathPlanner(problem, GeometryCheck(problem)).plan(steps)
    if isinstance(planned, Rejection):
        raise InputError(f"script: the arm's paths cannot be planned: {planned.why}")
    return planned


def _graph(robot: str, poses: dict[str, np.ndarray], state: _State) -> tuple[tuple[str, str, str], ...]:
    edges = [(robot, "world", "free")]
    for name in poses:
        if name in state.edges:
            eff, motion = state.edges[name]
            edges.append((eff.partition(".")[0], name, "fixed"))
            edges.append((name, "world", motion))
        else:
            edges.append((name, "world", "fixed"))
    return tuple(edges)


def _ik(arm: Any, hand: np.ndarray, q0: np.ndarray, raw: Any) -> np.ndarray:
    q = arm.ik(hand, q0=q0)
    if q is None:
        q = arm.ik(hand)
    if q is None:
        xyz = ", ".join(f"{v:.3f}" for v in hand[:3, 3])
        raise InputError(f"script step {raw!r}: the arm cannot reach the effector pose at ({xyz}) m")
    return np.asarray(q, dtype=float)


def _add(
    state: _State, arm: Any, types: dict, aff: Affordance, body: str, eff: str, own: str, value: float, raw: Any
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Add the affordance to the state; return the joints at the start of the step (effector in
    place) and the start pose of a held tool that enacts it."""
    action = aff.action.pose.matrix() if isinstance(aff.action, FixedC) and aff.action.pose else np.eye(4)
    if isinstance(aff.motion, FreeC):  # a grasp: the hand goes to the tool's grasp frame
        hand = state.poses[body] @ action
        state.q = _ik(arm, hand, state.q, raw)
        state.held, state.grasp = body, action
        return state.q.copy(), {}
    body_start = state.poses[body]
    body_end = affordance_motion(aff, body_start, value)
    motion = body_end @ np.linalg.inv(body_start)
    owner, _, frame = eff.partition(".")
    pusher_start = body_start @ action
    tool_start = None
    if eff == own:
        hand_start = pusher_start
    elif owner == state.held:
        tool_frame = types[owner].frame(frame)
        if tool_frame is None:
            raise InputError(f"script step {raw!r}: {types[owner].name} has no frame `{frame}`")
        tool_start = pusher_start @ np.linalg.inv(tool_frame.pose.matrix())
        hand_start = tool_start @ state.grasp
        state.poses[owner] = motion @ tool_start
    else:
        raise InputError(f"script step {raw!r}: effector {eff} is neither the robot's nor a held tool's")
    q_start = _ik(arm, hand_start, state.q, raw)
    state.q = _ik(arm, motion @ hand_start, q_start, raw)
    state.poses[body] = body_end
    return q_start, ({owner: tool_start} if eff != own else {})


def _remove(state: _State, aff: Affordance, body: str, scene: Any, types: dict) -> None:
    if isinstance(aff.motion, FreeC) and state.held == body:  # a release: the tool is put down where it is
        pose = state.poses[body].copy()
        yaw = float(Rotation.from_matrix(pose[:3, :3]).as_euler("ZYX")[0])
        flat = np.eye(4)
        flat[:3, :3] = Rotation.from_euler("z", yaw).as_matrix()
        flat[:3, 3] = [pose[0, 3], pose[1, 3], resting_height(types[body], yaw, table_top(scene))]
        state.poses[body] = flat
        state.held, state.grasp = None, None
