"""Exact geometric reasoning about a graph sequence, before any optimisation.

`closed_form(problem, seq)` either proves that the goal cannot hold for a
sequence (a `Rejection` that says why) or returns a start for the task-space
optimiser and whether the goal pins every motion value. It relies on
three facts of the model:

- a goal body's pose depends only on its own motions (composed in mode order);
- turns about vertical axes add up: the goal's heading fixes one turn's angle
  (values >= 0, at most half a turn each), and with two turns the second
  follows from the first, so one angle is scanned on a fine grid;
- with the turns fixed, the position is affine in the slides, so non-negative
  least squares (scipy `nnls`) gives the closest reachable position.

A carried goal body (`vkgl.plan.graphs.carry`) may be set down anywhere: the optimiser decides, from
`carry_start`. And one about the hand: when the last mode holds the hand on a goal body whose
goal fixes position and heading, the hand's final pose follows from the goal;
if that is out of the arm's reach by more than the goal's tolerance can move
it, nothing can help; the same of every earlier mode in which the hand acts on a
goal body, whose later motions can take it only so far (`hand_reach`).
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.families import offset_bounds
from vkgl.plan.graphs.graph import Engagement, motion_type
from vkgl.plan.graphs.members import arc_seed, pivot_travel
from vkgl.plan.graphs.mode_shapes import acting_engagement
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, hand_chain
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.reach.hand_heading import hand_out_of_reach_at_free_heading
from vkgl.plan.task_space.reach.hand_reach import hand_out_of_reach_on_the_way
from vkgl.plan.task_space.reach.workspace import REACH_MARGIN, UPRIGHT, hand_reach_violation, unreachable
from vkgl.plan.task_space.slides import affine_positions, best_row, closest, position_out_of_reach, value_limits
from vkgl.se3 import wrap_angle, yaw_of

TURN_GRID = 181
"""Angles scanned for the first of two turns of one body (1 deg apart over half a turn)."""

LEVER_BOUND = 1.0
"""m: bound on how far a point moves per radian of a turn (pivots and contacts lie within a metre)."""


def closed_form(problem: Problem, seq: Sequence) -> tuple[np.ndarray, bool] | Rejection:
    """A start for the optimiser and whether the goal pins every value; or why the goal cannot hold."""
    values = np.zeros(len(seq.variables))
    pinned = np.zeros(len(seq.variables), dtype=bool)
    for goal in problem.goals:
        outcome = _goal_values(problem, seq, goal, values)
        if isinstance(outcome, Rejection):
            return outcome
        for i, (v, exact) in outcome.items():
            values[i] = v
            pinned[i] = exact
    far = (
        _hand_beyond_reach_at_goal(problem, seq)
        or hand_out_of_reach_on_the_way(problem, seq)
        or _hand_beyond_reach_at_free_headings(problem, seq)
    )
    if far is not None:
        return far
    return values, bool(pinned.all())


def _hand_beyond_reach_at_free_headings(problem: Problem, seq: Sequence) -> Rejection | None:
    """`hand_heading.hand_out_of_reach_at_free_heading` for each goal that leaves the heading free (a body that
    lies level and turns about vertical axes only), after the cheaper hand checks."""
    for goal in problem.goals:
        if goal.yaw is not None or goal.position is None or goal.opening is not None:
            continue
        if any(e.body == goal.body for _, e in seq.carries):
            continue
        turns, slides, signs = _own_motions(problem, seq, goal)
        if None in signs:
            continue
        far = hand_out_of_reach_at_free_heading(problem, seq, goal, turns, slides, signs)  # type: ignore[arg-type]
        if far is not None:
            return far
    return None


def _own_motions(problem: Problem, seq: Sequence, goal: GoalSpec) -> tuple[list[int], list[int], list[float | None]]:
    """The goal body's turns and slides (indices into `seq.variables`) and each turn's `_vertical_sign`."""
    own = [i for i, (_, e) in enumerate(seq.variables) if e.body == goal.body]
    turns = [i for i in own if motion_type(problem, seq.variables[i][1]) == "revolute"]
    slides = [i for i in own if i not in turns]
    rest = problem.bodies[goal.body].rest
    return turns, slides, [_vertical_sign(problem, seq, i, rest) for i in turns]


_CLOSED_FORMS: dict[int, tuple[Problem, Sequence, tuple[np.ndarray, bool] | Rejection]] = {}
_CLOSED_FORMS_KEPT = 64
"""`closed_form` answers kept, by sequence: a sequence with contacts on families is solved up to three times
(its contacts as written, then free along their faces, then pinned elsewhere: `contacts.other_contacts`), and
`closed_form` does not depend on the contacts' offsets."""


