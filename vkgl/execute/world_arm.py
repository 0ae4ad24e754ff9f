"""The robot in the execution world: an arm from its URDF, driven kinematically.

The arm is a DART skeleton loaded from the robot's URDF, fixed at its base and
*kinematically driven*: every control period the target pose of the effector
frame is turned into joint positions by the arm's inverse kinematics
(`vkgl.robot.Arm.ik`, warm-started at the current joints), and the joints are
given the constant velocities that reach them at the end of the period
(DART's VELOCITY actuators: the arm is not moved by contact forces, it moves
what it touches, like a stiff position-controlled robot).

What touches the world:
- the fingertip: the pad of the closed fingers, a capsule 2 cm wide across
  the push direction (the effector frame's y) with the radius of
  exploration's fingertip (`vkgl.sim.fingertip`), welded to the effector
  link so that its front point is the effector frame's origin: the effector
  frame sits on the contact point as in exploration. A pad rather than a
  point: a point pushing a flat face is unstable (the face turns away from
  it), the pad of a real gripper is not;
- a held tool: the tool's own DART body, switched to a kinematic joint that
  follows the effector frame rigidly while held (the grasp does not slip), and
  switched back to a free, dynamic body when released (the arm passes
  through it until the open hand has left its grip).

The arm's links (their URDF collision shapes) touch the bodies too, but not
the table (the base stands on it) or a tool they hold.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import dartpy as dart
import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.errors import SimulationError
from vkgl.execute.effector_path import Segment
from vkgl.robot.pad import FINGER_PAD_WIDTH, FINGERTIP_RADIUS, pad_pose
from vkgl.shapes import isometry
from vkgl.sim.fingertip import FINGERTIP_FRICTION  # the same fingertip as in exploration

CONTROL_PERIOD = 0.02  # s between two IK solutions
MAX_LINK_STEP = 0.03  # m any link may move in one control period; more means IK switched configuration
JOINT_SPEED = 0.8  # rad/s of the fastest joint in a joint-space move


class ArmStuck(Exception):
    """The arm cannot follow its path (no IK solution, or a jump between configurations)."""


def rx_pi() -> np.ndarray:
    """Rotation by 180 deg about x: turns the link's approach axis (z down) into an effector frame with z up."""
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("x", np.pi).as_matrix()
    return m


@dataclass
class HeldTool:
    """A tool in the hand: its DART body and the effector frame expressed in the tool's frame."""

    name: str
    skeleton: Any
    body_node: Any
    grasp: np.ndarray  # effector frame in the tool frame, as actually grasped


