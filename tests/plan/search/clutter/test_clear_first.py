"""Clear first, then solve (`vkgl.plan.search.clutter.clear_first`): the sides of a goal body's way (the sub-goal's
geometry), a plan one graph deeper than `max_depth` that clears the blocker first, and no such attempt where no
sequence of any length reaches the goal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from checkers.plan_geometry import check_plan

import vkgl
from vkgl.plan.problem.problem import Problem
from vkgl.plan.task_space.clearing import MARGIN, SIDE_TOLERANCE, footprint, polygon_distance, way_corridor, way_sides

_HERE = Path(__file__).resolve().parent

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene cluttered {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, {y2}) m yaw 90deg
}}

task through {{
    scene cluttered
    goal block at (0.75, 0) m within 1 cm
    search {{ max_depth 3  timeout 60 s }}
}}
"""


def _problem(y2: float) -> Problem:
    from vkgl.plan.problem.problem import build_problem

    program = vkgl.compile_source(SCENE.format(y2=y2), "aside.vkg", base_dir=_HERE)
    return build_problem(program, program.tasks["through"])


def test_a_blocker_moved_to_any_side_of_the_way_lies_clear_of_the_corridor_by_the_margin() -> None:
    """block2 lies across the block's way. Each side's half-plane lies `MARGIN + SIDE_TOLERANCE` out from the
    corridor: block2 moved straight across its edge by the side's distance (and anything farther out) is that
    far from the corridor, and at rest it overlaps it."""
    problem = _problem(0.0)
    goal = problem.goals[0]
    corridor = way_corridor(problem, goal)
    rest = problem.bodies["block2"].rest
    assert polygon_distance(footprint(problem, "block2", rest), corridor) == 0.0
    sides = way_sides(problem, goal, "block2")
    assert {side.words for side in sides} == {"left", "right", "beyond the goal"}
    for side in sides:
        normal = -side.halfplane[:2]  # the half-plane's inside is where `normal . p` is large
        for extra in (0.0, 0.05):
            moved = rest.copy()
            moved[:2, 3] += (side.distance + extra) * normal
            shape = footprint(problem, "block2", moved)
            assert float(np.max(shape @ side.halfplane[:2] - side.halfplane[2])) <= 1e-9
            assert polygon_distance(shape, corridor) >= MARGIN + SIDE_TOLERANCE - 1e-9


def test_sides_one_slide_reaches_come_first_the_shortest_slide_first() -> None:
    """block2 (turned 90 deg) slides along the world's y axis, to the left or the right of the block's way, never
    beyond its goal: those two come first, the shorter slide first (block2 lies 2 cm left of the way's middle)."""
    sides = way_sides(_problem(0.02), _problem(0.02).goals[0], "block2")
    assert [side.words for side in sides[:2]] == ["left", "right"]
    assert sides[0].slide < sides[1].slide < np.inf
    assert all(sides[0].movers)


def test_a_blocker_clear_of_the_straight_way_has_one_side_at_distance_zero() -> None:
    problem = _problem(0.3)
    sides = way_sides(problem, problem.goals[0], "block2")
    assert len(sides) == 1 and sides[0].distance == 0.0


def test_a_plan_one_graph_past_max_depth_clears_the_blocker_first_and_says_it_is_shortest() -> None:
    """With `max_depth 3` the search proves no plan of 3 graphs; clearing block2 first (one push) and then
    pushing the block gives 4 graphs: a shortest plan, every body where the plan says (the independent geometry
    check; the physical bench carries such plans out in DART)."""
    program = vkgl.compile_source(SCENE.format(y2=0.0), "aside.vkg", base_dir=_HERE)
    plan = vkgl.solve(program, "through")
    assert plan.status == "solved", plan.reason
    assert plan.depth == 4
    steps = plan.to_json()["steps"]
    assert steps[0]["body"] == "block2" and steps[-1]["body"] == "block"
    assert "cleared the way first: block2" in plan.reason
    assert "a shortest plan (no plan of at most 3 graphs exists)" in plan.reason
    assert plan.reason in plan.text()
    assert "reason" not in plan.to_json()  # vkg-plan/5 as before: a solved plan carries no reason
    assert [f.text for f in check_plan(program, "through", plan.to_json())] == []
    problem = plan.problem
    assert problem is not None
    corridor = way_corridor(problem, problem.goals[0])
    assert polygon_distance(footprint(problem, "block2", plan.final["block2"]), corridor) > 0.0


ONLY_SLIDES = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

body Crate {
    shape box (10, 10, 5) cm
    mass 0.3 kg
}

