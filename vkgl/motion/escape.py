"""The way out of a transit's room: a short straight hand move from an end inside it to the first configuration
clear of it, along which the real shapes never touch and the arm only gets farther from what is near.

Transits keep the arm a room away from the bodies (their shapes grown: `vkgl.plan.geometry.bodies`). An end
of a transit may lie inside that room although the arm touches nothing: the arm's ready pose beside a cupboard
(the hand's side 0 to 1 cm from its door), or wherever execution left the arm before a re-solve. Refusing such
a transit refuses every plan, which a person moving the arm would not do: they move the hand straight away from
what is close, and go on from there. `way_out` is that move:

- a straight move of the hand (its orientation kept), `ESCAPE_STEP` at a time by chained IK
  (`vkgl.motion.approach.follow_poses`), along each of `ESCAPE_DIRECTIONS` (up and the world's level axes), at
  most `ESCAPE_REACH`; along the level diagonals (`ESCAPE_DIAGONALS`) only when none of those leads out;
- it ends at the first pose clear of the room (the transit's own check), so it leaves the room as soon as
  it can; the shortest of the directions wins (the first of them on a tie);
- along it the arm's links (and a held tool) keep clear of the real shapes (the exact check, every
  `ESCAPE_TOLERANCE` of travel), no body the arm was not inside the room of comes within it, and each one it
  was inside the room of is left by at least `ESCAPE_GAIN` a step (its overlap with the grown shape shrinks):
  the arm leaves, it does not slide along a face.

The transit is planned from the end of that move (`vkgl.motion.transit_segment`) and the move joins it.
"""

from __future__ import annotations

import numpy as np

from vkgl.motion.approach import APPROACH_STEP, CartesianFailure, approach_poses, follow_poses
from vkgl.motion.arm_collision import ArmCollision, Held
from vkgl.motion.density import edge_resolution, segment_is_valid

ESCAPE_STEP = APPROACH_STEP
"""m: the hand moves this far between two configurations of the way out."""

ESCAPE_REACH = 0.04
"""m: the longest way out tried (the bare arm's room is 1 cm: straight away from a face it leaves in 1 cm,
slanted off it in more)."""

ESCAPE_GAIN = 0.001
"""m: each step takes the arm at least this much farther out of every grown shape it is still inside (a fifth
of a step: a move up to 78 deg off the face's normal), so that it never slides along what it is close to."""

ESCAPE_TOLERANCE = 0.002
"""m: no point of the arm (or a held tool) moves more than this between two configurations checked against the
real shapes on the way out (they are close there)."""

ESCAPE_DIRECTIONS = (
    np.array([0.0, 0.0, 1.0]),
    np.array([-1.0, 0.0, 0.0]),
    np.array([1.0, 0.0, 0.0]),
    np.array([0.0, -1.0, 0.0]),
    np.array([0.0, 1.0, 0.0]),
)
"""World directions of the hand's move: up first (over a table the room is usually above), then level along the
world's axes; never down (the table)."""

ESCAPE_DIAGONALS = tuple(
    np.array([x, y, 0.0]) / np.sqrt(2.0) for x, y in ((-1.0, 1.0), (-1.0, -1.0), (1.0, 1.0), (1.0, -1.0))
)
"""Level directions between the world's axes, tried only when none of `ESCAPE_DIRECTIONS` leads out: a held tool
that has just turned a body lies along one of its faces at the end of the contact, where a move along one axis
slides along the face or back into it and the other needs the wrist to flip (gen9_008 of the physical bench: the
Stick beside the cube it turned, out only along -x+y). Back towards the arm's base first (the arm folds rather
than stretches)."""


def way_out(
    room: ArmCollision, exact: ArmCollision, q: np.ndarray, held: Held | None = None, tool_reach: float = 0.0
) -> np.ndarray | None:
    """Joints (k x n, `q` first) of the shortest straight hand move from `q` to a configuration `room.free`,
    every configuration on the way `exact.free` and leaving the grown shapes it starts in; None when `q` is
    not free in `exact` or no direction leads out within `ESCAPE_REACH`. Both scenes must have the bodies
    placed. `tool_reach`: how far a held tool reaches beyond the effector (the check density)."""
    q = np.asarray(q, dtype=float)
    if not exact.free(q, held=held):
        return None
    resolution = edge_resolution(room.arm, ESCAPE_TOLERANCE, tool_reach)
    for directions in (ESCAPE_DIRECTIONS, ESCAPE_DIAGONALS):
        best: np.ndarray | None = None
        for direction in directions:
            found = _along(room, exact, q, held, direction, resolution)
            if found is not None and (best is None or len(found) < len(best)):
                best = found
        if best is not None:
            return best
    return None


def _along(
    room: ArmCollision, exact: ArmCollision, q: np.ndarray, held: Held | None, way: np.ndarray, resolution: float
) -> np.ndarray | None:
    """The way out along `way` (world, unit), or None when it touches, slides or does not get out in reach."""
    arm = room.arm
    start = arm.fk(q)
    poses = approach_poses(start, ESCAPE_REACH, ESCAPE_STEP, -way)[::-1]  # from `start` along `way`
    path = follow_poses(arm, poses, q)
    if isinstance(path, CartesianFailure):
        return None
    joints = path.joints.copy()
    joints[0] = q
    depths = _depths(room, q, held)

    def real(c: np.ndarray) -> bool:
        return exact.free(c, held=held)

    for k in range(1, len(joints)):
        if not (real(joints[k]) and segment_is_valid(joints[k - 1], joints[k], real, resolution)):
            return None
        if room.free(joints[k], held=held):
            return joints[: k + 1]
        now = _depths(room, joints[k], held)
        if any(body not in depths or depth > depths[body] - ESCAPE_GAIN for body, depth in now.items()):
            return None
        depths = now
    return None


def _depths(room: ArmCollision, q: np.ndarray, held: Held | None) -> dict[str, float]:
    """How deep the arm (or the held tool) is inside each grown body at `q` (m; bodies it is outside left out)."""
    out: dict[str, float] = {}
    for contact in room.overlap(q, held=held):
        out[contact.body_b] = max(out.get(contact.body_b, 0.0), contact.depth)
    return out


__all__ = [
    "ESCAPE_DIAGONALS",
    "ESCAPE_DIRECTIONS",
    "ESCAPE_GAIN",
    "ESCAPE_REACH",
    "ESCAPE_STEP",
    "ESCAPE_TOLERANCE",
    "way_out",
]
