"""A tool rolled over a wide body: its parts beside the contact pass over the body's top, not through its side.

The Hook's shaft lies 12 cm beside its tip. Lying flat at the middle of a 30
cm wide far face (the generated SlabW and CrateM) it would stand 4 cm inside
the body, and no contact along the face both clears the shaft and keeps the
cross-piece on the body's centre line (`vkgl.plan.graphs.tool_faces`). Off
the centre the pull turns the body, one way only: every pull of the hook turns
it clockwise (its shaft is on one side), and the opposite turn needs the
fingertip at the far face, beyond the arm's reach from where such pulls start
(docs/planning.md, "Wide hook pulls"). A person reaches over the body: the
hook rolled about the pull's direction, its shaft above the top and its
cross-piece slanting down behind the far face, pulls at the face's centre.

`over_members` offers that member for each slide of a goal body that a held
tool enacts lying flat only with a part standing in the body: the smallest
roll about the push direction (5 deg steps, then the least lift of the contact,
0.5 cm steps up to half-way from the written contact to the top) for which

- the tool's parts past the contact plane (the shaft) lie `PART_CLEARANCE`
  above the body's top or beside its width,
- no part of the tool comes within `TABLE_CLEARANCE` of the table, and
- the flat face (the cross-piece), where it is below the top, covers the
  body's centre line by `COVER_MARGIN` on both sides: the line contact then
  drives the body straight along the slide (as `tool_faces` argues).

The member is the same slide, its action rolled and raised
(`vkgl.lang.ir.families.over_member`, named `NAME/over+25deg+0.00cm`), and only
that tool may enact it (`PlanBody.tool_members`). The collision and arm checks
decide the rest, as for any contact.

An arc's member (`NAME@-1.74cm`, `vkgl.plan.problem.arcs`: the one push off the
centre that carries the body along an arc to a goal) is rolled the same way when
the tool lying flat at its offset would stand in the body: a Block's arc more
than 0.5 cm toward the Hook's shaft puts the shaft inside the Block's side. Its
offset is what makes its turn, so moving the contact along the face is no
alternative, and the rolled cross-piece must cover the contact itself, not the
centre line (a turn, not a straight pull). Named `NAME@-1.74cm/over+20deg+0.50cm`:
the turn the arc's member makes, enacted rolled and raised.

Both a slide and an arc's member are also rolled over the low bodies beside the contact (`roll_over_beside`,
`clearing_height`): the Hook's shaft, flat at a cube's mid-height, sweeps a CubeS or a Block standing 12 cm to the
side of the pull; rolled 15 to 30 deg it passes over them (the cross-piece on the centre line for a slide, on the
contact for an arc's member).
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.families import MEMBER_MARK, is_straight_member, over_member, over_name
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.nodes import Affordance, Body, FixedC, PrismaticC, RevoluteC, Shape, UnionShape

COVER_MARGIN = 0.01
"""m: a tool's flat face covers the body's centre line by at least this much on both sides (an uneven pressure
under the body moves its centre of friction off its origin)."""

PART_CLEARANCE = 0.005
"""m: a tool's parts past the contact plane (the hook's shaft) stay at least this far outside the body (the
collision checks of the approach and the sweep still decide with their own margins)."""

TABLE_CLEARANCE = 0.005
"""m: a rolled tool's lowest point stays this far above the table."""

FLAT = 0.001
"""m: a tool part whose far side lies within this of the contact plane is part of the flat face."""

ROLLS = np.radians(np.arange(5.0, 90.1, 5.0))
"""rad: the rolls tried, smallest first (the less the hand tilts, the farther the arm reaches)."""

MAX_BESIDE_ROLL = math.radians(45.0)
"""rad: the most a tool is rolled to pass over bodies beside its contact (`roll_over_beside`): the hand tilts with it,
and the grip carries the pull's torque about the shaft."""

MAX_BESIDE_HEIGHT = 0.10
"""m: bodies beside a contact taller than this are no body a rolled tool passes over (a 12 cm lever rolled 45 deg
lifts its part 8.5 cm)."""

MIN_ROLL_SAVED = math.radians(10.0)
"""rad: a contact raised past half-way is offered only when it rolls the tool at least this much less: a hand
tilted 35 deg reaches 0.694 m where 26 deg reaches 0.709 and 17.5 deg 0.731 (CrateM's rolled pull, IK from cold
starts), while each member offered costs the search (SlabW's 15 deg member besides its 20 deg one: its `free-`
goal 0, depth 6, ran out of its 40 CPU-s)."""

LIFT_STEP = 0.005
"""m: the contact is raised in these steps, up to half-way from the written contact to the body's top (higher where
the body's friction shows that the pull does not tip it there: `highest_lift`)."""

