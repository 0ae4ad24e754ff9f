"""Building an Arm: from a robot declaration (its errors), from a scene, from the stdlib Panda module."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import STDLIB
from panda_fixtures import FINGERTIP, URDF, fingertip_at, panda_robot

from vkgl.errors import InputError
from vkgl.lang.ir.nodes import Module, Placement, Pose, Quantity, Ref, Scene, SceneBody, SceneRobot, Vector
from vkgl.lang.ir.program import Program
from vkgl.robot import Arm, arm_for_scene


def test_load_errors_say_what_is_wrong(tmp_path) -> None:
    with pytest.raises(InputError, match=r"no effector `gripper`.*fingertip"):
        Arm.load(panda_robot(), "gripper", np.eye(4))
    with pytest.raises(InputError, match="URDF file not found"):
        Arm.load(panda_robot(urdf=str(tmp_path / "missing.urdf")), "fingertip", np.eye(4))
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'/>")
    with pytest.raises(InputError, match="DART cannot load"):
        Arm.load(panda_robot(urdf=str(broken)), "fingertip", np.eye(4))
    robot = panda_robot().model_copy(update={"effectors": [fingertip_at("panda_palm", 0.1)]})
    with pytest.raises(InputError, match="no link `panda_palm`"):
        Arm.load(robot, "fingertip", np.eye(4))


def test_arm_for_scene_places_the_scene_robot() -> None:
    robot = panda_robot()
    pose = Pose(position=Vector(values=(0.1, 0.0, 0.0)), yaw=Quantity(value=math.pi / 2))
    scene = Scene(
        name="tabletop",
        robots=[SceneRobot(name="arm", type=Ref(name="Panda"), pose=pose)],
        bodies=[SceneBody(name="b", type=Ref(name="Block"), placement=Placement(on_table=True, pose=pose))],
    )
    program = Program(root=Module(path="t.vkg"), robots={"Panda": robot}, scenes={"tabletop": scene})
    for placed in (arm_for_scene(program, scene), arm_for_scene(program, "tabletop", "arm", "fingertip")):
        np.testing.assert_allclose(placed.base, pose.matrix())
        assert placed.effector == "fingertip"
    with pytest.raises(InputError, match="no robot `other`"):
        arm_for_scene(program, scene, "other")
    with pytest.raises(InputError, match="no scene `nowhere`"):
        arm_for_scene(program, "nowhere")


def test_the_stdlib_panda_module_compiles_to_this_arm() -> None:
    from vkgl.lang.compiler import compile_file

    program = compile_file(str(STDLIB / "robots" / "panda.vkg"))
    robot = program.robots["Panda"]
    assert robot.effector("fingertip").offset.position.values == pytest.approx((0, 0, FINGERTIP))
    assert program.root.doc
    arm = Arm.load(robot, "fingertip", np.eye(4))
    assert arm.urdf == str(URDF.resolve())
