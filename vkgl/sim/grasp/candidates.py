"""Grasp candidates from a body's geometry: pairs of parallel faces that fit between the fingers.

Every box of the body's shape (and every cylinder, by the box around it: the
pads close across its diameter) is a candidate part. The hand comes to it from
above (`top`: the hand pointing down the body's -z) or from the side (`side`:
level, pointing along one of the part's horizontal axes, from either end). The
fingers close along one of the part's axes across the approach; the part's
extent there is the grasp's `width`, which must be at most the policy's
`max_width` and leave ROOM on each side of it when the hand opens. The pads
(`vkgl.robot.gripper`) are centred on the part across their own width and
reach DEPTH_MARGIN less than their length into it from its near face, or, for
a thin part such as a handle's bar, all of it but DEPTH_MARGIN (never less
than half of it).

A candidate is geometry only: whether the open hand has room there (nothing
of the body or the table in the way of the hand or the fingers) and whether
the grasp holds are the trial's questions (`vkgl.sim.grasp.trial`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from vkgl.formats.grasp_trials import GraspCandidate
from vkgl.lang.ir.grasps import GraspSettings
from vkgl.lang.ir.nodes import Body
from vkgl.robot.gripper import Gripper
from vkgl.shapes import dart_shapes

ROOM = 0.005
"""m the open pads keep from the body on each side before they close."""
DEPTH_MARGIN = 0.003
"""m: the pads stop this short of a part's far end (and of their own length beyond its near face)."""
ON_PART = 0.001
"""m: a body's frame this close to a part (or inside it) is a place to grasp that part."""
_AXIS_WORDS = ("x", "y", "z")


@dataclass(frozen=True)
class _Part:
    centre: np.ndarray  # body frame
    axes: np.ndarray  # 3 x 3, columns: the part's axes in the body frame
    extents: np.ndarray  # m along each axis


def grasp_candidates(body: Body, gripper: Gripper, settings: GraspSettings) -> list[GraspCandidate]:
    """Every candidate grasp of `body`'s boxes and cylinders (meshes have none), in a fixed order."""
    parts = _parts(body)
    pad_centre, pad_size = gripper.pad_box()
    found: list[GraspCandidate] = []
    for index, part in enumerate(parts):
        suffix = "" if len(parts) == 1 else f"_p{index}"
        for approach, direction in _approaches(part, settings):
            for closing in range(3):
                along = part.axes[:, closing]
                if abs(float(along @ direction)) > 1e-6:
                    continue
                width = float(part.extents[closing])
                opening = width + 2.0 * ROOM
                if width > settings.max_width or opening > gripper.max_opening:
                    continue
                name = f"grasp_{_approach_word(approach, direction, part)}_{_axis_word(along)}"
                for where, centre in _centres(body, part, direction, along):
                    pose = _effector_pose(part, centre, direction, along, pad_centre, pad_size)
                    named = name + (f"_{where}" if where else suffix)
                    found.append(GraspCandidate(named, pose, width, opening, approach))
    return _unique(sorted(found, key=lambda c: _has_frame(body, parts, c)))


def _has_frame(body: Body, parts: list[_Part], candidate: GraspCandidate) -> int:
    """0 for a candidate on a part that holds a frame of the body (a handle, a knob: a place named for a
    reason), else 1: those are tried first (the sort keeps the order within each)."""
    point = candidate.pose[:3, 3]
    for part in parts:
        inside = np.all(np.abs(part.axes.T @ (point - part.centre)) <= part.extents / 2.0 + 0.02)
        if inside and any(
            np.all(np.abs(part.axes.T @ (f.pose.matrix()[:3, 3] - part.centre)) <= part.extents / 2.0 + ON_PART)
            for f in body.frames
        ):
            return 0
    return 1