TIP_SHARE = 0.8
"""A contact raised past half-way keeps its height over the table times the body's friction under this share of
the body's half-depth along the push: a box pulled at height h with the force that slides it, friction times its
weight, tips about its leading bottom edge when friction times h exceeds its half-depth."""


def tool_parts(shape: Shape) -> list[np.ndarray]:
    """The vertices (n x 3, the tool's frame) of each convex part of a tool's shape: a union's parts, else the
    whole shape."""
    if isinstance(shape, UnionShape):
        return [shape_vertices(p.shape) @ p.pose.matrix()[:3, :3].T + p.pose.matrix()[:3, 3] for p in shape.parts]
    return [np.asarray(shape_vertices(shape))]


def over_members(
    affordances: tuple[Affordance, ...],
    body_points: np.ndarray,
    tools: list[tuple[str, Body, np.ndarray]],
    beside: float = 0.0,
    friction: float | None = None,
) -> tuple[tuple[Affordance, ...], frozenset[tuple[str, str]]]:
    """The rolled members (module docstring) of the slides among `affordances` of a body lying flat, whose hull
    points (body frame) are `body_points`, for each tool effector in `tools` (its name, the tool's type, its frame
    in the tool's frame); with the (member, effector) pairs that may enact them. `beside`: the height (m above the
    table) of the tallest other body that a tool at this body could sweep and a roll could pass over
    (`clearing_height`): a slide or an arc's member is also rolled so that the tool's parts beside the contact
    pass over it. `friction`: the body's (`Body.friction`): where raising the contact past half-way to the top,
    as high as the pull does not tip the body (`highest_lift`), lets a roll `MIN_ROLL_SAVED` smaller pass over
    it, that member is offered too, after the half-way one (the less the hand tilts, the farther the arm
    reaches); None: half-way only."""
    found: dict[str, Affordance] = {}
    pairs: set[tuple[str, str]] = set()
    for affordance in affordances:
        action = affordance.action
        turn = is_arc_turn(affordance)
        if not (isinstance(affordance.motion, PrismaticC) or turn):
            continue
        if not isinstance(action, FixedC) or action.pose is None:
            continue
        if action.pose.rpy is not None:
            continue  # only a level push: a yaw alone
        contact = action.pose.matrix()
        into_contact = np.linalg.inv(contact)
        body = body_points @ into_contact[:3, :3].T + into_contact[:3, 3]
        for effector, tool, frame in tools:
            frame_inverse = np.linalg.inv(frame)
            parts = [p @ frame_inverse[:3, :3].T + frame_inverse[:3, 3] for p in tool_parts(tool.shape)]
            pose = roll_for(parts, body, float(into_contact[1, 3]), turn=turn)
            if pose is None:  # an arc's member, or a straight pull with a low body beside it (gen11_015)
                pose = roll_over_beside(parts, body, beside, 0.0 if turn else float(into_contact[1, 3]))
            if pose is None:
                continue
            higher = roll_for(parts, body, float(into_contact[1, 3]), turn=turn, friction=friction)
            for chosen in (pose, higher):  # half-way first: where it works, the plan is the same
                if chosen is not None and (chosen is pose or abs(chosen[0]) <= abs(pose[0]) - MIN_ROLL_SAVED + 1e-9):
                    name = over_name(affordance.name, *chosen)
                    found.setdefault(name, over_member(affordance, *chosen).model_copy(update={"name": name}))
                    pairs.add((name, effector))
    return tuple(found.values()), frozenset(pairs)


def is_arc_turn(affordance: Affordance) -> bool:
    """Whether `affordance` is an arc's member (`NAME@+0.32cm`, `vkgl.plan.problem.arcs`): a turn made by a push
    at that offset along a slide's face."""
    name = affordance.name
    return isinstance(affordance.motion, RevoluteC) and MEMBER_MARK in name and not is_straight_member(name)


