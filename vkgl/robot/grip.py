"""The grip of a parallel gripper on a tool: what its fingers' friction carries, and the load a push puts on it.

The executor watches the real load against it (`vkgl.execute.grip`); the
planner estimates the load of each push with a held tool before it plans one
(`push_load`), so that a plan never asks the grip for more than it carries.

Why a model and not the fingers' own contacts: in DART 6.20, with the
execution world's friction-cone solver (NSGS, Coulomb law), two fingers pressed
on a 40 cm stick by their joints' force did not hold it (bench/robot/bench_grip.py:
the stick turned 16 deg and slid 5.6 mm in the grip while lifted and carried;
the fingers sank 3.3 mm into it per side at the 1 ms time step and jittered by
3.4 mm; a 0.25 ms step removed the sinking but not the turning, at 60 times the
wall time). So the held tool follows the hand rigidly (`vkgl.execute.world_arm`)
as long as the load on the grip stays within what the pads' Coulomb friction
can carry, and is let go of (it slips, falls, turns) the moment it does not:

- force in the pads' plane (the effector frame's x and z: the fingers close
  along its y): at most `2 mu F` (two pads, each pressed with F);
- torque about the pads' normal (y): at most `2 mu F r`, the torsional
  friction of a pad of effective radius r (2/3 of `PAD_RADIUS`: uniform
  pressure on a disc);
- both at once: within the ellipse (f / 2 mu F)^2 + (t / 2 mu F r)^2 <= 1 (the
  usual approximation of a contact patch's limit surface);
- force along y and torque about x and z are carried by the fingers
  themselves (the Panda's two fingers are coupled by one self-locking drive:
  they do not give way across the grip).

`mu` is the smaller of the pads' and the tool's friction, as DART pairs two
surfaces; F is the grasp's stated force, or the Panda's continuous grasp force
for a tool held by a `fixed` action (the stdlib tools' `wield`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

GRAVITY = 9.81
"""m/s^2."""

DEFAULT_FRICTION = 0.5
"""A body's friction when it declares none (the simulator's `vkgl.sim.world.DEFAULT_FRICTION`; a test holds them
equal)."""

GRIP_FORCE = 70.0
"""N each finger presses when the action states no force: Franka's continuous grasp force of the Panda hand."""

PAD_FRICTION = 1.0
"""The finger pads' friction coefficient: the same rubber-like pad that pushes (the simulator's
`vkgl.sim.fingertip.FINGERTIP_FRICTION`; a test holds them equal); the pair takes the smaller."""

PAD_RADIUS = 0.01
"""m: a Panda finger pad is about 2 cm across."""

SLIP_TOLERANCE = 0.005
"""m a held tool may move in the hand (from where it was grasped) before the step fails."""

SLIP_ANGLE_TOLERANCE = np.radians(5.0)
"""rad a held tool may turn in the hand before the step fails."""


@dataclass(frozen=True)
class Grip:
    """Two finger pads pressing a tool with `force` (N each) with friction `friction`."""

    force: float
    friction: float
    radius: float = PAD_RADIUS

    @property
    def max_force(self) -> float:
        """N the pads' friction carries in their plane: 2 mu F."""
        return 2.0 * self.friction * self.force

    @property
    def max_torque(self) -> float:
        """N m the pads' friction carries about their normal: 2 mu F times 2/3 of the pad's radius."""
        return self.max_force * self.radius * 2.0 / 3.0

    def usage(self, force: np.ndarray, torque: np.ndarray) -> float:
        """How much of the grip a load uses (1 = all: it slips beyond); `force` and `torque` (N, N m) are the
        load the grip must carry, in the effector frame (the fingers close along its y), about its origin."""
        tangential = float(np.hypot(force[0], force[2]))
        twist = abs(float(torque[1]))
        if self.max_force <= 0.0:
            return float("inf") if tangential > 0.0 or twist > 0.0 else 0.0
        return float(np.hypot(tangential / self.max_force, twist / self.max_torque))

    def usages(self, forces: np.ndarray, torques: np.ndarray) -> np.ndarray:
        """`usage` of each row of `forces` and `torques` (k x 3 each), at once: the grip's watch asks it for
        every physics step of a control period."""
        tangential = np.hypot(forces[:, 0], forces[:, 2])
        twist = np.abs(torques[:, 1])
        if self.max_force <= 0.0:
            return np.where((tangential > 0.0) | (twist > 0.0), np.inf, 0.0)
        return np.asarray(np.hypot(tangential / self.max_force, twist / self.max_torque), dtype=float)

    def text(self) -> str:
        """`2 x 70 N at mu 0.50: 70.0 N, 0.47 N m`."""
        return (
            f"2 x {self.force:.0f} N at mu {self.friction:.2f}: carries {self.max_force:.1f} N, "
            f"{self.max_torque:.2f} N m"
        )


