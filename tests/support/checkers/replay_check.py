"""An independent check of a `vkg-plan/8` plan: recompute everything from the JSON, the program and the URDF.

Nothing here imports the planner. Poses are recomposed from the affordances
(scipy for the rotations), the arm's forward kinematics comes from DART
loading the URDF named in the plan, with the base and effector offset the plan
states (`contact_chain_check.DartFK`). Along every contact chain the hand holds
the moving body rigidly (`contact_chain_check`). `check_plan` returns a list of
problems (empty when the plan is right).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from checkers.contact_chain_check import DartFK, check_contact_chains, motion
from vkgl.lang.ir.geometry import scene_body_anchor, scene_body_pose
from vkgl.lang.ir.nodes import FixedC
from vkgl.lang.ir.program import Program

POSE_TOL = 1e-6  # m / rad: recomposed poses agree with the plan's to this
HAND_TOL = 2e-3  # m: FK of the plan's joints puts the hand this close to where it must be
AXIS_TOL = np.radians(1.0)  # the hand's z axis is this close to where it must point
PAD_RADIUS = 0.005  # m: the fingertip pad's radius (its axis runs along the effector's y, this far behind the origin)
MAX_LEAN = np.radians(60.0)  # a pushing hand may lean back about the pad's axis by up to this much


def check_plan(program: Program, plan_json: dict[str, Any]) -> list[str]:
    """Every way the plan breaks its promises (see the module docstring); empty when it keeps them."""
    plan = json.loads(json.dumps(plan_json))  # only what survives JSON
    task = program.tasks[plan["task"]]
    scene = program.scenes[task.scene.name]
    types = {sb.name: program.bodies[sb.type.name] for sb in scene.bodies}
    poses = {sb.name: scene_body_pose(scene, sb, types[sb.name]) for sb in scene.bodies}
    rest = {sb.name: scene_body_anchor(scene, sb, types[sb.name]) for sb in scene.bodies}  # joints' zero
    fk = DartFK(plan["robot"])
    robot_effector = f"{plan['robot']['name']}.{plan['robot']['effector']}"
    problems: list[str] = []
    held: dict[str, np.ndarray] = {}  # tool -> grasp (hand in the tool's frame)
    for k, step in enumerate(plan["steps"], start=1):
        start = {n: np.array(m) for n, m in step["poses_start"].items()}
        end = {n: np.array(m) for n, m in step["poses_end"].items()}
        for name, pose in poses.items():  # continuity: only held tools move between steps
            if name not in held and not np.allclose(start[name], pose, atol=POSE_TOL):
                problems.append(f"step {k}: {name} jumps between steps")
        for q in (step["q_start"], step["q_end"]):
            if np.any(np.array(q) < fk.lower - 1e-9) or np.any(np.array(q) > fk.upper + 1e-9):
                problems.append(f"step {k}: joints outside the URDF limits")
        aff = _affordance(program, step["affordance"])
        action = aff.action.pose.matrix() if isinstance(aff.action, FixedC) and aff.action.pose else np.eye(4)
        problems += _check_step(k, step, aff, action, start, end, held, types, fk, robot_effector)
        for name in poses:
            if name not in held and name != step["body"] and not np.allclose(start[name], end[name], atol=POSE_TOL):
                problems.append(f"step {k}: {name} moves though the step does not move it")
        if aff.motion.type == "free":
            if step["op"] == "add":
                held[step["body"]] = action
            else:
                held.pop(step["body"], None)
        poses = end
    final = {n: np.array(m) for n, m in plan["final"].items()}
    problems += check_contact_chains(program, plan, fk)
    problems += _check_goals(task, final)
    problems += _check_joint_goals(task, final, rest, types)
    return problems


def _check_step(
    k: int,
    step: dict[str, Any],
    aff: Any,
    action: np.ndarray,
    start: dict[str, np.ndarray],
    end: dict[str, np.ndarray],
    held: dict[str, np.ndarray],
    types: dict[str, Any],
    fk: DartFK,
    robot_effector: str,
) -> list[str]:
    out = []
    body, value = step["body"], step["value"]
    if step["motion"] != aff.motion.type:
        out.append(f"step {k}: motion {step['motion']} but {step['affordance']} allows {aff.motion.type}")
    if value < 0:
        out.append(f"step {k}: negative motion value {value}")
    moves = step["op"] == "add" and aff.motion.type in ("prismatic", "revolute")
    expected = start[body] @ motion(aff.motion, value) if moves else start[body]
    if body not in held and not np.allclose(end[body], expected, atol=POSE_TOL):
        out.append(f"step {k}: {body} does not end where {step['affordance']} by {value} puts it")
    for name, grasp in held.items():  # held tools stay in the hand (a released one only until it is let go)
        released = step["op"] == "remove" and name == body
        for pose, q in ((start[name], step["q_start"]), *(() if released else ((end[name], step["q_end"]),))):
            out += _hand_at(k, f"holding {name}", fk(q), pose @ grasp, yaw_matters=True)
    if step["op"] != "add":
        return out
    owner, _, frame = step["effector"].partition(".")
    for pose, q in ((start[body], step["q_start"]), (expected, step["q_end"])):
        contact = pose @ action
        if step["effector"] == robot_effector and aff.motion.type != "free":
            out += _pad_at(k, f"touching {body}", fk(q), contact)
        elif step["effector"] == robot_effector:
            out += _hand_at(k, f"touching {body}", fk(q), contact, yaw_matters=True)
        else:
            tool_frame = types[owner].frame(frame).pose.matrix()
            tool_pose = start[owner] if pose is start[body] else end[owner]
            if not np.allclose(tool_pose @ tool_frame, contact, atol=1e-6):
                out.append(f"step {k}: {step['effector']} does not touch {body} where {step['affordance']} says")
    return out


def _hand_at(k: int, what: str, hand: np.ndarray, target: np.ndarray, *, yaw_matters: bool) -> list[str]:
    error = np.linalg.norm(hand[:3, 3] - target[:3, 3])
    if error > HAND_TOL:
        return [f"step {k}: the hand is {error * 1000:.1f} mm away while {what}"]
    if yaw_matters:
        angle = Rotation.from_matrix(hand[:3, :3].T @ target[:3, :3]).magnitude()
    else:
        angle = np.arccos(np.clip(hand[:3, 2] @ target[:3, 2], -1, 1))
    return [f"step {k}: the hand is turned {np.degrees(angle):.1f} deg off while {what}"] if angle > AXIS_TOL else []


def _pad_at(k: int, what: str, hand: np.ndarray, target: np.ndarray) -> list[str]:
    """The fingertip pad touches as the affordance's action says: the pad's axis (the effector's y through a
    point `PAD_RADIUS` behind its origin) where the action puts it, the hand upright (its yaw free) or leaned
    back about that axis by at most `MAX_LEAN` (the planner leans it to clear a tall face)."""
    tilt = np.arccos(np.clip(hand[:3, 2] @ target[:3, 2], -1, 1))
    if tilt <= AXIS_TOL:
        return _hand_at(k, what, hand, target, yaw_matters=False)  # upright: the pad's yaw about the vertical is free
    behind = np.array([-PAD_RADIUS, 0.0, 0.0, 1.0])
    error = np.linalg.norm((hand @ behind)[:3] - (target @ behind)[:3])
    if error > HAND_TOL:
        return [f"step {k}: the pad is {error * 1000:.1f} mm away while {what}"]
    along = np.arccos(np.clip(abs(hand[:3, 1] @ target[:3, 1]), -1, 1))
    if along > AXIS_TOL or tilt > MAX_LEAN + AXIS_TOL:
        return [f"step {k}: the hand is turned {np.degrees(tilt):.1f} deg off while {what}"]
    return []


def _check_goals(task: Any, final: dict[str, np.ndarray]) -> list[str]:
    out = []
    for goal in task.goals:
        pose = final[goal.body.name]
        tol_p, tol_y = goal.tolerance()
        if goal.position is not None:
            target = np.asarray(goal.position.values)
            if np.linalg.norm(pose[: len(target), 3] - target) > tol_p:
                out.append(f"{goal.body.name} misses its goal position")
        if goal.yaw is not None:
            yaw = np.arctan2(pose[1, 0], pose[0, 0])
            if abs((yaw - goal.yaw.value + np.pi) % (2 * np.pi) - np.pi) > tol_y:
                out.append(f"{goal.body.name} misses its goal heading")
    return out


def joint_goal_problems(program: Program, plan_json: dict[str, Any]) -> list[str]:
    """The joint goals a plan's final poses miss (only those: the rest of `check_plan` is not run)."""
    plan = json.loads(json.dumps(plan_json))
    task = program.tasks[plan["task"]]
    scene = program.scenes[task.scene.name]
    types = {sb.name: program.bodies[sb.type.name] for sb in scene.bodies}
    rest = {sb.name: scene_body_anchor(scene, sb, types[sb.name]) for sb in scene.bodies}  # joints' zero
    final = {n: np.array(m) for n, m in plan["final"].items()}
    return _check_joint_goals(task, final, rest, types)


