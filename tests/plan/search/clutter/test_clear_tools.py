"""Which tool clears a far way (`vkgl.plan.search.clutter.clear_tools`): the tools that can carry a goal body beyond the
hand's reach, and the sides of its way kept free for one of them (`clearing.way_sides(..., tools=...)`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter.clear_tools import far_move_grasps, far_move_tools
from vkgl.plan.task_space.clearing import MARGIN, footprint, polygon_distance, way_sides

_HERE = Path(__file__).resolve().parent

FAR = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.bodies.hook
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.affordances.hook
use stdlib.tools

scene far {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at ({start}, 0) m yaw 0deg
    block2 : Block on table at (0.75, 0) m yaw 90deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
    hook : Hook on table at (0.3, 0.4) m yaw 0deg
}}

task moved {{
    scene far
    goal block at ({goal}, 0) m within 1 cm
}}
"""


@pytest.fixture(scope="module")
def pulled() -> Problem:
    """The block pulled from 0.95 m (beyond the hand's reach) to 0.55 m, block2 across its way."""
    program = vkgl.compile_source(FAR.format(start=0.95, goal=0.55), "pulled.vkg", base_dir=_HERE)
    return build_problem(program, program.tasks["moved"])


@pytest.fixture(scope="module")
def pushed() -> Problem:
    """The block pushed from 0.55 m to 0.95 m (beyond the hand's reach), block2 across its way."""
    program = vkgl.compile_source(FAR.format(start=0.55, goal=0.95), "pushed.vkg", base_dir=_HERE)
    return build_problem(program, program.tasks["moved"])


def test_only_the_hook_can_start_a_pull_from_beyond_the_hands_reach(pulled: Problem) -> None:
    """The hand cannot reach the block where it rests, nor can a stick push it towards the arm from there (the
    hand would stand beyond it): the hook, which pulls, is the tool that clears the way and then pulls."""
    grasps = far_move_grasps(pulled, pulled.goals[0])
    assert grasps is not None and grasps and {tool for tool, _ in grasps} == {"hook"}
    assert far_move_tools(pulled, pulled.goals[0]) == frozenset({"hook"})


def test_a_push_the_hand_can_start_but_not_end_may_be_carried_by_either_tool(pushed: Problem) -> None:
    assert far_move_grasps(pushed, pushed.goals[0]) is None  # the hand reaches the block where it rests
    assert far_move_tools(pushed, pushed.goals[0]) == frozenset({"stick", "hook"})


def test_a_side_is_kept_free_for_one_tool_that_carries_the_goal_body_not_for_every_tool(pushed: Problem) -> None:
    """The hook's bar reaches past the block on one side, the stick on neither: with the tools that can carry
    the block, that side lies no farther out than the stick needs, and block2 moved there lies `MARGIN` clear
    of the stick wherever it pushes the block along its way; no side lies farther out than without them."""
    from vkgl.plan.graphs.graph import Engagement
    from vkgl.plan.graphs.rollout import tool_pose_on

    goal = pushed.goals[0]
    widest = {side.words: side for side in way_sides(pushed, goal, "block2")}
    kept = {side.words: side for side in way_sides(pushed, goal, "block2", tools=far_move_tools(pushed, goal))}
    assert all(kept[w].distance <= widest[w].distance + 1e-12 for w in widest)
    assert max(widest[w].distance - kept[w].distance for w in ("left", "right")) > 0.02  # the hook's bar
    rest, block2 = pushed.bodies["block"].rest, pushed.bodies["block2"].rest
    push = "push_center_px"  # the Block's slide along its +x axis: towards the goal
    for words in ("left", "right"):
        moved = block2.copy()
        moved[:2, 3] += kept[words].distance * -kept[words].halfplane[:2]
        shape = footprint(pushed, "block2", moved)
        for fraction in np.linspace(0.0, 1.0, 5):
            pose = rest.copy()
            pose[0, 3] += fraction * (goal.position[0] - rest[0, 3])
            stick = footprint(pushed, "stick", tool_pose_on(pushed, Engagement("stick.tip", "block", push), pose))
            assert polygon_distance(shape, stick) >= MARGIN - 1e-9, (words, fraction)


def test_a_far_goal_body_keeps_only_its_slides_while_its_way_is_cleared(pushed: Problem) -> None:
    """In the sub-problem that clears block2 from the far block's way, the block may step out of the tool's way
    by a slide, never turn; block2 keeps the motions that reach the side, the tools their grasps."""
    from vkgl.plan.search.clutter.side_problem import only_moving as _only_moving

    goal = pushed.goals[0]
    side = way_sides(pushed, goal, "block2", tools=far_move_tools(pushed, goal))[0]
    sub, _ = _only_moving(pushed, goal, "block2", side)
    kinds = {a.motion.type for a in sub.bodies["block"].affordances}
    assert kinds == {"prismatic"}
    assert {a.motion.type for a in pushed.bodies["block"].affordances} >= {"prismatic", "revolute"}
    assert sub.bodies["block2"].affordances and any(a.motion.type == "free" for a in sub.bodies["stick"].affordances)
