"""The planner never pushes a body where it tips: it uses a lower contact, or says why there is no plan."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

import vkgl
from vkgl.lang.compiler import compile_source
from vkgl.plan.problem.tipping import split_by_tipping

CARTON = """
use stdlib.robots.panda

body Carton {{
    shape box (6, 6, 12) cm
    mass 0.2 kg
    friction 0.8
    {joint}
}}

affordances Carton {{
    {tips}
    affordance push_high_px {{
        action fixed at (-3, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }}
    {low}
}}

scene carton_scene {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    carton : Carton on table at (0.45, 0.05) m yaw 0deg
}}

task push_carton {{
    scene carton_scene
    goal carton at (0.55, 0.05) m yaw 0deg within 1 cm, 3deg
    search {{ max_depth 3  timeout 30 s }}
}}
"""

LOW = """affordance push_low_px {
        action fixed at (-3, 0, -4) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }"""


def carton_program(*, tips: str = "tips above 2 cm on faces +x, -x", low: bool = True, joint: str = ""):
    """The carton task: a push at 6 cm over the table (first) and, with `low`, one at 2 cm."""
    source = CARTON.format(tips=tips, low=LOW if low else "", joint=joint)
    return compile_source(textwrap.dedent(source), "carton.vkg")


def test_the_planner_pushes_below_the_tipping_height() -> None:
    plan = vkgl.solve(carton_program(), "push_carton")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Carton.push_low_px"]


def test_without_the_clause_the_first_push_would_do() -> None:
    """The clause decides: the same module without it is solved with the high push, listed first."""
    plan = vkgl.solve(carton_program(tips=""), "push_carton")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Carton.push_high_px"]


def test_a_body_only_pushed_where_it_tips_has_no_plan_and_the_reason_says_so() -> None:
    plan = vkgl.solve(carton_program(low=False), "push_carton")
    assert plan.status == "infeasible"
    assert plan.reason.startswith("no affordance moves carton without tipping it over: push_high_px pushes Carton")
    assert "6.0 cm over the table on its -x face, above the 2.0 cm it tips over at" in plan.reason
    assert "heights" in plan.reason  # what to do about it


def test_a_clause_on_other_faces_leaves_the_push_alone() -> None:
    plan = vkgl.solve(carton_program(tips="tips above 2 cm on faces +y, -y", low=False), "push_carton")
    assert plan.status == "solved", plan.reason


@pytest.mark.parametrize(("limit_cm", "kept"), [(2.0, True), (1.96, True), (1.9, False), (0.0, False)])
def test_a_push_at_the_recorded_height_is_kept_and_one_above_it_is_not(limit_cm: float, kept: bool) -> None:
    """push_low_px touches 2 cm over the table; 0.5 mm covers the roundings of the printed numbers."""
    program = carton_program(tips=f"tips above {limit_cm} cm on faces -x")  # the face it presses
    low = tuple(a for a in program.affordances["Carton"] if a.name == "push_low_px")
    usable, left = split_by_tipping(program.bodies["Carton"], low, program.tipping["Carton"])
    assert (usable == low, [t.affordance for t in left]) == ((True, []) if kept else (False, ["push_low_px"]))


def test_a_body_on_a_joint_never_tips() -> None:
    program = carton_program(joint="joint prismatic axis (1, 0, 0) limits (0, 20) cm")
    body = program.bodies["Carton"]
    affordances = tuple(program.affordances["Carton"])
    assert split_by_tipping(body, affordances, program.tipping["Carton"]) == (affordances, ())
    assert np.isclose(program.tipping["Carton"][0].height.value, 0.02)


def test_the_stdlib_bodies_lose_no_affordance() -> None:
    """No stdlib module has a `tips above` clause, so the paper's tasks plan with every affordance as before."""
    from pathlib import Path

    from vkgl.plan.problem.problem import build_problem

    task = Path(__file__).resolve().parents[3] / "examples" / "tasks" / "e_rotate_stick_push.vkg"
    program = vkgl.compile(task)
    assert all(not clauses for clauses in program.tipping.values())
    problem = build_problem(program, next(iter(program.tasks.values())))
    for body in problem.bodies.values():
        assert body.too_high == ()
        assert len(body.affordances) == len(program.affordances[body.type.name])