def roll_for(
    parts: list[np.ndarray],
    body: np.ndarray,
    centre: float,
    *,
    turn: bool = False,
    fixed: bool = False,
    friction: float | None = None,
) -> tuple[float, float] | None:
    """(roll in rad, lift in m) of the least rolled tool that passes over the body (module docstring), or None:
    the tool lying flat stands in nothing, it has no flat face or no part beside it, or no roll clears the top.

    `parts`: the tool's convex parts' vertices in its effector frame (x into the body, the contact plane at x = 0);
    `body`: the body's hull points in the same frame (lying flat: z up); `centre`: the body's origin along y.
    `turn`: the contact is an arc's member (a turn at its own offset): the flat face must cover the contact
    itself (y = 0), not the centre line, and moving it along the face is no alternative (the offset makes the arc).
    `fixed`: the contact was moved along the face already (`vkgl.plan.problem.reach_members`: for the hand's reach),
    so moving it back aside is no alternative either; the face covers the centre line as for a slide.
    `friction`: the body's, for the highest lift (`highest_lift`).
    """
    face = [p for p in parts if abs(float(p[:, 0].max())) <= FLAT]
    beside = [p for p in parts if float(p[:, 0].max()) > FLAT]
    if not face or not beside or not any(_stands_in(p, body) for p in beside):
        return None
    if not (turn or fixed) and _slides_aside(face, beside, body, centre):
        return None  # moved along the face it clears the body lying flat (`vkgl.plan.graphs.tool_faces`)
    covered = 0.0 if turn else centre
    side = 1.0 if np.mean([p[:, 1].mean() for p in beside]) > centre else -1.0
    bottom, top = float(body[:, 2].min()), float(body[:, 2].max())
    lifts = np.arange(0.0, highest_lift(body, friction) + 1e-9, LIFT_STEP)
    faces = [_face_grid(p) for p in face]
    for roll in side * ROLLS:
        for lift in lifts:
            rolled = [_rolled(p, float(roll), float(lift)) for p in parts]
            if min(float(p[:, 2].min()) for p in rolled) < bottom + TABLE_CLEARANCE:
                continue  # into the table
            if any(_stands_in(p, body) for p in rolled):  # (only parts past the contact plane can)
                continue
            if _covers(np.vstack([_rolled(g, float(roll), float(lift)) for g in faces]), bottom, top, covered):
                return float(roll), float(lift)
    return None


def highest_lift(body: np.ndarray, friction: float | None) -> float:
    """The most (m) a contact is raised from its written height: half-way to the body's top, or, where the body's
    `friction` is known, as high as the pull does not tip it (`TIP_SHARE` of its half-depth along the push over
    its friction, as height over the table), a lift step below its top. `body`: its hull points in the contact's
    frame (x into the body, z up, the contact at 0). The 18 cm CrateM (friction 0.5, 20 cm deep) may be pulled
    16 cm up, 7 cm over its mid-height, where a 20 deg roll passes the Hook's shaft over it (35 deg at half-way: a
    hand tilted so far reaches 4 cm less far); the 6 cm SlabW 2.5 cm over its mid-height (15 deg, 2 cm up)."""
    bottom, top = float(body[:, 2].min()), float(body[:, 2].max())
    half_way = max(0.0, top / 2)
    if friction is None or friction <= 0:
        return half_way
    half_depth = (float(body[:, 0].max()) - float(body[:, 0].min())) / 2
    untipped = bottom + TIP_SHARE * half_depth / friction  # the highest contact, in the contact's frame
    return max(half_way, min(top - LIFT_STEP, untipped))


def roll_over_beside(
    parts: list[np.ndarray], body: np.ndarray, height: float, covered: float = 0.0
) -> tuple[float, float] | None:
    """(roll in rad, 0) of the least roll (`ROLLS`, at most `MAX_BESIDE_ROLL`) that lifts the tool's parts beside
    the contact `PART_CLEARANCE` above bodies `height` m tall standing beside the body, where lying flat they would
    not clear them; None when they clear them flat, or no such roll keeps them out of the body, the cross-piece
    above the table and on the line `covered` (along y: the contact, 0, for an arc's member; the body's centre line
    for a straight slide, as in `roll_for`).

    Same frames as `roll_for`. The parts beside the contact (the Hook's shaft) lie at the contact's height, 12 cm to
    its side: a Block or a SlabN (5 cm tall) beside a cube's pull passes under a shaft rolled 15 to 20 deg, and
    more roll only loads the grip with its torque (the grip check decides).
    """
    face = [p for p in parts if abs(float(p[:, 0].max())) <= FLAT]
    beside = [p for p in parts if float(p[:, 0].max()) > FLAT]
    bottom, top = float(body[:, 2].min()), float(body[:, 2].max())
    over = bottom + height + PART_CLEARANCE  # the contact frame's height of the beside bodies' tops, and the margin
    if not face or not beside or height <= 0.0 or min(float(p[:, 2].min()) for p in beside) >= over:
        return None
    side = 1.0 if np.mean([p[:, 1].mean() for p in beside]) > 0.0 else -1.0
    faces = [_face_grid(p) for p in face]
    for roll in side * ROLLS[np.abs(ROLLS) <= MAX_BESIDE_ROLL + 1e-9]:
        rolled = [_rolled(p, float(roll), 0.0) for p in parts]
        if min(float(p[:, 2].min()) for p in rolled) < bottom + TABLE_CLEARANCE:
            return None  # more roll only lowers the cross-piece's free end further
        if any(_stands_in(p, body) for p in rolled):
            continue
        lifted = [_rolled(p, float(roll), 0.0) for p in beside]
        if min(float(p[:, 2].min()) for p in lifted) < over:
            continue
        if _covers(np.vstack([_rolled(g, float(roll), 0.0) for g in faces]), bottom, top, covered):
            return float(roll), 0.0
    return None


