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
from dataclasses import dataclass

import numpy as np

from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import pivot_shift, pivot_travel
from vkgl.plan.graphs.mode_shapes import acting_engagement
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.reach.hand_reach import ACCEPTED_VIOLATION, LEVEL, hand_ring, offset_grid, reach_interval
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
    points, slack, height, lean = ring
    slack += lean  # a tilted hand is counted up to that much nearer or farther (`workspace.hand_down_point`)
    setup = scan_setup(problem, seq, goal, turns, slides)
    if setup is None:
        return None
    travels = [pivot_travel(problem, seq.variables[i][1].body, seq.variables[i][1].affordance) for i in turns]
    rest = problem.bodies[goal.body].rest
    heading0 = math.atan2(rest[1, 0], rest[0, 0])
    target = np.asarray(goal.position[:2], dtype=float) - problem.arm.base[:2, 3]
    low, high = reach_interval(problem, float(rest[2, 3]) + height)
    chain = np.array(points)  # q x 2, the hand in the body's frame at each grid offset
    last = _last_turn(seq, goal.body, mode, turns)
    turn = None if last is None else _LastTurn.of(problem, seq, last, acting, limits, chain, goal.tol_position + slack)
    reach = (low, high)
    base = problem.arm.base[:2, 3]
    scan = _Scan(problem, seq, goal, turns, slides, signs, setup, travels, heading0, target, reach, chain, slack, base)
    proven = scan.closest(None if turn is None or last is None else (turns.index(last), turn))
    if proven is None:
        return None
    closest, started = proven
    where = "where that turn starts or ends " if started else ""
    label = seq.actions[mode - 1].label(problem) if mode > 0 else "G0"
    why = (
        f"after {label}: at every heading at which {goal.body} can end within {goal.tol_position * 100:.1f} cm "
        f"of its goal, the hand {where}would be at least {closest * 1000:.1f} mm outside "
        f"the arm's usable reach ({low:.3f} to {high:.3f} m from its base at height {float(rest[2, 3]) + height:.3f} m)"
    )
    return Rejection(Kind.REACH, why, closest)


