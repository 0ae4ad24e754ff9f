"""A goal body's final position as an affine function of its slides, given its turns' angles.

Facts of the model this relies on (`closed_form` states them): a goal body's
pose depends only on its own motions, composed in mode order; a slide by v
along a moves it by v times a turned by the motions before it. So with the
turns fixed, bounded least squares (`closest`) gives exactly the closest
position its slides can reach (`best_row` picks the best of many rows of
angles). `position_out_of_reach` turns that into a proof, before any
optimisation, that a goal which leaves the heading free cannot be met.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable

import numpy as np

from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import pivot_travel
from vkgl.plan.graphs.motions import motion_matrices, unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, value_bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection

FREE_TURN_GRIDS = {0: (1,), 1: (19, 181), 2: (13, 61)}
"""Angles scanned per turn of the goal body by `position_out_of_reach`, coarse then fine, by how many turns it
has (one turn: 19 then 181 angles over its range; two: 13 x 13, then 61 x 61 rows)."""


def position_out_of_reach(
    problem: Problem, seq: Sequence, goal: GoalSpec, turns: list[int], slides: list[int]
) -> Rejection | None:
    """A Rejection when no values of `seq` bring `goal.body` within its goal position's tolerance (any heading),
    None when some may (the optimiser then decides, as before): a necessary test, never a start.

    `turns` (about vertical axes) and `slides` index `seq.variables` (the goal body's own motions). First,
    the goal farther from the body's start than all its slides and turns' chords can take it (the triangle
    inequality, no scan). Then each turn's angle is scanned on a grid (`FREE_TURN_GRIDS`, ends included,
    coarse then fine) and the slides are solved exactly at each row (`best_row`). Why the slack makes it
    sound: moving turn i's angle by d with every other value held
    turns the whole later path rigidly about its pivot, so the final position moves by at most d times the
    pivot's distance to it, which is at most L = r_i + D (r_i: the pivot's distance from the body's origin,
    fixed in the body; D: how far the later motions can take the origin, at most each slide's upper bound plus
    2 r_j per other turn j, a chord). Every angle lies within half a grid step h_i of a grid row, so the
    distance at the best true values is at least the grid's best less the sum of L h_i / 2. A turn whose
    contact may move along its family (`Sequence.offsets`) turns about a pivot moved by d: the same turn
    about the unmoved pivot followed by a translation of the whole later path by (I - R) d, at most a chord
    2 |d| sin(a / 2) at its largest angle a (`_drift_bound`), which is taken off too. Only if what is left
    still exceeds the tolerance is the sequence rejected. No scan with more than two turns (the triangle
    inequality only); nothing with unbounded values.
    """
    assert goal.position is not None
    setup = scan_setup(problem, seq, goal, turns, slides)
    if setup is None:
        return None
    turn_limits, slide_limits, lever, drifts = setup
    how = "whatever heading it ends with" if turns else "along its slides"
    # First the triangle inequality: no motion takes the origin farther than its slide or its chord.
    radii = [_pivot_radius(problem, seq, i) for i in turns]  # at offset 0 of their families
    chords = sum(2.0 * r * math.sin(min(hi, math.pi) / 2) for r, (_, hi) in zip(radii, turn_limits))
    start = problem.bodies[goal.body].rest[: len(goal.position), 3]
    at_least = float(np.linalg.norm(goal.position - start)) - float(slide_limits[:, 1].sum()) - chords - drifts
    if at_least > goal.tol_position + 1e-9:
        return Rejection(
            Kind.POSITION, f"{goal.body} ends at least {at_least * 100:.1f} cm from its goal position, {how}", at_least
        )
    if len(turns) not in FREE_TURN_GRIDS:
        return None
    for count in FREE_TURN_GRIDS[len(turns)]:  # a coarse scan decides most; a finer one only when it cannot
        angles, steps = turn_rows(turn_limits, count)
        origins, columns = affine_positions(problem, seq, goal.body, turns, slides, angles, turn_matrices)
        distance = best_row(columns, origins, goal.position, slide_limits)[0]
        if distance <= goal.tol_position:
            return None  # a row of the scan reaches the goal itself: no finer scan can prove it out of reach
        at_least = distance - sum(lever * h / 2 for h in steps) - drifts
        if at_least > goal.tol_position + 1e-9:
            why = f"{goal.body} ends at least {at_least * 100:.1f} cm from its goal position, {how}"
            return Rejection(Kind.POSITION, why, at_least)
    return None


def scan_setup(
    problem: Problem, seq: Sequence, goal: GoalSpec, turns: list[int], slides: list[int]
) -> tuple[list[tuple[float, float]], np.ndarray, float, float] | None:
    """What a scan of the goal body's turns needs (`position_out_of_reach` proves why): the turns' value limits,
    the slides' (s x 2), the lever L (how far the final position moves per radian of any one turn, at most)
    and the drifts (how far moving the turns' contacts along their families can move it); None when a value
    is unbounded."""
    turn_limits = [value_limits(problem, seq, i) for i in turns]
    slide_limits = np.array([value_limits(problem, seq, i) for i in slides]).reshape(len(slides), 2)
    if not (np.isfinite(turn_limits).all() and np.isfinite(slide_limits).all()):
        return None
    radii = [_pivot_radius(problem, seq, i) for i in turns]  # at offset 0 of their families
    drifts = sum(_drift_bound(problem, seq, i, hi) for i, (_, hi) in zip(turns, turn_limits))
    lever = max(radii, default=0.0) + float(slide_limits[:, 1].sum()) + 2.0 * sum(radii)
    return turn_limits, slide_limits, lever, drifts


def turn_rows(turn_limits: list[tuple[float, float]], count: int) -> tuple[np.ndarray, list[float]]:
    """Every combination of `count` angles per turn over its limits, ends included (rows x turns), and each
    turn's grid step."""
    grids = [np.linspace(lo, hi, count) for lo, hi in turn_limits]
    angles = np.stack([g.ravel() for g in np.meshgrid(*grids, indexing="ij")], axis=1) if grids else np.zeros((1, 0))
    steps = [(hi - lo) / (count - 1) if count > 1 else 0.0 for lo, hi in turn_limits]
    return angles, steps


def row_distances(columns: np.ndarray, origins: np.ndarray, position: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """Per row of turn angles, how close the slides within `limits` bring the body to `position`: exact with at
    most one slide (the clipped projection `closest` makes), a lower bound with more (no bounds at all)."""
    k = len(position)
    offsets = position - origins[:, :k]
    if columns.shape[2] == 0:
        return np.asarray(np.linalg.norm(offsets, axis=1))
    if columns.shape[2] > 1:
        return _unbounded_distances(columns[:, :k, :], offsets)
    a = columns[:, :k, 0]
    norm = np.einsum("ij,ij->i", a, a)
    along = np.divide(np.einsum("ij,ij->i", a, offsets), norm, out=np.zeros(len(a)), where=norm > 0)
    value = np.clip(along, limits[0, 0], limits[0, 1])
    return np.asarray(np.linalg.norm(a * value[:, None] - offsets, axis=1))


def turn_matrices(motion: object, angles: np.ndarray) -> np.ndarray:
    """A turn's motion matrices at each of `angles` (n x 4 x 4, Rodrigues' formula in one NumPy pass): the
    same rotations as `motion_matrices` up to rounding, for scans of thousands of angles."""
    axis, center = unit_axis_and_center(motion)
    assert center is not None
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    cos, sin = np.cos(angles)[:, None, None], np.sin(angles)[:, None, None]
    rotations = cos * np.eye(3) + sin * cross + (1.0 - cos) * np.outer(axis, axis)
    m = np.zeros((len(angles), 4, 4))
    m[:, :3, :3] = rotations
    m[:, :3, 3] = center - rotations @ center
    m[:, 3, 3] = 1.0
    return m


def value_limits(problem: Problem, seq: Sequence, index: int) -> tuple[float, float]:
    """The values motion value `index` may take (its affordance's `range` within the planner's caps)."""
    e = seq.variables[index][1]
    return value_bounds(problem.affordance(e.body, e.affordance).motion)


def _drift_bound(problem: Problem, seq: Sequence, index: int, largest: float) -> float:
    """How far moving turn `index`'s contact anywhere along its band can move the body's final position
    (m): the chord of the pivot's largest travel at the turn's largest angle (`members.pivot_travel`: a family's
    drift, an arc member's pivot); 0 without a family."""
    e = seq.variables[index][1]
    return 2.0 * pivot_travel(problem, e.body, e.affordance) * math.sin(min(largest, math.pi) / 2)


def _pivot_radius(problem: Problem, seq: Sequence, index: int) -> float:
    """How far turn `index`'s pivot lies from its body's origin (m; in the body's frame, where it stays)."""
    e = seq.variables[index][1]
    center = unit_axis_and_center(problem.affordance(e.body, e.affordance).motion)[1]
    return 0.0 if center is None else float(np.linalg.norm(center))


def affine_positions(
    problem: Problem,
    seq: Sequence,
    body: str,
    turns: list[int],
    slides: list[int],
    angles: np.ndarray,
    matrices: Callable[[object, np.ndarray], np.ndarray] = motion_matrices,
) -> tuple[np.ndarray, np.ndarray]:
    """For each row of turn `angles`: the body's final position with no slide, and how each slide moves it.

    The position is exactly affine in the slides: a slide by v along a moves
    the body by v times a turned by the motions before it (n x 3 and n x 3 x s). `matrices` gives a turn's
    motion matrices at many angles (`motion_matrices` by default, whose numbers the optimiser's starts keep).
    """
    own = tuple(
        (e, turns.index(i) if i in turns else -1 if i in slides else -2)
        for i, (_, e) in enumerate(seq.variables)
        if e.body == body
    )
    key = (id(problem), body, own, id(matrices), angles.shape, np.asarray(angles, dtype=float).tobytes())
    kept = _AFFINE.get(key)
    if kept is not None and kept[0]() is problem and kept[1] is matrices:
        return kept[2], kept[3]
    origins, stacked = _affine_positions(problem, body, own, angles, matrices)
    origins.flags.writeable = stacked.flags.writeable = False
    global _affine_bytes
    if _affine_bytes > _AFFINE_BYTES:
        _AFFINE.clear()
        _affine_bytes = 0
    _AFFINE[key] = (weakref.ref(problem), matrices, origins, stacked)
    _affine_bytes += origins.nbytes + stacked.nbytes + len(key[-1])
    return origins, stacked


_AFFINE: dict[tuple[object, ...], tuple[weakref.ref[Problem], object, np.ndarray, np.ndarray]] = {}
_affine_bytes = 0
_AFFINE_BYTES = 32 << 20
"""`affine_positions` answers kept (then forgotten all at once past this many bytes), by the goal body's own
motions (their engagements and roles, in mode order) and the angles: the search checks many sequences whose goal
body moves the same way (they differ in what the hand and the tools do besides), and a scan of 241 x 241 rows costs
milliseconds. One cache for every problem, so that its cap bounds them all (the clear-first walk keeps dozens of
problems alive at once); an entry names its problem weakly (a problem solved and dropped is not kept alive by it:
its id may then be another's, and the dead reference tells them apart) and keeps the matrices' function."""


def _affine_positions(
    problem: Problem,
    body: str,
    own: tuple[tuple[Engagement, int], ...],
    angles: np.ndarray,
    matrices: Callable[[object, np.ndarray], np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """`affine_positions` of the body's `own` motions (engagement, and the turn's column of `angles`, -1 for a
    slide, -2 for neither), computed."""
    n = len(angles)
    pose = np.broadcast_to(problem.bodies[body].rest, (n, 4, 4)).copy()
    columns = []
    for e, role in own:
        motion = problem.affordance(e.body, e.affordance).motion
        if role >= 0:
            pose = pose @ matrices(motion, angles[:, role])
        elif role == -1:
            columns.append(pose[:, :3, :3] @ unit_axis_and_center(motion)[0])
    stacked = np.stack(columns, axis=2) if columns else np.zeros((n, 3, 0))
    return pose[:, :3, 3].copy(), stacked  # a copy: the poses' other entries are not kept with it


SCREEN = 1e-9
"""m: rows whose estimated distance to the goal is within this of the best estimate are solved exactly."""


def best_row(
    columns: np.ndarray, origins: np.ndarray, position: np.ndarray, limits: np.ndarray
) -> tuple[float, int, np.ndarray]:
    """(distance left, row, slide values) of the first row of turn angles whose slides come closest to `position`.

    Every row's `closest`; with at most one slide, all rows are first estimated in one NumPy pass, and only
    those within `SCREEN` of the best estimate are solved by `closest` (the estimates differ from it by
    rounding only, far less than `SCREEN`, so the same row and numbers come out, in a fraction of the time:
    a two-turn sequence has up to `TURN_GRID` rows).
    """
    n, k = len(columns), len(position)
    offsets = position - origins[:, :k]
    rows: list[int] = list(range(n))
    if columns.shape[2] <= 1 and n > 1:
        if columns.shape[2] == 0:
            estimate = np.linalg.norm(offsets, axis=1)
        else:
            a = columns[:, :k, 0]
            norm = np.einsum("ij,ij->i", a, a)
            along = np.divide(np.einsum("ij,ij->i", a, offsets), norm, out=np.zeros(n), where=norm > 0)
            value = np.clip(along, limits[0, 0], limits[0, 1])
            estimate = np.linalg.norm(a * value[:, None] - offsets, axis=1)
        if np.isfinite(estimate).all():
            rows = np.flatnonzero(estimate <= estimate.min() + SCREEN).tolist()
    elif n > 1:
        return _best_row_screened(columns[:, :k, :], offsets, position, origins, limits)
    best: tuple[float, int, np.ndarray] | None = None
    for row in rows:
        residual, solution = closest(columns[row], position - origins[row, :k], limits)
        if best is None or residual < best[0]:
            best = (residual, row, solution)
    assert best is not None
    return best


def _best_row_screened(
    columns: np.ndarray, offsets: np.ndarray, position: np.ndarray, origins: np.ndarray, limits: np.ndarray
) -> tuple[float, int, np.ndarray]:
    """`best_row` with two slides or more: the same row and numbers, with fewer bounded least squares.

    Each row's unconstrained least-squares distance (one batched NumPy pass) is a lower bound of its bounded
    one. The row of the smallest bound is solved first; then, in row order, only rows whose bound (less
    `SCREEN` for rounding) does not exceed the best distance found so far can be closer, and only they are
    solved; equal distances keep the first row, as the plain loop over every row does.
    """
    k = len(position)
    lower = _unbounded_distances(columns, offsets) - SCREEN
    if not np.isfinite(lower).all():
        lower = np.full(len(columns), -np.inf)
    first = int(np.argmin(lower))
    residual, solution = closest(columns[first], position - origins[first, :k], limits)
    best = (residual, first, solution)
    for row in range(len(columns)):
        if row == first or lower[row] > best[0]:
            continue
        residual, solution = closest(columns[row], position - origins[row, :k], limits)
        if residual < best[0] or (residual == best[0] and row < best[1]):
            best = (residual, row, solution)
    return best


def _unbounded_distances(columns: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Per row, the distance left by the best slide values with no bounds at all (n x k x s columns)."""
    fitted = np.einsum("nks,ns->nk", columns, np.einsum("nsk,nk->ns", np.linalg.pinv(columns), offsets))
    return np.linalg.norm(offsets - fitted, axis=1)


def closest(columns: np.ndarray, offset: np.ndarray, limits: np.ndarray) -> tuple[float, np.ndarray]:
    """Slide values within `limits` (s x 2) that bring the position closest to `offset` away, and the distance left.

    Non-negative least squares (scipy `nnls`) when its answer is within the
    limits, else bounded least squares (`lsq_linear`, BVLS): both exact.
    """
    columns = columns[: len(offset)]
    if columns.shape[1] == 0:
        return float(np.linalg.norm(offset)), np.zeros(0)
    lower, upper = limits[:, 0], limits[:, 1]
    if columns.shape[1] == 1:  # one slide (the usual case): the projection, clipped
        a = columns[:, 0]
        norm = float(a @ a)
        value = min(max(float(a @ offset) / norm if norm > 0 else 0.0, lower[0]), upper[0])
        return float(np.linalg.norm(a * value - offset)), np.array([value])
    from scipy.optimize import lsq_linear, nnls  # here: two slides of one body are rare, the import is not cheap

    solution, residual = nnls(columns, offset)
    if np.all(solution >= lower) and np.all(solution <= upper):
        return float(residual), solution
    fixed = upper - lower < 1e-12  # BVLS wants lower < upper: a slide with no room is a constant
    solution = lower.copy()
    rest = offset - columns[:, fixed] @ lower[fixed]
    if not fixed.all():
        free = ~fixed
        solution[free] = lsq_linear(columns[:, free], rest, bounds=(lower[free], upper[free]), method="bvls").x
    return float(np.linalg.norm(columns @ solution - offset)), solution
