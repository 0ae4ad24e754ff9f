"""The search's bound (`vkgl.plan.search.bounds.bound`) never exceeds the true remaining depth.

On small generated problems (a block with a ranged slide and a ranged turn, a goal somewhere around it, with or
without a stick to push with), every sequence the search may make up to a depth is enumerated breadth first with
the search's own rules (`successors`, the reach cut), each one whose last mode moves the block is checked in task
space (a relaxation of the whole check: fewer sequences pass it, never more), and the true remaining depth of
each sequence is the fewest graphs to a descendant that passes. The bound must not exceed it.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from task_makers.block_problems import DEPTH, FAMILY, GRASP, PROGRAM, block_problem, drawn_block_problem

import vkgl
from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.task_space.feasible import Counters, task_space
from vkgl.plan.task_space.reach.workspace import unreachable


def _children(problem: Problem, seq: Sequence) -> list[Sequence]:
    """What the search makes from `seq`: its successors, less those whose hand is out of reach at once."""
    out = []
    for action in successors(problem, seq.graphs[-1], seq.last):
        child, hand = extend(problem, seq, action)
        if hand is None or unreachable(problem, hand) is None:
            out.append(child)
    return out


def _passes(problem: Problem, seq: Sequence) -> bool:
    mode = seq.depth - 1
    carried = any(m == mode - 1 and e.body == "block" for m, e in seq.carries)
    if not carried and not any(m == mode and e.body == "block" for m, e in seq.variables):
        return False  # ends where a shorter prefix ends: the search never checks it
    return not isinstance(task_space(problem, seq, math.inf, Counters()), Rejection)


def _remaining(problem: Problem, seq: Sequence, seen: list[tuple[Sequence, float]]) -> float:
    """The fewest graphs from `seq` to a descendant that passes (inf: none within DEPTH); every sequence with
    its own is appended to `seen`."""
    best = 0.0 if seq.actions and _passes(problem, seq) else math.inf
    if seq.depth < DEPTH:
        for child in _children(problem, seq):
            best = min(best, 1 + _remaining(problem, child, seen))
    seen.append((seq, best))
    return best


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    x=st.sampled_from([0.45, 0.6, 0.9]),
    dx=st.sampled_from([0.0, 0.05, 0.1, 0.15, 0.25, -0.05]),
    dy=st.sampled_from([0.0, 0.04]),
    yaw=st.sampled_from([None, -20, -40]),
    slide=st.sampled_from([6, 10, 30]),
    turn=st.sampled_from([15, 25]),
    stick=st.booleans(),
    grasp=st.booleans(),
    family=st.booleans(),
)
def test_the_bound_never_exceeds_the_true_remaining_depth(tmp_path, x, dx, dy, yaw, slide, turn, stick, grasp, family):
    # the goals past the fingertip's reach (x + dx beyond 0.8 m) exercise part 6, the far turned ones part 1's
    # slides and turns together, the family a pivot that moves with the contact
    problem = block_problem(
        tmp_path,
        x=x,
        gx=round(x + dx, 3),
        gy=dy,
        yaw="" if yaw is None else f" yaw {yaw}deg",
        slide=slide,
        turn=turn,
        stick="    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n" if stick else "",
        grasp=GRASP if grasp else "",
        family=FAMILY if family else "",
    )
    _assert_the_bound_never_exceeds_the_true_remaining_depth(problem)


def test_the_bound_is_the_true_depth_of_three_short_pushes(tmp_path):
    problem = block_problem(tmp_path, x=0.45, gx=0.6, gy=0, yaw="", slide=6, turn=25, stick="")
    seen: list[tuple[Sequence, float]] = []
    true = _remaining(problem, start_sequence(problem), seen)
    assert true == 5 and Bound(problem)(start_sequence(problem)) == 5  # push, break, push, break, push
    assert sum(1 for seq, depth in seen if depth < math.inf and Bound(problem)(seq) == depth) >= 5


def test_a_far_goal_with_short_slides_needs_a_contact_and_a_break_per_slide(tmp_path):
    problem = block_problem(tmp_path, x=0.45, gx=0.73, gy=0, yaw="", slide=8, turn=25, stick="")
    bound = Bound(problem)
    root = start_sequence(problem)
    assert bound(root) == 7  # 27 cm in slides of 8 cm: 4 pushes, 3 breaks between them
    first = next(c for c in _children(problem, root) if c.last.engagement.affordance == "push_px")
    assert bound(first) == 6  # one push made: three more, each after a break
    assert "block is 28.0 cm from its goal (within 1.0 cm wanted)" in bound.explain()


def test_a_body_the_hand_cannot_reach_needs_the_grasp_of_a_tool_first(tmp_path):
    stick = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"
    problem = block_problem(tmp_path, x=0.9, gx=0.95, gy=0, yaw="", slide=30, turn=25, stick=stick)
    assert Bound(problem)(start_sequence(problem)) == 2  # grasp the stick, push with its tip
    alone = block_problem(tmp_path, x=0.9, gx=0.95, gy=0, yaw="", slide=30, turn=25, stick="")
    assert Bound(alone)(start_sequence(alone)) == math.inf  # nothing reaches it


def test_a_block_the_hand_can_carry_needs_one_action_on_it_until_something_moves_it(tmp_path):
    problem = block_problem(tmp_path, x=0.45, gx=0.73, gy=0, yaw="", slide=8, turn=25, stick="", grasp=GRASP)
    bound = Bound(problem)
    root = start_sequence(problem)
    assert bound(root) == 1  # a carry moves it any distance in one contact: only "something must touch it" holds
    seen: list[tuple[Sequence, float]] = []
    assert _remaining(problem, root, seen) == 2  # grasp, set down: four pushes and three breaks are not needed
    grasped = next(c for c in _children(problem, root) if c.last.engagement.affordance == "grasp_top")
    assert bound(grasped) == 1  # the REMOVE that sets it down
    placed = next(c for c in _children(problem, grasped) if c.last.op == "remove")
    assert placed.carries and bound(placed) == 0


def test_a_heading_nothing_turns_is_never_reached_and_no_depth_is_suggested(tmp_path):
    path = tmp_path / "noturn.vkg"
    start, end = PROGRAM.index("    affordance turn_left"), PROGRAM.index("    }}\n{grasp}") + 7
    text = PROGRAM[:start] + PROGRAM[end:]  # the block only slides
    fields = {"x": 0.45, "gx": 0.5, "gy": 0, "yaw": " yaw 30deg", "slide": 10, "stick": "", "grasp": "", "family": ""}
    path.write_text(text.format(**fields), encoding="utf-8")
    program = compile_file(str(path))
    problem = build_problem(program, program.task())
    assert Bound(problem)(start_sequence(problem)) == math.inf
    plan = vkgl.solve(program)
    assert plan.status == "infeasible"
    assert "no affordance of Block turns it (push_px): no sequence of any length reaches that heading" in plan.reason
    assert "--max-depth" not in plan.reason


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(2, 40), slides=st.integers(2, 3), fixed=st.booleans())
def test_screening_rows_of_two_slides_gives_the_row_and_values_of_trying_every_row(seed, rows, slides, fixed):
    # the deep sequences' hot spot (two turns and two slides of one body): the screened search must not change
    # what closed_form decides
    from vkgl.plan.task_space.slides import best_row as _best_row
    from vkgl.plan.task_space.slides import closest as _closest

    rng = np.random.default_rng(seed)
    columns = rng.normal(size=(rows, 3, slides))
    origins, position = rng.normal(size=(rows, 3)) * 0.3, rng.normal(size=2) * 0.3
    limits = np.stack([np.zeros(slides), rng.uniform(0.0, 0.5, size=slides)], axis=1)
    if fixed:
        limits[0] = (0.1, 0.1)
    every = min(
        ((*_closest(columns[row], position - origins[row, :2], limits), row) for row in range(rows)),
        key=lambda found: (found[0], found[2]),
    )
    residual, row, values = _best_row(columns, origins, position, limits)
    assert (residual, row) == (every[0], every[2]) and np.array_equal(values, every[1])


def test_a_position_off_the_one_line_a_body_slides_on_is_never_reached(tmp_path):
    # a cube of the physical bench learns slides along its x axis only (its end pushes slide it, never turn it)
    path = tmp_path / "line.vkg"
    start, end = PROGRAM.index("    affordance turn_left"), PROGRAM.index("{grasp}")
    text = PROGRAM[:start] + PROGRAM[end:]  # the block only slides, along its x axis
    reasons = {}
    for gy, reached in ((0.04, False), (0.005, True)):
        path.write_text(text.format(x=0.45, gx=0.6, gy=gy, yaw="", slide=30, stick="", grasp=""), encoding="utf-8")
        program = compile_file(str(path))
        problem = build_problem(program, program.task())
        assert (Bound(problem)(start_sequence(problem)) == math.inf) is not reached
        plan = vkgl.solve(program)
        assert (plan.status == "solved") is reached, plan.reason
        reasons[reached] = plan.reason
    plan_reason = reasons[False]
    assert "block's goal position lies 4.0 cm off the line it slides on (within 1.0 cm wanted)" in plan_reason
    assert "no sequence of any length reaches that position" in plan_reason
    assert "--max-depth" not in plan_reason


def test_a_far_turned_goal_needs_a_turn_and_a_slide_and_a_turn_moves_it_little(tmp_path):
    problem = block_problem(tmp_path, x=0.45, gx=0.73, gy=0, yaw=" yaw -20deg", slide=30, turn=25, stick="")
    bound = Bound(problem)
    root = start_sequence(problem)
    assert bound(root) == 3  # 27 cm and 17 deg: a turn (at most 4.8 cm) and a slide, a break between them
    assert "a slide of Block moves it at most 30.0 cm and keeps its heading" in bound.explain()
    assert "a turn moves it at most 4.8 cm: at least 2 contacts" in bound.explain()
    turned = next(c for c in _children(problem, root) if c.last.engagement.affordance == "turn_left")
    assert bound(turned) == 2  # the slide still to come: break, push
    released = next(c for c in _children(problem, turned) if c.last.op == "remove")
    again = next(c for c in _children(problem, released) if c.last.engagement.affordance == "turn_left")
    assert bound(again) == 2  # two turns cover the heading, not the 27 cm: a slide still


def test_a_goal_beyond_the_hands_reach_needs_a_tool_to_move_the_body_last(tmp_path):
    stick = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"
    problem = block_problem(tmp_path, x=0.6, gx=0.95, gy=0, yaw="", slide=30, turn=25, stick=stick)
    bound = Bound(problem)
    assert [need.ends_by_tool for need in bound.needs] == [True]
    root = start_sequence(problem)
    assert bound(root) == 4  # two slides of at most 30 cm, a break between them, and the stick's grasp
    pushed = next(c for c in _children(problem, root) if c.last.engagement.affordance == "push_px")
    assert bound(pushed) == 3  # break, grasp the stick, push with its tip
    assert "only a tool can move it last" in bound.explain()
    near = block_problem(tmp_path, x=0.45, gx=0.6, gy=0, yaw="", slide=30, turn=25, stick=stick)
    assert [need.ends_by_tool for need in Bound(near).needs] == [False]
    alone = block_problem(tmp_path, x=0.6, gx=0.95, gy=0, yaw="", slide=30, turn=25, stick="")
    assert Bound(alone)(start_sequence(alone)) == math.inf  # nothing but the hand, which cannot end it there


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    gx=st.floats(0.55, 1.0),
    gy=st.floats(-0.3, 0.3),
    yaw=st.sampled_from([None, -30, 0, 45, 170]),
    family=st.booleans(),
    seed=st.integers(0, 2**16),
)
def test_a_goal_called_beyond_the_hand_has_every_hand_contact_out_of_reach(tmp_path, gx, gy, yaw, family, seed):
    from vkgl.plan.graphs.members import action_at
    from vkgl.se3 import yaw_of

    problem = drawn_block_problem(tmp_path, x=0.45, gx=gx, gy=gy, yaw=yaw, family=family)
    if not any(need.ends_by_tool for need in Bound(problem).needs):
        return
    goal, block = problem.goals[0], problem.bodies["block"]
    rng = np.random.default_rng(seed)
    for _ in range(300):  # poses the goal accepts, contacts anywhere on their bands
        radius, angle = goal.tol_position * np.sqrt(rng.uniform()), rng.uniform(0, 2 * math.pi)
        heading = rng.uniform(-math.pi, math.pi) if goal.yaw is None else goal.yaw + rng.uniform(-1, 1) * goal.tol_yaw
        turn = heading - yaw_of(block.rest)
        pose = block.rest.copy()
        pose[:3, :3] = np.array([[math.cos(turn), -math.sin(turn), 0], [math.sin(turn), math.cos(turn), 0], [0, 0, 1]])
        pose[:3, :3] = pose[:3, :3] @ block.rest[:3, :3]
        pose[:2, 3] = goal.position[:2] + radius * np.array([math.cos(angle), math.sin(angle)])
        for affordance in block.affordances:
            offset = rng.uniform(0.0, 0.04) if family and affordance.name == "turn_left" else 0.0
            hand = pose @ action_at(problem, "block", affordance.name, offset)
            assert unreachable(problem, hand) is not None, (affordance.name, hand[:3, 3])


def test_the_search_checks_only_sequences_the_bound_lets_end_there(tmp_path, monkeypatch):
    # a sequence whose bound is above 0 cannot pass its checks (the bound never exceeds the graphs still needed):
    # the search extends it without checking it, and its plan is as short as exhaustive search's
    import time

    import vkgl.plan.search.search as search_module

    problem = block_problem(tmp_path, x=0.45, gx=0.73, gy=0, yaw=" yaw -20deg", slide=30, turn=25, stick="")
    bound, checked = Bound(problem), []
    check = search_module.check

    def recording(problem_, seq, *args, **kwargs):
        checked.append(seq)
        return check(problem_, seq, *args, **kwargs)

    monkeypatch.setattr(search_module, "check", recording)
    result = search_module.search(problem, deadline=time.perf_counter() + 60)
    assert result.status == "solved" and result.sequence is not None
    assert checked and all(bound(seq) == 0 for seq in checked)
    seen: list[tuple[Sequence, float]] = []
    assert result.sequence.depth == 1 + _remaining(problem, start_sequence(problem), seen) == 4


def test_a_tool_held_so_that_it_cannot_end_the_body_there_is_let_go_of_first(tmp_path):
    stick = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"
    problem = block_problem(tmp_path, x=0.9, gx=1.15, gy=0, yaw="", slide=30, turn=25, stick=stick)
    bound = Bound(problem)
    assert bound.needs[0].wrong_grasps == {("stick", "grasp_top_y")}  # held by its middle it is 20 cm too short
    root = start_sequence(problem)
    assert bound(root) == 2  # grasp the stick, push with its tip
    grasps = {c.last.engagement.affordance: c for c in _children(problem, root) if c.last.engagement.body == "stick"}
    assert bound(grasps["wield"]) == 1  # push with its tip
    assert bound(grasps["grasp_top_y"]) == 3  # let go, grasp it otherwise, push


def test_a_grasp_called_wrong_has_every_hand_pose_out_of_reach(tmp_path):
    from vkgl.plan.graphs.graph import Action, Engagement, KGraph
    from vkgl.plan.graphs.rollout import hand_chain

    stick = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"
    rng = np.random.default_rng(7)
    for gx in (1.1, 1.15, 1.2):
        problem = block_problem(tmp_path, x=0.9, gx=gx, gy=0.03, yaw=" yaw 10deg", slide=30, turn=25, stick=stick)
        goal, block = problem.goals[0], problem.bodies["block"]
        for _, grasp in Bound(problem).needs[0].wrong_grasps:
            graph = KGraph((Engagement(problem.robot_effector.name, "stick", grasp),))
            for affordance in block.affordances:
                chain = hand_chain(
                    problem, graph, Action("add", Engagement("stick.tip", "block", affordance.name)).engagement
                )
                assert chain is not None
                for _ in range(50):
                    turn = math.radians(10 + rng.uniform(-3, 3))
                    pose = np.eye(4)
                    pose[:3, :3] = [
                        [math.cos(turn), -math.sin(turn), 0],
                        [math.sin(turn), math.cos(turn), 0],
                        [0, 0, 1],
                    ]
                    pose[:3, 3] = (*(goal.position[:2] + rng.uniform(-0.007, 0.007, 2)), block.rest[2, 3])
                    assert unreachable(problem, pose @ chain[0]) is not None, (grasp, affordance.name)


def _beyond(problem: Problem, normal: tuple[float, float], edge: float) -> Problem:
    """`problem` whose only goal puts the block's footprint beyond the line `normal . p = edge` (the half-plane
    `normal . p >= edge`, as `clear_first`'s side goals), any heading."""
    from dataclasses import replace

    from vkgl.plan.problem.problem import GoalSpec

    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    region = np.array([[-n[0], -n[1], -edge]])
    goal = GoalSpec("block", None, None, 0.005, math.pi, region=region, footprint=problem.footprint_points("block"))
    return replace(problem, goals=[goal])


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    x=st.sampled_from([0.45, 0.6]),
    normal=st.sampled_from([(1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0)]),
    past=st.sampled_from([-0.02, 0.01, 0.03, 0.08, 0.2]),
    slide=st.sampled_from([6, 10]),
    turn=st.sampled_from([15, 25]),
    family=st.booleans(),
)
def test_the_bound_of_a_region_goal_never_exceeds_the_true_remaining_depth(
    tmp_path, x, normal, past, slide, turn, family
):
    # a half-plane whose line lies `past` beyond the block's back (negative: it lies beyond already): the
    # footprint's farthest point, not the origin, must cross the line, and a turn moves a corner more than the origin
    fields = {"x": x, "gx": x, "gy": 0, "yaw": "", "slide": slide, "turn": turn, "stick": ""}
    base = block_problem(tmp_path, **fields, family=FAMILY if family else "")
    n = np.asarray(normal) / np.linalg.norm(normal)
    points = base.footprint_points("block") @ base.bodies["block"].rest[:2, :3].T + base.bodies["block"].rest[:2, 3]
    problem = _beyond(base, normal, float(np.min(points @ n)) + past)
    _assert_the_bound_never_exceeds_the_true_remaining_depth(problem)