def remembered_closed_form(problem: Problem, seq: Sequence) -> tuple[np.ndarray, bool] | Rejection:
    """`closed_form(problem, seq)`, computed once per sequence object (kept with it, so that its id stays its
    own); the values come as an array of the caller's own."""
    kept = _CLOSED_FORMS.get(id(seq))
    if kept is None or kept[0] is not problem or kept[1] is not seq:
        if len(_CLOSED_FORMS) >= _CLOSED_FORMS_KEPT:
            _CLOSED_FORMS.clear()
        kept = _CLOSED_FORMS[id(seq)] = (problem, seq, closed_form(problem, seq))
    found = kept[2]
    return found if isinstance(found, Rejection) else (found[0].copy(), found[1])


def _goal_values(
    problem: Problem, seq: Sequence, goal: GoalSpec, values: np.ndarray
) -> dict[int, tuple[float, bool]] | Rejection:
    """Values of the goal body's motions that meet its goal (and whether they are unique), or a Rejection."""
    if goal.opening is not None:
        return _joint_goal_values(problem, seq, goal)
    if any(e.body == goal.body for _, e in seq.carries):
        return {}  # set down anywhere: the carry's start aims at the goal (`carry_start`), the optimiser decides
    turns, slides, signs = _own_motions(problem, seq, goal)
    rest = problem.bodies[goal.body].rest
    if goal.yaw is None and goal.position is not None and None not in signs:
        far = position_out_of_reach(problem, seq, goal, turns, slides)
        return far if far is not None else {}  # a necessary test only: the optimiser alone decides the values
    if goal.yaw is None or None in signs:
        return {}  # the optimiser alone decides
    limits = [value_limits(problem, seq, i) for i in turns]
    needed = wrap_angle(goal.yaw - yaw_of(rest))
    if len(turns) > 2:
        return _many_turns(problem, seq, goal, turns, slides, signs, limits, needed)  # type: ignore[arg-type]
    candidates = _turn_candidates(needed, goal.tol_yaw, signs, limits)  # type: ignore[arg-type]
    if not candidates:
        return _yaw_rejection(problem, seq, goal, turns, signs, limits, needed)  # type: ignore[arg-type]
    if goal.position is None:
        first = candidates[0]
        return {i: (a, len(candidates) == 1) for i, a in zip(turns, first)}
    angles = np.array(candidates).reshape(len(candidates), len(turns))
    origins, columns = affine_positions(problem, seq, goal.body, turns, slides, angles)
    slide_limits = np.array([value_limits(problem, seq, i) for i in slides]).reshape(len(slides), 2)
    best = best_row(columns, origins, goal.position, slide_limits)
    slack = goal.tol_position + (0.5 * math.pi / (TURN_GRID - 1) * LEVER_BOUND if len(turns) > 1 else 0.0)
    slack += _arc_slack(problem, seq, goal, turns, limits, needed)  # type: ignore[arg-type]
    if best[0] > slack:
        how = "along its slides" if slides else "and nothing slides it"
        return Rejection(
            Kind.POSITION,
            f"{goal.body} ends at least {best[0] * 100:.1f} cm from its goal "
            f"position with the heading the goal asks for, {how}{_at_range_end(problem, seq, slides, best[2])}",
            best[0],
        )
    exact_turns = len(candidates) == 1
    unique = bool(np.linalg.matrix_rank(columns[best[1]], tol=1e-9) == len(slides)) if slides else True
    out = {i: (float(a), exact_turns) for i, a in zip(turns, angles[best[1]])}
    out.update({i: (float(v), exact_turns and unique) for i, v in zip(slides, best[2])})
    return out


