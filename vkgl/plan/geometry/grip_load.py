"""Whether the hand's grip holds a tool through the pushes it makes with it: the planner's side of the grip model
(`vkgl.robot.grip`) the executor watches.

A push with a held tool loads the grip with the force the pushed body resists
with, at the tool's contact: that force, and its moment about the effector,
must stay within what the pads' Coulomb friction carries (`Grip.usage`), or the
tool turns or slides in the hand and the body is not pushed where the plan
says. Measured on generated tasks (a 1.62 kg crate turned with the stdlib
Stick held at its middle by a 20 N grasp): the executor saw 7.2 N and
0.15 N m at the grip, 103 % of what it carries, and the Stick slipped 7.6 mm;
the estimate here (the crate's weight times its friction, 7.9 N, at the Stick's
tip) is on the safe side of it. The estimate is quasi-static: a slide resists
with the body's whole friction on the table, a turn about a pivot with less,
so turns are judged as slides (on the safe side too). Bodies on joints are
left out: a joint resists with its own damping and friction, which the
exploration measured as motion, not as force.
"""

from __future__ import annotations

import numpy as np

from vkgl.plan.graphs.graph import KGraph
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.robot.grip import grip_for, push_load, resisting_force

PUSH_FACTOR = 2.0
"""How much harder than the estimate a push may load the grip: the estimate leaves out what the tool's contact
carries along the tool (friction at the contact pushes the tip up or down: a moment about the pads' normal) and
the push's dynamics, so the push's part of the load is doubled (the tool's weight is known and is not).
Measured in DART on generated tasks (`vkgc solve --execute`, the executor's peak load against the estimate with
the push's part as it is): a 20 N grasp turning a 1.62 kg crate, estimated 0.58, broke at 1.03 (1.8 times);
pushes with the stick or hook held at the handle by 70 N, estimated 0.32-0.38, peaked at 0.30-0.55."""


def grip_rejection(problem: Problem, graph: KGraph, trace: ModeTrace, q: np.ndarray, tool: str) -> Rejection | None:
    """Why the grip on `tool` (held by the hand at joints `q` at the start of the mode) would give way under a
    push the mode makes with it, or None."""
    robot = problem.robot_effector.name
    holding = next((e for e in graph.engaged if e.body == tool and e.effector == robot), None)
    if holding is None:
        return None
    grip = grip_for(problem.affordance(tool, holding.affordance).action, problem.bodies[tool].type.friction)
    effector = problem.arm.fk(q)
    for e in graph.engaged:
        spec = problem.effector(e.effector)
        body = problem.bodies[e.body]
        if spec.tool != tool or trace.values.get(e, 0.0) <= 0.0 or body.joint is not None:
            continue
        start = (trace.start[tool] @ spec.frame)[:3, 3]
        direction = (trace.end[tool] @ spec.frame)[:3, 3] - start
        if float(np.linalg.norm(direction)) < 1e-6:
            continue
        force = resisting_force(float(body.type.mass.value), body.type.friction)
        tool_mass = float(problem.bodies[tool].type.mass.value)
        load = push_load(effector, start, direction, PUSH_FACTOR * force, trace.start[tool][:3, 3], tool_mass)
        usage = grip.usage(*load)
        if usage > 1.0:
            return Rejection(
                Kind.GRIP,
                f"{spec.name} would push {e.body} ({force:.1f} N: its weight times its friction) with "
                f"{usage:.0%} of what the grip on {tool} carries ({grip.text()}; the push counted twice, for what "
                "the estimate leaves out): it would slip in the hand",
                usage - 1.0,
            )
    return None


__all__ = ["grip_rejection"]
