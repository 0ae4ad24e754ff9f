"""One grasp trial in DART: the open hand placed at a candidate, the fingers closed with the stated force, the
body lifted (a free body) or pulled along its joint (a drawer, a door), its slip in the hand measured.

The world is exploration's (`vkgl.sim.world`: 1 ms steps, ODE contacts,
friction the smaller of the two surfaces') with the boxed LCP, which holds a
body between two pressed fingers where the friction cone lets it turn
(`vkgl.sim.world.new_grasp_world`): a free body rests on the table, a
body on a joint hangs on it at its lower limit. The hand (`vkgl.sim.grasp.hand`)
starts at the candidate's pose, moved by the trial's `offset` (the hand never
lands exactly where it aims), fingers open. If it overlaps the body or the
table there, the trial is `blocked` and does not run. Otherwise:

1. SETTLE: the body comes to rest under gravity (the hand waits);
2. CLOSE: the fingers close until both have stopped on the body (at most
   CLOSE_TIME), then HOLD_TIME more to let the squeeze build up;
3. the body's pose in the hand is taken as the grasp's;
4. MOVE: the hand lifts by `lift` (straight up), or, on a joint, carries the
   grasp `lift` along the joint's motion (a slide along its axis, a turn about
   its hinge by the angle that moves the grasp point that far), on a
   minimum-jerk profile over MOVE_TIME, then holds still for REST_TIME.

The slip is the largest distance, over steps 3-4, between where points of the
body near the grasp (the pads' middle, and SLIP_ARM from it across the pads
and along the fingers: a body turning in the hand slips there too) are in the
hand and where they were at step 3: contact and friction alone hold the body
(no weld). Points far from the grasp are not used: a door held at its handle
turns about the hinge however firmly it is held. A
trial ends early once the slip passes GIVE_UP (the body is gone), or a smaller
limit the caller gives (the slip past which the grasp will not be kept anyway).
"""

from __future__ import annotations

from typing import Any

import dartpy as dart
import numpy as np

from vkgl.formats.grasp_trials import GraspCandidate, GraspTrial
from vkgl.lang.ir.geometry import shape_mesh
from vkgl.lang.ir.nodes import Body
from vkgl.robot.gripper import Gripper
from vkgl.shapes import translation
from vkgl.sim.grasp.hand import SimHand
from vkgl.sim.world import add_body, add_table, new_grasp_world

SETTLE_TIME = 0.05  # s
CLOSE_TIME = 0.4  # s: the widest opening closes in 0.1 s at the no-load speed
STOPPED = 0.002  # m/s: a finger slower than this has stopped on the body
HOLD_TIME = 0.05  # s
MOVE_TIME = 0.4  # s for the lift or the pull (10 cm: 0.47 m/s at most, 3.6 m/s^2 at most)
REST_TIME = 0.1  # s
GIVE_UP = 0.02  # m of slip: the body has left the hand
OVERLAP = 2e-4  # m: the open hand overlapping something deeper than this has no room
SLIP_ARM = 0.02  # m from the middle of the pads to the points whose slip is measured


def run_grasp_trial(
    body: Body,
    gripper: Gripper,
    candidate: GraspCandidate,
    index: int,
    force: float,
    lift: float,
    offset: np.ndarray,
    give_up: float = GIVE_UP,
) -> GraspTrial:
    """Try `candidate` (number `index`) on `body` once, the hand moved by `offset` (3, effector frame, m); the
    trial stops once the body has slipped more than `give_up` (m) or GIVE_UP, whichever is less."""
    world = new_grasp_world()
    if body.joint is None:
        add_table(world)
        rest = translation(np.array([0.0, 0.0, -float(shape_mesh(body.shape).bounds[0][2])]))
        _, node = add_body(world, "body", body, rest)
    else:
        _, node = add_body(world, "body", body, np.eye(4), joint_position=body.joint.lower.value)
    body_pose = np.asarray(node.getWorldTransform().matrix(), dtype=float)
    start = body_pose @ candidate.pose @ translation(np.asarray(offset, dtype=float))
    hand = SimHand(world, gripper, start, candidate.opening, force)
    if _overlaps(world, hand):
        return GraspTrial(index, blocked=True)
    path = _path(body, node, start, lift)
    return _run(world, hand, node, start, path, candidate.pose, index, min(give_up, GIVE_UP))


def _overlaps(world: Any, hand: SimHand) -> bool:
    # FCL for this one geometric question: ODE's detector (the world's) answers group queries made outside a
    # simulation step with nothing at all
    detector = dart.collision.FCLCollisionDetector()
    mine = detector.createCollisionGroup()
    mine.addShapeFramesOf(hand.skeleton)
    others = detector.createCollisionGroup()
    for i in range(world.getNumSkeletons()):
        skeleton = world.getSkeleton(i)
        if skeleton.getName() != hand.skeleton.getName():
            others.addShapeFramesOf(skeleton)
    option = dart.collision.CollisionOption()
    option.enableContact = True
    option.maxNumContacts = 100
    result = dart.collision.CollisionResult()
    mine.collide(others, option, result)
    return any(result.getContact(i).penetrationDepth > OVERLAP for i in range(result.getNumContacts()))


