"""E420 and E426: bodies (and robot bases) that interpenetrate at the start, with where to move one to clear it,
and bodies on a joint too close to another where the simulator hangs them."""

from __future__ import annotations

import numpy as np

from vkgl.lang.checks.context import CheckContext
from vkgl.lang.checks.geometry.overlap_fix import clearing_move
from vkgl.lang.checks.geometry.placed import JOINT_GAP, TOUCH, Base, Placed, Table
from vkgl.lang.checks.geometry.placed import cm as _cm
from vkgl.lang.checks.geometry.placed import m as _m
from vkgl.lang.checks.geometry.placed import where as _where
from vkgl.lang.checks.geometry.solids import bounds, pieces_depth
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir.geometry import JOINT_LIFT


def check_overlaps(bodies: list[Placed], bases: list[Base], ctx: CheckContext, table: Table | None = None) -> None:
    """E420: pairs of bodies, and bodies and robot bases, that interpenetrate by more than TOUCH.

    Only pairs whose bounds overlap by more than TOUCH are compared piece by piece (a sort-and-sweep
    along x finds them), so a scene of thousands of bodies stays fast.
    """
    if not bodies:
        return
    lows, highs = np.array([b.low for b in bodies]), np.array([b.high for b in bodies])
    for i, j in _close_pairs(lows, highs):
        depth = pieces_depth(bodies[i].pieces, bodies[j].pieces)
        if depth > TOUCH:
            ctx.error(
                codes.BODIES_OVERLAP,
                f"`{bodies[i].name}` and `{bodies[j].name}` overlap by {_cm(depth)} at the start: move one of them",
                _where(bodies[j].scene_body),
                f"bodies may touch, but not interpenetrate by more than {TOUCH * 1000:g} mm",
                *_clearing_note(bodies[i], bodies[j], bodies, table),
            )
    for base in bases:
        low, high = bounds(base.pieces)
        near = np.all(np.minimum(highs, high) - np.maximum(lows, low) > TOUCH, axis=1)
        for k in np.flatnonzero(near):
            depth = pieces_depth(bodies[k].pieces, base.pieces)
            if depth > TOUCH:
                ctx.error(
                    codes.BODIES_OVERLAP,
                    f"`{bodies[k].name}` overlaps the base of robot `{base.name}` by {_cm(depth)} at the start: "
                    f"move it",
                    _where(bodies[k].scene_body),
                )


def check_joint_clearance(bodies: list[Placed], ctx: CheckContext) -> None:
    """E426: a body on a joint less than JOINT_GAP from another body where it hangs (not already E420)."""
    jointed = [k for k, b in enumerate(bodies) if b.body.joint is not None]
    if not jointed:
        return
    lows, highs = np.array([b.low for b in bodies]), np.array([b.high for b in bodies])
    for k in jointed:
        item = bodies[k]
        near = np.all(np.minimum(highs, item.high) - np.maximum(lows, item.low) > -JOINT_GAP, axis=1)
        for j in np.flatnonzero(near):
            if j == k or (j in jointed and j < k):  # each pair of jointed bodies once
                continue
            depth = pieces_depth(item.pieces, bodies[j].pieces)
            if -JOINT_GAP < depth <= TOUCH:
                gap = max(0.0, -depth)
                ctx.error(
                    codes.JOINT_BODY_TOUCHES,
                    f"`{item.name}` hangs on its joint {JOINT_LIFT * 1000:g} mm above where it is placed, as in "
                    f"simulation, and is {gap * 1000:.1f} mm from `{bodies[j].name}`: moving on its joint it "
                    f"would rub on `{bodies[j].name}` and drag it",
                    _where(item.scene_body),
                    f"leave at least {JOINT_GAP * 1000:g} mm between them where `{item.name}` hangs",
                )


def _clearing_note(first: Placed, second: Placed, bodies: list[Placed], table: Table | None) -> list[str]:
    """E420's suggestion: where the body to move (one placed relative to the other, else the second) clears
    every body it overlaps."""
    mover, other = (first, second) if _placed_in(first, second) else (second, first)
    others = [b.pieces for b in bodies if b is not mover and pieces_depth(mover.pieces, b.pieces) > TOUCH]
    floor = table.top if table is not None else None
    vertical = not mover.scene_body.placement.on_table  # a body on the table only slides on it
    # touching at most; a body on a joint JOINT_GAP clear (E426: touching, it would drag what it rubs on)
    touch = -JOINT_GAP if mover.body.joint is not None else 0.0
    found = clearing_move(mover.pieces, others or [other.pieces], touch, floor, vertical=vertical)
    if found is None:
        return []
    words, shift = found
    x, y, z = mover.pose[:3, 3] + shift
    if mover.body.joint is not None:  # checked where it hangs; written where it is placed, JOINT_LIFT lower
        z -= JOINT_LIFT
    note = f"`{mover.name}` clears it moved {words} by {_cm(float(np.linalg.norm(shift)))}, "
    note += f"to ({_m(x)}, {_m(y)}, {_m(z)}) m"
    ref = mover.scene_body.placement.relative_to
    if ref is None:
        return [note]
    host = next((b for b in bodies if b.name == ref.body), None)
    if host is None:
        return [note]
    local = host.pose[:3, :3].T @ shift  # the same move in the host's frame, where its type declares the frame
    moved = ", ".join(_m(v * 100) for v in local)
    return [
        note,
        f"it is placed at `{ref.body}.{ref.frame}`: move the frame `{ref.frame}` of `{host.body.name}` by ({moved}) cm",
    ]


def _placed_in(item: Placed, host: Placed) -> bool:
    ref = item.scene_body.placement.relative_to
    return ref is not None and ref.body == host.name


def _close_pairs(lows: np.ndarray, highs: np.ndarray, chunk: int = 512) -> list[tuple[int, int]]:
    """The pairs (i < j) of boxes that overlap by more than TOUCH along every axis, in order."""
    order = np.argsort(lows[:, 0], kind="stable")
    ends = np.searchsorted(lows[order, 0], highs[order, 0] - TOUCH, side="left")
    pairs: list[tuple[int, int]] = []
    for first in range(0, len(order), chunk):
        ks = np.arange(first, min(first + chunk, len(order)))
        counts = np.maximum(ends[ks] - ks - 1, 0)
        if not counts.any():
            continue
        left = np.repeat(ks, counts)
        right = left + 1 + np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        i, j = order[left], order[right]
        close = np.all(np.minimum(highs[i], highs[j]) - np.maximum(lows[i], lows[j]) > TOUCH, axis=1)
        pairs += zip(np.minimum(i, j)[close].tolist(), np.maximum(i, j)[close].tolist())
    return sorted(pairs)


__all__ = ["check_joint_clearance", "check_overlaps"]
