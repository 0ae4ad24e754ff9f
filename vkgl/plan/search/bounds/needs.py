"""What each goal body needs from its start, fixed per problem: parts 1, 4, 6 and 7 of the search's bound
(`vkgl.plan.search.bounds.bound`, whose docstring proves each), found once per problem (`body_needs`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.search.bounds.goal_reach import End, WrongEnds, ends_beyond_the_hand
from vkgl.plan.search.bounds.motions import SLACK, PoseNeed, fewest_modes, pose_need, translation, vertical
from vkgl.plan.search.bounds.one_mode import missing_ends, missing_movers
from vkgl.plan.search.bounds.region_need import region_modes
from vkgl.plan.task_space.reach.workspace import unreachable
from vkgl.se3 import wrap_angle, yaw_of

_SLACK = SLACK  # `motions.SLACK`: rounding room

MOVING = ("prismatic", "revolute")
"""The motion types that move a body by a value (part 1)."""


@dataclass(frozen=True)
class BodyNeed:
    """What a goal body needs from its start, fixed per problem: `modes` (moving modes in all, `inf`: never) and
    `why` (the words that explain it, with the numbers), and whether only a tool can move it (`needs_tool`)."""

    body: str
    modes: float
    why: str
    needs_tool: bool
    ends_by_tool: bool = False  # part 6: the hand cannot hold any of its contacts where its goal puts it
    beyond_why: str = ""  # part 6's reason, with the reach's numbers
    pose: PoseNeed | None = None  # part 2: what slides and turns must still cover, given those made
    wrong_grasps: frozenset[tuple[str, str]] = frozenset()  # part 6: (tool, grasp) that cannot end it there either
    wrong_ends: tuple[WrongEnds, ...] = ()  # part 6 contact by contact, per goal: (tool, grasp, mover) that cannot
    misses: frozenset[str] = frozenset()  # part 7: movers whose one mode from rest cannot end it there
    missed_ends: frozenset[End] = frozenset()  # part 7: (tool, grasp, mover) that cannot, the hand in reach

    def cannot_end(self, end: End) -> bool:
        """Part 6 contact by contact: whether `end` (tool or None, grasp or None, mover) cannot end the body where
        a goal of it accepts it."""
        return any(end in wrong for wrong in self.wrong_ends)

    def ends_that_cannot(self) -> frozenset[End]:
        """Every such end (what `cannot_end` says yes to)."""
        return frozenset().union(*(wrong.every() for wrong in self.wrong_ends))


_NEEDS: dict[tuple[int, ...], tuple[tuple[object, ...], list[BodyNeed]]] = {}
"""`_needs` by what it reads (the same objects): the clear-first walk's searches share goals, bodies and arm."""


def body_needs(problem: Problem, tools: frozenset[str]) -> list[BodyNeed]:
    """`_needs`, kept for the same goals, goal bodies, tools, effectors, arm and table (the objects, kept with it so
    that their ids stay their own): a search that keeps other bodies still (`clutter.still.kept_still`) reuses it."""
    inputs = (
        *problem.goals,
        *(problem.bodies.get(g.body) for g in problem.goals),  # what it reads of the bodies: the goal bodies',
        *(problem.bodies[e.tool] for e in problem.effectors if e.tool is not None),  # and the tools'
        *problem.effectors,
        problem.arm,
        problem.table_center,
        problem.table_size,
    )
    key = tuple(id(x) for x in inputs)
    kept = _NEEDS.get(key)
    if kept is not None and all(a is b for a, b in zip(kept[0], inputs, strict=True)):
        return kept[1]
    if len(_NEEDS) >= 64:
        _NEEDS.clear()
    needs = _needs(problem, tools)
    _NEEDS[key] = (inputs, needs)
    return needs


def _needs(problem: Problem, tools: frozenset[str]) -> list[BodyNeed]:
    """Per goal body, the moving modes its goals need (the largest over its goals) and whether only a tool can."""
    out: dict[str, BodyNeed] = {}
    for goal in problem.goals:
        body = problem.bodies[goal.body]
        if goal.body in tools or any(a.motion.type == "free" for a in body.affordances):
            continue  # carried in the hand, or put down where it was let go: no bound on how far one step goes (part 5)
        movers = movers_of(body)
        modes, why, pose = _goal_modes(problem, body, goal, movers)
        misses = missing_movers(problem, body, goal, movers)
        missed = missing_ends(problem, body, goal, movers, misses)
        if modes == 1 and misses and misses == {m.name for m in movers}:
            modes, why = 2.0, _no_one_mode_words(body, goal)  # part 7: no one mode from rest ends it there
        kept = out.get(goal.body)
        beyond = ends_beyond_the_hand(problem, body, goal, movers) or (kept.beyond_why if kept is not None else "")
        if kept is None or modes > kept.modes:
            kept = BodyNeed(goal.body, modes, why, _needs_tool(problem, body, movers), pose=pose)
        wrong = _wrong_grasps(problem, body, goal, movers, tools) if beyond else frozenset()
        ends = (WrongEnds(problem, body, goal, movers),) if len(tools) == len(_frames(problem)) else ()
        out[goal.body] = replace(
            kept,
            ends_by_tool=bool(beyond),
            beyond_why=beyond or "",
            wrong_grasps=kept.wrong_grasps | wrong,
            wrong_ends=kept.wrong_ends + ends,
            misses=kept.misses | misses,
            missed_ends=kept.missed_ends | missed,
        )
    return list(out.values())


