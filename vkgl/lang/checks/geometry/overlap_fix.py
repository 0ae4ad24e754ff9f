"""Where a body would clear an overlap at the start (E420's suggestion).

A drawer 5 mm too low in its cabinet is reported with the position that
clears it: of the six moves along the world axes, the shortest that leaves the
body interpenetrating nothing it overlapped by more than the touch tolerance
(bisection on each axis, to a tenth of a millimetre). For a body placed
relative to another (`in B`, `at B.F`) the note also says how to change the
frame of B's type that placed it.
"""

from __future__ import annotations

from vkgl.lang.checks.geometry.rigid import Vec3, scaled
from vkgl.lang.checks.geometry.solids import Piece, lowest, pieces_depth

AXES = (
    ("up", (0, 0, 1)),
    ("along +x", (1, 0, 0)),
    ("along -x", (-1, 0, 0)),
    ("along +y", (0, 1, 0)),
    ("along -y", (0, -1, 0)),
    ("down", (0, 0, -1)),
)
"""The moves tried, in this order of preference when two are equally short (lifting is the usual fix)."""

RESOLUTION = 1e-4
"""m: how finely the clearing distance is found."""

SCAN = 0.002
"""m: the step of the scan along each axis, before the bisection."""

REACH = 0.3
"""m: the longest move suggested."""


def clearing_move(
    moving: list[Piece], others: list[list[Piece]], touch: float, floor: float | None = None, *, vertical: bool = True
) -> tuple[str, Vec3] | None:
    """The shortest axis move (its words and the displacement vector, m) after which `moving` interpenetrates
    none of `others` by more than `touch` and (given a `floor`, the table top) does not sink below the floor;
    None when no move of up to `REACH` does. Each axis is scanned in `SCAN` steps (a drawer may clear its
    cabinet's bottom board a few millimetres up and hit its top board further on), then bisected. Without
    `vertical` only the horizontal moves are tried (a body resting on the table)."""
    bottom = lowest(moving)
    best: tuple[float, str, Vec3] | None = None
    for words, axis in AXES:
        direction = (float(axis[0]), float(axis[1]), float(axis[2]))
        if direction[2] and not vertical:
            continue
        if floor is not None and direction[2] < 0 and bottom - SCAN < floor - touch:
            continue
        distances = [k * SCAN for k in range(1, int(REACH / SCAN) + 1)]
        free = next((d for d in distances if not _overlaps(moving, scaled(direction, d), others, touch)), None)
        if free is None:
            continue
        low, high = free - SCAN, free
        while high - low > RESOLUTION:
            middle = (low + high) / 2
            low, high = (middle, high) if _overlaps(moving, scaled(direction, middle), others, touch) else (low, middle)
        if floor is not None and bottom + direction[2] * high < floor - touch:
            continue
        if best is None or high < best[0] - RESOLUTION:
            best = (high, words, scaled(direction, high))
    return None if best is None else (best[1], best[2])


def _overlaps(moving: list[Piece], shift: Vec3, others: list[list[Piece]], touch: float) -> bool:
    moved = [p.shifted(shift) for p in moving]
    return any(pieces_depth(moved, other, touch) > touch for other in others)


__all__ = ["clearing_move"]