class WorldArm:
    """The arm in a DART world, following effector paths by IK.

    `arm` follows the `vkgl.robot.Arm` contract (`fk`, `ik`, `joint_names`);
    `link_offset` is the effector frame in the effector link's frame
    (offset * Rx(180 deg), the effector frame convention of docs/language.md).
    """

    def __init__(
        self,
        world: Any,
        arm: Any,
        skeleton: Any,
        effector_link: str,
        link_offset: np.ndarray,
        base: np.ndarray,
        q0: np.ndarray,
        *,
        table: Any | None = None,
    ) -> None:
        self.world = world
        self.arm = arm
        self.skeleton = skeleton
        self.link = skeleton.getBodyNode(effector_link)
        if self.link is None:
            raise SimulationError(f"the robot's URDF has no link `{effector_link}` for its effector")
        self.link_offset = np.asarray(link_offset, dtype=float)
        self.joints = [skeleton.getJoint(name) for name in arm.joint_names]
        if any(j is None for j in self.joints):
            missing = [n for n, j in zip(arm.joint_names, self.joints) if j is None]
            raise SimulationError(f"the robot's URDF has no joint(s) {', '.join(missing)}")
        self.dofs = [j.getIndexInSkeleton(0) for j in self.joints]
        self.held: HeldTool | None = None
        self.filter = _world_filter(world)
        self._letting_go: list[Any] = []  # body nodes of tools let go of that the hand has not yet left
        self._groups: dict[tuple[str, str], Any] = {}  # collision groups for `_overlaps`, made when first needed
        self._place_base(base)
        self._make_kinematic()
        self.fingertip = self._add_fingertip()
        world.addSkeleton(skeleton)
        if table is not None:
            for i in range(skeleton.getNumBodyNodes()):
                self.filter.addBodyNodePairToBlackList(skeleton.getBodyNode(i), table)
        self.set_joints(q0)
        self._check_agrees_with_arm(q0)

    # ------------------------------------------------------------ setup

    def _place_base(self, base: np.ndarray) -> None:
        root = self.skeleton.getRootJoint()
        if isinstance(root, dart.dynamics.FreeJoint):
            root.setPositions(dart.dynamics.FreeJoint.convertToPositions(isometry(base)))
            root.setActuatorType(dart.dynamics.ActuatorType.LOCKED)
        else:
            root.setTransformFromParentBodyNode(isometry(base))

    def _make_kinematic(self) -> None:
        for joint in self.joints:
            joint.setActuatorType(dart.dynamics.ActuatorType.VELOCITY)
        # the other joints with degrees of freedom (the Panda's fingers) hold still: a velocity of 0, not moved
        # by contacts (a FORCE joint without gravity would be pushed open by whatever the fingers touch)
        arm = set(self.arm.joint_names)
        for i in range(self.skeleton.getNumJoints()):
            joint = self.skeleton.getJoint(i)
            if joint.getNumDofs() > 0 and joint.getName() not in arm and joint is not self.skeleton.getRootJoint():
                joint.setActuatorType(dart.dynamics.ActuatorType.VELOCITY)
                joint.setCommands(np.zeros(joint.getNumDofs()))
        self.skeleton.setGravity(np.zeros(3))

    def _add_fingertip(self) -> Any:
        joint, body = self.link.createWeldJointAndBodyNodePair()
        joint.setTransformFromParentBodyNode(isometry(self.link_offset @ pad_pose()))
        body.setName("fingertip")
        shape = body.createShapeNode(dart.dynamics.CapsuleShape(FINGERTIP_RADIUS, FINGER_PAD_WIDTH))
        shape.createVisualAspect()
        shape.createCollisionAspect()
        shape.createDynamicsAspect().setFrictionCoeff(FINGERTIP_FRICTION)
        inertia = dart.dynamics.Inertia()
        inertia.setMass(0.01)
        body.setInertia(inertia)
        return body

    def _check_agrees_with_arm(self, q: np.ndarray) -> None:
        ours = self.effector_pose()
        theirs = self.arm.fk(q)
        if np.abs(ours - theirs).max() > 1e-6:
            raise SimulationError(
                "the arm in the execution world and the arm model disagree on the effector pose "
                f"by {np.abs(ours - theirs).max():.2e} (same URDF, link and offset expected)"
            )

    # ------------------------------------------------------------ state

    @property
    def q(self) -> np.ndarray:
        """The arm's joint positions, in the order of `arm.joint_names`."""
        return self.skeleton.getPositions()[self.dofs]

    def set_joints(self, q: np.ndarray) -> None:
        """Put the arm at joint positions `q` (only before the simulation starts)."""
        positions = self.skeleton.getPositions()
        positions[self.dofs] = np.asarray(q, dtype=float)
        self.skeleton.setPositions(positions)
        self.skeleton.setVelocities(np.zeros(self.skeleton.getNumDofs()))

    def effector_pose(self) -> np.ndarray:
        """The world pose of the effector frame, as the simulated arm has it now."""
        return self.link.getWorldTransform().matrix() @ self.link_offset

    def fingertip_collides(self, on: bool) -> None:
        """Let the fingertip pad touch things (pushing) or not (grasping, holding a tool).

        Switched on its body node, which DART's collision filter reads: a
        shape's own collision flag does not keep DART's constraint solver
        from making contact forces (the pad inside a released tool's grip
        dragged the tool up with the hand).
        """
        self.fingertip.setCollidable(on)

    # ------------------------------------------------------------ tools

    def grasp(self, name: str, skeleton: Any, body_node: Any) -> None:
        """Hold a tool as it lies now: it follows the effector rigidly from here on."""
        tool_pose = body_node.getWorldTransform().matrix()
        grasp = np.linalg.inv(tool_pose) @ self.effector_pose()
        joint = skeleton.getRootJoint()
        joint.setActuatorType(dart.dynamics.ActuatorType.VELOCITY)
        joint.setCommands(np.zeros(6))
        skeleton.setVelocities(np.zeros(skeleton.getNumDofs()))
        if not any(node is body_node for node in self._letting_go):  # else still excluded since it was let go of
            self._exclude(body_node, True)
        self._letting_go = [node for node in self._letting_go if node is not body_node]
        self.held = HeldTool(name, skeleton, body_node, grasp)

    def release(self) -> None:
        """Let go of the held tool: it becomes a free dynamic body again.

        The open hand is still around the tool's grip (the pad and the
        fingers overlap the grip: the effector frame sits on it), so the arm
        keeps passing through the tool until it has left it
        (`update_letting_go`); touching it before would lift the tool with
        the hand.
        """
        if self.held is None:
            return
        joint = self.held.skeleton.getRootJoint()
        joint.setActuatorType(dart.dynamics.ActuatorType.FORCE)
        joint.setCommands(np.zeros(6))
        self.held.skeleton.setVelocities(np.zeros(self.held.skeleton.getNumDofs()))
        self._letting_go.append(self.held.body_node)
        self.held = None

    def update_letting_go(self) -> None:
        """Let the arm touch again the tools it let go of and no longer overlaps (called every control period)."""
        for node in list(self._letting_go):
            if not self._overlaps(node):
                self._exclude(node, False)
                self._letting_go.remove(node)

    def _exclude(self, body_node: Any, on: bool) -> None:
        """Keep every body of the arm (links and pad) from touching `body_node`, or let them touch it again."""
        for i in range(self.skeleton.getNumBodyNodes()):
            if on:
                self.filter.addBodyNodePairToBlackList(self.skeleton.getBodyNode(i), body_node)
            else:
                self.filter.removeBodyNodePairFromBlackList(self.skeleton.getBodyNode(i), body_node)

    def _overlaps(self, body_node: Any) -> bool:
        """Whether any shape of the arm (the pad too, switched on or not) intersects `body_node`'s shapes."""
        detector = self.world.getConstraintSolver().getCollisionDetector()
        # keyed by names, not by the Python wrappers' ids (a wrapper freed may hand its id to another)
        keys = [(self.skeleton.getName(), ""), (body_node.getSkeleton().getName(), body_node.getName())]
        for key, owner in zip(keys, (self.skeleton, body_node), strict=True):
            if key not in self._groups:
                group = detector.createCollisionGroup()
                group.addShapeFramesOf(owner)
                self._groups[key] = group
        option = dart.collision.CollisionOption()
        option.enableContact = False
        option.maxNumContacts = 1
        return bool(self._groups[keys[0]].collide(self._groups[keys[1]], option))

    # ------------------------------------------------------------ motion

    def follow(
        self,
        segment: Segment,
        step: Callable[[int, float], None],
        q_hint: np.ndarray | None = None,
        q_path: list[np.ndarray] | None = None,
    ) -> None:
        """Carry out one path segment: IK every control period, `step(n, s)` runs n physics steps
        (s: the phase of the segment reached at their end).

        `q_hint` (e.g. the plan's joints for this pose) seeds the first IK
        solution. `q_path`, joints at evenly spaced phases of the segment
        (a continuous IK chain: the plan's contact chain), is followed: each
        period's IK starts from the chain's joints at that phase, so that the
        redundant arm keeps the configuration the planner checked instead of
        drifting in its null space; from the current joints where that fails.
        Raises ArmStuck when the arm cannot follow.
        """
        dt = self.world.getTimeStep()
        periods = max(1, int(np.ceil(segment.duration / CONTROL_PERIOD - 1e-9)))
        substeps = max(1, round(CONTROL_PERIOD / dt))
        for k in range(1, periods + 1):
            target = segment.pose(k / periods)
            hint = q_hint if k == 1 else None
            if hint is None and q_path:
                hint = q_path[min(len(q_path) - 1, round(k / periods * (len(q_path) - 1)))]
            planned = _along(q_path, k / periods) if q_path else None
            q_next = self._solve(target, hint, planned)
            self._command(q_next, substeps * dt)
            step(substeps, k / periods)
        self._stop()

    def solve(self, target: np.ndarray, seeds: list[np.ndarray | None]) -> np.ndarray:
        """Joint positions that put the effector at `target`, trying IK from each seed in turn."""
        for seed in seeds:
            if seed is None:
                continue
            q = self.arm.ik(target, q0=np.asarray(seed, dtype=float))
            if q is not None:
                return np.asarray(q, dtype=float)
        xyz = ", ".join(f"{v:.3f}" for v in target[:3, 3])
        raise ArmStuck(f"the arm cannot reach the effector pose at ({xyz}) m (no IK solution)")

    def move_joints(
        self, q_target: np.ndarray, step: Callable[[int, float], None], *, min_duration: float = 0.0
    ) -> None:
        """Move to `q_target` along a straight line in joint space (free-space transit)."""
        dt = self.world.getTimeStep()
        q_start = self.q
        duration = max(float(np.abs(q_target - q_start).max()) / JOINT_SPEED, min_duration, CONTROL_PERIOD)
        periods = max(1, int(np.ceil(duration / CONTROL_PERIOD - 1e-9)))
        substeps = max(1, round(CONTROL_PERIOD / dt))
        for k in range(1, periods + 1):
            self._command(q_start + (q_target - q_start) * k / periods, substeps * dt)
            step(substeps, k / periods)
        self._stop()

    def follow_joints(self, joints: np.ndarray, times: np.ndarray, step: Callable[[int, float], None]) -> None:
        """Move through joint waypoints `joints` (k x n), reaching waypoint i at `times[i]` s (a planned path).

        Between waypoints the joints move along the straight joint-space line
        at constant velocity, one command per control period; a waypoint
        closer in time than a control period is reached in one.
        """
        dt = self.world.getTimeStep()
        substeps = max(1, round(CONTROL_PERIOD / dt))
        joints = np.asarray(joints, dtype=float)
        total = max(float(times[-1]), 1e-9)
        for i in range(len(joints) - 1):
            a, b = joints[i], joints[i + 1]
            periods = max(1, int(np.ceil((float(times[i + 1]) - float(times[i])) / CONTROL_PERIOD - 1e-9)))
            for k in range(1, periods + 1):
                self._command(a + (b - a) * k / periods, substeps * dt)
                step(substeps, float(times[i] + (times[i + 1] - times[i]) * k / periods) / total)
        self._stop()

    def _solve(self, target: np.ndarray, q_hint: np.ndarray | None, planned: np.ndarray | None = None) -> np.ndarray:
        q = self.q
        if planned is not None:
            # near the plan's joints for this pose: Gauss-Newton from them lands on the planned configuration
            q_plan = self.arm.ik_near(target, planned)
            if q_plan is not None and self.link_travel(q, np.asarray(q_plan)) <= MAX_LINK_STEP:
                return np.asarray(q_plan, dtype=float)
        # one control period's move is small: Gauss-Newton steps from where the arm is move its joints least
        # (no switch of configuration), NLopt from there only when they stall
        q_next = self.arm.ik_near(target, q)
        if q_hint is not None and (q_next is None or self.link_travel(q, np.asarray(q_next)) > MAX_LINK_STEP):
            from_hint = self.arm.ik(target, q0=q_hint)
            q_next = from_hint if from_hint is not None else q_next
        if q_next is None:
            xyz = ", ".join(f"{v:.3f}" for v in target[:3, 3])
            raise ArmStuck(f"the arm cannot reach the effector pose at ({xyz}) m (no IK solution)")
        q_next = np.asarray(q_next, dtype=float)
        jump = self.link_travel(q, q_next)
        if jump > MAX_LINK_STEP:
            raise ArmStuck(
                f"a link of the arm would jump {jump * 100:.1f} cm in one control period (IK changed configuration)"
            )
        return q_next

    def link_travel(self, q_a: np.ndarray, q_b: np.ndarray, samples: int = 4) -> float:
        """How far (m) any link origin moves between two consecutive samples of the joint line from q_a to q_b.

        Measured in space, not in joint angles: near the shoulder singularity
        (joints 1 and 3 aligned) IK may trade one for the other without any
        link moving, which is harmless; a switch of configuration moves links.
        """
        points = [self._link_points(q_a + (q_b - q_a) * s) for s in np.linspace(0.0, 1.0, samples + 1)]
        return float(max(np.linalg.norm(b - a, axis=1).max() for a, b in itertools.pairwise(points)))

    def _link_points(self, q: np.ndarray) -> np.ndarray:
        model = getattr(self.arm, "skeleton", None)
        if model is None:  # an arm model without a skeleton: the effector is all we can see
            return self.arm.fk(q)[None, :3, 3]
        self.arm.fk(q)  # sets the model's joints
        return np.array(
            [model.getBodyNode(i).getWorldTransform().translation() for i in range(model.getNumBodyNodes())]
        )

    def _command(self, q_next: np.ndarray, period: float) -> None:
        for joint, velocity in zip(self.joints, (q_next - self.q) / period):
            joint.setCommand(0, float(velocity))
        if self.held is not None:
            hand_next = self.arm.fk(q_next)
            tool_next = hand_next @ np.linalg.inv(self.held.grasp)
            drive_body(self.held.skeleton, self.held.body_node, tool_next, period)

    def _stop(self) -> None:
        for joint in self.joints:
            joint.setCommand(0, 0.0)
        if self.held is not None:
            self.held.skeleton.getRootJoint().setCommands(np.zeros(6))