def _check_joint_goals(
    task: Any, final: dict[str, np.ndarray], rest: dict[str, np.ndarray], types: dict[str, Any]
) -> list[str]:
    """`goal B open Q`: B's joint coordinate (from where the scene places it, `rest`: along or about the joint's
    axis) is within tolerance."""
    out = []
    for goal in task.goals:
        if goal.opening is None:
            continue
        name = goal.body.name
        joint = types[name].joint
        axis = np.asarray(joint.axis.values, dtype=float) / np.linalg.norm(joint.axis.values)
        start, end = rest[name], final[name]
        if joint.type == "prismatic":
            state = axis @ (start[:3, :3].T @ (end[:3, 3] - start[:3, 3]))
        else:
            state = axis @ Rotation.from_matrix(start[:3, :3].T @ end[:3, :3]).as_rotvec()
        if abs(state - goal.opening.value) > goal.opening_tolerance():
            out.append(f"{name} opens {state:.4f}, not {goal.opening.value:.4f} within {goal.opening_tolerance()}")
    return out


def _affordance(program: Program, dotted: str) -> Any:
    """The affordance a step names: `Type.name`, or `Type.name@+1.25cm`, the member of `name`'s family at that
    offset, recomposed here (docs/language.md, "Families"): the action's position moved along the family's
    direction, a turn's pivot by the offset times its drift."""
    type_name, _, name = dotted.partition(".")
    base, mark, rest = name.partition("@")
    aff = next(a for a in program.affordances[type_name] if a.name == base)
    if not mark:
        return aff
    offset = float(rest.removesuffix("cm")) / 100.0
    family = aff.family
    assert family is not None and family.lower.value - 5e-5 <= offset <= family.upper.value + 5e-5, dotted
    along = np.array(family.along.values) / np.linalg.norm(family.along.values)
    pose = aff.action.pose
    position = pose.position.model_copy(update={"values": tuple(np.array(pose.position.values) + offset * along)})
    action = aff.action.model_copy(update={"pose": pose.model_copy(update={"position": position})})
    motion = aff.motion
    if family.drift is not None and motion.type == "revolute":
        center = tuple(np.array(motion.center.values) + offset * np.array(family.drift.values))
        motion = motion.model_copy(update={"center": motion.center.model_copy(update={"values": center})})
    return aff.model_copy(update={"action": action, "motion": motion})
