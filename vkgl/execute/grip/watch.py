"""Watching the grip on a held tool while the world runs: its load, its slip, and when it gives way.

`GripWatch` is told when the hand takes a tool (`hold`) and lets go of it
(`let_go`). While it holds, after every physics step it adds up the normal
contact forces other bodies exert on the tool, and every control period it
turns their mean, the tool's weight and its inertia into the load the grip
must carry (about the effector frame's origin, in its axes), averages it over
the last 0.1 s (`LOAD_WINDOW_PERIODS`) and compares it with what the fingers'
friction carries (`vkgl.execute.grip.model.Grip.usage`). Past 1 the grip breaks: the tool is let
go of where it is, moving as it moves, and physics decides where it goes.

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
from dataclasses import dataclass
from typing import Any

import numpy as np

from vkgl.execute.effector_path import rotation_angle
from vkgl.execute.grip.model import SLIP_ANGLE_TOLERANCE, SLIP_TOLERANCE, Grip
from vkgl.execute.world_arm import ArmStuck, WorldArm
from vkgl.formats.execution_report import GripReport
from vkgl.sim.world import GRAVITY

LOAD_WINDOW_PERIODS = 5
"""Control periods (0.1 s) over which the load on the grip is averaged before it is compared with what the grip
carries: the kinematic tool's first touch of a body is an impact of a few milliseconds (in task b the stick's
usage jumped from 0.32 to 1.09 for one 20 ms period as it met the block), which moves a tool held by friction
by far less than the slip tolerance; a load that lasts breaks the grip."""


class GripSlipped(ArmStuck):
    """The held tool slipped in the hand beyond the tolerance, or the grip on it broke."""


@dataclass
class _Held:
    name: str
    node: Any
    skeleton_name: str
    grip: Grip
    grasp: np.ndarray  # effector frame in the tool's frame at the grasp
    mass: float
    broken: str = ""  # why the grip broke, once it has
    raised: bool = False  # the failure has been raised


class GripWatch:
    """The grip on the tool in the hand of `arm`: load and slip, per step."""

    def __init__(self, arm: WorldArm) -> None:
        self.arm = arm
        self.held: _Held | None = None
        self._force = np.zeros(3)  # sum over this control period's physics steps: contact force on the tool (world)
        self._torque = np.zeros(3)  # and its moment about the tool's centre of mass
        self._steps = 0
        self._velocity: np.ndarray | None = None  # the tool's centre of mass velocity at the last period's end
        self._window: deque[tuple[np.ndarray, np.ndarray]] = deque(maxlen=LOAD_WINDOW_PERIODS)  # loads, hand frame
        self.report: GripReport | None = None  # the current step's

    # ------------------------------------------------------------ hand events

    def hold(self, name: str, node: Any, grip: Grip) -> None:
        """The hand has just taken tool `name` (its body node `node`) with `grip`."""
        grasp = np.linalg.inv(node.getWorldTransform().matrix()) @ self.arm.effector_pose()
        self.held = _Held(name, node, node.getSkeleton().getName(), grip, grasp, float(node.getMass()))
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
        com = h.node.getCOM()
        result = world.getLastCollisionResult()
        for i in range(result.getNumContacts()):
            contact = result.getContact(i)
            sign = 0.0
            if _skeleton_name(contact.collisionObject1) == h.skeleton_name:
                sign = 1.0  # DART's contact force acts on the first object, its opposite on the second
            elif _skeleton_name(contact.collisionObject2) == h.skeleton_name:
                sign = -1.0
            if sign:
                normal = np.asarray(contact.normal, dtype=float)
                force = sign * float(np.dot(contact.force, normal)) * normal  # the normal part: see the docstring
                self._force += force
                self._torque += np.cross(np.asarray(contact.point, dtype=float) - com, force)
        self._steps += 1

    def after_period(self, period: float) -> None:
        """At the end of a control period: the grip's load and the tool's slip; break, or fail the step."""
        h = self.held
        if h is None:
            return
        if not h.broken:
            self._check_load(h, period)
        self._check_slip(h)

    def _check_load(self, h: _Held, period: float) -> None:
        n = max(self._steps, 1)
        velocity = np.asarray(h.node.getCOMLinearVelocity(), dtype=float)
        acceleration = np.zeros(3) if self._velocity is None else (velocity - self._velocity) / period
        self._velocity = velocity
        # what the grip must exert on the tool: m a minus everything else acting on it (contacts, weight);
        # its moment about the grip balances the contacts' about the centre of mass (the tool turns slowly)
        force = h.mass * (acceleration - np.asarray(GRAVITY)) - self._force / n
        hand = self.arm.effector_pose()
        torque = -self._torque / n + np.cross(h.node.getCOM() - hand[:3, 3], force)
        rotation = hand[:3, :3].T
        self._window.append((rotation @ force, rotation @ torque))
        force, torque = (np.mean([w[k] for w in self._window], axis=0) for k in (0, 1))
        usage = h.grip.usage(force, torque)
        self._reset_period()
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
        self._force = np.zeros(3)
        self._torque = np.zeros(3)
        self._steps = 0


def _skeleton_name(collision_object: Any) -> str:
    return collision_object.getShapeFrame().asShapeNode().getBodyNodePtr().getSkeleton().getName()


__all__ = ["GripSlipped", "GripWatch"]
