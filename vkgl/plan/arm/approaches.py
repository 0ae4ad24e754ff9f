"""The ways into a contact the planner tries, in order, and how a failed search over them is told.

A way in is a direction (world, unit: the way the hand, or the tool it holds,
moves into the contact) and a stand-off (m: how far back from the contact the
straight move starts). `StraightMoves.into_contact` tries them in this order
and takes the first that is clear, has a straight IK path and lets the
transit end at its start:

1. the three rules (`rules`), as before: along the push, from above, and
   `SLANT` below the push;
2. only when all three fail, the search (`searched`), at most `MAX_SEARCHED`
   ways, deterministic, closest to the push direction first:

   - a cone about the push direction: `CONE_ANGLES` off it, at 8 azimuths
     each (the azimuths with the stand-off above the contact first, those
     below it last: above is where the room usually is over a table);
   - from the side along the bar: level along the contact's horizontal
     axis across the push (a handle's bar, a hook's cross-piece: the
     fingertip or the cross-piece slides in behind the bar from its end),
     either way, then `SIDE_TILT` higher and lower;
   - shorter stand-offs (`SHORT_STANDOFF`: a narrow gap leaves no room for
     3 cm) along the push, from above and from either side, then a longer one
     (`LONG_STANDOFF`: a transit that cannot end 3 cm back may end farther).

How the arm leaves a contact depends on the way it came in
(`vkgl.motion.moves.way_out`: straight up after coming down, back against the
push after coming in near it, else back out the way it came); the planner
checks that move (`StraightMoves.leave`, `StraightMoves.retreat`) and
execution makes it (`vkgl.execute.steps`).

The cost, measured with `bench/plan/bench_approaches.py` (the Hook behind the
Drawer's bar; 2 cores shared, load 12): one way costs one chained IK of 7 to
13 poses and their collision checks, 2 to 6 ms; the contact a ledge leaves
only the side open is reached at the 20th way in 40 ms; one none of the
3 + 28 ways reaches costs 145 ms (where the three rules alone cost 11 ms).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vkgl.motion.moves import STANDOFF

SLANT = np.radians(30.0)
"""rad: below the push direction, the last rule tried into a contact (after along the push and from above);
less than 45 deg, so that execution leaves such a contact straight back, as `StraightMoves.leave` checks."""

CONE_ANGLES = tuple(np.radians((20.0, 40.0)))
"""rad off the push direction of the searched cone's ways (less than 45 deg: see the module's docstring)."""

AZIMUTHS = tuple(np.radians((90.0, 45.0, 135.0, 0.0, 180.0, -45.0, -135.0, -90.0)))
"""rad about the push direction, 90 deg: the stand-off above the contact, 0 and 180 deg: beside it, level;
ordered so that the ways from above come first and those from below last."""

SIDE_TILT = np.radians(30.0)
"""rad: the side ways tried higher (the stand-off above the level side way) and lower."""

SHORT_STANDOFF = 0.015
"""m: the shorter stand-off tried (a fingertip or a cross-piece in a narrow gap)."""

LONG_STANDOFF = 0.06
"""m: the longer stand-off tried (the transit's end farther from what is near the contact)."""

MAX_SEARCHED = 28
"""The most ways the search tries into one contact (after the three rules): 16 in the cone, 6 from the side,
4 shorter and 2 longer."""

DOWN = np.array([0.0, 0.0, -1.0])


@dataclass(frozen=True)
class Way:
    """A way into a contact: `direction` (world, unit, into the contact), `standoff` (m), its `name` in a
    reason, and its `family` (the summary counts ways by family)."""

    name: str
    family: str
    direction: np.ndarray
    standoff: float = STANDOFF


def rules(push: np.ndarray) -> list[Way]:
    """The three rules, in order: along the push, from above, `SLANT` below the push."""
    slanted = np.cos(SLANT) * push + np.sin(SLANT) * DOWN
    return [
        Way("along the push", "along the push", push),
        Way("from above", "from above", DOWN),
        Way(
            f"{np.degrees(SLANT):.0f} deg below the push",
            f"{np.degrees(SLANT):.0f} deg below the push",
            slanted / np.linalg.norm(slanted),
        ),
    ]


def searched(push: np.ndarray) -> list[Way]:
    """The search's ways into a contact pushing along `push` (world, unit), in the order they are tried;
    at most `MAX_SEARCHED`, none repeating a rule."""
    side, up = _across(push)
    ways: list[Way] = []
    for angle in CONE_ANGLES:
        family = f"in a {np.degrees(CONE_ANGLES[-1]):.0f} deg cone about the push"
        for azimuth in AZIMUTHS:
            # the stand-off lies toward `side` at azimuth 0 and above at 90 deg: the way in points from there
            off = -(np.cos(azimuth) * side + np.sin(azimuth) * up)
            way = np.cos(angle) * push + np.sin(angle) * off
            name = f"{np.degrees(angle):.0f} deg off the push ({_where(azimuth)})"
            ways.append(Way(name, family, _unit(way)))
    side_family = "from the side along the bar (level, higher and lower)"
    for tilt, level in ((0.0, ""), (SIDE_TILT, ", higher"), (-SIDE_TILT, ", lower")):
        for sign, end in ((1.0, "one end"), (-1.0, "the other end")):
            # the stand-off toward `sign * side`, `tilt` above the level way (below for a negative tilt)
            way = -sign * np.cos(tilt) * side + np.sin(tilt) * DOWN
            ways.append(Way(f"from the side along the bar, from {end}{level}", side_family, _unit(way)))
    short = [push, DOWN, -side, side]
    for way, what in zip(short, ("along the push", "from above", "from one side", "from the other side")):
        ways.append(Way(f"{what}, {SHORT_STANDOFF * 100:g} cm back", "shorter", way, SHORT_STANDOFF))
    for way, what in zip((push, DOWN), ("along the push", "from above")):
        ways.append(Way(f"{what}, {LONG_STANDOFF * 100:g} cm back", "longer", way, LONG_STANDOFF))
    return ways[:MAX_SEARCHED]


def summary(tried: Sequence[Way]) -> str:
    """The ways tried, counted by family in the order first tried: "tried 31 approaches: along the push, from
    above, 30 deg below the push, 16 in a 40 deg cone about the push, ..."."""
    counts: dict[str, int] = {}
    for way in tried:
        counts[way.family] = counts.get(way.family, 0) + 1
    parts = []
    for family, count in counts.items():
        if family in ("shorter", "longer"):
            standoff = SHORT_STANDOFF if family == "shorter" else LONG_STANDOFF
            parts.append(f"{count} with a {family} stand-off ({standoff * 100:g} cm)")
        else:
            parts.append(family if count == 1 else f"{count} {family}")
    noun = "approach" if len(tried) == 1 else "approaches"
    return f"tried {len(tried)} {noun}: " + ", ".join(parts)


def _across(push: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors across `push`: `side`, horizontal (along a handle's bar across the push), and `up`,
    the rest of the world's up across the push. A vertical push has no horizontal across it: world x then."""
    side = np.cross(np.array([0.0, 0.0, 1.0]), push)
    if np.linalg.norm(side) < 1e-6:
        side = np.cross(push, np.array([0.0, 1.0, 0.0]))
    side = _unit(side)
    return side, _unit(np.cross(push, side))


def _where(azimuth: float) -> str:
    """Where an azimuth of `AZIMUTHS` puts the stand-off, in words."""
    degrees = round(float(np.degrees(azimuth)))
    return {
        90: "from above",
        45: "from above and one side",
        135: "from above and the other side",
        0: "from one side",
        180: "from the other side",
        -45: "from below and one side",
        -135: "from below and the other side",
        -90: "from below",
    }[degrees]


def _unit(vector: np.ndarray) -> np.ndarray:
    return np.asarray(vector, dtype=float) / float(np.linalg.norm(vector))


__all__ = [
    "AZIMUTHS",
    "CONE_ANGLES",
    "LONG_STANDOFF",
    "MAX_SEARCHED",
    "SHORT_STANDOFF",
    "SIDE_TILT",
    "SLANT",
    "Way",
    "rules",
    "searched",
    "summary",
]
