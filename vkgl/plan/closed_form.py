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

And one about the hand: when the last mode holds the hand on a goal body whose
goal fixes position and heading, the hand's final pose follows from the goal;
if that is out of the arm's reach by more than the goal's tolerance can move
it, nothing can help.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import nnls

from vkgl.plan.graph import motion_type
from vkgl.plan.model import GoalSpec, Problem
from vkgl.plan.reach import Rejection, reach_violation, unreachable
from vkgl.plan.rollout import (
    Sequence,
    acting_engagement,
    hand_chain,
    motion_matrices,
    unit_axis_and_center,
)
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
    far = _hand_beyond_reach_at_goal(problem, seq)
    if far is not None:
        return far
    return values, bool(pinned.all())


def _goal_values(
    problem: Problem, seq: Sequence, goal: GoalSpec, values: np.ndarray
) -> dict[int, tuple[float, bool]] | Rejection:
    """Values of the goal body's motions that meet its goal (and whether they are unique), or a Rejection."""
    own = [i for i, (_, e) in enumerate(seq.variables) if e.body == goal.body]
    turns = [i for i in own if motion_type(problem, seq.variables[i][1]) == "revolute"]
    slides = [i for i in own if i not in turns]
    rest = problem.bodies[goal.body].rest
    signs = [_vertical_sign(problem, seq, i, rest) for i in turns]
    if goal.yaw is None or None in signs or len(turns) > 2:
        return {}  # the optimiser alone decides
    needed = wrap_angle(goal.yaw - yaw_of(rest))
    candidates = _turn_candidates(needed, goal.tol_yaw, signs)  # type: ignore[arg-type]
    if not candidates:
        what = "nothing turns it" if not turns else "its turns cannot add up to that (each turns one way, <= 180 deg)"
        return Rejection("yaw", f"{goal.body} must turn by {math.degrees(needed):.1f} deg but {what}")
    if goal.position is None:
        first = candidates[0]
        return {i: (a, len(candidates) == 1) for i, a in zip(turns, first)}
    angles = np.array(candidates).reshape(len(candidates), len(turns))
    origins, columns = _affine_positions(problem, seq, goal.body, turns, slides, angles)
    best: tuple[float, int, np.ndarray] | None = None
    for row in range(len(angles)):
        residual, solution = _closest(columns[row], goal.position - origins[row, : len(goal.position)])
        if best is None or residual < best[0]:
            best = (residual, row, solution)
    assert best is not None
    slack = goal.tol_position + (0.5 * math.pi / (TURN_GRID - 1) * LEVER_BOUND if len(turns) > 1 else 0.0)
    if best[0] > slack:
        how = "along its slides" if slides else "and nothing slides it"
        return Rejection(
            "position",
            f"{goal.body} ends at least {best[0] * 100:.1f} cm from its goal "
            f"position with the heading the goal asks for, {how}",
            best[0],
        )
    exact_turns = len(candidates) == 1
    unique = bool(np.linalg.matrix_rank(columns[best[1]], tol=1e-9) == len(slides)) if slides else True
    out = {i: (float(a), exact_turns) for i, a in zip(turns, angles[best[1]])}
    out.update({i: (float(v), exact_turns and unique) for i, v in zip(slides, best[2])})
    return out


def _affine_positions(
    problem: Problem, seq: Sequence, body: str, turns: list[int], slides: list[int], angles: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """For each row of turn `angles`: the body's final position with no slide, and how each slide moves it.

    The position is exactly affine in the slides: a slide by v along a moves
    the body by v times a turned by the motions before it (n x 3 and n x 3 x s).
    """
    n = len(angles)
    pose = np.broadcast_to(problem.bodies[body].rest, (n, 4, 4)).copy()
    columns = []
    for i, (_, e) in enumerate(seq.variables):
        if e.body != body:
            continue
        motion = problem.affordance(e.body, e.affordance).motion
        if i in turns:
            pose = pose @ motion_matrices(motion, angles[:, turns.index(i)])
        elif i in slides:
            columns.append(pose[:, :3, :3] @ unit_axis_and_center(motion)[0])
    stacked = np.stack(columns, axis=2) if columns else np.zeros((n, 3, 0))
    return pose[:, :3, 3], stacked


def _closest(columns: np.ndarray, offset: np.ndarray) -> tuple[float, np.ndarray]:
    """Non-negative slide values that bring the position closest to `offset` away, and the distance left."""
    columns = columns[: len(offset)]
    if columns.shape[1] == 0:
        return float(np.linalg.norm(offset)), np.zeros(0)
    solution, residual = nnls(columns, offset)
    return float(residual), solution


def _vertical_sign(problem: Problem, seq: Sequence, index: int, rest: np.ndarray) -> float | None:
    """+1 / -1 when turn `index` is about the world's +z / -z axis (the body level), else None."""
    e = seq.variables[index][1]
    axis = problem.affordance(e.body, e.affordance).motion.axis.array()  # type: ignore[union-attr]
    axis = rest[:3, :3] @ (axis / np.linalg.norm(axis))
    return math.copysign(1.0, axis[2]) if abs(abs(axis[2]) - 1.0) < 1e-6 else None


def _turn_candidates(needed: float, tol: float, signs: list[float]) -> list[tuple[float, ...]]:
    """Turn angles in [0, pi] whose signed sum gives the heading change `needed` (within `tol`)."""
    if not signs:
        return [()] if abs(needed) <= tol else []
    if len(signs) == 1:
        angle = _in_half_turn(signs[0] * needed, tol)
        return [] if angle is None else [(angle,)]
    out: list[tuple[float, ...]] = []
    for first in np.linspace(0.0, math.pi, TURN_GRID):
        second = _in_half_turn(signs[1] * (needed - signs[0] * first), tol)
        if second is not None:
            out.append((float(first), second))
    return out


def _in_half_turn(angle: float, tol: float) -> float | None:
    """`angle` moved by whole turns into [0, pi] (within `tol` of it), or None."""
    angle %= 2 * math.pi
    if angle <= math.pi:
        return angle
    if angle - math.pi <= tol:
        return math.pi
    if 2 * math.pi - angle <= tol:
        return 0.0
    return None


def _hand_beyond_reach_at_goal(problem: Problem, seq: Sequence) -> Rejection | None:
    """A Rejection when the hand, holding a goal body at its goal pose at the end, is surely out of reach."""
    graph = seq.graphs[-1]
    acting = acting_engagement(problem, graph)
    goal = next((g for g in problem.goals if acting is not None and g.body == acting.body), None)
    if acting is None or goal is None or goal.position is None or goal.yaw is None:
        return None
    rest = problem.bodies[goal.body].rest
    if abs(rest[2, 2] - 1.0) > 1e-9:
        return None
    chain = hand_chain(problem, graph, acting)
    if chain is None:
        return None
    pose = np.eye(4)
    pose[:3, :3] = np.array(
        [[math.cos(goal.yaw), -math.sin(goal.yaw), 0.0], [math.sin(goal.yaw), math.cos(goal.yaw), 0.0], [0.0, 0.0, 1.0]]
    )
    pose[:3, 3] = (*goal.position[:2], goal.position[2] if len(goal.position) > 2 else rest[2, 3])
    hand = pose @ chain[0]
    slack = goal.tol_position + math.hypot(chain[0][0, 3], chain[0][1, 3]) * goal.tol_yaw
    if reach_violation(problem, hand[:3, 3]) <= slack:
        return None
    found = unreachable(problem, hand)
    why = found.why if found is not None else "the hand would be out of reach"
    return Rejection("reach", f"at the goal pose of {goal.body}, {why}", found.excess if found else 1.0)
