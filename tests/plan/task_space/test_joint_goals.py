"""Planning with joint goals (`goal B open Q within Q`): the joint's coordinate reaches the value.

The stdlib Drawer is opened as a user would (`vkgc solve`); the rest uses a
slide and a hinge declared here with hand-written affordances, so that the
numbers the tests check do not depend on what `vkgc learn` last produced.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from checkers.replay_check import check_plan, joint_goal_problems

import vkgl
from vkgl.cli import main
from vkgl.errors import InputError
from vkgl.lang.compiler import compile_file
from vkgl.lang.ir.geometry import joint_pose
from vkgl.lang.ir.nodes import Quantity
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.result.picture import _goal_pose, plan_image
from vkgl.plan.task_space.feasible import goal_holds, goal_residuals

HERE = Path(__file__).resolve().parent

STDLIB_KITCHEN = """use stdlib.robots.panda
use stdlib.bodies.drawer
use stdlib.affordances.drawer

scene kitchen {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    drawer : Drawer on table at (0.45, 0) m yaw 0deg
}
"""

LOCAL = """use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

# Both 5 cm tall: the hand clears their tops while the fingertip touches their faces, so the arm's
# collision checks let it push them upright (two pushes in a row too), and the replay check holds exactly.
body Slide {
    shape box (30, 40, 5) cm
    mass 2 kg
    joint prismatic axis (1, 0, 0) limits (0, 30) cm damping 5 N*s/m friction 1 N
}

body Hinge {
    shape box (2, 40, 5) cm
    mass 0.5 kg
    joint revolute axis (0, 0, 1) through (0, -20, 0) cm limits (0, 90) deg damping 0.5 N*m*s/rad
}

