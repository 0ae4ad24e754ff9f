"""What a region goal needs of slides and turns: part 1 of the search's bound for a goal "in a region" or "beyond a
half-plane" (a user's `in region` goal, or the clearing sub-problem's side of a goal body's way,
`vkgl.plan.search.clutter.clear_first`).

A region goal holds when no point of the body's footprint (the body-frame points of its convex hull, `GoalSpec.
footprint`) passes an edge of the region (rows `n, d`: inside when `n . p <= d`) by more than the tolerance `t`
(`vkgl.plan.task_space.feasible.goal_holds`). **Admissibility.** Let `e = max_i max_p (n_i . p - d_i) / |n_i|`,
over the footprint points `p` where the body rests and the edges `i`, attained at point `p*` and edge `i*`. For
the goal to hold, `p*` (a material point of the body: the footprint's points move with it) must end with
`n_i* . p*' - d_i* <= t`, so its (x, y) must move by at least `D = e - t / |n_i*|` towards the inside (Cauchy-
Schwarz: a move of length `s` changes `n . p` by at most `|n| s`); its 3-D displacement is no shorter. Only the
body's own moving modes move it (`vkgl.plan.search.bounds.bound`, part 1). One slide translates the body, so every point
by at most the slide's upper end `S`. One turn by `θ <= θmax` about an axis fixed in the body's frame moves a point
at distance `r` from the axis by the chord `2 r sin(θ / 2) <= 2 r sin(min(θmax, π) / 2)`, and `r` of `p*` is at
most the largest over the footprint's points and, for a turn whose pivot moves along its family (`offset *
drift`), over the band's two ends (the distance to a line is convex in the line's offset): the largest such chord
is `C`. Then `k` turns and `j` slides bring `p*` at most `k C + j S` (triangle inequality), so they number at
least `fewest_modes(D, Ψ, S, T, C)` (`vkgl.plan.search.bounds.motions`, with the heading `Ψ` a yaw goal still needs
and `T` the most one turn gives it). The bound's part 2 (`PoseNeed.left`) and parts 3-6 apply unchanged: they only
use that every mode of `b` moves each footprint point by at most `S` (slides) or `C` (turns).

**Sharper before the first turn** (`RegionNeed.left`). Slides keep the heading, so until the body's first turn
each slide moves it along its axis as it lies at rest: by at most `A` (`across`, the largest over its slides of
`max(v (-n_i* . R a))` over the slide's values `v`, `R a` the world axis) against the edge's normal. A plan whose
remaining modes make no turn therefore needs at least `ceil(D' / A)` slides (`inf` when `A` is 0: a body that
slides only along the edge never crosses it), `D'` what the slides made so far left (each gained at most `A`);
one that makes a turn needs at least `fewest_modes` with one turn at least. And the end of every mode keeps the
body's outline on the table (`body_limits.body_constraints`): the unturned poses lie in a box of translations (on a
line when all the slides are parallel), so when none of them gains `D` against the normal (`straight_reach`), a
turn is needed whatever the slides' ranges (an `open` slide may go 2 m by its range alone). While nothing has
moved the body, a plan with a turn needs two modes at least when no one turn from rest puts the footprint in the
region (`one_turn_reaches`, rigorous on its grid of angles and family offsets). The fewer of the two (no turn,
a turn) is a lower bound; after a turn (or with a heading still to change) the general count stands.

A body that already lies in the region (`e <= t`) needs nothing; one with no moving affordance that lies outside
needs `inf` (never): nothing else moves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.families import offset_bounds
from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.members import family_vectors
from vkgl.plan.graphs.motions import motion_matrices, unit_axis_and_center
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.search.bounds.motions import SLACK, PoseNeed, fewest_modes, vertical
from vkgl.se3 import wrap_angle, yaw_of


@dataclass(frozen=True)
class RegionNeed(PoseNeed):
    """`PoseNeed` of a region goal, with `across` (m): the most one slide moves the body towards the inside of
    the edge its footprint passes farthest while its heading is still its rest's (before its first turn)."""

    across: float = 0.0
    reach_straight: float = math.inf  # the most any unturned pose on the table gains (m), `straight_reach`
    one_turn: bool = True  # whether one turn from rest may put the footprint in the region (`one_turn_reaches`)

    def left(self, slides: int, turns: int) -> float:
        """The fewest moving modes still needed after `slides` slides and `turns` turns (part 2): while no turn
        has been made, the rest either makes none (each slide gains at most `across`) or makes one at least."""
        anyhow = super().left(slides, turns)
        if turns > 0 or self.heading > SLACK:
            return anyhow
        rest = self.distance - slides * self.across
        turned = self._with_a_turn(self.distance - slides * self.slide, moved=slides > 0)
        if self.reach_straight < self.distance - SLACK:  # no final pose on the table, still unturned, lies there
            return max(anyhow, turned)
        straight = 0.0 if rest <= SLACK else (math.ceil(rest / self.across - SLACK) if self.across > 0 else math.inf)
        return max(anyhow, min(straight, turned))

    def _with_a_turn(self, distance: float, moved: bool = True) -> float:
        """The fewest modes, one turn at least among them, that cover `distance` (`fewest_modes`); two at least
        when nothing has moved the body yet and no one turn from rest reaches the region."""
        if self.turn <= 0:
            return math.inf
        modes = fewest_modes(distance, self.turn, self.slide, self.turn, self.chord)  # a heading of one full turn
        return modes if moved or self.one_turn else max(modes, 2.0)