def _arc_slack(
    problem: Problem, seq: Sequence, goal: GoalSpec, turns: list[int], limits: list[tuple[float, float]], needed: float
) -> float:
    """How far the arc members among `turns` may end the body from where their members as named put it (m): the
    task space moves their contacts along the face (`members.ArcSeed`), which moves each pivot by up to `p` and
    the final position by the chord `2 p sin(a / 2)` at the turn's angle `a` (one turn: at most the goal's change
    of heading and its tolerance), as a turn family's drift does (`slides._drift_bound`). Like every turn here,
    the test is made at the goal's heading exactly."""
    slack = 0.0
    for i, (_, high) in zip(turns, limits):
        e = seq.variables[i][1]
        travel = pivot_travel(problem, e.body, e.affordance) if arc_seed(problem, e.body, e.affordance) else 0.0
        if travel > 0.0:
            largest = min(high, abs(needed) + goal.tol_yaw) if len(turns) == 1 else high
            slack += 2.0 * travel * math.sin(min(largest, math.pi) / 2.0)
    return slack


def _joint_goal_values(problem: Problem, seq: Sequence, goal: GoalSpec) -> dict[int, tuple[float, bool]] | Rejection:
    """Motion values that give the goal body's joint the goal's coordinate, or why none can.

    The coordinate is linear in the body's motion values when a slide's body
    only slides (each slide adds its value times its axis along the joint's)
    or a hinge's body only turns about axes along the hinge's (each turn adds
    its angle, signed); then the reachable interval is exact and one motion is
    pinned. Otherwise the optimiser alone decides.
    """
    body = problem.bodies[goal.body]
    own = [i for i, (_, e) in enumerate(seq.variables) if e.body == goal.body]
    if body.joint_axis is None or goal.opening is None or not own:
        return {}
    weights = []
    for i in own:
        e = seq.variables[i][1]
        axis, center = unit_axis_and_center(problem.affordance(e.body, e.affordance).motion)
        along = float(body.joint_axis @ axis)
        if body.joint == "prismatic" and center is not None:
            return {}  # a turn moves the body's position nonlinearly
        if body.joint == "revolute" and center is not None and abs(abs(along) - 1.0) > 1e-6:
            return {}  # a turn about another axis: not a sum of angles
        weights.append(0.0 if body.joint == "revolute" and center is None else along)
    limits = [value_limits(problem, seq, i) for i in own]
    low = sum(min(w * lo, w * hi) for w, (lo, hi) in zip(weights, limits))
    high = sum(max(w * lo, w * hi) for w, (lo, hi) in zip(weights, limits))
    target = goal.opening - body.start_state  # what the motions must add to where the joint starts
    if not low - goal.tol_opening <= target <= high + goal.tol_opening:
        why = _joint_why(problem, seq, goal.body, target, own, (low, high))
        return Rejection(Kind.GOAL, why, max(low - target, target - high))
    # A start: every value at its lower bound, then the motions that move the joint the needed way share
    # what is left in proportion to how far each can move it (for one motion, the exact value).
    values = [lo for lo, _ in limits]
    left = min(max(target, low), high) - sum(w * v for w, v in zip(weights, values))
    helping = [k for k, w in enumerate(weights) if w * left > 0]
    room = sum(abs(weights[k]) * (limits[k][1] - limits[k][0]) for k in helping)
    for k in helping:
        values[k] += (limits[k][1] - limits[k][0]) * min(1.0, abs(left) / room) if room > 0 else 0.0
    exact = len(own) == 1 and weights[0] != 0.0
    return {i: (float(v), exact) for i, v in zip(own, values)}


