"""The Program API: compile from a string, pick a task, change a goal or a start pose and re-solve."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from vkgl.errors import CompileError, InputError
from vkgl.lang.compiler import compile_file, compile_source
from vkgl.lang.ir.nodes import DEFAULT_TOL_POSITION, DEFAULT_TOL_YAW, Goal, Quantity, Ref

REPO = Path(__file__).resolve().parents[3]
A_PUSH = REPO / "examples" / "tasks" / "a_push.vkg"

TWO_TASKS = """\
use "../scenes/tabletop.vkg"
use stdlib.affordances.block

task near {
    scene tabletop
    goal block at (0.6, 0) m within 1 cm
}

task far {
    scene tabletop
    goal block at (0.7, 0) m yaw 10deg
}
"""


@pytest.fixture(scope="module")
def program():  # type: ignore[no-untyped-def]
    return compile_file(A_PUSH)


# ---------------------------------------------------------------- compile_source


def test_compile_source_resolves_uses_from_base_dir_and_equals_the_file() -> None:
    from_text = compile_source(A_PUSH.read_text(encoding="utf-8"), "a_push.vkg", base_dir=A_PUSH.parent)
    from_file = compile_file(A_PUSH)
    assert from_text.tasks == from_file.tasks
    assert from_text.scenes == from_file.scenes
    assert from_text.root.path == "a_push.vkg"


def test_compile_source_names_the_text_in_diagnostics() -> None:
    with pytest.raises(CompileError) as info:
        compile_source("body B {\n    mass 0 kg\n    shape box (1, 1, 1) cm\n}\n", "mine.vkg")
    assert str(info.value).startswith("mine.vkg:2:10: error[E401]: the mass of `B` must be positive")


def test_compile_source_resolves_uses_from_the_working_directory(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO / "examples" / "tasks")
    program = compile_source(TWO_TASKS)
    assert sorted(program.tasks) == ["far", "near"]
    with pytest.raises(CompileError, match=r"<string>:1:1: error\[E501\]: no file `nowhere.vkg`"):
        compile_source('use "nowhere.vkg"\n')


def test_compile_source_resolves_mesh_paths_from_base_dir(tmp_path: Path) -> None:
    import trimesh

    trimesh.creation.box(extents=[0.05, 0.05, 0.05]).export(tmp_path / "part.stl")
    text = 'body Part {\n    shape mesh "part.stl"\n    mass 0.2 kg\n}\n'
    body = compile_source(text, base_dir=tmp_path).body("Part")
    assert body.shape.resolved == str((tmp_path / "part.stl").resolve())  # type: ignore[union-attr]


# ---------------------------------------------------------------- task()


def test_task_without_a_name_is_the_only_one(program) -> None:  # type: ignore[no-untyped-def]
    assert program.task().name == "a_push"
    assert program.task("a_push") is program.tasks["a_push"]


def test_task_is_an_input_error_listing_the_tasks_when_unknown_or_ambiguous() -> None:
    two = compile_source(TWO_TASKS, base_dir=A_PUSH.parent)
    with pytest.raises(InputError, match=r"declares 2 tasks \(near, far\); say which by name"):
        two.task()
    with pytest.raises(InputError, match=r"no task `nope` \(tasks: far, near\)"):
        two.task("nope")
    assert two.task("far").name == "far"
    with pytest.raises(InputError, match="declares no task"):
        compile_source("body B {\n    shape box (1, 1, 1) cm\n    mass 1 kg\n}\n").task()


# ---------------------------------------------------------------- goals


def test_goal_tolerance_defaults_and_si() -> None:
    assert Goal(body=Ref(name="b")).tolerance() == (DEFAULT_TOL_POSITION, DEFAULT_TOL_YAW)
    goal = Goal(
        body=Ref(name="b"), tol_position=Quantity(value=0.02, unit="cm"), tol_yaw=Quantity(value=0.1, unit="rad")
    )
    assert goal.tolerance() == (0.02, 0.1)


def test_with_goal_replaces_the_goal_and_keeps_the_original(program) -> None:  # type: ignore[no-untyped-def]
    moved = program.with_goal("a_push", "block", at=(0.62, 0.05), yaw=math.radians(30), within=(0.02, 0.1))
    goal = moved.task().goals[0]
    assert goal.position.values == (0.62, 0.05)
    assert goal.yaw.value == pytest.approx(math.radians(30))
    assert goal.tolerance() == (0.02, 0.1)
    assert len(moved.task().goals) == 1
    original = program.task().goals[0]
    assert original.position.values == (0.6, 0.0)  # the IR is frozen: the old program is unchanged
    assert moved.scenes == program.scenes and moved.root is program.root


def test_with_goal_keeps_the_tolerances_when_not_given(program) -> None:  # type: ignore[no-untyped-def]
    before = program.task().goals[0].tolerance()
    assert program.with_goal(None, "block", at=(0.5, 0.1)).task().goals[0].tolerance() == before
    heading_only = program.with_goal(program.task(), "block", yaw=1.0).task().goals[0]
    assert heading_only.position is None and heading_only.yaw.value == 1.0


def test_with_goal_rejects_what_cannot_be_a_goal(program) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(
        InputError,
        match=r"scene `tabletop` has no body `blok` \(did you mean `block`\? its bodies: block, stick, hook\)",
    ):
        program.with_goal("a_push", "blok", at=(0.6, 0))
    with pytest.raises(InputError, match="needs a position"):
        program.with_goal("a_push", "block")
    with pytest.raises(InputError, match="tolerances must be positive"):
        program.with_goal("a_push", "block", at=(0.6, 0), within=(0.0, 0.1))
    with pytest.raises(InputError, match="no task `b_push`"):
        program.with_goal("b_push", "block", at=(0.6, 0))


def test_with_goal_gives_a_region_goal_and_refuses_what_is_no_region(program) -> None:  # type: ignore[no-untyped-def]
    tray = program.with_goal("a_push", "block", region=[(0.55, -0.16), (0.75, 0.12)], yaw=0.0, within=(0.02, 0.1))
    (goal,) = tray.task().goals
    assert goal.region is not None and goal.region.kind == "box" and goal.position is None
    assert goal.yaw.value == 0.0 and goal.tolerance() == (0.02, 0.1)
    triangle = program.with_goal("a_push", "block", region=[(0.5, -0.2), (0.8, -0.2), (0.7, 0.2)])
    assert triangle.task().goals[0].region.kind == "polygon"
    with pytest.raises(InputError, match="not a region \\(swapped\\)"):
        program.with_goal("a_push", "block", region=[(0.75, -0.16), (0.55, 0.12)])
    with pytest.raises(InputError, match="not a region \\(concave\\)"):
        program.with_goal("a_push", "block", region=[(0, 0), (1, 0), (0.5, 0.2), (1, 1), (0, 1)])
    with pytest.raises(InputError, match="takes no position"):
        program.with_goal("a_push", "block", region=[(0.55, -0.16), (0.75, 0.12)], at=(0.6, 0))


# ---------------------------------------------------------------- start poses


def test_with_start_places_a_body_on_the_table(program) -> None:  # type: ignore[no-untyped-def]
    for where in ("tabletop", "a_push", program.task()):
        moved = program.with_start(where, "block", at=(0.42, -0.1), yaw=0.5)
        placed = next(b for b in moved.scenes["tabletop"].bodies if b.name == "block")
        assert placed.placement.on_table
        assert placed.placement.pose.position.values == (0.42, -0.1)
        assert placed.placement.pose.yaw.value == 0.5
    assert next(b for b in program.scenes["tabletop"].bodies if b.name == "block").placement.pose.position.values == (
        0.45,
        0.0,
    )
    with pytest.raises(InputError, match="no scene or task `kitchen`"):
        program.with_start("kitchen", "block", at=(0.4, 0))


def test_with_start_poses_places_level_bodies_on_the_table_and_tilted_ones_at_their_pose(program) -> None:  # type: ignore[no-untyped-def]
    level = np.eye(4)
    level[:3, 3] = (0.5, 0.1, 0.025)
    c, s = math.cos(0.3), math.sin(0.3)
    level[:2, :2] = [[c, -s], [s, c]]
    tilted = np.eye(4)
    tilted[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # turned 90 deg about x
    tilted[:3, 3] = (0.3, -0.4, 0.05)
    moved = program.with_start_poses("a_push", {"block": level, "stick": tilted, "ghost": np.eye(4)})
    bodies = {b.name: b for b in moved.scenes["tabletop"].bodies}
    block = bodies["block"].placement
    assert block.on_table and block.pose.position.values == pytest.approx((0.5, 0.1))
    assert block.pose.yaw.value == pytest.approx(0.3)
    stick = bodies["stick"].placement
    assert not stick.on_table and stick.pose.position.values == pytest.approx((0.3, -0.4, 0.05))
    assert stick.pose.rpy.values == pytest.approx((math.pi / 2, 0, 0))
    assert bodies["hook"] == next(b for b in program.scenes["tabletop"].bodies if b.name == "hook")


def test_a_changed_goal_is_solved(program) -> None:  # type: ignore[no-untyped-def]
    import vkgl

    plan = vkgl.solve(program.with_goal("a_push", "block", at=(0.62, 0.0), yaw=0.0))
    assert plan.status == "solved"
    assert plan.final["block"][:2, 3] == pytest.approx((0.62, 0.0), abs=0.01)


# ---------------------------------------------------------------- bodies on physical joints

KITCHEN = """\
use stdlib.robots.panda
use stdlib.affordances.drawer
use stdlib.affordances.door
use stdlib.bodies.block