affordances Crate {
    affordance push_center_nx {
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 40 cm
    }
}

scene short {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    crate : Crate on table at (0.4, 0) m yaw 0deg
    block : Block on table at (0.55, 0) m yaw 90deg
}

task turned {
    scene short
    goal crate at (0.7, 0) m yaw 30deg within 1 cm, 3deg
    search { max_depth 3 }
}
"""


def test_a_goal_no_sequence_of_any_length_reaches_is_answered_at_once_without_clearing() -> None:
    """The crate only slides, so no sequence turns it: the bound says so at G0 and nothing is searched, not
    even with the block in its way cleared first."""
    program = vkgl.compile_source(ONLY_SLIDES, "turned.vkg", base_dir=_HERE)
    plan = vkgl.solve(program, "turned")
    assert plan.status == "infeasible"
    assert "no sequence of any length" in plan.reason
    assert "clearing the way first" not in plan.reason
    assert plan.stats["graphs_expanded"] == 0


def test_the_sub_goal_is_a_region_goal_on_the_blocker_with_any_heading() -> None:
    from vkgl.plan.search.clutter.side_problem import side_goal

    problem = _problem(0.0)
    side = way_sides(problem, problem.goals[0], "block2")[0]
    goal = side_goal(problem, problem.goals[0], "block2", side)
    assert goal.body == "block2" and goal.position is None and goal.yaw is None
    assert goal.region is not None and goal.region.shape == (1, 3)
    assert "block's way" in goal.region_words


def test_a_plan_longer_than_one_past_the_proof_is_not_called_shortest() -> None:
    from vkgl.plan.graphs.rollout import Sequence
    from vkgl.plan.search.clutter.words import plan_words as _words

    prefix = Sequence()
    assert "a shortest plan (no plan of at most 6 graphs exists)" in _words("b left of the way", prefix, 7, 6)
    longer = _words("b left of the way", prefix, 8, 6)
    assert "not proven shortest (no plan of at most 6 graphs exists; this one has 8)" in longer


HOOKED = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.hook
use stdlib.affordances.block
use stdlib.affordances.hook
use stdlib.tools

scene cluttered {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, 0) m yaw 90deg
    hook : Hook on table at (0.3, 0.4) m yaw 0deg
}

task through {
    scene cluttered
    goal block at (0.75, 0) m within 1 cm
}
"""


def test_a_blocker_moved_beside_the_way_lies_clear_of_the_hook_that_may_move_the_goal_body() -> None:
    """With a hook that can slide the block towards its goal, left and right lie farther out by how far the hook
    reaches past the block there: block2 moved to either lies `MARGIN` clear of the hook's footprint wherever
    the hook carries the block along its straight way, and one side lies farther out than without the hook."""
    from vkgl.plan.graphs.graph import Engagement
    from vkgl.plan.graphs.motions import unit_axis_and_center
    from vkgl.plan.graphs.rollout import tool_pose_on
    from vkgl.plan.problem.problem import build_problem

    program = vkgl.compile_source(HOOKED, "hooked.vkg", base_dir=_HERE)
    problem = build_problem(program, program.tasks["through"])
    goal = problem.goals[0]
    rest, block2 = problem.bodies["block"].rest, problem.bodies["block2"].rest
    sides = {side.words: side for side in way_sides(problem, goal, "block2")}
    plain = {side.words: side for side in way_sides(_problem(0.0), _problem(0.0).goals[0], "block2")}
    assert max(sides[w].distance - plain[w].distance for w in ("left", "right")) > 0.02  # the hook's bar
    pushes = [a.name for a in problem.bodies["block"].affordances if a.motion.type == "prismatic"]
    for words in ("left", "right"):
        moved = block2.copy()
        moved[:2, 3] += sides[words].distance * -sides[words].halfplane[:2]
        shape = footprint(problem, "block2", moved)
        for fraction in np.linspace(0.0, 1.0, 5):
            pose = rest.copy()
            pose[0, 3] += fraction * (goal.position[0] - rest[0, 3])
            for name in pushes:
                engagement = Engagement("hook.tip", "block", name)
                axis = pose[:2, :3] @ unit_axis_and_center(problem.affordance("block", name).motion)[0]
                if float(axis[0]) < np.cos(np.radians(45.0)) * float(np.linalg.norm(axis)):
                    continue  # a slide away from the goal: not how the hook moves it there
                tool = footprint(problem, "hook", tool_pose_on(problem, engagement, pose))
                assert polygon_distance(shape, tool) >= MARGIN - 1e-9, (words, name, fraction)