def grip_for(action: Any, tool_friction: float | None) -> Grip:
    """The grip an affordance's action holds a tool with: its stated `force` (a grasp) or `GRIP_FORCE`, with the
    smaller of the pads' and the tool's friction (DART's pairing rule; the tool's default if it declares none)."""
    force = getattr(action, "force", None)
    mu = DEFAULT_FRICTION if tool_friction is None else tool_friction
    return Grip(GRIP_FORCE if force is None else float(force), min(PAD_FRICTION, mu))


PAD_SETBACK = 0.006
"""m the Panda's closed pads are centred behind the effector frame's origin along its x (stdlib/robots/panda.urdf)."""

TOUCH_GAP = 0.0005
"""m left between a closed pad and the tool's face: kinematic pads pressed into the free tool would shove it."""


def width_across_grip(mesh: Any, grasp: np.ndarray, reach: float = 0.03) -> float | None:
    """The tool's width along the effector frame's y (where the fingers close) at the grasp: the extent of its
    section by the plane through the pads' centre normal to the effector frame's x, within `reach` of the origin
    along z (the pads' length). `mesh`: the tool's trimesh; `grasp`: the effector frame in the tool's frame;
    None if the plane misses."""
    import trimesh  # only where a grip is measured

    local = mesh.copy()
    local.apply_transform(np.linalg.inv(grasp))
    lines = trimesh.intersections.mesh_plane(local, plane_normal=[1.0, 0.0, 0.0], plane_origin=[-PAD_SETBACK, 0.0, 0.0])
    points = np.asarray(lines, dtype=float).reshape(-1, 3)
    points = points[np.abs(points[:, 2]) <= reach]
    if len(points) == 0:
        return None
    return float(points[:, 1].max() - points[:, 1].min())


def tool_width(action: Any, mesh: Any, grasp: np.ndarray) -> float:
    """m across the grip of a tool held by `action`: its stated `width` (a grasp), else measured on the tool's
    `mesh` where the effector frame holds it (`grasp`: the effector frame in the tool's frame), 0 if the plane of
    the pads misses it."""
    width = getattr(action, "width", None)
    if width is not None:
        return float(width)
    measured = width_across_grip(mesh, grasp)
    return 0.0 if measured is None else measured


def holding_opening(action: Any, mesh: Any, grasp: np.ndarray) -> float:
    """m each finger stands open while the hand holds a tool by `action` (arguments of `tool_width`): the pads
    close onto the tool's faces, `TOUCH_GAP` short of them. The executor opens the fingers exactly so; the
    planner checks the fingers so opened (`vkgl.motion.arm_collision.Held.opening`): a finger beside a thin
    grip stands a tool's half width out from the effector frame, where closed fingers do not reach."""
    return tool_width(action, mesh, grasp) / 2 + TOUCH_GAP


def push_load(
    effector: np.ndarray,
    contact: np.ndarray,
    direction: np.ndarray,
    force: float,
    tool_centre: np.ndarray,
    tool_mass: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The quasi-static load of a push with a held tool on the grip, in the effector frame (`Grip.usage`'s
    arguments): the body's resistance and the tool's weight, with their moments about the effector's origin.

    `effector`: the effector's world pose (4x4); `contact`: the world point where the tool meets the body;
    `direction`: the way the contact moves (world, any length); `force`: N the body resists with, pushing the
    tool back along `direction`; `tool_centre`: the world point the tool's weight acts at; `tool_mass`: kg.
    """
    unit = np.asarray(direction, dtype=float)
    unit = unit / max(float(np.linalg.norm(unit)), 1e-12)
    push = -force * unit
    weight = np.array([0.0, 0.0, -tool_mass * GRAVITY])
    origin = effector[:3, 3]
    torque = np.cross(np.asarray(contact, dtype=float) - origin, push)
    torque += np.cross(np.asarray(tool_centre, dtype=float) - origin, weight)
    rotation = effector[:3, :3]
    return rotation.T @ (push + weight), rotation.T @ torque


def resisting_force(mass: float, friction: float | None) -> float:
    """N a body resting on the table resists a slide with: its weight times the pair's Coulomb friction (the
    table's is 1.0, so the body's own, or `DEFAULT_FRICTION`)."""
    mu = DEFAULT_FRICTION if friction is None else friction
    return mu * mass * GRAVITY


__all__ = [
    "DEFAULT_FRICTION",
    "GRAVITY",
    "GRIP_FORCE",
    "PAD_FRICTION",
    "PAD_RADIUS",
    "PAD_SETBACK",
    "SLIP_ANGLE_TOLERANCE",
    "SLIP_TOLERANCE",
    "TOUCH_GAP",
    "Grip",
    "grip_for",
    "holding_opening",
    "push_load",
    "resisting_force",
    "tool_width",
    "width_across_grip",
]