def _joint_why(
    problem: Problem, seq: Sequence, body: str, target: float, own: list[int], reach: tuple[float, float]
) -> str:
    """`drawer must open 20.0 cm on its prismatic joint, but Drawer.push_center_px opens it 0.0 to 8.8 cm here`."""
    joint = problem.bodies[body].joint
    low, high = reach
    scale, unit = (100.0, "cm") if joint == "prismatic" else (math.degrees(1.0), "deg")
    names = sorted({_name(problem, seq, i) for i in own})
    movers = names[0] if len(names) == 1 else f"its {len(own)} motions ({', '.join(names)})"
    ranged = sorted(
        {
            f"{_name(problem, seq, i)} {value_limits(problem, seq, i)[1] * scale:.1f} {unit}"
            for i in own
            if _has_range(problem, seq, i)
        }
    )
    within = f", each contact within the range it was explored over ({', '.join(ranged)})" if ranged else ""
    start = problem.bodies[body].start_state
    if abs(start) > 1e-12:  # it starts open: say from where to where
        end = start + target
        return (
            f"{body} must move {target * scale:.1f} {unit} on its {joint} joint (from {start * scale:.1f} to "
            f"{end * scale:.1f} {unit}), but {movers} move{'s' if len(names) == 1 else ''} it "
            f"{low * scale:.1f} to {high * scale:.1f} {unit} here{within}"
        )
    return (
        f"{body} must open {target * scale:.1f} {unit} on its {joint} joint, but {movers} "
        f"open{'s' if len(names) == 1 else ''} it {low * scale:.1f} to {high * scale:.1f} {unit} here{within}"
    )


def _name(problem: Problem, seq: Sequence, index: int) -> str:
    e = seq.variables[index][1]
    return f"{problem.bodies[e.body].type.name}.{e.affordance}"


def _has_range(problem: Problem, seq: Sequence, index: int) -> bool:
    e = seq.variables[index][1]
    return getattr(problem.affordance(e.body, e.affordance).motion, "range", None) is not None


def _many_turns(
    problem: Problem,
    seq: Sequence,
    goal: GoalSpec,
    turns: list[int],
    slides: list[int],
    signs: list[float],
    limits: list[tuple[float, float]],
    needed: float,
) -> dict[int, tuple[float, bool]] | Rejection:
    """Three or more vertical turns: their signed sum spans an interval, which must hold the heading change.

    Then a start for the optimiser (nothing pinned): the turns that go the
    needed way share it in proportion to their ranges, and the slides come
    from the linear solve at those angles.
    """
    low = sum(min(s * lo, s * hi) for s, (lo, hi) in zip(signs, limits))
    high = sum(max(s * lo, s * hi) for s, (lo, hi) in zip(signs, limits))
    middle = 0.5 * (low + high)
    target = needed + 2 * math.pi * round((middle - needed) / (2 * math.pi))
    if not low - goal.tol_yaw <= target <= high + goal.tol_yaw:
        return _yaw_rejection(problem, seq, goal, turns, signs, limits, needed)
    target = min(max(target, low), high)
    angles = [lo for lo, _ in limits]
    left = target - sum(s * a for s, a in zip(signs, angles))
    helping = [k for k, s in enumerate(signs) if s * left > 0]
    room = sum(limits[k][1] - limits[k][0] for k in helping)
    for k in helping:
        angles[k] += (limits[k][1] - limits[k][0]) * min(1.0, abs(left) / room) if room > 0 else 0.0
    out = {i: (float(a), False) for i, a in zip(turns, angles)}
    if goal.position is not None and slides:
        origins, columns = affine_positions(problem, seq, goal.body, turns, slides, np.array([angles]))
        slide_limits = np.array([value_limits(problem, seq, i) for i in slides]).reshape(len(slides), 2)
        _, solution = closest(columns[0], goal.position - origins[0, : len(goal.position)], slide_limits)
        out.update({i: (float(v), False) for i, v in zip(slides, solution)})
    return out


def _yaw_rejection(
    problem: Problem,
    seq: Sequence,
    goal: GoalSpec,
    turns: list[int],
    signs: list[float],
    limits: list[tuple[float, float]],
    needed: float,
) -> Rejection:
    """Why no turn values give the heading, with the numbers (and the ranges that stop it).

    The excess is how many radians the turns fall short by (the closest miss is reported).
    """
    low = sum(min(s * lo, s * hi) for s, (lo, hi) in zip(signs, limits))
    high = sum(max(s * lo, s * hi) for s, (lo, hi) in zip(signs, limits))
    miss = min(max(low - target, target - high, 0.0) for target in (needed - 2 * math.pi, needed, needed + 2 * math.pi))
    return Rejection(Kind.YAW, _yaw_why(problem, seq, goal.body, turns, signs, limits, needed, low, high), miss)