def _centres(body: Body, part: _Part, direction: np.ndarray, closing: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """Where along the part the pads go: its middle, and each frame of the body that lies on the part (a tool's
    `handle`), moved onto the part's middle across the pads and along the fingers."""
    across = np.cross(closing, direction)
    out: list[tuple[str, np.ndarray]] = [("", part.centre)]
    if abs(float(across @ part.axes[:, int(np.argmax(part.extents))])) < 1 - 1e-6:
        return out  # a frame says where along the part's length to hold it: only when the pads slide along that
    for frame in body.frames:
        point = frame.pose.matrix()[:3, 3]
        local = np.abs(part.axes.T @ (point - part.centre))
        if np.all(local <= part.extents / 2.0 + ON_PART):
            out.append((frame.name, part.centre + across * float(across @ (point - part.centre))))
    return out


def _parts(body: Body) -> list[_Part]:
    parts = []
    for shape, pose in dart_shapes(body.shape):
        kind = shape.getType()
        if kind == "BoxShape":
            extents = np.asarray(shape.getSize(), dtype=float)
        elif kind == "CylinderShape":
            diameter = 2.0 * float(shape.getRadius())
            extents = np.array([diameter, diameter, float(shape.getHeight())])
        else:
            continue
        parts.append(_Part(np.asarray(pose[:3, 3], dtype=float), np.asarray(pose[:3, :3], dtype=float), extents))
    return parts


def _approaches(part: _Part, settings: GraspSettings) -> list[tuple[str, np.ndarray]]:
    """(approach, direction the hand points in the body frame) for each approach the part has faces for."""
    down = np.array([0.0, 0.0, -1.0])
    out: list[tuple[str, np.ndarray]] = []
    if "top" in settings.approaches and any(abs(float(part.axes[:, i] @ down)) > 1 - 1e-6 for i in range(3)):
        out.append(("top", down))
    if "side" in settings.approaches:
        for i in range(3):
            axis = part.axes[:, i]
            if abs(float(axis[2])) < 1e-6:  # a horizontal axis of the part: its two ends face the hand
                out.append(("side", -axis))
                out.append(("side", axis))
    return out


def _effector_pose(
    part: _Part,
    centre: np.ndarray,
    direction: np.ndarray,
    closing: np.ndarray,
    pad_centre: np.ndarray,
    pad_size: np.ndarray,
) -> np.ndarray:
    """The effector frame that puts the pads across `closing` on the part, reaching in along `direction`."""
    z = -direction
    y = closing / np.linalg.norm(closing)
    x = np.cross(y, z)
    if x[2] < -1e-9:  # from the side, the hand's x axis up: the hand sits above the pads, clear of the table
        y, x = -y, -x
    depth_axis = int(np.argmax(np.abs(part.axes.T @ direction)))
    extent = float(part.extents[depth_axis])
    pad_length = float(pad_size[2])
    depth = min(pad_length - DEPTH_MARGIN, max(extent - DEPTH_MARGIN, extent / 2.0))
    near_face = centre - direction * float(direction @ (centre - part.centre)) - direction * extent / 2.0
    origin = near_face + direction * depth - x * float(pad_centre[0]) - y * float(pad_centre[1])
    pose = np.eye(4)
    pose[:3, :3] = np.column_stack([x, y, z])
    pose[:3, 3] = origin
    return _snapped(pose)


def _snapped(pose: np.ndarray) -> np.ndarray:
    """Rotation entries of exactly 0 and +-1 where they are within 1e-12 (turns of 90 deg print as such)."""
    out = pose.copy()
    rotation = out[:3, :3]
    for target in (0.0, 1.0, -1.0):
        rotation[np.abs(rotation - target) < 1e-12] = target
    return out


def _axis_word(axis: np.ndarray) -> str:
    i = int(np.argmax(np.abs(axis)))
    return _AXIS_WORDS[i] if abs(float(axis[i])) > 1 - 1e-6 else "o"


def _approach_word(approach: str, direction: np.ndarray, part: _Part) -> str:
    """`top`, or `side_px` for a hand that comes from the +x side (pointing along -x), `side_ny`, ..."""
    if approach == "top":
        return "top"
    i = int(np.argmax(np.abs(direction)))
    side = "n" if direction[i] > 0 else "p"  # the hand points along +x: it comes from the -x side
    return f"side_{side}{_AXIS_WORDS[i]}"


def _unique(found: list[GraspCandidate]) -> list[GraspCandidate]:
    """The first of candidates with the same pose (a frame at a part's middle), names made unique."""
    seen: dict[str, int] = {}
    poses: list[np.ndarray] = []
    out = []
    for candidate in found:
        if any(np.allclose(candidate.pose, other, atol=1e-9) for other in poses):
            continue
        poses.append(candidate.pose)
        count = seen.get(candidate.name, 0)
        seen[candidate.name] = count + 1
        name = candidate.name if count == 0 else f"{candidate.name}_{count + 1}"
        out.append(GraspCandidate(name, candidate.pose, candidate.width, candidate.opening, candidate.approach))
    return out


def candidate_summary(candidates: list[GraspCandidate]) -> list[dict[str, Any]]:
    """The candidates as plain data (name, approach, width), for reports and tests."""
    return [{"name": c.name, "approach": c.approach, "width": c.width} for c in candidates]


__all__ = ["DEPTH_MARGIN", "ROOM", "candidate_summary", "grasp_candidates"]