def clearing_height(
    rest: np.ndarray,
    points: np.ndarray,
    tools: list[Body],
    others: list[tuple[np.ndarray, np.ndarray]],
    table: float,
) -> float:
    """The height (m above the table top `table`) of the tallest body among `others` (each its world pose and hull
    points) that comes within a tool's length (the longest of `tools`) of the outline of the body resting at `rest`
    with hull points `points`, and is at most `MAX_BESIDE_HEIGHT` tall: what a tool rolled over the low bodies
    beside its contact must pass over. Taller bodies no small roll passes over: the collision checks decide about
    them as for any tool."""
    length = max(_diameter(np.vstack(tool_parts(tool.shape))) for tool in tools)
    reach = length + float(np.linalg.norm(points[:, :2], axis=1).max())
    tallest = 0.0
    for pose, hull in others:
        world = hull @ pose[:3, :3].T + pose[:3, 3]
        height = float(world[:, 2].max()) - table
        if height <= MAX_BESIDE_HEIGHT and float(np.hypot(*(world[:, :2] - rest[:2, 3]).T).min()) <= reach:
            tallest = max(tallest, height)
    return tallest


def _diameter(points: np.ndarray) -> float:
    """The largest distance between two of `points` (n x 3)."""
    return float(np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2).max())


def _slides_aside(face: list[np.ndarray], beside: list[np.ndarray], body: np.ndarray, centre: float) -> bool:
    """Whether the tool lying flat, moved along the face, still covers the centre line and clears the body's width:
    the band of `tool_faces.slide_band` is not empty."""
    low = centre + COVER_MARGIN - max(float(p[:, 1].max()) for p in face)
    high = centre - COVER_MARGIN - min(float(p[:, 1].min()) for p in face)
    for part in beside:  # at offset s the part spans its y + s: clear below or above the body's width
        below = (low, min(high, float(body[:, 1].min()) - float(part[:, 1].max()) - PART_CLEARANCE))
        above = (max(low, float(body[:, 1].max()) - float(part[:, 1].min()) + PART_CLEARANCE), high)
        low, high = max((below, above), key=lambda b: b[1] - b[0])
    return high - low >= 1e-4


def _rolled(points: np.ndarray, roll: float, lift: float) -> np.ndarray:
    """`points` rolled by `roll` about x (y toward z) and raised by `lift`."""
    c, s = math.cos(roll), math.sin(roll)
    y, z = points[:, 1], points[:, 2]
    return np.stack([points[:, 0], c * y - s * z, s * y + c * z + lift], axis=1)


def _stands_in(part: np.ndarray, body: np.ndarray) -> bool:
    """Whether a part's box of vertices comes within `PART_CLEARANCE` of the body's box, across the face (y) and
    in height (z), where it reaches past the contact plane (x > 0)."""
    if float(part[:, 0].max()) <= FLAT:
        return False
    across = (
        part[:, 1].min() < body[:, 1].max() + PART_CLEARANCE and part[:, 1].max() > body[:, 1].min() - PART_CLEARANCE
    )
    up = part[:, 2].min() < body[:, 2].max() + PART_CLEARANCE and part[:, 2].max() > body[:, 2].min()
    return bool(across and up)


def _face_grid(part: np.ndarray, n: int = 33) -> np.ndarray:
    """Points on a flat part's face in the contact plane (its y-z rectangle), n x n."""
    y = np.linspace(float(part[:, 1].min()), float(part[:, 1].max()), n)
    z = np.linspace(float(part[:, 2].min()), float(part[:, 2].max()), n)
    yy, zz = np.meshgrid(y, z)
    return np.stack([np.zeros(yy.size), yy.ravel(), zz.ravel()], axis=1)


def _covers(face: np.ndarray, bottom: float, top: float, centre: float) -> bool:
    """Whether the rolled face's points between the table and the body's top span the centre line ± the margin."""
    touching = face[(face[:, 2] >= bottom) & (face[:, 2] <= top), 1]
    return touching.size > 0 and touching.min() <= centre - COVER_MARGIN and touching.max() >= centre + COVER_MARGIN