def _world_filter(world: Any) -> Any:
    """The collision filter of `world`'s constraint solver, to which pairs of bodies kept apart are added.

    dartpy hands out the solver's collision option by value: assigning a
    filter of our own to it changes a copy and leaves DART's default filter
    (a `BodyNodeCollisionFilter`) in force, so pairs are added to that one.
    """
    found = world.getConstraintSolver().getCollisionOption().collisionFilter
    if not isinstance(found, dart.collision.BodyNodeCollisionFilter):
        raise SimulationError(f"DART's constraint solver has no body-node collision filter ({type(found).__name__})")
    return found


def drive_body(skeleton: Any, body_node: Any, target: np.ndarray, period: float) -> None:
    """Command a kinematic free body the constant body-frame twist that reaches `target` in `period`."""
    joint = skeleton.getRootJoint()
    current = dart.dynamics.FreeJoint.convertToPositions(body_node.getWorldTransform())
    wanted = dart.dynamics.FreeJoint.convertToPositions(isometry(target))
    joint.setCommands(joint.getPositionDifferences(wanted, current) / period)


def _along(chain: list[np.ndarray], phase: float) -> np.ndarray:
    """The joints at `phase` (0 to 1) of `chain` (joints at evenly spaced phases), linearly between entries."""
    if len(chain) < 2:
        return np.asarray(chain[0], dtype=float)
    where = min(max(phase, 0.0), 1.0) * (len(chain) - 1)
    i = min(int(where), len(chain) - 2)
    a, b = np.asarray(chain[i], dtype=float), np.asarray(chain[i + 1], dtype=float)
    return a + (b - a) * (where - i)
