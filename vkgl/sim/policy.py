"""Exploration policies: a body's `explore` blocks checked and unrolled into trials.

A policy is a grid search (docs/method.md, "Exploration"):

- `contacts on faces F... steps K` with `force normal Q`: K contact points
  along the centre line of each named face (the horizontal line at mid height
  of a side face; the line along the longer horizontal side for `+z`), at the
  centres of K equal cells; the force pushes along the face's inward normal.
  `heights H` repeats the line at H heights up a side face (the centres of H
  equal cells of the body's height, lowest first), so that exploration finds
  the heights at which a push tips the body.
- `contacts at FRAME, ...` with `force normal Q`: one contact per frame, at
  its origin, the force along its x axis (the effector frame convention: x
  into the touched surface), e.g. behind a handle's bar, pulling the body.
- `grasp FRAME` with `force directions I x J x K Q`: the effector holds the
  body at FRAME; the directions are the points of the I x J x K grid over
  [-1, 1]^3 (a count of 1 gives 0 on that axis) without the zero point,
  normalised; the force has the declared magnitude.

A body on a physical joint is explored from both ends of its joint's range:
every grid point is tried once with the joint at its lower limit and once at
its upper limit (in that order, block by block), so that a push that closes a
drawer and a pull that opens it both find something to move.

The policy is taken as checked: every rule about an `explore` block (a push
or a grasp, positive force and duration, reachable faces, contact points on the
surface) is a diagnostic of vkgl/lang/checks/explore.py, reported when the
program compiles. Only a body with no `explore` block at all is an InputError
here: it is a legal body, but there is nothing to explore.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np

from vkgl.errors import InputError
from vkgl.lang.ir.geometry import FACES, at_heights, body_mesh, face_line, surface_point
from vkgl.lang.ir.nodes import Body, Explore
from vkgl.lang.ir.units import SCALE


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
    joint_start: float | None = None  # where a jointed body's joint starts (SI); None: its declared pose


def plan_trials(body: Body) -> list[TrialSpec]:
    """All trials of all `explore` blocks of `body`, in declaration order.

    `body` must come from a checked program (vkgl.compile); raises InputError
    when it has no `explore` block.
    """
    if not body.explores:
        where = body.name_span or body.span
        raise InputError(
            f"{where if where is not None else '<input>'}: body `{body.name}` has no `explore` block, "
            "so there is nothing to explore; add one, e.g. "
            "`explore pushes { contacts on faces +x, -x steps 9  force normal 1 N  duration 2 s }`"
        )
    specs: list[TrialSpec] = []
    for policy in body.explores:
        assert policy.force is not None and policy.duration is not None, "explore blocks are checked"
        magnitude, duration = float(policy.force.magnitude.value), float(policy.duration.value)
        if policy.contacts is not None and policy.contacts.frames:
            grid = _frame_trials(body, policy, magnitude, duration)
        elif policy.contacts is not None:
            grid = _push_trials(body, policy, magnitude, duration)
        else:
            grid = _grasp_trials(body, policy, magnitude, duration)
        for start, suffix in joint_starts(body):
            specs += [
                dataclasses.replace(spec, index=len(specs) + k, joint_start=start, label=spec.label + suffix)
                for k, spec in enumerate(grid)
            ]
    return specs


def joint_starts(body: Body) -> list[tuple[float | None, str]]:
    """Where each grid point starts: (joint position, label suffix); both limits for a body on a joint."""
    if body.joint is None:
        return [(None, "")]
    lower, upper = float(body.joint.lower.value), float(body.joint.upper.value)
    unit = body.joint.upper.unit or ("cm" if body.joint.type == "prismatic" else "deg")
    ends: list[tuple[float | None, str]] = [(lower, f", from its lower limit ({_shown(lower, unit)})")]
    if upper > lower:
        ends.append((upper, f", from its upper limit ({_shown(upper, unit)})"))
    return ends


def _shown(value: float, unit: str) -> str:
    return f"{value / float(SCALE.get(unit, 1.0)):g} {unit}"


def _push_trials(body: Body, policy: Explore, magnitude: float, duration: float) -> list[TrialSpec]:
    contacts = policy.contacts
    assert contacts is not None
    mesh = body_mesh(body)
    specs: list[TrialSpec] = []
    for face in contacts.faces:
        outward = FACES[face]
        line_axis, points = face_line(mesh, outward, contacts.steps)
        for k, up, point in at_heights(mesh, points, contacts.heights):
            hit = surface_point(mesh, point, outward)
            assert hit is not None, "contact points are checked (E415)"
            specs.append(
                TrialSpec(
                    index=len(specs),
                    body=body,
                    policy=policy.name,
                    kind="push",
                    contact=hit,
                    direction=-outward,
                    magnitude=magnitude,
                    duration=duration,
                    line_axis=line_axis,
                    label=f"{policy.name} {face} {k + 1}/{contacts.steps}" + _height_label(up, contacts.heights),
                )
            )
    return specs


def _height_label(up: float, heights: int) -> str:
    return f" at {100 * up:.1f} cm" if heights > 1 else ""  # mid-height pushes keep their old labels


def _frame_trials(body: Body, policy: Explore, magnitude: float, duration: float) -> list[TrialSpec]:
    """`contacts at FRAME, ...`: at each frame's origin, along its x axis (a check put it on the surface)."""
    assert policy.contacts is not None
    specs: list[TrialSpec] = []
    for ref in policy.contacts.frames:
        frame = body.frame(ref.name)
        assert frame is not None, "contact frames are checked (E303)"
        pose = frame.pose.matrix()
        specs.append(
            TrialSpec(
                index=len(specs),
                body=body,
                policy=policy.name,
                kind="push",
                contact=pose[:3, 3].copy(),
                direction=pose[:3, 0].copy(),
                magnitude=magnitude,
                duration=duration,
                line_axis=pose[:3, 1].copy(),
                label=f"{policy.name} at {ref.name}",
            )
        )
    return specs


def _grasp_trials(body: Body, policy: Explore, magnitude: float, duration: float) -> list[TrialSpec]:
    assert policy.grasp is not None and policy.force is not None and policy.force.grid is not None
    frame = body.frame(policy.grasp.name)
    assert frame is not None, "grasp frames are checked (E303)"
    grasp = frame.pose.matrix()
    return [
        TrialSpec(
            index=i,
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
        for i, d in enumerate(direction_grid(policy.force.grid))
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