def test_a_side_no_plan_reaches_says_its_closest_miss() -> None:
    """What the clearing tried names, per side, why its closest sequence failed (the hand a few millimetres
    beyond the arm's reach), and nothing when no sequence was rejected (the bound said no side is reachable)."""
    from vkgl.plan.problem.rejection import Kind, Rejection
    from vkgl.plan.search.clutter.clear_first import _closest
    from vkgl.plan.search.search import SearchResult
    from vkgl.plan.search.stats import SearchStats

    stats = SearchStats()
    assert _closest(SearchResult("infeasible", "", stats)) == ""
    stats.reject(Rejection(Kind.REACH, "the hand 5.6 mm outside it", 0.0056), "add Hook.wield on hook")
    stats.reject(Rejection(Kind.REACH, "the hand 9.0 mm outside it", 0.009), "add Stick.wield on stick")
    assert _closest(SearchResult("infeasible", "", stats)) == " (closest: the hand 5.6 mm outside it)"


def test_a_near_goal_body_keeps_its_slides_but_no_turn_while_its_way_is_cleared() -> None:
    """The hand can carry the block to its goal (no tool must): in the sub-problem that clears block2 from its
    way the block may still step aside by a slide, never turn (a Block has both); block2 keeps what reaches the
    side."""
    from vkgl.plan.search.clutter.clear_tools import far_move_tools
    from vkgl.plan.search.clutter.side_problem import only_moving as _only_moving

    problem = _problem(0.0)
    goal = problem.goals[0]
    assert far_move_tools(problem, goal) is None
    side = way_sides(problem, goal, "block2")[0]
    sub, _ = _only_moving(problem, goal, "block2", side)
    assert {a.motion.type for a in problem.bodies["block"].affordances} >= {"prismatic", "revolute"}
    assert {a.motion.type for a in sub.bodies["block"].affordances} == {"prismatic"}
    assert sub.bodies["block2"].affordances


def test_a_third_body_is_kept_still_in_the_clearing_not_stripped() -> None:
    """A body in no goal body's way keeps its contacts in the sub-problem that clears block2, withheld until a
    rejection names it (`search(still=)`): a tool's way to the blocker may cross it (gen1_001 of the physical
    bench: the stick that pushes the cube aside would pass through a crate the hand must push away first)."""
    from vkgl.plan.problem.problem import build_problem
    from vkgl.plan.search.clutter.side_problem import only_moving as _only_moving

    third = SCENE.replace("}}\n\ntask", "    block3 : Block on table at (0.45, -0.3) m yaw 0deg\n}}\n\ntask")
    program = vkgl.compile_source(third.format(y2=0.0), "third.vkg", base_dir=_HERE)
    problem = build_problem(program, program.tasks["through"])
    goal = problem.goals[0]
    side = way_sides(problem, goal, "block2")[0]
    sub, still = _only_moving(problem, goal, "block2", side)
    assert still == frozenset({"block3"})
    assert sub.bodies["block3"].affordances == problem.bodies["block3"].affordances


def test_a_clearing_sub_problem_keeps_every_contact_the_plan_before_engages() -> None:
    """The plan before turned the block (a turn the sub-problem otherwise leaves out of a goal body) and pushed
    block2 by an affordance that does not reach the side: both stay in the sub-problem, which rolls that plan
    out (leaving them out was a KeyError in its search)."""
    from vkgl.plan.graphs.graph import Action, Engagement
    from vkgl.plan.graphs.rollout import extend, start_sequence
    from vkgl.plan.search.clutter.side_problem import only_moving as _only_moving

    problem = _problem(0.0)
    goal = problem.goals[0]
    side = way_sides(problem, goal, "block2")[0]
    turn = next(a.name for a in problem.bodies["block"].affordances if a.motion.type == "revolute")
    other = next(a.name for a in problem.bodies["block2"].affordances if a.name not in side.movers)
    root = start_sequence(problem)
    for body, name in [("block", turn), ("block2", other)]:
        e = Engagement("arm.fingertip", body, name)
        root, _ = extend(problem, root, Action("add", e))
        root, _ = extend(problem, root, Action("remove", e))
    without, _ = _only_moving(problem, goal, "block2", side)
    sub, _ = _only_moving(problem, goal, "block2", side, root)
    assert turn not in {a.name for a in without.bodies["block"].affordances}
    assert turn in {a.name for a in sub.bodies["block"].affordances}
    assert other not in {a.name for a in without.bodies["block2"].affordances}
    assert other in {a.name for a in sub.bodies["block2"].affordances}
    for action in root.actions:  # every contact of the plan before is found in the sub-problem
        sub.affordance(action.engagement.body, action.engagement.affordance)