def test_a_region_far_beyond_short_slides_needs_a_contact_and_a_break_per_slide(tmp_path):
    base = block_problem(tmp_path, x=0.45, gx=0.45, gy=0, yaw="", slide=8, turn=25, stick="")
    back = float(np.min(base.footprint_points("block")[:, 0])) + 0.45  # its whole footprint must pass the line
    problem = _beyond(base, (1.0, 0.0), back + 0.205)  # 20.5 cm, 0.5 cm tolerance: 20 cm in slides of 8 cm
    bound = Bound(problem)
    root = start_sequence(problem)
    assert bound(root) == 5  # 3 modes (slides of 8 cm, turns moving a corner 9.4 cm), 2 breaks between them
    assert "at least 3 contacts" in bound.explain()
    inside = _beyond(base, (1.0, 0.0), back - 0.01)
    assert Bound(inside)(start_sequence(inside)) == 0  # it lies there already


def test_a_region_beside_a_body_that_slides_straight_needs_a_turn(tmp_path):
    # the block slides along x only (push_px) until it turns: a half-plane 3 cm beyond its left side is never
    # reached by pushes alone, however far they go
    base = block_problem(tmp_path, x=0.45, gx=0.45, gy=0, yaw="", slide=30, turn=25, stick="")
    problem = _beyond(base, (0.0, 1.0), float(np.min(base.footprint_points("block")[:, 1])) + 0.03)
    bound = Bound(problem)
    pushed = next(c for c in _children(problem, start_sequence(problem)) if c.last.engagement.affordance == "push_px")
    assert bound(pushed) == 2  # let go of the push, make a turn


