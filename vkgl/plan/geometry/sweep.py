"""Bodies moving along a prismatic or revolute motion, checked against the bodies that stay still.

The motion is the planner's (`vkgl.plan.graphs.motions.motion_matrices`): a body at
`F` moved by value `v` is at `F @ M(v)`, and whatever is rigidly attached to it
(a tool pushing it, a tool held against it) moves with it. `sweep` samples the
motion densely enough that no overlap can slip between two samples:

Sampling bound. Call an overlap of depth D a configuration where some point p
of a moving body lies inside a still body at distance >= D from that body's
surface (for a union: inside one part, from that part's surface). Every point
within `reach` of the frame origin moves along the motion by at most
`|dv|` (prismatic, v in metres) or `|dv| * (reach + |c|)` (revolute about a
line through the point c of the frame, v in radians: the arc of a point at
distance r <= reach + |c| from the axis). The samples are evenly spaced so
that this displacement bound between neighbours is at most `STEP`, so at any
configuration between samples the nearest sample is within `STEP / 2` of it
and every point has moved by at most `STEP / 2`. Since the distance of a point
to a surface changes by at most how far the point moves, p lies at depth
>= D - STEP / 2 inside the still body at that sample, and a body holding a
point that deep cannot be separated by any translation shorter than that, so
FCL's penetration depth there is >= D - STEP / 2. With D = `MAX_SLIP` (5 mm)
and STEP = 6 mm that is >= 2 mm > `TOUCH_TOL` (1 mm): the sample reports it,
with 1 mm to spare for the detector's depth error. So no overlap deeper than
5 mm can slip between samples. (The ends are always samples.)

Samples whose movers' bounding balls are apart from every still body's (and
from the table's slab) are not handed to FCL: that numpy test is conservative.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Iterable, Mapping

import numpy as np

from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.motion.collision import TABLE, TOUCH_TOL, CollisionScene, Contact, pair
from vkgl.plan.graphs.motions import motion_matrices, unit_axis_and_center
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem

MAX_SLIP = 0.005
"""m: no overlap deeper than this can slip between the samples of a sweep."""

STEP = 0.006
"""m: the largest displacement of any point of a mover between neighbouring samples (see the module's bound)."""

assert MAX_SLIP - STEP / 2 > TOUCH_TOL, "the sampling bound needs MAX_SLIP - STEP / 2 > TOUCH_TOL"


def sample_values(constraint: PrismaticC | RevoluteC, value: float, reach: float, step: float = STEP) -> np.ndarray:
    """Motion values from 0 to `value`, evenly spaced.

    No point within `reach` of the frame moves more than `step` between two of them.
    """
    _, center = unit_axis_and_center(constraint)
    lever = 1.0 if center is None else reach + float(np.linalg.norm(center))
    travel = abs(value) * lever
    return np.linspace(0.0, value, max(2, math.ceil(travel / step) + 1))


def sweep(
    scene: CollisionScene,
    frame: np.ndarray,
    constraint: PrismaticC | RevoluteC,
    value: float,
    movers: Mapping[str, np.ndarray],
    still: Mapping[str, np.ndarray],
    ignore: Iterable[frozenset[str]] = (),
    table: bool = True,
    step: float = STEP,
) -> list[Contact]:
    """The overlaps where a mover first hits a still body along a motion, at their deepest (`_deepest_after`); []
    if none does.

    `frame`: the world pose of the body whose affordance moves (the motion's
    frame); `movers`: the start world poses of everything that moves with it
    (that body included); `still`: the world poses of the bodies that stay;
    `ignore`: pairs allowed to overlap; `table`: whether the table counts.
    The sampling step keeps every point of every mover within `step` of its
    previous sample (module docstring: then no 5 mm overlap slips through).
    """
    frame = np.asarray(frame, dtype=float)
    inverse = np.linalg.inv(frame)
    relative = {name: inverse @ np.asarray(pose, dtype=float) for name, pose in movers.items()}
    reach = max(float(np.linalg.norm(rel[:3, 3])) + scene.radius[name] for name, rel in relative.items())
    motions = frame @ motion_matrices(constraint, sample_values(constraint, value, reach, step))
    scene.place(still)
    skip = set(ignore)
    targets: dict[str, list[tuple[str, np.ndarray]]] = {}  # mover -> [(still body, mask of samples near it)]
    for name, rel in relative.items():
        poses = motions @ rel
        centres = poses[:, :3, 3]
        near = []
        for other, pose in still.items():
            if other in relative or pair(name, other) in skip:
                continue
            gap = np.linalg.norm(centres - np.asarray(pose)[:3, 3], axis=1)
            mask = gap < scene.radius[name] + scene.radius[other]
            if mask.any():
                near.append((other, mask))
        if table and scene.table_box is not None and pair(name, TABLE) not in skip:
            mask = scene.near_table(name, poses)
            if mask.any():
                near.append((TABLE, mask))
        targets[name] = near
    candidates = sorted({int(k) for near in targets.values() for _, mask in near for k in np.flatnonzero(mask)})

    def hits(k: int) -> list[Contact]:
        found: list[Contact] = []
        for name, near in targets.items():
            others = [other for other, mask in near if mask[k]]
            if others:
                found.extend(scene.against(name, motions[k] @ relative[name], others))
        return found

    for i, k in enumerate(candidates):
        found = hits(k)
        if found:
            return _deepest_after(found, k, candidates[i + 1 :], hits)
    return []


def _deepest_after(
    found: list[Contact], k: int, later: list[int], hits: Callable[[int], list[Contact]]
) -> list[Contact]:
    """The overlaps of the deepest sample of the stretch that starts with the first hit `found` (at sample `k`):
    the samples after it are checked while they follow one another, overlap and go deeper. What a rejection says
    (and how close a miss it counts, `Rejection.excess`) is then how deep the mover goes into the body, not how
    deep it is at the first sample that touches: a cube pushed right through a slab overlapped it by 0.1 cm at
    its first overlapping sample and by 3 cm at the deepest (gen1_023 of the physical bench), and every such
    rejection read as a graze. Checked only once the motion is rejected, and only until the overlap stops growing
    (along a straight motion the depth of two convex bodies rises, then falls)."""
    deepest = max(c.depth for c in found)
    for n in later:
        if n != k + 1:
            break
        deeper = hits(n)
        if not deeper or max(c.depth for c in deeper) <= deepest:
            break
        found, k, deepest = deeper, n, max(c.depth for c in deeper)
    return found


def sweep_mode(
    scene: CollisionScene,
    problem: Problem,
    trace: ModeTrace,
    ignore: Iterable[frozenset[str]] = (),
    step: float = STEP,
    *,
    only: Collection[str] | None = None,
    table: bool = True,
) -> list[Contact]:
    """The overlaps along one mode of a rollout: every moving affordance's body and what moves with it vs the rest.

    `problem` gives the affordances' motions and the effectors' tools. The
    bodies that move with an engagement's body are found from the trace itself
    (their end pose is the start pose carried by the same rigid motion): the
    tool pushing it, a tool held against it. A tool and the body it acts on may
    touch (their pair is ignored, as are the `ignore` pairs). Bodies that do
    not move in the mode are the still ones; a body that moves but follows no
    engagement's motion is only checked at the mode's ends (by `overlap`).
    `only`: of the movers, check these alone (a tool against the bystanders, `bodies.BYSTANDER_CLEARANCE`);
    `table`: whether the table counts.
    """
    moving = {n for n in trace.start if not _close(trace.start[n], trace.end[n], 1e-9)}
    still = {n: p for n, p in trace.start.items() if n not in moving}
    skip = set(ignore)
    for e in trace.values:
        tool = problem.effector(e.effector).tool
        if tool is not None:
            skip.add(pair(tool, e.body))
    for frame, constraint, value, movers in moving_groups(problem, trace):
        if only is not None:
            movers = {name: pose for name, pose in movers.items() if name in only}
            if not movers:
                continue
        found = sweep(scene, frame, constraint, value, movers, still, skip, table=table, step=step)
        if found:
            return found
    return []


def moving_groups(
    problem: Problem, trace: ModeTrace
) -> Iterable[tuple[np.ndarray, PrismaticC | RevoluteC, float, dict[str, np.ndarray]]]:
    """Each motion of a mode: the moved body's start pose (the motion's frame), its motion, value, and the start
    poses of everything that moves rigidly with it (the body, a tool pushing it, a tool held against it)."""
    moving = {n for n in trace.start if not _close(trace.start[n], trace.end[n], 1e-9)}
    for e, value in trace.values.items():
        if value == 0.0 or e.body not in moving:
            continue
        constraint = problem.affordance(e.body, e.affordance).motion
        if not isinstance(constraint, (PrismaticC, RevoluteC)):  # only these carry motion values
            continue
        frame = trace.start[e.body]
        carried = frame @ motion_matrices(constraint, np.array([value]))[0] @ np.linalg.inv(frame)
        movers = {n: trace.start[n] for n in moving if _close(trace.end[n], carried @ trace.start[n], 1e-6)}
        movers[e.body] = frame
        yield frame, constraint, value, movers


def _close(a: np.ndarray, b: np.ndarray, atol: float) -> bool:
    """`np.allclose(a, b, atol=atol)` for finite poses, without its overhead (it is asked per body and mode)."""
    return bool((np.abs(a - b) <= atol + 1e-5 * np.abs(b)).all())