def region_gap(body: PlanBody, goal: GoalSpec) -> tuple[float, np.ndarray]:
    """How far the footprint point farthest outside an edge of `goal`'s region must move at least (m, less the
    tolerance; <= 0 when the goal's region already holds `body` where it rests), and that edge's unit normal."""
    assert goal.region is not None and goal.footprint is not None, "not a region goal"
    normals = np.linalg.norm(goal.region[:, :2], axis=1)
    outside = goal.region_excess(body.rest) / normals - goal.tol_position / normals
    worst = int(np.argmax(outside))
    return float(outside[worst]), goal.region[worst, :2] / normals[worst]


def straight_reach(problem: Problem, body: PlanBody, normal: np.ndarray, movers: list[Affordance]) -> float:
    """The most any pose of `body` that its slides alone reach from rest, with its outline on the table, lies
    against `normal` from its rest (m, `inf` when it does not lie on a table): the end of a mode keeps the outline
    on the table (`body_limits.body_constraints`), slides keep the heading and move the body along their axes (a
    line when they are all parallel, else the plane), and the translations that keep the outline on the table form
    a box."""
    if not body.on_table or problem.table_center is None or problem.table_size is None:
        return math.inf
    axes = [body.rest[:2, :3] @ unit_axis_and_center(a.motion)[0] for a in movers if a.motion.type == "prismatic"]
    axes = [a / float(np.linalg.norm(a)) for a in axes if float(np.linalg.norm(a)) > 1e-9]
    if not axes:
        return 0.0
    corners = (body.outline @ body.rest[:3, :3].T + body.rest[:3, 3])[:, :2]
    half = np.asarray(problem.table_size, dtype=float) / 2
    centre = np.asarray(problem.table_center, dtype=float)
    low = centre - half - corners.min(axis=0)  # the translations (per axis) that keep every corner on the table
    high = centre + half - corners.max(axis=0)
    if np.any(low > high + 1e-12):
        return math.inf  # it does not fit where it lies: nothing to say
    if any(abs(float(axes[0] @ a)) < 1.0 - 1e-9 for a in axes[1:]):
        return max(float(-normal @ np.array([x, y])) for x in (low[0], high[0]) for y in (low[1], high[1]))
    line = axes[0]  # the translations t * line inside the box: t in [t0, t1]
    t0, t1 = -math.inf, math.inf
    for k in range(2):
        if abs(line[k]) < 1e-12:
            if not low[k] - 1e-12 <= 0.0 <= high[k] + 1e-12:
                return math.inf
            continue
        a, b = sorted((low[k] / line[k], high[k] / line[k]))
        t0, t1 = max(t0, a), min(t1, b)
    if t0 > t1:
        return math.inf
    return max(0.0, float(-normal @ line) * t0, float(-normal @ line) * t1)


TURN_SAMPLES = 64
"""Angles (and `TURN_SAMPLES // 8` family offsets) at which `one_turn_reaches` tries a turn."""