def _yaw_why(
    problem: Problem,
    seq: Sequence,
    body: str,
    turns: list[int],
    signs: list[float],
    limits: list[tuple[float, float]],
    needed: float,
    low: float,
    high: float,
) -> str:
    head = f"{body} must turn by {math.degrees(needed):.1f} deg"
    if not turns:
        return f"{head} but nothing turns it"
    if len(turns) == 1:
        angle = (signs[0] * needed) % (2 * math.pi)
        if angle <= math.pi and angle > limits[0][1] and _has_range(problem, seq, turns[0]):
            return (
                f"{head}: the turn would need {math.degrees(angle):.1f} deg, past the "
                f"{math.degrees(limits[0][1]):.1f} deg {_name(problem, seq, turns[0])} was explored over"
            )
        return f"{head} but its turn cannot give that (it turns one way, <= 180 deg)"
    ranged = [
        f"{_name(problem, seq, i)} <= {math.degrees(hi):.1f} deg"
        for i, (_, hi) in zip(turns, limits)
        if _has_range(problem, seq, i)
    ]
    within = f", each within the range it was explored over ({', '.join(ranged)})" if ranged else ""
    return (
        f"{head} but its {len(turns)} turns add up to between {math.degrees(low):.1f} and "
        f"{math.degrees(high):.1f} deg{within}"
    )


def _at_range_end(problem: Problem, seq: Sequence, slides: list[int], solution: np.ndarray) -> str:
    """`; Block.push_center_px slides at most 5.7 cm (its explored range)` for slides stopped by their range."""
    stopped: dict[str, float] = {}
    for i, v in zip(slides, solution):
        upper = value_limits(problem, seq, i)[1]
        if _has_range(problem, seq, i) and v >= upper - 1e-9:
            stopped[_name(problem, seq, i)] = upper
    parts = [f"{name} slides at most {upper * 100:.1f} cm per contact" for name, upper in stopped.items()]
    return f"; {', '.join(parts)} (the range it was explored over)" if parts else ""


def _vertical_sign(problem: Problem, seq: Sequence, index: int, rest: np.ndarray) -> float | None:
    """+1 / -1 when turn `index` is about the world's +z / -z axis (the body level), else None."""
    e = seq.variables[index][1]
    axis = problem.affordance(e.body, e.affordance).motion.axis.array()  # type: ignore[union-attr]
    axis = rest[:3, :3] @ (axis / np.linalg.norm(axis))
    return math.copysign(1.0, axis[2]) if abs(abs(axis[2]) - 1.0) < 1e-6 else None


def _turn_candidates(
    needed: float, tol: float, signs: list[float], limits: list[tuple[float, float]]
) -> list[tuple[float, ...]]:
    """Turn angles within their `limits` whose signed sum gives the heading change `needed` (within `tol`)."""
    if not signs:
        return [()] if abs(needed) <= tol else []
    if len(signs) == 1:
        angle = _within(signs[0] * needed, tol, limits[0])
        return [] if angle is None else [(angle,)]
    firsts = np.linspace(limits[0][0], limits[0][1], TURN_GRID)
    seconds = _within_all(signs[1] * (needed - signs[0] * firsts), tol, limits[1])
    found = ~np.isnan(seconds)
    return list(zip(firsts[found].tolist(), seconds[found].tolist()))


def _within_all(angles: np.ndarray, tol: float, limits: tuple[float, float]) -> np.ndarray:
    """`_within` of each of `angles` at once (NaN for None): the same operations, elementwise."""
    low, high = limits
    turn = 2 * math.pi
    base = np.remainder(angles, turn)  # Python's float % and NumPy's remainder round alike
    shifted = np.stack([base - turn, base, base + turn], axis=1)
    values = np.minimum(np.maximum(shifted, low), high)
    misses = np.abs(values - shifted)
    ok = misses <= tol
    pick = np.argmin(np.where(ok, misses, np.inf), axis=1)  # the first of equal misses, as `_within` keeps
    chosen = values[np.arange(len(angles)), pick]
    return np.where(ok.any(axis=1), chosen, np.nan)