def test_a_region_one_turn_reaches_is_never_said_to_need_two(tmp_path):
    from vkgl.plan.graphs.motions import motion_matrices
    from vkgl.plan.search.bounds.region_need import one_turn_reaches

    base = block_problem(tmp_path, x=0.45, gx=0.45, gy=0, yaw="", slide=30, turn=25, stick="")
    body = base.bodies["block"]
    turn = next(a for a in body.affordances if a.motion.type == "revolute")
    turned = body.rest @ motion_matrices(turn.motion, np.array([np.radians(25.0)]))[0]
    points = base.footprint_points("block") @ turned[:3, :3].T + turned[:3, 3]
    resting = base.footprint_points("block") @ body.rest[:3, :3].T + body.rest[:3, 3]
    directions = [(np.cos(a), np.sin(a)) for a in np.linspace(0.0, 2 * np.pi, 16, endpoint=False)]
    gains = {n: float(np.min(points[:, :2] @ n) - np.min(resting[:, :2] @ n)) for n in directions}
    normal = max(gains, key=lambda n: gains[n])
    assert gains[normal] > 0.01  # the turn takes the footprint's back past a line it lay behind
    edge = float(np.min(points[:, :2] @ np.array(normal)))
    problem = _beyond(base, normal, edge)  # where the turn ends it
    goal = problem.goals[0]
    assert one_turn_reaches(body, goal, [turn])
    assert Bound(problem)(start_sequence(problem)) == 1  # the one ADD of that turn
    seen: list[tuple[Sequence, float]] = []
    assert _remaining(problem, start_sequence(problem), seen) == 1
    far = _beyond(base, normal, edge + 0.1)
    assert not one_turn_reaches(body, far.goals[0], [turn])  # 10 cm farther than the turn takes it


def _assert_the_bound_never_exceeds_the_true_remaining_depth(problem) -> None:
    """Every sequence of `problem` enumerated to its max_depth: the bound is at most its true remaining depth."""
    bound = Bound(problem)
    seen: list[tuple[Sequence, float]] = []
    _remaining(problem, start_sequence(problem), seen)
    for seq, true in seen:
        assert bound(seq) <= true, (
            f"bound {bound(seq)} > true remaining {true} after {[a.label(problem) for a in seq.actions]}"
        )
