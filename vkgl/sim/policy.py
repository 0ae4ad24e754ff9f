"""Exploration policies: a body's `explore` blocks checked and unrolled into trials.

A policy is a grid search (PAPER.md, "Exploration"):

- `contacts on faces F... steps K` with `force normal Q`: K contact points
  along the centre line of each named face (the horizontal line at mid height
  of a side face; the line along the longer horizontal side for `+z`), at the
  centres of K equal cells; the force pushes along the face's inward normal.
- `grasp FRAME` with `force directions I x J x K Q`: the effector holds the
  body at FRAME; the directions are the points of the I x J x K grid over
  [-1, 1]^3 (a count of 1 gives 0 on that axis) without the zero point,
  normalised; the force has the declared magnitude.

Bad policies are CompileErrors whose diagnostics point at the offending
source (file:line:col), codes E701-E708 (docs/exploration.md).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import trimesh

from vkgl.errors import CompileError
from vkgl.lang.diagnostics import Diagnostic
from vkgl.lang.geometry import body_mesh
from vkgl.lang.ir import Body, Explore, Node, Span

FACES = {
    "+x": np.array([1.0, 0.0, 0.0]),
    "-x": np.array([-1.0, 0.0, 0.0]),
    "+y": np.array([0.0, 1.0, 0.0]),
    "-y": np.array([0.0, -1.0, 0.0]),
    "+z": np.array([0.0, 0.0, 1.0]),
    "-z": np.array([0.0, 0.0, -1.0]),
}

E_NO_EXPLORE = "E701"
E_NO_ACTION = "E702"
E_BAD_FACE = "E703"
E_BAD_STEPS = "E704"
E_UNKNOWN_FRAME = "E705"
E_BAD_FORCE = "E706"
E_BAD_DURATION = "E707"
E_NO_SURFACE = "E708"


@dataclass(frozen=True)
class TrialSpec:
    """One point of a policy's grid: everything a worker needs to run the trial.

    `contact` and `direction` are in the body frame: for a push, the point on
    the body's surface and the inward normal; for a grasp, the grasp frame's
    origin and the force direction. `grasp` is the grasp frame (4x4, body frame).
    """

    index: int
    body: Body
    policy: str
    kind: str  # "push" or "grasp"
    contact: np.ndarray
    direction: np.ndarray
    magnitude: float
    duration: float
    line_axis: np.ndarray  # push: the face's centre line direction (body frame); grasp: unused zeros
    grasp: np.ndarray | None = None
    label: str = ""


def _error(code: str, message: str, node: Node | None, fallback: Span | None) -> CompileError:
    span = node.span if node is not None and node.span is not None else fallback
    return CompileError([Diagnostic(code, message, span)])


def plan_trials(body: Body) -> list[TrialSpec]:
    """All trials of all `explore` blocks of `body`, in declaration order; raises CompileError on a bad policy."""
    where = body.name_span or body.span
    if not body.explores:
        raise _error(
            E_NO_EXPLORE,
            f"body `{body.name}` has no `explore` block, so there is nothing to explore; "
            "add one, e.g. `explore pushes { contacts on faces +x, -x steps 9  force normal 1 N  duration 2 s }`",
            None,
            where,
        )
    specs: list[TrialSpec] = []
    for policy in body.explores:
        duration, magnitude = _check_common(body, policy)
        if policy.contacts is not None and policy.grasp is not None:
            raise _error(
                E_NO_ACTION,
                f"explore `{policy.name}` has both `contacts` and `grasp`; split them into two `explore` blocks",
                policy,
                where,
            )
        if policy.contacts is not None:
            specs += _push_trials(body, policy, magnitude, duration, len(specs))
        elif policy.grasp is not None:
            specs += _grasp_trials(body, policy, magnitude, duration, len(specs))
        else:
            raise _error(
                E_NO_ACTION,
                f"explore `{policy.name}` says neither where to touch the body nor what to hold: "
                "add `contacts on faces ... steps K` or `grasp FRAME`",
                policy,
                where,
            )
    return specs


def _check_common(body: Body, policy: Explore) -> tuple[float, float]:
    where = policy.span or body.name_span or body.span
    if policy.duration is None:
        raise _error(E_BAD_DURATION, f"explore `{policy.name}` has no `duration`; add e.g. `duration 2 s`", None, where)
    duration = float(policy.duration.value)
    if not np.isfinite(duration) or duration <= 0.0:
        raise _error(
            E_BAD_DURATION,
            f"the duration of explore `{policy.name}` must be positive, got {duration:g} s; "
            "give the simulated time of one trial, e.g. `duration 2 s`",
            policy.duration,
            where,
        )
    if policy.force is None:
        raise _error(
            E_BAD_FORCE,
            f"explore `{policy.name}` has no `force`; add `force normal 1 N` (pushes) "
            "or `force directions 3 x 3 x 3 1 N` (grasps)",
            None,
            where,
        )
    magnitude = float(policy.force.magnitude.value)
    if not np.isfinite(magnitude) or magnitude <= 0.0:
        raise _error(
            E_BAD_FORCE,
            f"the force of explore `{policy.name}` must be positive, got {magnitude:g} N; a zero force moves nothing",
            policy.force.magnitude,
            policy.force.span or where,
        )
    return duration, magnitude


def _push_trials(body: Body, policy: Explore, magnitude: float, duration: float, first: int) -> list[TrialSpec]:
    contacts = policy.contacts
    assert contacts is not None and policy.force is not None
    where = contacts.span or policy.span
    if policy.force.mode != "normal":
        raise _error(
            E_BAD_FORCE,
            f"explore `{policy.name}` pushes at contacts: its force must be "
            "`force normal Q` (along the face's inward normal)",
            policy.force,
            where,
        )
    if contacts.steps < 1:
        raise _error(E_BAD_STEPS, f"`steps` must be at least 1, got {contacts.steps}", contacts, where)
    mesh = body_mesh(body)
    specs = []
    for face in contacts.faces:
        outward = FACES.get(face)
        if outward is None:
            raise _error(E_BAD_FACE, f"there is no face `{face}`; faces are +x, -x, +y, -y, +z, -z", contacts, where)
        if face == "-z":
            raise _error(
                E_BAD_FACE,
                f"face -z of `{body.name}` is its underside, which lies on the table: "
                "the fingertip cannot reach it; explore side faces or +z",
                contacts,
                where,
            )
        line_axis, points = face_line(mesh, outward, contacts.steps)
        for k, point in enumerate(points):
            hit = surface_point(mesh, point, outward)
            if hit is None:
                along = "xyz"[int(np.argmax(line_axis))]
                raise _error(
                    E_NO_SURFACE,
                    f"face {face} of `{body.name}` has no surface at contact point {k + 1} "
                    f"of {contacts.steps} ({along} = {100 * point[int(np.argmax(line_axis))]:.1f} cm on its "
                    "centre line): the shape is hollow or flat there; use fewer steps or another face",
                    contacts,
                    where,
                )
            specs.append(
                TrialSpec(
                    index=first + len(specs),
                    body=body,
                    policy=policy.name,
                    kind="push",
                    contact=hit,
                    direction=-outward,
                    magnitude=magnitude,
                    duration=duration,
                    line_axis=line_axis,
                    label=f"{policy.name} {face} {k + 1}/{contacts.steps}",
                )
            )
    return specs


def _grasp_trials(body: Body, policy: Explore, magnitude: float, duration: float, first: int) -> list[TrialSpec]:
    assert policy.grasp is not None and policy.force is not None
    frame = body.frame(policy.grasp.name)
    if frame is None:
        known = ", ".join(f.name for f in body.frames) or "none"
        raise _error(
            E_UNKNOWN_FRAME,
            f"body `{body.name}` has no frame `{policy.grasp.name}` to grasp "
            f"(its frames: {known}); declare it with `frame {policy.grasp.name} = (x, y, z) cm`",
            policy.grasp,
            policy.span,
        )
    if policy.force.mode != "directions" or policy.force.grid is None:
        raise _error(
            E_BAD_FORCE,
            f"explore `{policy.name}` holds the body: its force must be `force directions I x J x K Q`",
            policy.force,
            policy.span,
        )
    grid = policy.force.grid
    if min(grid) < 1:
        raise _error(
            E_BAD_FORCE,
            f"a direction grid needs at least 1 point per axis, got {grid[0]} x {grid[1]} x {grid[2]}",
            policy.force,
            policy.span,
        )
    directions = direction_grid(grid)
    if not directions:
        raise _error(
            E_BAD_FORCE,
            "the direction grid 1 x 1 x 1 holds only the zero direction; use e.g. 3 x 3 x 3",
            policy.force,
            policy.span,
        )
    grasp = frame.pose.matrix()
    return [
        TrialSpec(
            index=first + i,
            body=body,
            policy=policy.name,
            kind="grasp",
            contact=grasp[:3, 3].copy(),
            direction=d,
            magnitude=magnitude,
            duration=duration,
            line_axis=np.zeros(3),
            grasp=grasp,
            label=f"{policy.name} direction ({d[0]:+.2f}, {d[1]:+.2f}, {d[2]:+.2f})",
        )
        for i, d in enumerate(directions)
    ]


def direction_grid(grid: tuple[int, int, int]) -> list[np.ndarray]:
    """Unit directions of the I x J x K grid over [-1, 1]^3 without its zero point, in lexicographic order."""
    axes = [np.linspace(-1.0, 1.0, n) if n > 1 else np.zeros(1) for n in grid]
    out = []
    for point in itertools.product(*axes):
        v = np.array(point, dtype=float)
        norm = float(np.linalg.norm(v))
        if norm > 1e-12:
            out.append(v / norm)
    return out


def face_line(mesh: trimesh.Trimesh, outward: np.ndarray, steps: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """The direction of a face's centre line and `steps` points on it, just outside the body.

    Side faces: the horizontal line at mid height; the top: the line along the
    longer horizontal side through the centre. Points sit at the centres of
    `steps` equal cells of the body's extent along the line, one body size
    outside the face (rays start there).
    """
    lo, hi = mesh.bounds
    centre = (lo + hi) / 2
    normal_axis = int(np.argmax(np.abs(outward)))
    if normal_axis == 2:
        line = 0 if hi[0] - lo[0] >= hi[1] - lo[1] else 1
    else:
        line = 1 - normal_axis  # the other horizontal axis
    direction = np.zeros(3)
    direction[line] = 1.0
    fractions = (np.arange(steps) + 0.5) / steps
    outside = centre + outward * (float(np.max(hi - lo)) + 1.0)
    points = []
    for f in fractions:
        p = outside.copy()
        p[line] = lo[line] + f * (hi[line] - lo[line])
        points.append(p)
    return direction, points


def surface_point(mesh: trimesh.Trimesh, start: np.ndarray, outward: np.ndarray) -> np.ndarray | None:
    """Where a ray from `start` along -outward first meets the body's surface, or None.

    (trimesh's own ray queries need the optional `rtree` package; a ray against
    every triangle plane plus trimesh's barycentric test is enough for one ray.)
    """
    direction = -np.asarray(outward, dtype=float)
    triangles = mesh.triangles
    normals = mesh.face_normals
    facing = np.abs(normals @ direction) > 1e-12
    if not facing.any():
        return None
    triangles, normals = triangles[facing], normals[facing]
    distance = np.einsum("ij,ij->i", triangles[:, 0] - start, normals) / (normals @ direction)
    points = start + distance[:, None] * direction
    barycentric = trimesh.triangles.points_to_barycentric(triangles, points)
    inside = (distance > 0) & np.all(barycentric >= -1e-9, axis=1)
    if not inside.any():
        return None
    first = int(np.argmin(np.where(inside, distance, np.inf)))
    return np.asarray(points[first], dtype=float)