def _within(angle: float, tol: float, limits: tuple[float, float]) -> float | None:
    """The value in `limits` (inside [0, pi]) nearest `angle` up to whole turns, if within `tol` of it; else None."""
    low, high = limits
    turn = 2 * math.pi
    best: tuple[float, float] | None = None  # (miss, value)
    for shifted in (angle % turn - turn, angle % turn, angle % turn + turn):
        value = min(max(shifted, low), high)
        miss = abs(value - shifted)
        if miss <= tol and (best is None or miss < best[0]):
            best = (miss, value)
    return None if best is None else best[1]


def _hand_beyond_reach_at_goal(problem: Problem, seq: Sequence) -> Rejection | None:
    """A Rejection when the hand, holding a goal body at its goal pose at the end, is surely out of reach."""
    graph = seq.graphs[-1]
    acting = acting_engagement(problem, graph)
    goal = next((g for g in problem.goals if acting is not None and g.body == acting.body), None)
    if acting is None or goal is None or goal.position is None:
        return None
    rest = problem.bodies[goal.body].rest
    if abs(rest[2, 2] - 1.0) > 1e-9:
        return None
    chain = hand_chain(problem, graph, acting)
    if chain is None:
        return None
    if goal.yaw is None:
        return _hand_beyond_reach_any_heading(problem, goal, acting, chain[0], rest)
    pose = np.eye(4)
    pose[:3, :3] = np.array(
        [[math.cos(goal.yaw), -math.sin(goal.yaw), 0.0], [math.sin(goal.yaw), math.cos(goal.yaw), 0.0], [0.0, 0.0, 1.0]]
    )
    pose[:3, 3] = (*goal.position[:2], goal.position[2] if len(goal.position) > 2 else rest[2, 3])
    hand = pose @ chain[0]
    slack = goal.tol_position + math.hypot(chain[0][0, 3], chain[0][1, 3]) * goal.tol_yaw
    if hand_reach_violation(problem, hand) <= slack:
        return None
    found = unreachable(problem, hand)
    why = found.why if found is not None else "the hand would be out of reach"
    return Rejection(Kind.REACH, f"at the goal pose of {goal.body}, {why}", found.excess if found else 1.0)


def _hand_beyond_reach_any_heading(
    problem: Problem, goal: GoalSpec, acting: Engagement, chain: np.ndarray, rest: np.ndarray
) -> Rejection | None:
    """A Rejection when the hand, holding a goal body that ends at its goal position at any heading, is out of
    reach whatever the heading.

    The body lies level, so the hand stays at its height above the body and on a circle of radius rho (the
    chain's horizontal offset, give or take how far the contact may move along its family) about the body's
    position, which lies within the tolerance of the goal: its distance from the arm's base lies between
    d - rho - tol and d + rho + tol (d: the goal's). Rejected only when that whole interval lies outside
    the usable reach (`REACH_MARGIN` inside the arm's) at that height.
    """
    assert goal.position is not None
    drift = max(abs(v) for v in offset_bounds(problem.affordance(acting.body, acting.affordance)))
    rho = math.hypot(chain[0, 3], chain[1, 3]) + drift
    if chain[2, 2] < 1.0 - UPRIGHT:  # a tilted hand is counted up to this much nearer or farther (`hand_down_point`)
        rho += problem.arm.wrist_lever * math.hypot(chain[0, 2], chain[1, 2])
    height = (goal.position[2] if len(goal.position) > 2 else rest[2, 3]) + chain[2, 3]
    r_min, r_max = problem.arm.reach(float(height))
    base = problem.arm.base[:2, 3]
    d = math.hypot(goal.position[0] - base[0], goal.position[1] - base[1])
    nearest, farthest = max(0.0, d - rho - goal.tol_position), d + rho + goal.tol_position
    beyond = nearest - (r_max - REACH_MARGIN) if r_max > 0 else 1.0
    short = (r_min + REACH_MARGIN) - farthest if r_max > 0 else 1.0
    excess = max(beyond, short)
    if excess <= 0:
        return None
    where = f"{nearest:.3f} m or more" if beyond > 0 else f"at most {farthest:.3f} m"
    return Rejection(
        Kind.REACH,
        f"at the goal position of {goal.body}, at any heading, the hand would be {where} from the arm's base "
        f"at height {height:.3f} m (usable reach there: {r_min + REACH_MARGIN:.3f} to "
        f"{r_max - REACH_MARGIN:.3f} m)",
        excess,
    )
