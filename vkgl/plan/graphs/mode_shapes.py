"""What a rollout of one mode reads of its sequence and problem, found once per sequence (`ModeShape`).

The task-space optimiser rolls a sequence out at every point it tries and every step of its finite differences
(hundreds of thousands of modes in a search): which tool jumps to its contact at the transition, which tools
follow their targets, how the hand is attached, are the same every time. `mode_shapes` finds them once per
sequence (kept on the sequence), and `rollout.roll_mode` only multiplies the poses, with the same matrices in
the same order as before: its results are the same to the last bit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from vkgl.plan.graphs.graph import Action, Engagement, KGraph, motion_type
from vkgl.plan.graphs.members import action_at
from vkgl.plan.problem.problem import Problem

if TYPE_CHECKING:
    from vkgl.plan.graphs.rollout import Sequence

HAND_FREE, HAND_RETURNED, HAND_HELD, HAND_ACTING = "free", "returned", "held", "acting"
"""How the hand is attached during a mode: free, letting go of a tool put back, holding a tool that acts on
nothing, acting on a body (its own push or its tool's)."""

CACHED_OFFSETS = 256
"""Contact frames (`ModeShape.contact`) and hand chains (`ModeShape.chains`) a mode keeps, by offset: the
optimiser's finite differences move one value at a time, so an offset repeats across most of its steps."""


@dataclass
class ModeShape:
    """Mode k of a sequence as `roll_mode` reads it.

    `action`: the transition into it (None for G0); `jump`: the tool that jumps to its contact then, with its
    frame's inverse (an ADD by a tool's frame); `put_down`: the rest height of a body released from a free
    motion (a REMOVE); `returned`: the world pose of a tool put back where it was picked up; `tools`: each
    engaged tool frame (engagement, tool, frame inverse), whose tool follows its target; `hand`: how the hand
    is attached (`HAND_*`) with `hand_engagement` the engagement that pins it (the acting one, the grasp held or
    the tool returned) and `hand_action` its action frame (for the returned and held kinds); `just_grasped`:
    the held grasp was made at this transition. `frames` and `chains` remember the contact frames and hand
    chains by offset (`contact`, `rollout.hand_chain`)."""

    graph: KGraph
    action: Action | None
    jump: tuple[str, np.ndarray] | None
    put_down: float | None
    returned: np.ndarray | None
    tools: tuple[tuple[Engagement, str, np.ndarray], ...]
    hand: str
    hand_engagement: Engagement | None
    hand_action: np.ndarray | None
    just_grasped: bool
    frames: dict[tuple[Engagement, float], np.ndarray] = field(default_factory=dict)
    chains: dict[float, tuple[np.ndarray, bool]] = field(default_factory=dict)

    def contact(self, problem: Problem, e: Engagement, offset: float) -> np.ndarray:
        """`members.action_at` of engagement `e` at `offset` (the same array for the same offset)."""
        key = (e, offset)
        frame = self.frames.get(key)
        if frame is None:
            if len(self.frames) >= CACHED_OFFSETS:
                self.frames.clear()
            frame = self.frames[key] = action_at(problem, e.body, e.affordance, offset)
        return frame


def mode_shapes(problem: Problem, seq: Sequence) -> list[ModeShape]:
    """The `ModeShape` of every mode of `seq` for `problem` (found once, then kept on the sequence)."""
    kept = seq.__dict__.get("_shapes")
    if kept is not None and kept[0] is problem:
        return kept[1]
    shapes = [_shape(problem, seq, k) for k in range(len(seq.graphs))]
    object.__setattr__(seq, "_shapes", (problem, shapes))  # a frozen dataclass: the cache is no field of it
    return shapes


def acting_engagement(problem: Problem, graph: KGraph) -> Engagement | None:
    """The engagement through which the hand touches a body it moves: its own push, or its tool's; else None."""
    holding = graph.using(problem.robot_effector.name)
    if holding is None or motion_type(problem, holding) != "free":
        return holding
    return next((e for e in graph.engaged if problem.effector(e.effector).tool == holding.body), None)


def _shape(problem: Problem, seq: Sequence, k: int) -> ModeShape:
    graph = seq.graphs[k]
    action = seq.actions[k - 1] if k > 0 else None
    jump, put_down, returned = None, None, None
    if action is not None:
        e = action.engagement
        effector = problem.effector(e.effector)
        if action.op == "add" and effector.tool is not None:
            jump = (effector.tool, effector.frame_inverse)
        elif action.op == "remove" and motion_type(problem, e) == "free":
            put_down = problem.bodies[e.body].rest_z
        if action.op == "remove":
            for mode, pose in seq.returns:  # the last one given for the mode, as the rollout always read them
                if mode == k:
                    returned = pose
    tools = tuple(
        (e, tool, problem.effector(e.effector).frame_inverse)
        for e in graph.engaged
        if (tool := problem.effector(e.effector).tool) is not None
    )
    hand, engagement, frame, just_grasped = _hand(problem, seq, k)
    return ModeShape(graph, action, jump, put_down, returned, tools, hand, engagement, frame, just_grasped)


def _hand(problem: Problem, seq: Sequence, k: int) -> tuple[str, Engagement | None, np.ndarray | None, bool]:
    """How the hand is attached during mode k (`HAND_*`), the engagement that pins it, its action frame (for a
    tool returned or held) and whether the held grasp was made at this transition."""
    graph = seq.graphs[k]
    holding = graph.using(problem.robot_effector.name)
    if holding is None:
        if not any(mode == k for mode, _ in seq.returns):
            return HAND_FREE, None, None, False
        returned = seq.actions[k - 1].engagement  # the hand lets go of the tool where it set it down
        return HAND_RETURNED, returned, problem.action(returned.body, returned.affordance), False
    acting = acting_engagement(problem, graph)
    if acting is None:  # a tool free in the hand: only a grasp made at this transition pins the hand
        just_grasped = k > 0 and seq.actions[k - 1].op == "add" and seq.actions[k - 1].engagement == holding
        return HAND_HELD, holding, problem.action(holding.body, holding.affordance), just_grasped
    return HAND_ACTING, acting, None, False
