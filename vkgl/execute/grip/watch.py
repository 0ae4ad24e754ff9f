"""Watching the grip on a held tool while the world runs: its load, its slip, and when it gives way.

`GripWatch` is told when the hand takes a tool (`hold`) and lets go of it
(`let_go`). While it holds, after every physics step it adds up the normal
contact forces other bodies exert on the tool, and every control period it
turns them, the tool's weight and its inertia into the load the grip
must carry in each of the period's steps (about the effector frame's origin,
in its axes) and compares it with what the fingers' friction carries
(`vkgl.robot.grip.Grip.usage`); the median over the last 0.1 s
(`LOAD_WINDOW`) decides. Past 1 the grip breaks: the tool is let
go of where it is, moving as it moves, and physics decides where it goes.

A body on a physical joint held by its handle (`hold(..., jointed=True)`: a
weld constraint holds it to the hand, `vkgl.execute.world_arm.WorldArm.
hold_handle`) loads the grip with the force its joint needs to follow
(`_handle_load`), not with contact forces.

Slip, measured every control period, is how far the effector frame has moved
on the tool since the grasp (m, and the angle it turned); past
`SLIP_TOLERANCE` or `SLIP_ANGLE_TOLERANCE` the step fails (`GripSlipped`); a
step in which the grip broke fails at its end in any case (the tool is no
longer in the hand). Each step's peak load and slip are kept for the report
(`vkgl.formats.execution_report.GripReport`).

Why the normal forces only: the held tool is rigid and kinematic, so the static
friction at its contacts is indeterminate, and DART's friction-cone solver
picks one force among many: pushing the block in task b it put 1.1 N of
vertical friction on the stick's tip (a moment of 0.39 N m about the grip,
more than the weight's 0.15 N m) where a Dantzig solve of the same contact
puts none. The contacts' normal forces are determinate.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vkgl.execute.effector_path import rotation_angle
from vkgl.execute.grip.model import SLIP_ANGLE_TOLERANCE, SLIP_TOLERANCE, Grip
from vkgl.execute.world_arm import ArmStuck, WorldArm
from vkgl.formats.execution_report import GripReport
from vkgl.sim.world import GRAVITY

LOAD_WINDOW = 0.1
"""s: the grip breaks when the load exceeds what it carries for more than half of the physics steps of the last
0.1 s (the median of their loads). A kinematic tool that meets a body that cannot give way (a drawer on its
joint) gets, for a step or two, whatever contact force stops it: 2.9e13 N in one step of task i, where the hook
meets the drawer's bar; an impact that short moves a tool held by friction by far less than the slip tolerance.
A load that lasts breaks the grip."""


class GripSlipped(ArmStuck):
    """The held tool slipped in the hand beyond the tolerance, or the grip on it broke."""


@dataclass
class _Held:
    name: str
    node: Any
    grip: Grip
    grasp: np.ndarray  # effector frame in the tool's frame at the grasp
    mass: float
    shapes: frozenset[int] = frozenset()  # the ids of its shapes, by which its contacts are found (`shape_ids`)
    jointed: bool = False  # a body on a physical joint held by its handle
    broken: str = ""  # why the grip broke, once it has
    raised: bool = False  # the failure has been raised
    objects: dict[Any, bool] = field(default_factory=dict)  # collision object -> on the tool? (`_on_tool`)


class GripWatch:
    """The grip on the tool in the hand of `arm`: load and slip, per step."""

    def __init__(self, arm: WorldArm) -> None:
        self.arm = arm
        self.held: _Held | None = None
        self._forces: list[np.ndarray] = []  # this control period's physics steps: contact force on the tool (world)
        self._torques: list[np.ndarray] = []  # and its moment about the tool's centre of mass
        self._velocity: np.ndarray | None = None  # the tool's centre of mass velocity at the last period's end
        self._joint_speed: float | None = None  # a held handle's body: its joint's speed at the last step
        steps = max(1, round(LOAD_WINDOW / arm.world.getTimeStep()))
        self._window: deque[tuple[float, np.ndarray, np.ndarray]] = deque(maxlen=steps)  # (usage, force, torque)
        self.report: GripReport | None = None  # the current step's

    # ------------------------------------------------------------ hand events

    def hold(self, name: str, node: Any, grip: Grip, *, jointed: bool = False) -> None:
        """The hand has just taken tool `name` (its body node `node`) with `grip`; `jointed`: a body on a
        physical joint held by its handle."""
        grasp = np.linalg.inv(node.getWorldTransform().matrix()) @ self.arm.effector_pose()
        self.held = _Held(name, node, grip, grasp, float(node.getMass()), shape_ids(node), jointed)
        self._joint_speed = None
        self._reset_period()
        self._velocity = None
        self._window.clear()
        self.report = GripReport(name, grip.force, grip.friction, grip.max_force, grip.max_torque)

    def let_go(self) -> None:
        """The hand has opened: nothing is held from here on."""
        self.held = None

    def begin_step(self) -> None:
        """A plan step begins: its report starts afresh (the tool still in the hand, if any)."""
        h = self.held
        self.report = (
            None
            if h is None
            else GripReport(h.name, h.grip.force, h.grip.friction, h.grip.max_force, h.grip.max_torque)
        )

    def end_step(self) -> None:
        """A plan step ends: if the grip broke in it and that has not failed it yet, it fails now."""
        h = self.held
        if h is not None and h.broken and not h.raised:
            self._fail(f"the grip on {h.name} broke ({h.broken}); it is no longer in the hand")

    # ------------------------------------------------------------ while the world runs

    def after_physics_step(self, world: Any) -> None:
        """Add up the contact forces on the held tool in the step just taken (nothing if none is held)."""
        h = self.held
        if h is None or h.broken:
            return
        if h.jointed:
            self._handle_load(h, world.getTimeStep())
            return
        total, moment = np.zeros(3), np.zeros(3)  # contact force on the tool (world), its moment about the com
        result = world.getLastCollisionResult()
        if not result.inCollision(h.node):  # most steps: nothing touches the tool (one call, not a loop)
            self._forces.append(total)
            self._torques.append(moment)
            return
        com = h.node.getCOM()
        for contact in result.getContacts():  # about 14 a step, 2 of them on the tool: see `_on_tool`
            sign = 0.0
            if _on_tool(h, contact.collisionObject1):
                sign = 1.0  # DART's contact force acts on the first object, its opposite on the second
            elif _on_tool(h, contact.collisionObject2):
                sign = -1.0
            if sign:
                normal = np.asarray(contact.normal, dtype=float)
                force = sign * float(np.dot(contact.force, normal)) * normal  # the normal part: see the docstring
                total += force
                moment += _cross(np.asarray(contact.point, dtype=float) - com, force)
        self._forces.append(total)
        self._torques.append(moment)

    def _handle_load(self, h: _Held, dt: float) -> None:
        """The force the grip exerts on a body on a joint in the step just taken: the generalised force its joint
        needed (its inertia, gravity along the joint, the joint's damping and Coulomb friction) at the grip's
        point, the smallest force that gives it (F = tau J / |J|^2 with J the point's velocity per unit of the
        joint's speed). What else touches the body is not counted."""
        skeleton = h.node.getSkeleton()
        joint = skeleton.getJoint(0)
        speed = float(skeleton.getVelocity(0))
        accel = 0.0 if self._joint_speed is None else (speed - self._joint_speed) / dt
        self._joint_speed = speed
        tau = float(skeleton.getMassMatrix()[0, 0]) * accel + float(skeleton.getCoriolisAndGravityForces()[0])
        tau += float(joint.getDampingCoefficient(0)) * speed
        if abs(speed) > 1e-4:
            tau += float(joint.getCoulombFriction(0)) * np.sign(speed)
        grip_point = np.linalg.inv(h.node.getWorldTransform().matrix()) @ self.arm.effector_pose()
        jacobian = np.asarray(h.node.getLinearJacobian(grip_point[:3, 3]), dtype=float)[:, 0]
        reach = float(jacobian @ jacobian)
        force = tau * jacobian / reach if reach > 1e-12 else np.zeros(3)
        self._forces.append(-force)  # stored as the opposite of a contact force on a tool: see `_check_load`
        self._torques.append(np.zeros(3))

    def after_period(self, period: float) -> None:
        """At the end of a control period: the grip's load and the tool's slip; break, or fail the step."""
        h = self.held
        if h is None:
            return
        if not h.broken:
            self._check_load(h, period)
        self._check_slip(h)

    def _check_load(self, h: _Held, period: float) -> None:
        velocity = np.asarray(h.node.getCOMLinearVelocity(), dtype=float)
        acceleration = np.zeros(3) if self._velocity is None else (velocity - self._velocity) / period
        self._velocity = velocity
        hand = self.arm.effector_pose()
        rotation = hand[:3, :3].T
        lever = h.node.getCOM() - hand[:3, 3]  # from the grip to the centre of mass
        # a handle's body: its joint carries its weight and its inertia is in the force already stored
        inertial = np.zeros(3) if h.jointed else h.mass * (acceleration - np.asarray(GRAVITY))
        if self._forces:  # the period's steps at once (a loop over them cost a third of a hook pull's watch)
            # what the grip must exert on the tool: m a minus everything else acting on it (contacts, weight);
            # its moment about the grip balances the contacts' about the centre of mass (the tool turns slowly)
            forces = inertial - np.array(self._forces)
            torques = -np.array(self._torques)
            if not h.jointed:
                torques += _cross_rows(lever, forces)
            usages = h.grip.usages(forces @ rotation.T, torques @ rotation.T)
            self._window.extend(zip(usages.tolist(), forces, torques, strict=True))
        self._reset_period()
        if not self._window:
            return
        # the load sustained over half of the window: its median step
        ranked = sorted(self._window, key=lambda load: load[0])
        usage, force, torque = ranked[len(ranked) // 2]
        if self.report is not None:
            self.report.note_load(usage)
        if usage > 1.0:
            h.broken = (
                f"a load of {np.linalg.norm(force):.1f} N, {np.linalg.norm(torque):.2f} N m used "
                f"{usage * 100:.0f} % of what {h.grip.text()}"
            )
            if self.report is not None:
                self.report.broke = h.broken
            self.arm.break_grip()

    def _check_slip(self, h: _Held) -> None:
        now = np.linalg.inv(h.node.getWorldTransform().matrix()) @ self.arm.effector_pose()
        slip = float(np.linalg.norm(now[:3, 3] - h.grasp[:3, 3]))
        turn = rotation_angle(h.grasp, now)
        if self.report is not None:
            self.report.note_slip(slip, turn)
        if not h.raised and (slip > SLIP_TOLERANCE or turn > SLIP_ANGLE_TOLERANCE):
            self._fail(
                f"{h.name} slipped {slip * 1000:.1f} mm, {np.degrees(turn):.1f} deg in the hand (tolerance "
                f"{SLIP_TOLERANCE * 1000:.0f} mm, {np.degrees(SLIP_ANGLE_TOLERANCE):.0f} deg)"
                + (f": the grip broke ({h.broken})" if h.broken else "")
            )

    def _fail(self, why: str) -> None:
        assert self.held is not None
        self.held.raised = True
        self.held = None  # the tool is not in the hand any more: nothing more to watch
        raise GripSlipped(why)

    def _reset_period(self) -> None:
        self._forces = []
        self._torques = []


def _on_tool(h: _Held, collision_object: Any) -> bool:
    """Whether a contact's collision object is one of the held tool's shapes: by its shape's id the first time it
    is met in this hold, then by the object itself. dartpy hands back the same Python object for a DART collision
    object while one is alive (`h.objects` keeps them alive), and looking that up costs a third of asking for its
    shape (a new wrapper every call: `getShape` is most of the watch's time). The objects of the world's collision
    group live as long as their shape nodes, and no skeleton comes or goes while a tool is held."""
    on = h.objects.get(collision_object)
    if on is None:
        on = h.objects[collision_object] = int(collision_object.getShape().getID()) in h.shapes
    return on


def shape_ids(node: Any) -> frozenset[int]:
    """The ids of the shapes of body node `node` (DART's `Shape.getID`, drawn from a counter: unique, never
    reused): a contact is on the node when the shape of one of its collision objects has one of them. The watch
    looks at every contact (about 14) of every physics step; comparing ids costs a fifth of comparing the shape
    nodes' names (`getName` makes a string, ~11 us). Kept as ints, not as DART objects, which must not outlive
    their world."""
    return frozenset(int(node.getShapeNode(i).getShape().getID()) for i in range(node.getNumShapeNodes()))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for two 3-vectors (numpy's cross costs 0.25 ms a call, every physics step)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for a 3-vector `a` and each row of `b` (k x 3), without numpy's `cross` (its axis handling cost
    more than the products)."""
    return np.stack(
        [a[1] * b[:, 2] - a[2] * b[:, 1], a[2] * b[:, 0] - a[0] * b[:, 2], a[0] * b[:, 1] - a[1] * b[:, 0]], axis=1
    )


__all__ = ["GripSlipped", "GripWatch"]