def one_turn_reaches(body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> bool:
    """Whether one turn of `body` from rest may put its footprint within `goal`'s region (False: none can).

    Rigorous on a grid: between two samples `h` apart in angle a point at distance `r` from the axis moves at
    most `r h / 2` from the nearer sample, and a pivot moved by `delta` (a family's offset) moves a point by at
    most `2 |delta|` (`p = c + Rot (p0 - c)`), so a turn is ruled out only when every sample misses by more."""
    assert goal.region is not None and goal.footprint is not None
    normals = goal.region[:, :2] / np.linalg.norm(goal.region[:, :2], axis=1, keepdims=True)
    limits = goal.region[:, 2] / np.linalg.norm(goal.region[:, :2], axis=1) + goal.tol_position
    points = np.c_[goal.footprint, np.ones(len(goal.footprint))]
    for affordance in movers:
        if affordance.motion.type != "revolute":
            continue
        low, high = value_bounds(affordance.motion)
        angles = np.linspace(low, high, TURN_SAMPLES + 1)
        _, drift = family_vectors(affordance)
        ends = offset_bounds(affordance) if drift is not None else (0.0, 0.0)
        offsets = np.linspace(ends[0], ends[1], TURN_SAMPLES // 8 + 1)
        step = 0.0 if drift is None else float(np.linalg.norm(drift)) * float(offsets[1] - offsets[0])
        room = point_chord(affordance, goal.footprint) / max(2.0 * math.sin(min(high, math.pi) / 2.0), 1e-12)
        slack = room * (high - low) / TURN_SAMPLES / 2.0 + step  # the radius times half an angle step, the pivot's
        for offset in offsets:
            shift = np.eye(4)
            if drift is not None:
                shift[:3, 3] = offset * np.asarray(drift, dtype=float)
            for matrix in motion_matrices(affordance.motion, angles):
                pose = body.rest @ shift @ matrix @ np.linalg.inv(shift)
                xy = (points @ pose.T)[:, :2]
                if float(np.max(np.max(xy @ normals.T, axis=0) - limits)) <= slack:
                    return True
    return False


def slide_across(rest: np.ndarray, affordance: Affordance, normal: np.ndarray) -> float:
    """The most one slide of `affordance` moves its body against `normal` (m; the body at `rest`'s heading)."""
    low, high = value_bounds(affordance.motion)
    axis = rest[:2, :3] @ unit_axis_and_center(affordance.motion)[0]
    inward = -float(axis @ normal)
    return max(0.0, high * inward, low * inward)


def point_chord(affordance: Affordance, points: np.ndarray) -> float:
    """The farthest one mode of turn `affordance` moves any of the body-frame `points` (n x 3, m): the chord of
    the largest distance from its axis, over the family's band when its pivot moves with the contact."""
    upper = value_bounds(affordance.motion)[1]
    axis, center = unit_axis_and_center(affordance.motion)
    assert center is not None, "not a turn"
    _, drift = family_vectors(affordance)
    ends = offset_bounds(affordance) if drift is not None else (0.0, 0.0)
    radius = 0.0
    for s in ends:
        pivot = center if drift is None else center + s * drift
        rel = points - pivot
        radius = max(radius, float(np.max(np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1))))
    return 2.0 * radius * math.sin(min(upper, math.pi) / 2.0)


def region_pose_need(problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> RegionNeed | None:
    """What a region goal needs of slides and turns (the module's docstring), or None when it holds already and
    its heading (if any) too."""
    gap, normal = region_gap(body, goal)
    distance = max(0.0, gap)
    heading = 0.0
    if goal.yaw is not None:
        heading = max(0.0, abs(wrap_angle(yaw_of(body.rest) - goal.yaw)) - goal.tol_yaw)
    if distance <= SLACK and heading <= SLACK:
        return None
    assert goal.footprint is not None
    turners = [a for a in movers if a.motion.type == "revolute"]
    level = all(vertical(body.rest, a) for a in turners)  # else one turn may tilt the others' axes
    return RegionNeed(
        distance=distance,
        heading=heading,
        slide=max((value_bounds(a.motion)[1] for a in movers if a.motion.type == "prismatic"), default=0.0),
        turn=max((value_bounds(a.motion)[1] if level else math.pi for a in turners), default=0.0),
        chord=max((point_chord(a, goal.footprint) for a in turners), default=0.0),
        across=max((slide_across(body.rest, a, normal) for a in movers if a.motion.type == "prismatic"), default=0.0),
        reach_straight=straight_reach(problem, body, normal, movers),
        one_turn=one_turn_reaches(body, goal, movers),
    )


def region_modes(
    problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]
) -> tuple[float, str, PoseNeed | None]:
    """The moving modes a region goal needs at least, why in words (when more than one, or never), and its
    `PoseNeed` for the bound's part 2 (None: the goal holds already)."""
    need = region_pose_need(problem, body, goal, movers)
    if need is None:
        return 0.0, "", None
    modes = need.left(0, 0)
    where = goal.region_words or "its goal region"
    if math.isinf(modes):
        return modes, f"{body.name} lies outside {where} and nothing of {body.type.name} moves it there", need
    if modes <= 1:
        return modes, "", need
    return (
        modes,
        (
            f"{body.name}'s footprint lies {need.distance * 100:.1f} cm outside {where} (beyond the tolerance); a "
            f"slide of {body.type.name} moves it at most {need.slide * 100:.1f} cm ({need.across * 100:.1f} cm "
            f"towards it before a turn), a turn at most {need.chord * 100:.1f} cm: at least {modes:g} contacts"
        ),
        need,
    )