affordances Slide {
    affordance push_open {
        action fixed at (-15, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 8 cm
    }
}

affordances Hinge {
    affordance push_open {
        action fixed at (1, 0, 0) cm yaw 180deg
        motion revolute about (0, -20, 0) cm axis (0, 0, 1) range 0 to 30deg
    }
}

scene slides {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    slide : Slide on table at (0.45, 0) m
    block : Block on table at (0.45, -0.4) m yaw 0deg
}

scene hinges {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    hinge : Hinge on table at (0.5, 0.35) m yaw 180deg
}
"""


def write(tmp_path: Path, text: str, name: str = "tasks.vkg") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def local(tasks: str):
    """The LOCAL bodies and scenes with `tasks`, compiled."""
    return vkgl.compile_source(LOCAL + tasks, "local.vkg", base_dir=HERE)


# ---------------------------------------------------------------- vkgc solve on the stdlib Drawer


def test_vkgc_solve_opens_the_stdlib_drawer_5_cm(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Its learned pull_center_px (the fingertip hooked behind the handle) pulls along +x, the sense its joint opens
    in: one pull of 5 cm, the hand coming down into the gap behind the bar."""
    task = write(tmp_path, STDLIB_KITCHEN + "task open { scene kitchen  goal drawer open 5 cm within 1 cm }\n")
    out = tmp_path / "plan.json"
    assert main(["solve", str(task), "--json", str(out)]) == 0
    assert "solved in 1 step (depth 2: graphs G0 to G1" in capsys.readouterr().out
    plan = json.loads(out.read_text(encoding="utf-8"))
    (step,) = plan["steps"]
    assert step["affordance"] == "Drawer.pull_center_px" and step["value"] == pytest.approx(0.05, abs=1e-6)
    assert joint_goal_problems(compile_file(str(task)), plan) == []  # the opening, recomputed independently
    # backing away from the bar along the pull would put the hand into the drawer: it comes straight down instead
    (approach,) = [segment for segment in step["path"] if segment["phase"] == "approach"]
    program = compile_file(str(task))
    problem = build_problem(program, program.task("open"))
    first, last = (problem.arm.fk(np.array(q)) for q in (approach["joints"][0], approach["joints"][-1]))
    assert first[:3, 3] - last[:3, 3] == pytest.approx([0.0, 0.0, 0.03], abs=1e-3)


CABINET_KITCHEN = """use stdlib.robots.panda
use stdlib.affordances.drawer
use stdlib.furniture.drawer_cabinet

scene kitchen {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    cabinet : DrawerCabinet on table at (0.7, 0.25) m yaw 180deg
    drawer : Drawer at (0.7, 0.25, 0.073) m yaw 180deg
}

task open { scene kitchen  goal drawer open 20 cm within 1 cm }
"""


def test_the_drawer_in_its_cabinet_is_pulled_with_the_hand_along_its_front() -> None:
    """The fingertip's yaw is free, and IK's choice stands the 20 cm long hand across the handle, into the
    cabinet's top board; the search then pins the yaw to the action frame's: the hand lies along the front."""
    program = vkgl.compile_source(CABINET_KITCHEN, "kitchen.vkg", base_dir=HERE)
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    (step,) = plan.steps
    assert step.affordance == "Drawer.pull_center_px" and step.value == pytest.approx(0.20, abs=1e-6)
    hand = plan.problem.arm.fk(np.asarray(step.q_start))
    pull = plan.start["drawer"][:3, :3] @ np.array([1.0, 0.0, 0.0])  # the drawer's +x: toward the robot
    assert hand[:3, 0] @ pull == pytest.approx(1.0, abs=1e-3)  # the hand's x along the pull: across the front
    assert joint_goal_problems(program, json.loads(json.dumps(plan.to_json()))) == []


def test_a_joint_goal_past_the_limit_is_a_warning_then_no_plan_with_the_numbers(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    task = write(tmp_path, STDLIB_KITCHEN + "task far { scene kitchen  goal drawer open 35 cm within 1 cm }\n")
    assert main(["check", str(task)]) == 0
    assert "warning[W604]: `drawer` cannot open `35 cm`: its slide stops at 30 cm" in capsys.readouterr().out
    assert main(["solve", str(task)]) == 2
    out = capsys.readouterr().out
    assert "infeasible" in out
    assert "the goal needs it at 35.0 cm on its prismatic joint, past its upper limit of 30.0 cm" in out
    assert "graphs expanded" in out and "0 graphs expanded" in out  # answered before searching


# ---------------------------------------------------------------- the planner's answers


def test_one_contact_opens_the_slide_to_exactly_the_goal() -> None:
    plan = vkgl.solve(local("task t { scene slides  goal slide open 6 cm within 5 mm }\n"))
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    assert plan.steps[0].value == pytest.approx(0.06, abs=1e-9)  # the closed form pins it
    assert plan.final["slide"][:3, 3] == pytest.approx([0.51, 0.0, plan.start["slide"][2, 3]], abs=1e-9)


def test_an_opening_beyond_one_contacts_range_takes_two_contacts() -> None:
    program = local("task t { scene slides  goal slide open 12 cm within 5 mm  search { max_depth 4 } }\n")
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.depth == 4, plan.reason
    pushes = [s.value for s in plan.steps if s.op == "add"]
    assert len(pushes) == 2 and sum(pushes) == pytest.approx(0.12, abs=0.005)
    assert all(v <= 0.08 + 1e-9 for v in pushes)
    assert check_plan(program, json.loads(json.dumps(plan.to_json()))) == []


def test_a_sequence_too_short_for_the_opening_says_how_far_it_gets() -> None:
    plan = vkgl.solve(local("task t { scene slides  goal slide open 12 cm within 5 mm  search { max_depth 2 } }\n"))
    assert plan.status == "infeasible"
    assert (
        "slide's opening (from 0.0 cm to 12.0 cm) is 12.0 cm from its goal (within 0.5 cm wanted) and "
        "Slide.push_open opens it at most 8.0 cm per contact: at least 2 contacts: the goal needs at least 4 graphs"
    ) in plan.reason
    assert plan.reason.splitlines()[-1].endswith("(try --max-depth 4)")  # two pushes: ADD, REMOVE, ADD


def test_a_hinge_opens_by_the_goals_angle_about_its_axis() -> None:
    program = local("task t { scene hinges  goal hinge open 20deg within 2deg }\n")
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    assert plan.steps[0].value == pytest.approx(math.radians(20), abs=1e-9)
    turned = np.degrees(math.atan2(plan.final["hinge"][1, 0], plan.final["hinge"][0, 0]))
    assert turned == pytest.approx(-160.0, abs=1e-6)  # from yaw 180deg, 20deg about +z
    assert check_plan(program, json.loads(json.dumps(plan.to_json()))) == []


def test_a_hinge_goal_below_its_lower_limit_is_no_plan_with_the_numbers() -> None:
    plan = vkgl.solve(local("task t { scene hinges  goal hinge open -10deg within 2deg }\n"))
    assert plan.status == "infeasible"
    assert "the goal needs it at -10.0 deg on its revolute joint, past its lower limit of 0.0 deg" in plan.reason


def test_a_joint_goal_that_holds_at_the_start_needs_no_step() -> None:
    plan = vkgl.solve(local("task t { scene slides  goal slide open 0 cm }\n"))
    assert plan.status == "solved" and plan.depth == 1 and plan.steps == []


def test_a_joint_goal_and_a_pose_goal_on_other_bodies_hold_together() -> None:
    plan = vkgl.solve(local("task t { scene slides  goal slide open 5 cm and block at (0.55, -0.4) m }\n"))
    assert plan.status == "solved", plan.reason
    assert plan.final["block"][:2, 3] == pytest.approx([0.55, -0.4], abs=0.01)
    assert plan.final["slide"][0, 3] - plan.start["slide"][0, 3] == pytest.approx(0.05, abs=0.01)


def test_goal_holds_and_residuals_measure_the_joint_coordinate() -> None:
    program = local("task t { scene slides  goal slide open 5 cm within 1 cm }\n")
    problem = build_problem(program, program.tasks["t"])
    rest = {n: b.rest.copy() for n, b in problem.bodies.items()}
    assert not goal_holds(problem, rest)
    assert goal_residuals(problem, rest) == pytest.approx([-5.0])  # 5 cm short, in tolerances
    moved = dict(rest)
    moved["slide"] = rest["slide"].copy()
    moved["slide"][0, 3] += 0.055
    assert goal_holds(problem, moved) and goal_residuals(problem, moved) == pytest.approx([0.5])
    moved["slide"][1, 3] += 0.3  # sideways: not along the joint's axis, so not an opening
    assert goal_holds(problem, moved)


def test_a_joint_goal_made_through_the_api_on_a_body_without_a_joint_is_an_input_error() -> None:
    program = local("task t { scene slides  goal slide open 5 cm }\n")
    task = program.tasks["t"]
    goal = task.goals[0].model_copy(update={"body": task.goals[0].body.model_copy(update={"name": "block"})})
    wrong = task.model_copy(update={"goals": [goal]})
    with pytest.raises(InputError, match="the joint goal on `block` cannot hold: `block` has no physical joint"):
        build_problem(program, wrong)
    angle = task.goals[0].model_copy(update={"opening": Quantity(value=0.3, unit="rad")})
    with pytest.raises(InputError, match="a prismatic joint, which opens by a length"):
        build_problem(program, task.model_copy(update={"goals": [angle]}))
    exact = task.goals[0].model_copy(update={"tol_opening": Quantity(value=0.0, unit="cm")})
    with pytest.raises(InputError, match="the joint goal on `slide` needs a positive tolerance"):
        build_problem(program, task.model_copy(update={"goals": [exact]}))


# ---------------------------------------------------------------- the joint's coordinate and pose


@pytest.mark.parametrize(("name", "value"), [("slide", 0.07), ("slide", -0.02), ("hinge", 0.6), ("hinge", -1.2)])
def test_joint_pose_and_joint_coordinate_are_inverse(name: str, value: float) -> None:
    program = local("task t { scene slides  goal slide open 5 cm }\ntask u { scene hinges  goal hinge open 5deg }\n")
    problem = build_problem(program, program.tasks["t" if name == "slide" else "u"])
    body = problem.bodies[name]
    pose = joint_pose(body.type.joint, body.rest, value)
    assert body.joint_state(pose) == pytest.approx(value, abs=1e-12)
    if name == "hinge":  # it turns about the line through its `through` point: that point stays put
        hinge = np.array([0.0, -0.20, 0.0, 1.0])
        assert (pose @ hinge)[:3] == pytest.approx((body.rest @ hinge)[:3], abs=1e-12)


def test_the_plan_picture_outlines_the_body_at_its_joint_goal() -> None:
    program = local("task t { scene hinges  goal hinge open 20deg within 2deg }\n")
    plan = vkgl.solve(program)
    body = plan.problem.bodies["hinge"]
    assert _goal_pose(plan.problem, plan.problem.goals[0]) == pytest.approx(plan.final["hinge"], abs=1e-9)
    assert _goal_pose(plan.problem, plan.problem.goals[0]) == pytest.approx(
        joint_pose(body.type.joint, body.rest, math.radians(20)), abs=1e-12
    )
    assert plan_image(plan, "png").startswith(b"\x89PNG")


def test_the_joint_goals_example_of_the_language_reference_solves(tmp_path: Path) -> None:
    """docs/language.md, "Joint goals", says `vkgc solve` solves both of its tasks with one contact each."""
    text = (HERE.parents[2] / "docs" / "language.md").read_text(encoding="utf-8")
    section = text.split("### Joint goals", 1)[1]
    snippet = section.split("```vkg\n", 1)[1].split("```", 1)[0]
    program = compile_file(str(write(tmp_path, snippet, "kitchen.vkg")))
    for task in ("open_drawer", "open_door"):
        plan = vkgl.solve(program, task)
        assert plan.status == "solved" and plan.depth == 2, plan.reason
        assert joint_goal_problems(program, json.loads(json.dumps(plan.to_json()))) == []


# ---------------------------------------------------------------- a joint that starts open

OPENED = """
scene opened {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    slide : Slide open 10 cm on table at (0.4, 0) m
    block : Block on table at (0.45, -0.4) m yaw 0deg
}
"""


def test_a_slide_that_starts_open_is_measured_from_where_it_is_placed() -> None:
    """`open 10 cm` starts it 10 cm out; `goal slide open 16 cm` is 6 cm more, one contact of exactly 6 cm."""
    program = local(OPENED + "task t { scene opened  goal slide open 16 cm within 5 mm }\n")
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    body = plan.problem.bodies["slide"]
    assert body.start_state == pytest.approx(0.10, abs=1e-12)
    assert plan.start["slide"][0, 3] == pytest.approx(0.50, abs=1e-12)  # placed at 0.40, started 10 cm out
    assert plan.steps[0].value == pytest.approx(0.06, abs=1e-9)
    assert body.joint_state(plan.final["slide"]) == pytest.approx(0.16, abs=1e-9)
    assert _goal_pose(plan.problem, plan.problem.goals[0]) == pytest.approx(plan.final["slide"], abs=1e-9)
    assert joint_goal_problems(program, json.loads(json.dumps(plan.to_json()))) == []


def test_a_start_opening_counts_in_what_the_motions_must_add_and_in_the_limits() -> None:
    program = local(OPENED + "task t { scene opened  goal slide open 25 cm within 5 mm  search { max_depth 2 } }\n")
    plan = vkgl.solve(program)
    assert plan.status == "infeasible"
    assert "slide's opening (from 10.0 cm to 25.0 cm) is 15.0 cm from its goal" in plan.reason
    past = vkgl.solve(local(OPENED + "task t { scene opened  goal slide open 35 cm within 1 cm }\n"))
    assert past.status == "infeasible"
    assert "the goal needs it at 35.0 cm on its prismatic joint, past its upper limit of 30.0 cm" in past.reason
    held = vkgl.solve(local(OPENED + "task t { scene opened  goal slide open 10 cm }\n"))
    assert held.status == "solved" and held.steps == []  # it starts there


@pytest.mark.parametrize(
    ("scene", "goal", "words"),
    [
        (
            "kitchen",
            "door open 100deg",
            "door: the goal needs it at 100.0 deg on its revolute joint, past its upper limit",
        ),
        (
            "kitchen_door_open",
            "door open -10deg",
            "door: the goal needs it at -10.0 deg on its revolute joint, past its lower",
        ),
        (
            "kitchen_door_open",
            "drawer open 31.5 cm",
            "the goal needs it at 31.5 cm on its prismatic joint, past its upper",
        ),
    ],
)
def test_vkgc_solve_says_no_plan_with_the_numbers_for_the_stdlib_door_and_drawer_past_their_limits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], scene: str, goal: str, words: str
) -> None:
    examples = HERE.parents[2] / "examples"
    task = write(
        tmp_path,
        f'use "{(examples / "scenes" / "kitchen.vkg").as_posix()}"\nuse stdlib.affordances.drawer\n'
        f"use stdlib.affordances.door\n\ntask past {{ scene {scene}  goal {goal} }}\n",
    )
    assert main(["solve", str(task)]) == 2
    out = capsys.readouterr().out
    assert "infeasible" in out and words in out and "0 graphs expanded" in out