def _path(body: Body, node: Any, start: np.ndarray, lift: float) -> Any:
    """The hand's effector pose (and velocity) at phase s of the move, 0 to 1: lifted, or carried by the joint."""
    joint = body.joint
    if joint is None:
        return lambda s: (translation(np.array([0.0, 0.0, lift * s])) @ start, np.array([0.0, 0.0, lift]))
    parent = node.getParentJoint()
    frame = np.asarray(parent.getTransformFromParentBodyNode().matrix(), dtype=float)  # joint frame in the world
    axis = frame[:3, :3] @ (joint.axis.array() / np.linalg.norm(joint.axis.array()))
    if joint.type == "prismatic":
        return lambda s: (translation(axis * lift * s) @ start, axis * lift)
    centre = frame[:3, 3]
    radius = float(np.linalg.norm(np.cross(start[:3, 3] - centre, axis)))
    angle = lift / max(radius, 1e-3)

    def turned(s: float) -> tuple[np.ndarray, np.ndarray]:
        turn = np.eye(4)
        turn[:3, :3] = _axis_angle(axis, angle * s)
        about = translation(centre) @ turn @ translation(-centre)
        pose = about @ start
        return pose, np.cross(axis * angle, pose[:3, 3] - centre)

    return turned


def _axis_angle(axis: np.ndarray, angle: float) -> np.ndarray:
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def _run(
    world: Any,
    hand: SimHand,
    node: Any,
    start: np.ndarray,
    path: Any,
    grasp: np.ndarray,
    index: int,
    give_up: float,
) -> GraspTrial:
    dt = world.getTimeStep()
    still = np.zeros(3)
    for _ in range(round(SETTLE_TIME / dt)):
        hand.drive(start, still)
        world.step()
    hand.closing = True
    stopped_for = 0
    for _ in range(round(CLOSE_TIME / dt)):
        hand.drive(start, still)
        world.step()
        stopped_for = stopped_for + 1 if float(np.abs(hand.finger_speeds()).max()) < STOPPED else 0
        if stopped_for * dt >= 0.02:
            break
    for _ in range(round(HOLD_TIME / dt)):
        hand.drive(start, still)
        world.step()
    points = _slip_points(grasp, hand.gripper.pad_box()[0])
    reference = _in_hand(hand, node, points)
    begin = np.asarray(node.getWorldTransform().matrix(), dtype=float)[:3, 3]
    slip = 0.0
    steps = round(MOVE_TIME / dt)
    for k in range(steps + round(REST_TIME / dt)):
        s = min(1.0, (k + 1) / steps)
        target, velocity = path(_min_jerk(s))
        hand.drive(target, velocity * _min_jerk_rate(s) / MOVE_TIME if k < steps else still)
        world.step()
        slip = max(slip, float(np.linalg.norm(_in_hand(hand, node, points) - reference, axis=0).max()))
        if slip > give_up:
            break
    end = np.asarray(node.getWorldTransform().matrix(), dtype=float)[:3, 3]
    return GraspTrial(index, slip=slip, moved=float(np.linalg.norm(end - begin)))


def _slip_points(grasp: np.ndarray, pad_middle: np.ndarray) -> np.ndarray:
    """Where slip is measured (4 x 5, body frame, homogeneous): the middle of the pads and SLIP_ARM from it
    either way across the pads and along the fingers, so that the body turning in the hand counts too."""
    centre = grasp @ np.array([*pad_middle, 1.0])
    arms = [grasp[:3, 0] * SLIP_ARM, -grasp[:3, 0] * SLIP_ARM, grasp[:3, 2] * SLIP_ARM, -grasp[:3, 2] * SLIP_ARM]
    return np.column_stack([centre, *(centre + np.append(a, 0.0) for a in arms)])


def _in_hand(hand: SimHand, node: Any, points: np.ndarray) -> np.ndarray:
    """`points` (4 x n, body frame) in the effector frame (the rigid inverse written out: every step)."""
    world = node.getWorldTransform().matrix() @ points
    effector = hand.pose()
    rotation = effector[:3, :3]
    return rotation.T @ (world[:3] - effector[:3, 3:4])


def _min_jerk(s: float) -> float:
    return s**3 * (10.0 - 15.0 * s + 6.0 * s * s)


def _min_jerk_rate(s: float) -> float:
    return 30.0 * s * s * (1.0 - s) ** 2


__all__ = ["GIVE_UP", "run_grasp_trial"]
