"""How far a body may end from where its arcs' law puts it: the margin its goal keeps for that error.

An arc member (`NAME@+S.SScm`, rolled or not: `vkgl.lang.ir.arcs`) is a prediction with an error its family
states: `sigma`, the law's RMS error in the turn over 10 cm of the contact's travel (`arc_turn_error`).

Where the contact is flat along the face (the arm's 2 cm pad, the hook's cross-piece) it holds the planned arc:
its force line moves to wherever along it the body's own arc is the planned one (docs/planning.md, "Arcs": "what
DART keeps is the learned arc of a force line that crosses the pad"), so the plans of the Block's pad arcs end
within 0.1 cm and 0.1 deg of the law in DART, the rolled hook's 71 deg arc of CrateM 7.5 cm off its centre within
0.16 cm and 0.10 deg, although sigma over those pulls is 1 to 4 deg. That holds while the flat part reaches, inside
the family's band and the body's face, the offsets whose law turns one sigma faster and one sigma slower than the
planned arc (`holds_arc`). Where it does not, the law's error is the body's: CrateM pulled by the hook at its far
face's band edge (`@+13.33cm`, the cross-piece reaching no farther out in the band) turned 1.54 deg less in DART
than the law's 76 deg (sigma 0.53 deg over 10 cm, 31 cm of travel: 1.6 deg), its contact sliding 0.5 cm along the
face, and a plan that ended 0.78 cm from its goal (tolerance 1 cm) missed it by 1.07 cm. A plan is a promise, so
an accepted solution keeps such errors inside each goal body's tolerance (`feasible.goal_holds`, `margins`).

A family whose law holds `beyond` an offset (`arc ... beyond D`, docs/language.md) does not know how fast its
members nearer the centre turn, only that it is between none (the slide at the centre) and the law's turn at `D`.
A flat contact holds such a member's arc when it reaches both where the body surely turns slower and where it
surely turns faster (the centre, or past `D`); any other contact, a point's among them, promises nothing there
(`UNKNOWN_TURN`): CrateT's members 0.24 to 2 cm off its centre turned 3.7 to 14 deg less over 10 cm in DART than
its law, whose sigma (0.34 deg) was measured from 2.67 cm out.

The tool carries its contact along the planned path (the executor tracks it to 0.02 cm): what the law gets wrong
is how fast the body turns about that contact. A turn error `e` about the contact `c` at the end of the member's
motion moves the body's final position by `e * |p - c|` (to first order; later motions are the body's own, so they
carry the error along) and its heading by `e`. The errors of several arcs add.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.arcs import SIGMA_TRAVEL, arc_lever_arm, arc_turn_error, law_beyond, law_known
from vkgl.lang.ir.families import is_straight_member, member_offset, over_pose
from vkgl.lang.ir.nodes import Arc
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import action_at, arc_seed
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, mode_values
from vkgl.plan.problem.over import FLAT, tool_parts
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.robot.pad import FINGER_PAD_WIDTH
from vkgl.se3 import screw_motion, wrap_angle, yaw_of

POINT_SIGMAS = 2.0
"""How many of its law's sigmas an arc enacted by a point contact (the hand turned about its axis) is kept inside its
goal by (`point_margins`). Not one: the hand follows the planned arc while the body turns at its own rate, so the
contact slides along the face and the error feeds itself (gen15_028 of the physical bench: CubeS turned 22.8 deg
past the law's 69, twice its sigma over the 28 cm of travel)."""


def arc_law(problem: Problem, body: str, name: str) -> tuple[Arc, float, float] | None:
    """(the law, its sigma in rad over 10 cm, the member's own offset in m) of `name` when it names a member of an
    arc family (`push@+3.12cm`, or rolled: `push@-1.74cm/over+20deg+0.50cm`) whose family states its sigma; None
    for anything else (a written affordance, a straight member, a family without `arc` or `sigma`)."""
    over = over_pose(name)
    base = over[0] if over is not None else name
    if is_straight_member(base):
        return None
    slide_name, offset = member_offset(base)
    if slide_name == base or offset == 0.0:
        return None
    slide = next((a for a in problem.bodies[body].affordances if a.name == slide_name), None)
    family = None if slide is None else slide.family
    if family is None or family.arc is None or family.sigma is None:
        return None
    return family.arc, float(family.sigma.value), offset


def holds_arc(problem: Problem, engagement: Engagement, offset: float) -> bool:
    """Whether the contact enacting the arc member `engagement` (at `offset`, m, along its family) holds the planned
    arc against the law's error: its flat part reaches, inside the family's band and the body's face, the offsets
    whose law turns sigma faster and sigma slower per metre of travel (the module's docstring)."""
    law = arc_law(problem, engagement.body, engagement.affordance)
    if law is None:
        return True
    arc, sigma, _ = law
    slide_name = member_offset(_unrolled(engagement.affordance))[0]
    slide = problem.affordance(engagement.body, slide_name)
    assert slide.family is not None  # `arc_law` found its arc
    along = slide.family.along.array() / np.linalg.norm(slide.family.along.array())
    low, high = _flat_span(problem, engagement, along)
    centre = float(problem.action(engagement.body, slide_name)[:3, 3] @ along)  # the contact at offset 0
    face = problem.footprint_points(engagement.body) @ along - centre
    inner = max(offset + low, float(slide.family.lower.value), float(face.min()))
    outer = min(offset + high, float(slide.family.upper.value), float(face.max()))
    planned, spread = _rate(arc, offset), sigma / SIGMA_TRAVEL
    return (
        inner <= outer
        and _rate_at_most(arc, inner) <= planned - spread
        and _rate_at_least(arc, outer) >= planned + spread
    )


def _rate(arc: Arc, offset: float) -> float:
    """The law's turn per metre of the contact's travel at `offset` (signed: the sense of a push at `offset`;
    increasing with the offset, 0 at the centre)."""
    return 0.0 if offset == 0.0 else math.copysign(1.0 / arc_lever_arm(arc, offset), offset)


def _rate_at_most(arc: Arc, offset: float) -> float:
    """The most the body may turn per metre at `offset`: the law's rate where it is known (`law_known`), else the
    rate at the nearest known offset above it (the centre's 0, or the law's at `beyond`): the turn grows with the
    offset."""
    if law_known(arc, offset):
        return _rate(arc, offset)
    return 0.0 if offset < 0.0 else _rate(arc, law_beyond(arc))


def _rate_at_least(arc: Arc, offset: float) -> float:
    """The least the body may turn per metre at `offset` (`_rate_at_most`'s mirror: the nearest known offset
    below it)."""
    return -_rate_at_most(arc, -offset)


def _turn_error(arc: Arc, sigma: float, offset: float, turn: float) -> float:
    """The law's error (rad) in the turn `turn` of its member at `offset`: `arc_turn_error` where the law is known,
    else `UNKNOWN_TURN`."""
    return arc_turn_error(arc, sigma, offset, turn) if law_known(arc, offset) else UNKNOWN_TURN


UNKNOWN_TURN = math.pi
"""rad: the error of a member's turn where its law is not known (nearer the centre than its `beyond`,
`vkgl.lang.ir.arcs.law_known`) and its contact does not hold the planned arc: anything up to half a turn, so that
no goal is promised by it (CrateT's law there turned 13 to 14 deg faster over 10 cm than DART)."""


def _flat_span(problem: Problem, engagement: Engagement, along: np.ndarray) -> tuple[float, float]:
    """The part of the contact that lies flat on the face, as offsets (m) along `along` from the contact: the arm's
    pad (`FINGER_PAD_WIDTH`), or a tool's parts that touch the contact plane (`over.FLAT`; a rolled tool's
    shortened by its roll's cosine)."""
    effector = problem.effector(engagement.effector)
    action = problem.action(engagement.body, engagement.affordance)
    sense = 1.0 if float(action[:3, 1] @ along) >= 0.0 else -1.0  # the effector frame's y along the face
    if effector.tool is None:
        return -FINGER_PAD_WIDTH / 2, FINGER_PAD_WIDTH / 2
    spans = []
    for part in tool_parts(problem.bodies[effector.tool].type.shape):
        local = part @ effector.frame_inverse[:3, :3].T + effector.frame_inverse[:3, 3]
        if abs(float(local[:, 0].max())) <= FLAT:
            spans.append((float(local[:, 1].min()), float(local[:, 1].max())))
    if not spans:
        return 0.0, 0.0
    over = over_pose(engagement.affordance)
    scale = sense * (math.cos(over[1]) if over is not None else 1.0)
    ends = (scale * min(lo for lo, _ in spans), scale * max(hi for _, hi in spans))
    return min(ends), max(ends)


def _unrolled(name: str) -> str:
    over = over_pose(name)
    return over[0] if over is not None else name


def law_margins(
    problem: Problem, seq: Sequence, values: np.ndarray, traces: list[ModeTrace]
) -> dict[str, tuple[float, float]]:
    """Per body an arc member moves in `seq` (with `values`, rolled out as `traces`): how far (m) its final position
    and (rad) its heading may lie from the rollout's by the arcs' law errors (the module's docstring)."""
    given = mode_values(seq, values)
    live: dict = {}  # the offsets (m) of the family contacts in force, as the rollout keeps them
    turns: dict[str, list[tuple[np.ndarray, float]]] = {}
    for k, trace in enumerate(traces):
        if k > 0:
            action = seq.actions[k - 1]
            if action.op == "add":
                live[action.engagement] = given.offsets.get((k, action.engagement), 0.0)
            elif action.op == "remove":
                live.pop(action.engagement, None)
        for e, value in trace.values.items():
            law = arc_law(problem, e.body, e.affordance)
            if law is None or value == 0.0:
                continue
            arc, sigma, own = law
            change = live.get(e, 0.0) if arc_seed(problem, e.body, e.affordance) is not None else 0.0
            if holds_arc(problem, e, own + change):
                continue
            error = _turn_error(arc, sigma, own + change, value)
            contact = trace.end[e.body] @ action_at(problem, e.body, e.affordance, change)[:, 3]
            turns.setdefault(e.body, []).append((contact[:2], error))
    final = traces[-1].end
    return {
        body: (
            sum(error * float(np.linalg.norm(final[body][:2, 3] - contact)) for contact, error in items),
            sum(error for _, error in items),
        )
        for body, items in turns.items()
    }


def point_margins(
    problem: Problem, body: str, name: str, motion: tuple[np.ndarray, np.ndarray], final: np.ndarray
) -> dict[str, tuple[float, float]]:
    """How far (m, rad) `body`'s `final` pose may lie from the plan's when the arc member `name` that moves it from
    `motion[0]` to `motion[1]` (world poses) is pushed by a point, not a flat contact: `POINT_SIGMAS` of its law's
    error over the member's turn (`arc_turn_error`), about the contact where the turn ends (the module's
    docstring). Empty for anything but an arc member with a sigma.

    The flat pad holds an arc (`holds_arc`); the pad's rounded end, which a hand turned about its axis pushes with
    (`vkgl.robot.pad.turned_pad`), is exploration's point, whose arc is the law's with its error."""
    law = arc_law(problem, body, name)
    if law is None:
        return {}
    arc, sigma, offset = law
    start, end = motion
    turn = float(np.linalg.norm(screw_motion(start, end).rotvec))
    error = POINT_SIGMAS * _turn_error(arc, sigma, offset, turn)
    contact = end @ problem.action(body, name)[:, 3]
    return {body: (error * float(np.linalg.norm(final[:2, 3] - contact[:2])), error)}


def uncertain_rejection(
    problem: Problem,
    final: dict[str, np.ndarray],
    margins: dict[str, tuple[float, float]],
    cause: str = "its law's sigma over the pull",
) -> Rejection:
    """Why a solution inside the goal's tolerance is no promise: its arcs' law errors (`law_margins`) reach past it
    (the goal it misses most by, with the numbers; `cause` words the margin)."""
    worst: tuple[float, str] = (-math.inf, "the arcs' law errors reach past the goal's tolerance")
    for goal in problem.goals:
        margin, turn_margin = margins.get(goal.body, (0.0, 0.0))
        pose = final[goal.body]
        if goal.position is not None and margin > 0.0:
            off = float(np.linalg.norm(pose[: len(goal.position), 3] - goal.position))
            why = (
                f"{goal.body} would end {off * 100:.2f} cm from its goal, and its arc may end {margin * 100:.2f} cm "
                f"farther ({cause}; tolerance {goal.tol_position * 100:.2f} cm)"
            )
            worst = max(worst, (off + margin - goal.tol_position, why))
        if goal.yaw is not None and turn_margin > 0.0:
            off = abs(wrap_angle(yaw_of(pose) - goal.yaw))
            why = (
                f"{goal.body} would end {math.degrees(off):.2f} deg from its goal heading, and its arc may turn "
                f"{math.degrees(turn_margin):.2f} deg less or more (tolerance {math.degrees(goal.tol_yaw):.2f} deg)"
            )
            worst = max(worst, (off + turn_margin - goal.tol_yaw, why))
    return Rejection(Kind.GOAL, worst[1], max(worst[0], 0.0))
