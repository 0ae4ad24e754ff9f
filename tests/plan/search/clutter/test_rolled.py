"""A blocker's slides enacted by a hook rolled over the low bodies beside it (`vkgl.plan.search.clutter.rolled`): the
least roll and the most, offered to the hook only, and the way aside they open (gen1_023 of the physical bench)."""

from __future__ import annotations

import math
import time
from dataclasses import replace

import pytest
from task_makers import generated_tasks

import vkgl
from vkgl.lang.ir.families import over_pose
from vkgl.plan.problem.over import MAX_BESIDE_ROLL
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter.blocking import blocking_bodies
from vkgl.plan.search.clutter.clear_tools import far_move_tools
from vkgl.plan.search.clutter.rolled import with_rolled_members
from vkgl.plan.search.clutter.side_problem import only_moving as _only_moving
from vkgl.plan.search.clutter.side_problem import side_goal
from vkgl.plan.search.search import search
from vkgl.plan.task_space.clearing import way_sides

SIDEWAYS = """affordances CubeS {
    affordance push_center_ny {
        action fixed at (0, 4, 0) cm yaw -90deg
        motion prismatic along (0, -1, 0) from (0, 0, 0) cm range 0 to 75.2 cm open
    }
"""
"""The CubeS's slide along -y as the physical bench learns it on four faces (the tests' fixtures explore +-x only)."""


@pytest.fixture(scope="module")
def cube_before_slab(tmp_path_factory: pytest.TempPathFactory) -> Problem:
    """gen1_023: a CubeS 1.9 cm before a SlabN (24 cm wide, 5 cm tall) that the hook must pull 28.7 cm, turned 20
    deg to it, with its slide sideways."""
    spec = generated_tasks.task_spec(1, 23)
    folder = tmp_path_factory.mktemp(spec.name)
    task = generated_tasks.write_task(spec, folder, generated_tasks.fixture_library())
    learned = folder / "affordances.vkg"
    text = learned.read_text(encoding="utf-8")
    assert "affordances CubeS {\n" in text
    learned.write_text(text.replace("affordances CubeS {\n", SIDEWAYS, 1), encoding="utf-8")
    program = vkgl.compile(task)
    return build_problem(program, program.tasks[spec.name])


def _rolled(problem: Problem, body: str) -> dict[str, tuple[float, float]]:
    names = (a.name for a in problem.bodies[body].affordances)
    return {name: pose[1:] for name in names if (pose := over_pose(name)) is not None}


def test_the_blockers_slides_get_the_least_roll_and_the_most_for_the_hook_only(cube_before_slab: Problem) -> None:
    problem = with_rolled_members(cube_before_slab, "clutter1")
    rolled = _rolled(problem, "clutter1")
    assert not _rolled(cube_before_slab, "clutter1")  # a body in the way had none
    slides = {name.partition("/")[0] for name in rolled}
    assert slides and all("push" in s for s in slides)
    for slide in slides:
        rolls = sorted(abs(roll) for name, (roll, _) in rolled.items() if name.startswith(slide + "/"))
        assert len(rolls) == 2 and 0 < rolls[0] < rolls[1] == pytest.approx(MAX_BESIDE_ROLL)
    enacted = problem.bodies["clutter1"].tool_members
    assert {name for name, _ in enacted} == set(rolled)
    assert {effector for _, effector in enacted} == {"hook.tip"}
    assert problem.bodies["target"] is cube_before_slab.bodies["target"]  # the other bodies as they were


def test_a_body_off_the_table_or_without_tools_gets_none(cube_before_slab: Problem) -> None:
    lifted = replace(cube_before_slab.bodies["clutter1"], on_table=False)
    problem = replace(cube_before_slab, bodies={**cube_before_slab.bodies, "clutter1": lifted})
    assert with_rolled_members(problem, "clutter1") is problem
    bare = replace(cube_before_slab, effectors=[e for e in cube_before_slab.effectors if e.tool is None])
    assert with_rolled_members(bare, "clutter1") is bare


def test_the_hook_rolled_over_the_slab_clears_the_cube_off_its_side(cube_before_slab: Problem) -> None:
    """Off the slab's left side the only pull puts the hook's shaft 12 cm toward the slab: lying flat (or at the
    least roll) it passes through the slab's top; rolled 45 deg over it, one pull clears the cube there."""
    goal, blocker = blocking_bodies(cube_before_slab)[0]
    sides = way_sides(cube_before_slab, goal, blocker, tools=far_move_tools(cube_before_slab, goal))
    left = next(side for side in sides if side.words == "left")
    moving, still = _only_moving(cube_before_slab, goal, blocker, left)
    deadline = time.perf_counter() + generated_tasks.TEST_SOLVE_TIMEOUT_S
    for problem, solved in ((moving, False), (with_rolled_members(moving, blocker), True)):
        sub = replace(problem, goals=[side_goal(cube_before_slab, goal, blocker, left)], max_depth=3)
        found = search(sub, deadline=deadline, still=still)
        assert (found.status == "solved") is solved, found.reason
    assert found.sequence is not None
    pull = found.sequence.actions[-1].label(sub)
    pose = over_pose(pull.split()[1].partition(".")[2])
    assert pose is not None and math.isclose(abs(pose[1]), MAX_BESIDE_ROLL)