def _no_one_mode_words(body: PlanBody, goal: GoalSpec) -> str:
    return (
        f"no one contact moves {body.name} from where it rests to its goal (within "
        f"{goal.tol_position * 100:.1f} cm wanted), whatever its value and offset: at least 2 contacts"
    )


def _frames(problem: Problem) -> list[str]:
    """The tool frames' tools, one per frame (a tool with two frames is named twice)."""
    return [e.tool for e in problem.effectors if e.tool is not None]


def _wrong_grasps(
    problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance], tools: frozenset[str]
) -> frozenset[tuple[str, str]]:
    """Part 6: the (tool, grasp) pairs with which no frame of the tool can hold a mover's contact of `body`
    anywhere `goal` accepts (the hand out of reach, `goal_reach.ends_beyond_the_hand` through the tool)."""
    out = set()
    for tool in sorted(tools):
        frames = [e for e in problem.effectors if e.tool == tool]
        for grasp in problem.bodies[tool].affordances:
            if grasp.motion.type != "free":
                continue
            chains = [e.frame_inverse @ problem.action(tool, grasp.name) for e in frames]
            if all(ends_beyond_the_hand(problem, body, goal, movers, chain) for chain in chains):
                out.add((tool, grasp.name))
    return frozenset(out)


def movers_of(body: PlanBody) -> list[Affordance]:
    """The affordances that can move `body` (only its physical joint's type, if it has one)."""
    return [a for a in body.affordances if a.motion.type in MOVING and (body.joint in (None, a.motion.type))]


def _goal_modes(
    problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]
) -> tuple[float, str, PoseNeed | None]:
    """The moving modes `goal` needs at least (part 1 of the module's docstring), why in words, and what its
    position and heading need of slides and turns (None when neither is off)."""
    parts: list[tuple[float, str]] = [(0.0, "")]
    pose = pose_need(body, goal, movers)
    if goal.region is not None:  # part 1 for a region: its footprint's farthest point (`region_need`)
        modes, why, pose = region_modes(problem, body, goal, movers)
        parts.append((modes, why))
    rest = body.rest
    kind = body.type.name
    far: _Gap | None = None
    if goal.position is not None:
        far = _Gap(float(np.linalg.norm(rest[: len(goal.position), 3] - goal.position)), goal.tol_position, "cm")
        if far.needed > _SLACK:
            step, name = max(((translation(a, body.affordances), a.name) for a in movers), default=(0.0, ""))
            parts.append(far.modes(step, f"{body.name} is", f"{kind}.{name} moves it"))
            off = _off_its_line(rest, goal, movers)
            if off is not None and off - goal.tol_position > _SLACK:
                parts.append((math.inf, _off_line_words(body, movers, _Gap(off, goal.tol_position, "cm"))))
    if goal.yaw is not None:
        turn = _Gap(abs(wrap_angle(yaw_of(rest) - goal.yaw)), goal.tol_yaw, "deg")
        if turn.needed > _SLACK:
            turners = [a for a in movers if a.motion.type == "revolute"]
            level = all(vertical(rest, a) for a in turners)  # else one turn may tilt the others' axes
            turns = [(value_bounds(a.motion)[1] if level else math.pi, a.name) for a in turners]
            if not turns:
                parts.append((math.inf, _no_turn(body, turn)))
            else:
                step, name = max(turns)
                parts.append(turn.modes(step, f"{body.name}'s heading is", f"{kind}.{name} turns it"))
                if far is not None and far.needed > _SLACK and pose is not None:
                    parts.append(_slides_and_turns(body, pose, far, turn))
    if goal.opening is not None and body.joint is not None:
        unit = "cm" if body.joint == "prismatic" else "deg"
        opening = _Gap(abs(body.start_state - goal.opening), goal.tol_opening, unit)
        if opening.needed > _SLACK:
            if body.joint == "prismatic":
                step, name = max(((value_bounds(a.motion)[1], a.name) for a in movers), default=(0.0, ""))
                span = f"from {opening.words(body.start_state)} to {opening.words(goal.opening)}"
                parts.append(opening.modes(step, f"{body.name}'s opening ({span}) is", f"{kind}.{name} opens it"))
            else:
                parts.append((1.0, ""))
    modes, why = max(parts, key=lambda p: p[0])
    return modes, why, pose