scene kitchen {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    drawer : Drawer on table at (0.45, -0.2) m yaw 0deg
    door : Door open 30deg on table at (0.5, 0.35) m yaw 180deg
    block : Block on table at (0.2, -0.45) m yaw 0deg
}

task open_drawer {
    scene kitchen
    goal drawer open 5 cm within 1 cm
}
"""


@pytest.fixture(scope="module")
def kitchen():  # type: ignore[no-untyped-def]
    return compile_source(KITCHEN, "kitchen.vkg")


def test_with_goal_open_makes_a_joint_goal_of_the_joints_kind(kitchen) -> None:  # type: ignore[no-untyped-def]
    wider = kitchen.with_goal("open_drawer", "drawer", open=0.12, within=0.005)
    (goal,) = wider.task().goals
    assert (goal.opening.value, goal.opening.unit) == (0.12, "m") and goal.opening_tolerance() == 0.005
    assert goal.position is None and goal.yaw is None
    kept = kitchen.with_goal("open_drawer", "drawer", open=0.1).task().goals[0]
    assert kept.opening_tolerance() == pytest.approx(0.01)  # the replaced joint goal's tolerance
    door = kitchen.with_goal("open_drawer", "door", open=math.radians(45)).task().goals
    assert [g.body.name for g in door] == ["drawer", "door"]  # added: the task had no goal on the door
    assert (door[1].opening.unit, door[1].opening_tolerance()) == ("rad", pytest.approx(DEFAULT_TOL_YAW))
    back = kitchen.with_goal("open_drawer", "drawer", at=(0.5, -0.2)).task().goals[0]
    assert back.opening is None and back.position.values == (0.5, -0.2)  # a pose goal replaces the joint goal


def test_with_goal_open_refuses_what_cannot_be_a_joint_goal(kitchen) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InputError, match="`block` has no physical joint to open: its type `Block` declares no"):
        kitchen.with_goal("open_drawer", "block", open=0.05)
    with pytest.raises(InputError, match="takes no position or heading"):
        kitchen.with_goal("open_drawer", "drawer", open=0.05, at=(0.5, 0))
    with pytest.raises(InputError, match="one positive number of m"):
        kitchen.with_goal("open_drawer", "drawer", open=0.05, within=(0.01, 0.05))
    with pytest.raises(InputError, match="one positive number of rad"):
        kitchen.with_goal("open_drawer", "door", open=0.5, within=-0.1)
    with pytest.raises(InputError, match="finite number of m"):
        kitchen.with_goal("open_drawer", "drawer", open=math.nan)
    with pytest.raises(InputError, match=r"tolerances of a pose goal are \(metres, radians\)"):
        kitchen.with_goal("open_drawer", "block", at=(0.2, -0.45), within=0.01)


def test_a_joint_goal_from_python_is_solved(kitchen) -> None:  # type: ignore[no-untyped-def]
    import vkgl

    plan = vkgl.solve(kitchen.with_goal("open_drawer", "drawer", open=0.08, within=0.005))
    assert plan.status == "solved", plan.reason
    assert plan.problem.bodies["drawer"].joint_state(plan.final["drawer"]) == pytest.approx(0.08, abs=0.005)


def test_with_start_poses_keeps_a_jointed_body_on_its_anchor_and_starts_it_open(kitchen) -> None:  # type: ignore[no-untyped-def]
    from vkgl.lang.ir.geometry import joint_pose, scene_body_anchor, scene_body_pose

    scene = kitchen.scenes["kitchen"]
    placed = {b.name: b for b in scene.bodies}
    drawer, door = kitchen.bodies["Drawer"], kitchen.bodies["Door"]
    pulled = joint_pose(drawer.joint, scene_body_anchor(scene, placed["drawer"], drawer), 0.07)
    swung = joint_pose(door.joint, scene_body_anchor(scene, placed["door"], door), math.radians(50))
    moved = kitchen.with_start_poses("open_drawer", {"drawer": pulled, "door": swung})
    bodies = {b.name: b for b in moved.scenes["kitchen"].bodies}
    assert bodies["drawer"].placement == placed["drawer"].placement  # the slide stays where it is fixed
    assert (bodies["drawer"].opening.value, bodies["drawer"].opening.unit) == (pytest.approx(0.07), "m")
    assert bodies["door"].placement == placed["door"].placement
    assert bodies["door"].start_opening() == pytest.approx(math.radians(50))
    new_scene = moved.scenes["kitchen"]
    assert scene_body_pose(new_scene, bodies["drawer"], drawer) == pytest.approx(pulled, abs=1e-12)
    assert scene_body_pose(new_scene, bodies["door"], door) == pytest.approx(swung, abs=1e-12)
    assert scene_body_pose(scene, placed["door"], door) == pytest.approx(
        joint_pose(door.joint, scene_body_anchor(scene, placed["door"], door), math.radians(30)), abs=1e-12
    )  # `open 30deg` as written
    beyond = joint_pose(drawer.joint, scene_body_anchor(scene, placed["drawer"], drawer), 0.3002)
    past = moved.with_start_poses("open_drawer", {"drawer": beyond})
    assert next(b for b in past.scenes["kitchen"].bodies if b.name == "drawer").start_opening() == 0.3  # its stop


def test_with_keep_out_adds_a_keep_out_region_and_refuses_what_is_no_region(program) -> None:  # type: ignore[no-untyped-def]
    kept = program.with_keep_out("a_push", [(0.5, 0.06), (0.7, 0.3)], body="block")
    (keep,) = kept.task().keep_out
    assert keep.body.name == "block" and keep.region.kind == "box" and program.task().keep_out == []
    with pytest.raises(InputError, match="has no body `blok`"):
        program.with_keep_out("a_push", [(0.5, 0.06), (0.7, 0.3)], body="blok")
    with pytest.raises(InputError, match="not a region"):
        program.with_keep_out("a_push", [(0.7, 0.06), (0.5, 0.3)])
