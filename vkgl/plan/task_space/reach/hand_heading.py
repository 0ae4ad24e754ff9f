"""A proof, before any optimisation, that the hand's last push on a goal body whose heading the goal leaves free
ends out of reach at every heading that lets the body reach its goal position.

`hand_reach.hand_out_of_reach_on_the_way` bounds the body's heading at a mode by the sum of its turns' ranges,
whatever the slides do; `slides.position_out_of_reach` scans the turns' angles for the goal's position, whatever
the hand does. Neither sees that the two are tied: a crate whose turns may leave it anywhere between 0 and 60 deg
reaches a far goal along its slide only at a few of those headings, and at those the held stick's hand may lie
past the arm's reach while at the others it would not (the physical bench's gen1_005: 217 sequences, each
rejected for the hand's reach after up to eight NLopt runs, 18 of its 20 CPU-s). This module scans the turns'
angles as `position_out_of_reach` does, keeps the rows at which the slides can still bring the body to its goal,
and asks where the hand is at each of them.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import pivot_travel
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, acting_engagement, bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.reach.hand_reach import ACCEPTED_VIOLATION, LEVEL, hand_ring, reach_interval
from vkgl.plan.task_space.slides import (
    FREE_TURN_GRIDS,
    affine_positions,
    row_distances,
    scan_setup,
    turn_matrices,
    turn_rows,
)

FINER = {0: (1,), 1: (19, 181, 1801), 2: (13, 61, 241)}
"""Angles scanned per turn, coarse then finer, by how many turns the body has: the hand's slack shrinks with the
step, and a sequence the optimiser leaves 0.1 mm out of reach is proven out of reach only by a fine scan (the
rows are one NumPy pass each; a scan stops at the first grid that decides)."""


def hand_out_of_reach_at_free_heading(
    problem: Problem, seq: Sequence, goal: GoalSpec, turns: list[int], slides: list[int], signs: list[float]
) -> Rejection | None:
    """A Rejection when, at the end of the last motion of `goal.body` (made by the hand, or by the tool it holds,
    alone in its mode), the hand lies out of the arm's usable reach at every motion value that lets the body end
    within its goal position's tolerance; None when it may not (the optimiser decides, as before).

    `turns` (about vertical axes, `signs` +1 / -1 for +z / -z in the world) and `slides` index
    `seq.variables`: the goal body's own motions, the goal free of heading, the body level. Why it is sound.
    The hand is sampled where that motion ends (`hand_reach.hand_bounds`: the acting engagement is the body's
    only motion in its mode), and nothing moves the body after it, so the body's pose there is its final pose:
    its origin p within `tol` of the goal g, its heading the rest heading plus the signed sum of the turns'
    angles, and the hand at p + R(heading) c, c the fixed chain from the body to the hand at the contact's offset
    (`hand_reach.hand_ring`: a grid over the offset's band, each offset within `slack` of one of them).
    Scan each turn's angle on a grid of step h_i (`slides.turn_rows`). Any true values lie within h_i / 2 of a
    row; at that row the slides' best distance to the goal is at most tol + `lever` sum(h_i) / 2 + the drifts of
    the contacts along their families at that row's angles (`row_drifts`)
    (`slides.position_out_of_reach` proves the same bound the other way), so only rows within that of the goal
    can hold the true values. At such a row the true heading differs from the row's by at most sum(h_i) / 2,
    which moves the hand by at most |c| sum(h_i) / 2 (a chord is no longer than its arc). So the hand's distance
    from the arm's base lies within tol + slack + |c| sum(h_i) / 2 of |g + R(row) c|, at the chain's height.
    When that interval lies more than `ACCEPTED_VIOLATION` outside the usable reach for every possible row and
    grid offset, task space would reject the sequence too.
    """
    assert goal.position is not None
    found = _last_push(problem, seq, goal.body)
    if found is None or len(turns) not in FREE_TURN_GRIDS or not _stays_level(problem, seq, goal.body, slides):
        return None
    mode, acting = found
    limits = bounds(problem, seq, offsets=True)
    ring = hand_ring(problem, seq, seq.graphs[mode], acting, limits)
    if ring is None:
        return None
    points, slack, height = ring
    setup = scan_setup(problem, seq, goal, turns, slides)
    if setup is None:
        return None
    turn_limits, slide_limits, lever, _ = setup
    travels = [pivot_travel(problem, seq.variables[i][1].body, seq.variables[i][1].affordance) for i in turns]
    rest = problem.bodies[goal.body].rest
    heading0 = math.atan2(rest[1, 0], rest[0, 0])
    target = np.asarray(goal.position[:2], dtype=float) - problem.arm.base[:2, 3]
    low, high = reach_interval(problem, float(rest[2, 3]) + height)
    chain = np.array(points)  # q x 2, the hand in the body's frame at each grid offset
    radius = float(np.max(np.linalg.norm(chain, axis=1)))
    closest: float | None = None
    for count in FINER[len(turns)]:
        angles, steps = turn_rows(turn_limits, count)
        origins, columns = affine_positions(problem, seq, goal.body, turns, slides, angles, turn_matrices)
        distance = row_distances(columns, origins, goal.position, slide_limits)
        spread = sum(steps) / 2
        possible = (
            distance <= goal.tol_position + lever * spread + row_drifts(travels, turn_limits, angles, steps) + 1e-9
        )
        if not possible.any():
            return None  # no row reaches the goal: `position_out_of_reach` speaks for that (its own slack)
        headings = heading0 + angles[possible] @ np.asarray(signs, dtype=float)
        cos, sin = np.cos(headings)[:, None], np.sin(headings)[:, None]
        hands_x = target[0] + cos * chain[:, 0] - sin * chain[:, 1]  # rows x offsets
        hands_y = target[1] + sin * chain[:, 0] + cos * chain[:, 1]
        centre = np.hypot(hands_x, hands_y)
        give = goal.tol_position + slack + radius * spread
        excess = np.maximum(centre - give - high, low - centre - give)
        worst = float(excess.min())
        at_goal = distance[possible] <= goal.tol_position
        if worst <= ACCEPTED_VIOLATION and (np.maximum(centre - high, low - centre)[at_goal] <= 0.0).any():
            return None  # a row reaches the goal with the hand in reach itself: no finer scan can prove otherwise
        if worst > ACCEPTED_VIOLATION:
            closest = worst
            break
    if closest is None:
        return None
    label = seq.actions[mode - 1].label(problem) if mode > 0 else "G0"
    why = (
        f"after {label}: at every heading at which {goal.body} can end within {goal.tol_position * 100:.1f} cm "
        f"of its goal, the hand would be at least {closest * 1000:.1f} mm outside the arm's usable reach "
        f"({low:.3f} to {high:.3f} m from its base at height {float(rest[2, 3]) + height:.3f} m)"
    )
    return Rejection(Kind.REACH, why, closest)


def row_drifts(
    travels: list[float], limits: list[tuple[float, float]], angles: np.ndarray, steps: list[float]
) -> np.ndarray:
    """Per row of turn `angles` (rows x turns, grid steps `steps`, each turn's values within `limits`), how far
    moving the turns' contacts along their families can move the body's final position at any true angles within
    half a step of the row's (m).

    A turn by `a` whose pivot is moved by `d` (`members.pivot_travel`: |d| at most `travel`) is the same turn about
    the unmoved pivot followed by a translation of the whole later path by (I - R(a)) d, whose length is the chord
    2 |d| sin(a / 2) (`slides.position_out_of_reach`), increasing in `a` up to half a turn: at most
    2 travel sin(min(|a_row| + h / 2, a_max, pi) / 2) for true angles within h / 2 of the row's and at most
    a_max (the upper limit; the values are never negative). The sum over the turns
    bounds them all. `slides.scan_setup`'s `drifts` is the same at each turn's largest angle, for every row: an
    open slide's arc member (a turn of up to half a turn whose pivot moves by 2 cm) then widens every row by 4 cm,
    where the rows near its goal turn it by a few tens of degrees (gen1_005 of the physical bench: 56 sequences
    of 100 ms each, one NLopt run after another, that this proof now rejects)."""
    total = np.zeros(len(angles))
    for k, travel in enumerate(travels):
        if travel > 0.0:
            largest = np.minimum(np.abs(angles[:, k]) + steps[k] / 2, min(abs(limits[k][1]), math.pi))
            total += 2.0 * travel * np.sin(largest / 2.0)
    return total


def _last_push(problem: Problem, seq: Sequence, body: str) -> tuple[int, Engagement] | None:
    """(mode, engagement) of the hand's (or its held tool's) push that makes `body`'s last motion, alone in its
    mode; None when the body's last motion is not of that kind (the hand is then not sampled at its final pose)."""
    own = [(mode, e) for mode, e in seq.variables if e.body == body]
    if not own:
        return None
    mode = own[-1][0]
    acting = acting_engagement(problem, seq.graphs[mode])
    if acting is None or [e for m, e in own if m == mode] != [acting]:
        return None
    return mode, acting


def _stays_level(problem: Problem, seq: Sequence, body: str, slides: list[int]) -> bool:
    """Whether `body` lies level at rest, is no tool, and slides only horizontally (its turns are about vertical
    axes: the caller's signs), so that it keeps its height and the hand its height above it."""
    rest = problem.bodies[body].rest
    if abs(rest[2, 2] - 1.0) > LEVEL or any(f.tool == body for f in problem.effectors):
        return False
    for i in slides:
        e = seq.variables[i][1]
        axis = unit_axis_and_center(problem.affordance(e.body, e.affordance).motion)[0]
        if abs(float((rest[:3, :3] @ axis)[2])) > LEVEL:
            return False
    return True