def _slides_and_turns(body: PlanBody, pose: PoseNeed, far: _Gap, turn: _Gap) -> tuple[float, str]:
    """The moving modes a goal needs that is both far and turned (part 1): a slide keeps the heading, a turn
    changes it by at most `pose.turn` and moves the origin by at most its chord, so the modes are at least
    `fewest_modes` of the largest slide and the largest chord."""
    slide, chord = pose.slide, pose.chord
    modes = fewest_modes(pose.distance, pose.heading, slide, pose.turn, chord)
    if modes <= 1 or math.isinf(modes):
        return modes, ""
    return modes, (
        f"{body.name} is {far.words(far.distance)} from its goal and its heading {turn.words(turn.distance)} from "
        f"the goal's (within {far.words(far.tolerance)}, {turn.words(turn.tolerance)} wanted); a slide of "
        f"{body.type.name} moves it at most {far.words(slide)} and keeps its heading, a turn moves it at most "
        f"{far.words(chord)}: at least {modes:g} contacts"
    )


@dataclass(frozen=True)
class _Gap:
    """How far a goal is (`distance`, m or rad), its tolerance, and the unit its words use."""

    distance: float
    tolerance: float
    unit: str

    @property
    def needed(self) -> float:
        """What the motions must cover at least (triangle inequality)."""
        return self.distance - self.tolerance

    def words(self, value: float) -> str:
        """`value` in the gap's unit: "27.6 cm", "35.0 deg"."""
        scale = 100.0 if self.unit == "cm" else 180.0 / math.pi
        return f"{value * scale:.1f} {self.unit}"

    def modes(self, step: float, subject: str, mover: str) -> tuple[float, str]:
        """`ceil(needed / step)` moving modes and the words: "block is 27.6 cm from its goal (within 1.0 cm
        wanted) and Block.push_px moves it at most 8.0 cm per contact: at least 4 contacts"."""
        where = f"{subject} {self.words(self.distance)} from its goal (within {self.words(self.tolerance)} wanted)"
        if step <= 0:
            return math.inf, f"{where} and nothing moves it"
        modes = max(1, math.ceil(self.needed / step - _SLACK))
        if modes == 1:
            return 1.0, ""  # one contact: nothing worth saying
        return float(modes), f"{where} and {mover} at most {self.words(step)} per contact: at least {modes} contacts"


def _no_turn(body: PlanBody, gap: _Gap) -> str:
    names = ", ".join(a.name for a in body.affordances) or "none"
    return (
        f"{body.name}'s heading is {gap.words(gap.distance)} from its goal (within {gap.words(gap.tolerance)} "
        f"wanted) and no affordance of {body.type.name} turns it ({names}): no sequence of any length reaches "
        f"that heading"
    )


def _off_its_line(rest: np.ndarray, goal: GoalSpec, movers: list[Affordance]) -> float | None:
    """How far the goal position lies from the one line a body that only slides along one axis can be on (m), or
    None when its motions span more than a line (a turn, or slides along two axes).

    Slides keep the heading, and only a body's own affordances move it, so a body whose every moving
    affordance slides along one axis of its frame keeps its origin on the world line through where it rests
    along that axis, whatever the sequence."""
    if not movers or any(a.motion.type != "prismatic" for a in movers):
        return None
    axes = [unit_axis_and_center(a.motion)[0] for a in movers]
    if any(abs(float(np.dot(axes[0], other))) < 1.0 - 1e-9 for other in axes[1:]):
        return None
    assert goal.position is not None
    dims = len(goal.position)
    origin, direction = rest[:dims, 3], (rest[:3, :3] @ axes[0])[:dims]
    offset = np.asarray(goal.position, dtype=float) - origin
    length = float(np.linalg.norm(direction))
    if length < 1e-9:  # a vertical slide: the position in these dimensions never changes
        return float(np.linalg.norm(offset))
    along = direction / length
    return float(np.linalg.norm(offset - np.dot(offset, along) * along))


def _off_line_words(body: PlanBody, movers: list[Affordance], gap: _Gap) -> str:
    names = ", ".join(a.name for a in movers)
    return (
        f"{body.name}'s goal position lies {gap.words(gap.distance)} off the line it slides on (within "
        f"{gap.words(gap.tolerance)} wanted), and every affordance of {body.type.name} that moves it slides it "
        f"along that line ({names}): no sequence of any length reaches that position"
    )


def _needs_tool(problem: Problem, body: PlanBody, movers: list[Affordance]) -> bool:
    """Whether the hand itself reaches none of `body`'s moving contacts where it rests (part 4)."""
    if not movers:
        return False
    return all(unreachable(problem, body.rest @ problem.action(body.name, a.name)) is not None for a in movers)