@dataclass(frozen=True)
class _Scan:
    """The rows of turn angles at which the goal body can reach its goal, scanned coarse to fine (`FINER`), and
    how far outside the usable reach the hand lies at each (the arguments of `hand_out_of_reach_at_free_heading`)."""

    problem: Problem
    seq: Sequence
    goal: GoalSpec
    turns: list[int]
    slides: list[int]
    signs: list[float]
    setup: tuple[list[tuple[float, float]], np.ndarray, float, object]
    travels: list[float]
    heading0: float
    target: np.ndarray
    reach: tuple[float, float]
    chain: np.ndarray  # offsets x 2, the hand in the body's frame at each grid offset
    slack: float
    base: np.ndarray  # the arm's base, x and y in the world

    def closest(self, start: tuple[int, _LastTurn] | None) -> tuple[float, bool] | None:
        """(the least excess over the rows that may hold the true values, more than `ACCEPTED_VIOLATION`: proven
        out of reach; whether the turn's start was needed to prove it), or None. The hand where the push ends is
        judged as before; with `start` (the last turn's column among the rows, and the turn), when that proves
        nothing, a row also counts as out of reach when the hand is so where the turn starts (on at most
        `START_GRIDS` grids: each finer grid costs more than the optimiser's runs it saves, `FINER`)."""
        goal = self.goal
        assert goal.position is not None
        turn_limits, slide_limits, lever, _ = self.setup
        radius = float(np.max(np.linalg.norm(self.chain, axis=1)))
        ended = False  # the end alone has decided nothing can be proven from it
        for grid, count in enumerate(FINER[len(self.turns)]):
            if ended and (start is None or grid >= START_GRIDS):
                return None
            angles, steps = turn_rows(turn_limits, count)
            origins, columns = affine_positions(
                self.problem, self.seq, goal.body, self.turns, self.slides, angles, turn_matrices
            )
            distance = row_distances(columns, origins, goal.position, slide_limits)
            spread = sum(steps) / 2
            drifts = row_drifts(self.travels, turn_limits, angles, steps)
            possible = distance <= goal.tol_position + lever * spread + drifts + 1e-9
            if not possible.any():
                return None  # no row reaches the goal: `position_out_of_reach` speaks for that (its own slack)
            headings = self.heading0 + angles[possible] @ np.asarray(self.signs, dtype=float)
            give = goal.tol_position + self.slack + radius * spread
            excess, bare = _excess(self.target, headings, self.chain, give, self.reach)
            at_goal = distance[possible] <= goal.tol_position
            if not ended:
                worst = float(excess.min())
                if worst > ACCEPTED_VIOLATION:
                    return worst, False
                # a row reaches the goal with the hand in reach where it ends: no finer scan proves otherwise
                ended = bool((bare[at_goal] <= 0.0).any())
            if start is None or grid >= START_GRIDS:
                continue
            column, turn = start  # the hand where the last turn starts: the body's final pose, that turn undone
            back, start_give = turn.back(angles[possible, column], spread, steps[column])
            begun, begun_bare = _excess(self.target, headings, back, start_give, self.reach)
            excess, bare = np.maximum(excess, begun), np.maximum(bare, begun_bare)
            if not self.slides:  # and where the turns before it leave the body (no slide: exact per row)
                begun, begun_bare = self._before_last(angles[possible], steps, column, radius + lever)
                excess, bare = np.maximum(excess, begun), np.maximum(bare, begun_bare)
            worst = float(excess.min())
            if worst > ACCEPTED_VIOLATION:
                return worst, True
            if (bare[at_goal] <= 0.0).any():
                return None
        return None

    def _before_last(
        self, angles: np.ndarray, steps: list[float], column: int, reach_per_radian: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """(rows x offsets) how far outside the usable reach the hand lies where the last turn starts, read
        forward: the body's rest pose turned by the rows' angles of the turns before it (no slide between), less
        the give (the chain's slack, its and the body's motion over the rows' half steps, `reach_per_radian`
        times their sum, and the drifts of those turns' contacts along their families), and without it."""
        before = [k for k in range(len(self.turns)) if k != column]
        turns = [self.turns[k] for k in before]
        origins, _ = affine_positions(
            self.problem, self.seq, self.goal.body, turns, [], angles[:, before], turn_matrices
        )
        headings = self.heading0 + angles[:, before] @ np.asarray([self.signs[k] for k in before], dtype=float)
        turn_limits = self.setup[0]
        spread = sum(steps[k] for k in before) / 2
        drifts = row_drifts(
            [self.travels[k] for k in before],
            [turn_limits[k] for k in before],
            angles[:, before],
            [steps[k] for k in before],
        )
        give = self.slack + reach_per_radian * spread + drifts[:, None]
        cos, sin = np.cos(headings)[:, None], np.sin(headings)[:, None]
        cx, cy = self.chain[:, 0], self.chain[:, 1]
        x = origins[:, 0:1] - self.base[0] + cos * cx - sin * cy
        y = origins[:, 1:2] - self.base[1] + sin * cx + cos * cy
        centre = np.hypot(x, y)
        low, high = self.reach
        bare = np.maximum(centre - high, low - centre)
        return bare - give, bare


START_GRIDS = 2
"""Grids of `FINER` on which the hand where a last turn starts is judged too: the finest (1801 rows for one turn,
241 x 241 for two) cost 5 ms a sequence on the physical bench's far tasks, more than the optimiser's runs it saved."""


def _excess(
    target: np.ndarray, headings: np.ndarray, chain: np.ndarray, give: np.ndarray | float, reach: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """(rows x offsets) how far the hand at `target` plus the body-frame `chain` (offsets x 2, or rows x offsets x
    2) turned by each of `headings` lies outside the usable `reach` (low, high) less `give`, and without it."""
    cos, sin = np.cos(headings)[:, None], np.sin(headings)[:, None]
    cx, cy = chain[..., 0], chain[..., 1]
    centre = np.hypot(target[0] + cos * cx - sin * cy, target[1] + sin * cx + cos * cy)
    low, high = reach
    bare = np.maximum(centre - high, low - centre)
    return bare - give, bare


def _last_turn(seq: Sequence, body: str, mode: int, turns: list[int]) -> int | None:
    """The index (in `seq.variables`) of `body`'s motion in `mode`, the last push, when it is one of `turns`."""
    own = [i for i, (m, e) in enumerate(seq.variables) if m == mode and e.body == body]
    return own[0] if len(own) == 1 and own[0] in turns else None


@dataclass(frozen=True)
class _LastTurn:
    """The goal body's last motion, a turn made by the pushing hand's contact, as the hand sees it where the turn
    starts: at each grid offset of the contact (`hand_reach.offset_grid`) the chain `chain` (body frame, the same at
    the turn's start and end: the contact holds), its pivot `pivots` there (the family's drift or an arc member's
    pivot shift, `members.pivot_shift`), how far the pivot may lie from that within half a grid step `pivot_give`,
    and `give` (the goal's tolerance and the chain's own slack between grid offsets)."""

    sign: float  # +1 / -1: the turn about +z / -z of the body's frame (level: the world's)
    chain: np.ndarray  # offsets x 2
    pivots: np.ndarray  # offsets x 2
    pivot_give: np.ndarray  # offsets
    give: float

    @staticmethod
    def of(
        problem: Problem,
        seq: Sequence,
        index: int,
        acting: Engagement,
        limits: tuple[np.ndarray, np.ndarray],
        chain: np.ndarray,
        give: float,
    ) -> _LastTurn | None:
        """The last turn `seq.variables[index]` with the hand's `chain` at `acting`'s grid offsets; None when its
        axis is not vertical."""
        e = seq.variables[index][1]
        axis, center = unit_axis_and_center(problem.affordance(e.body, e.affordance).motion)
        if center is None or abs(abs(float(axis[2])) - 1.0) > LEVEL:
            return None
        grid = offset_grid(seq, acting, limits)
        half = (grid[-1] - grid[0]) / (len(grid) - 1) / 2 if len(grid) > 1 else 0.0

        def pivot(offset: float) -> np.ndarray:
            shift = pivot_shift(problem, e.body, e.affordance, float(offset))
            return np.asarray(center[:2] if shift is None else center[:2] + shift[:2], dtype=float)

        pivots = np.array([pivot(o) for o in grid])
        near = [[pivot(min(max(o + d, grid[0]), grid[-1])) for d in (-half, half)] for o in grid]
        give_pivot = np.array([max(float(np.linalg.norm(q - p)) for q in qs) for p, qs in zip(pivots, near)])
        return _LastTurn(float(np.sign(axis[2])), chain, pivots, give_pivot, give)

    def back(self, angles: np.ndarray, spread: float, step: float) -> tuple[np.ndarray, np.ndarray]:
        """(rows x offsets x 2) the hand in the final body frame where the turn by each of `angles` started (the
        chain turned back about its pivot: the end frame is the start frame times the turn), and (rows x offsets)
        how far the true one may lie from it: `give`, the heading's `spread` over the chain's length (a chord is no
        longer than its arc), the turn's own half `step` over the chain's distance from its pivot, and the chord of
        the pivot's give at the turn's angle (the same turn about a moved pivot, then a translation)."""
        a = -self.sign * angles[:, None]  # rows x 1: the turn undone
        cos, sin = np.cos(a), np.sin(a)
        rel = self.chain - self.pivots  # offsets x 2
        back_x = self.pivots[:, 0] + cos * rel[:, 0] - sin * rel[:, 1]
        back_y = self.pivots[:, 1] + sin * rel[:, 0] + cos * rel[:, 1]
        back = np.stack((back_x, back_y), axis=2)
        largest = np.minimum(np.abs(angles)[:, None] + step / 2, math.pi)
        give = (
            self.give
            + np.linalg.norm(back, axis=2) * spread
            + np.linalg.norm(rel, axis=1) * step / 2
            + 2.0 * self.pivot_give * np.sin(largest / 2)
        )
        return back, give


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
