"""E420 and E426: bodies (and robot bases) that interpenetrate at the start, with where to move one to clear it,
and bodies on a joint too close to another where the simulator hangs them."""

from __future__ import annotations

from collections.abc import Sequence

from vkgl.lang.checks.context import CheckContext
from vkgl.lang.checks.geometry.placed import JOINT_GAP, TOUCH, Base, Placed, Table
from vkgl.lang.checks.geometry.placed import cm as _cm
from vkgl.lang.checks.geometry.placed import m as _m
from vkgl.lang.checks.geometry.placed import where as _where
from vkgl.lang.checks.geometry.rigid import Vec3, add, norm, rotate, transposed
from vkgl.lang.checks.geometry.solids import bounds, pieces_depth
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir.nodes import JOINT_LIFT


def check_overlaps(bodies: list[Placed], bases: list[Base], ctx: CheckContext, table: Table | None = None) -> None:
    """E420: pairs of bodies, and bodies and robot bases, that interpenetrate by more than TOUCH.

    Only pairs whose bounds overlap by more than TOUCH are compared piece by piece (a sort-and-sweep
    along x finds them), so a scene of thousands of bodies stays fast.
    """
    if not bodies:
        return
    for i, j in _close_pairs([b.low for b in bodies], [b.high for b in bodies]):
        depth = pieces_depth(bodies[i].pieces, bodies[j].pieces, TOUCH)
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
        for k, item in enumerate(bodies):
            if not _boxes_overlap(item.low, item.high, low, high, TOUCH):
                continue
            depth = pieces_depth(bodies[k].pieces, base.pieces, TOUCH)
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
    for k in jointed:
        item = bodies[k]
        for j, other in enumerate(bodies):
            if j == k or (j in jointed and j < k):  # each pair of jointed bodies once
                continue
            if not _boxes_overlap(other.low, other.high, item.low, item.high, -JOINT_GAP):
                continue
            depth = pieces_depth(item.pieces, bodies[j].pieces, -JOINT_GAP)
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
    from vkgl.lang.checks.geometry.overlap_fix import clearing_move  # only for a scene with an overlap

    mover, other = (first, second) if _placed_in(first, second) else (second, first)
    others = [b.pieces for b in bodies if b is not mover and pieces_depth(mover.pieces, b.pieces, TOUCH) > TOUCH]
    floor = table.top if table is not None else None
    vertical = not mover.scene_body.placement.on_table  # a body on the table only slides on it
    # touching at most; a body on a joint JOINT_GAP clear (E426: touching, it would drag what it rubs on)
    touch = -JOINT_GAP if mover.body.joint is not None else 0.0
    found = clearing_move(mover.pieces, others or [other.pieces], touch, floor, vertical=vertical)
    if found is None:
        return []
    words, shift = found
    x, y, z = add(mover.pose[1], shift)
    if mover.body.joint is not None:  # checked where it hangs; written where it is placed, JOINT_LIFT lower
        z -= JOINT_LIFT
    note = f"`{mover.name}` clears it moved {words} by {_cm(norm(shift))}, "
    note += f"to ({_m(x)}, {_m(y)}, {_m(z)}) m"
    ref = mover.scene_body.placement.relative_to
    if ref is None:
        return [note]
    host = next((b for b in bodies if b.name == ref.body), None)
    if host is None:
        return [note]
    local = rotate(transposed(host.pose[0]), shift)  # the same move in the host's frame, where its type declares it
    moved = ", ".join(_m(v * 100) for v in local)
    return [
        note,
        f"it is placed at `{ref.body}.{ref.frame}`: move the frame `{ref.frame}` of `{host.body.name}` by ({moved}) cm",
    ]


def _placed_in(item: Placed, host: Placed) -> bool:
    ref = item.scene_body.placement.relative_to
    return ref is not None and ref.body == host.name


def _boxes_overlap(
    low_a: Sequence[float], high_a: Sequence[float], low_b: Sequence[float], high_b: Sequence[float], by: float
) -> bool:
    """Whether two axis-aligned boxes overlap by more than `by` along every axis."""
    return all(min(high_a[k], high_b[k]) - max(low_a[k], low_b[k]) > by for k in range(3))


def _close_pairs(lows: list[Vec3], highs: list[Vec3]) -> list[tuple[int, int]]:
    """The pairs (i < j) of boxes that overlap by more than TOUCH along every axis, in order.

    Sort and sweep: along x, each box is compared with the boxes that start before it ends."""
    order = sorted(range(len(lows)), key=lambda k: lows[k][0])
    pairs: list[tuple[int, int]] = []
    for place, i in enumerate(order):
        end = highs[i][0] - TOUCH
        for later in range(place + 1, len(order)):
            j = order[later]
            if not lows[j][0] < end:
                break
            if _boxes_overlap(lows[i], highs[i], lows[j], highs[j], TOUCH):
                pairs.append((min(i, j), max(i, j)))
    return sorted(pairs)


__all__ = ["check_joint_clearance", "check_overlaps"]
