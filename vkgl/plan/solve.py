"""`solve(program, task)`: plan for a task of a compiled program, the planner behind `vkgl.solve`.

Input errors raise `vkgl.errors.InputError`; a goal that no plan can reach or
a search that runs out of time are results, not errors: `plan.status` is
"infeasible" or "timeout" and `plan.reason` says why.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from vkgl.lang.checks.learn_hint import affordance_hint
from vkgl.lang.ir.nodes import Task
from vkgl.lang.ir.program import Program
from vkgl.plan.graphs.carry import carriable
from vkgl.plan.problem.avoid import Avoid
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.result.plan import Plan, PlanStep, graph_edges, robot_entry
from vkgl.plan.search.clutter.blocking import blocked
from vkgl.plan.search.clutter.clear_first import SEARCH_SHARE, clear_first, work_budget
from vkgl.plan.search.clutter.still import search_moving_less
from vkgl.plan.search.search import Paused, SearchResult
from vkgl.plan.search.stats import SearchStats


def solve(
    program: Program,
    task: Task,
    *,
    max_depth: int | None = None,
    timeout: float | None = None,
    progress: bool = False,
    avoid: Avoid | None = None,
    arm_start: Sequence[float] | None = None,
) -> Plan:
    """Plan for `task` of `program`; `max_depth`/`timeout` override its `search` block.

    Best-first search over graph sequences guided by an admissible bound of the graphs still needed
    (`vkgl.plan.search.search`, `vkgl.plan.search.bounds.bound`: plans stay shortest) with
    task-space and joint-space feasibility checks (`vkgl.plan.task_space.feasible`).
    `progress` shows the search on stderr; `arm_start` are the arm's joints
    where its first path starts (its home configuration by default: where
    execution puts it). `avoid` names the plans already tried and the steps
    that failed in execution (`vkgl.plan.problem.avoid`): a re-solve returns none of
    them (rejections of kind "excluded").
    Deterministic: the same input gives the same plan.
    """
    started = time.perf_counter()
    problem = build_problem(program, task, max_depth=max_depth, timeout=timeout, avoid=avoid, arm_start=arm_start)
    deadline = started + problem.timeout
    why = _hopeless(problem)
    if why is not None:
        return _plan(problem, SearchResult("infeasible", why, SearchStats()), started)
    way = blocked(problem)  # a body in a goal body's way: part of the time is kept for clearing it first
    paused = Paused() if way else None  # where the first search stops, to go on with the time the walk leaves
    result, searched = search_moving_less(  # bodies in no goal body's way kept still until a sequence meets one
        problem,
        deadline=deadline,
        progress=progress,
        budget=SEARCH_SHARE * work_budget(problem) if way else None,  # (the count ends it the same everywhere)
        pause_at=started + SEARCH_SHARE * problem.timeout if way else None,
        paused=paused,
    )
    if way and result.status != "solved":
        cleared = clear_first(
            searched,
            result,
            deadline=deadline,
            budget=(1.0 - SEARCH_SHARE) * work_budget(problem),
            progress=progress,
        )
        if cleared is not None and cleared.result is not None:
            result = replace(cleared.result, reason=cleared.words)
        else:
            result = _given_back(problem, result, paused, deadline, progress)
            if cleared is not None and result.status != "solved":  # (a plan found then is the search's own)
                result = replace(result, reason=f"{result.reason}\n{cleared.words}")
    if result.status == "infeasible" and (hint := _unusable_tools_hint(problem)):
        result = replace(result, reason=f"{result.reason}\n{hint}")
    if result.status == "infeasible" and (tips := _tipping_hint(problem)):
        result = replace(result, reason=f"{result.reason}\n{tips}")
    return _plan(problem, result, started)


def _given_back(
    problem: Problem, before: SearchResult, paused: Paused | None, deadline: float, progress: bool
) -> SearchResult:
    """The first search of a blocked task gone on from where its share stopped it, until `deadline`, when the
    clear-first walk found no plan and left time (`before` when that search ended otherwise: it proved no plan,
    or nothing is left): a task ends at its timeout, not when the walk gives up (docs/planning.md, "The time the
    walk leaves")."""
    if paused is None or not paused.holds(problem) or time.perf_counter() >= deadline:
        return before
    return search_moving_less(problem, deadline=deadline, progress=progress, paused=paused)[0]


def _tipping_hint(problem: Problem) -> str:
    """A line naming the affordances left out because they would tip their body, or ""."""
    left = [t.why for b in problem.bodies.values() for t in b.too_high]
    return "left out, as they would tip a body over: " + "; ".join(left) if left else ""


def _unusable_tools_hint(problem: Problem) -> str:
    """Lines naming the scene's tools that no plan could use, or "": tools that no correspondence names
    (warning W602), and tools with no affordance in the compilation (nothing lets the arm grasp them).

    A goal out of the hand's reach is then infeasible although a tool would reach it: the reason must say
    so, not only the hand's distance.
    """
    program = problem.program
    named = {c.frame.body for c in program.correspondences}
    unnamed, ungraspable = [], []
    for placed in problem.scene.bodies:
        body = program.bodies.get(placed.type.name)
        if body is None or not any(e.grasp is not None for e in body.explores):
            continue  # not a tool
        if body.name not in named:
            unnamed.append((placed.name, body.name))
        elif not program.affordances.get(body.name):
            ungraspable.append((placed.name, body.name))
    lines = []
    if unnamed:
        lines.append(
            f"{_names(unnamed)} {_are(unnamed)} that no correspondence names (warning W602), so no plan could "
            f"use {'it' if len(unnamed) == 1 else 'them'}: add `use stdlib.tools` (or `correspondences "
            f"{{ {unnamed[0][1]}.tip ~ fingertip }}`) to let a tool reach further"
        )
    if ungraspable:
        uses = ", ".join(f"`use stdlib.affordances.{kind.lower()}`" for _, kind in ungraspable)
        lines.append(
            f"{_names(ungraspable)} {_are(ungraspable)} with no affordance in the program, so no plan could "
            f"grasp {'it' if len(ungraspable) == 1 else 'them'}: add {uses} (or learn one with `vkgc learn`)"
        )
    return "\n".join(lines)


def _names(tools: list[tuple[str, str]]) -> str:
    return " and ".join(f"`{name}`" for name, _ in tools)


def _are(tools: list[tuple[str, str]]) -> str:
    return "is a tool" if len(tools) == 1 else "are tools"


def _hopeless(problem: Problem) -> str | None:
    """Why no search can succeed, found without searching, or None.

    A goal past the body's joint limits (a joint goal's opening, or where a
    position goal puts a slide), a goal off the table, or nothing to move the body.
    """
    from vkgl.plan.task_space.constraints.body_limits import goal_joint_state, limit_words

    for goal in problem.goals:
        body = problem.bodies[goal.body]
        state = goal_joint_state(problem, goal.body, goal)
        if state is not None and body.joint_limits is not None:
            lower, upper = body.joint_limits
            tolerance = goal.tol_opening if goal.opening is not None else goal.tol_position
            if not lower - tolerance <= state <= upper + tolerance:
                return limit_words(problem, goal.body, body.rest, goal)
        movers = [a for a in body.affordances if a.motion.type in ("prismatic", "revolute")]
        if carriable(problem, goal.body):  # a grasp of a body that is no tool carries it anywhere
            movers += [a for a in body.affordances if a.motion.type == "free"]
        if goal.position is not None and problem.table_center is not None and body.on_table:
            low = problem.table_center - problem.table_size / 2  # type: ignore[operator]
            high = problem.table_center + problem.table_size / 2  # type: ignore[operator]
            x, y = goal.position[:2]
            if not (low[0] <= x <= high[0] and low[1] <= y <= high[1]):
                return (
                    f"the goal puts {goal.body} at ({x:.3f}, {y:.3f}) m, off the table "
                    f"(x from {low[0]:.2f} to {high[0]:.2f} m, y from {low[1]:.2f} to {high[1]:.2f} m)"
                )
        if not movers and not _at_goal(problem, goal):
            if body.too_high:
                return (
                    f"no affordance moves {goal.body} without tipping it over: "
                    + "; ".join(t.why for t in body.too_high)
                    + " (explore it at lower contacts: `contacts on faces ... heights H`)"
                )
            if body.affordances:
                names = ", ".join(a.name for a in body.affordances)
                return (
                    f"no affordance moves {goal.body}: the affordances of {body.type.name} ({names}) only let "
                    f"it be held or touched, not slid, turned or carried to a goal"
                )
            return (
                f"no affordance moves {goal.body}: its type {body.type.name} has no affordance in the program "
                f"({affordance_hint(body.type)})"
            )
    return None


def _at_goal(problem: Problem, goal: Any) -> bool:
    from vkgl.plan.task_space.feasible import goal_holds

    return goal_holds(problem, {n: b.rest for n, b in problem.bodies.items()}, [goal])


def _plan(problem: Problem, result: SearchResult, started: float) -> Plan:
    elapsed = time.perf_counter() - started
    stats = {
        "solve_time_s": round(elapsed, 4),
        "graphs_expanded": result.stats.graphs_expanded,
        "task_space_checks": result.stats.task_space_checks,
        "joint_space_checks": result.stats.joint_space_checks,
    }
    rest = {n: b.rest.copy() for n, b in problem.bodies.items()}
    details = {
        "sequences": result.stats.sequences,
        "pruned": result.stats.pruned,
        "pruned_by_bound": result.stats.cut_by_bound,  # never queued: depth + bound passes max_depth
        "passed_over": result.stats.passed_over,
        "excluded": result.stats.excluded,
        "max_depth": problem.max_depth,
        "geometry_checks": result.stats.geometry_checks,
        "optimisations": result.stats.work.optimisations,
        "ik_calls": result.stats.work.ik_calls,
        "rejections": {str(kind): n for kind, n in result.stats.rejections.items()},
        "arm_paths": result.stats.arm_path_checks,
        "transit_checks": result.stats.transit_checks,
        "transits": result.stats.transits,
        "arm_path_time_s": round(result.stats.arm_path_time, 4),
        "transit_time_s": round(result.stats.transit_time, 4),
        "search_time_s": round(elapsed - result.stats.transit_time, 4),  # everything but the transits
    }
    graphs: list[list[tuple[str, str, str]]] = []
    steps: list[PlanStep] = []
    final: dict[str, np.ndarray] = {}
    if result.status == "solved":
        seq, task = result.sequence, result.task
        assert seq is not None and task is not None
        graphs, steps, final = graph_edges(problem, list(seq.graphs)), list(result.steps), dict(task.traces[-1].end)
    return Plan(
        problem.task.name,
        result.status,
        result.reason,
        stats,
        robot_entry(problem),
        graphs=graphs,
        steps=steps,
        final=final,
        start=rest,
        problem=problem,
        details=details,
    )


__all__ = ["Avoid", "Plan", "solve"]
