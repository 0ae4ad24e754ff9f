"""The arm: the stdlib Panda URDF under DART, forward and inverse kinematics, reach.

The forward kinematics is checked against an independent numpy composition of
Franka's published modified-DH table; IK and reach are checked by what they
promise (round trips, limits, what is inside and outside the reach).
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vkgl.errors import InputError
from vkgl.lang.ir import (
    Effector,
    Module,
    Placement,
    Pose,
    Quantity,
    Ref,
    Robot,
    Scene,
    SceneBody,
    SceneRobot,
    Vector,
)
from vkgl.lang.program import Program
from vkgl.robot import Arm, arm_for_scene, load_skeleton

from conftest import STDLIB

URDF = STDLIB / "robots" / "panda.urdf"

# Franka's published modified-DH table: (a_{i-1}, d_i, alpha_{i-1}), joints 1..7 and the flange.
DH = [
    (0.0, 0.333, 0.0),
    (0.0, 0.0, -math.pi / 2),
    (0.0, 0.316, math.pi / 2),
    (0.0825, 0.0, math.pi / 2),
    (-0.0825, 0.384, -math.pi / 2),
    (0.0, 0.0, math.pi / 2),
    (0.088, 0.0, math.pi / 2),
    (0.0, 0.107, 0.0),
]
LOWER = [-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973]
UPPER = [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973]
FINGERTIP = 0.103  # m along the hand's z axis


def fingertip_at(link: str, offset: float) -> Effector:
    return Effector(name="fingertip", link=link, offset=Pose(position=Vector(values=(0, 0, offset), unit="cm")))


def panda_robot(urdf: str = str(URDF), offset: float = FINGERTIP) -> Robot:
    """The IR of stdlib/robots/panda.vkg (built by hand, so these tests do not depend on the parser)."""
    return Robot(
        name="Panda",
        urdf="panda.urdf",
        urdf_resolved=urdf,
        effectors=[fingertip_at("panda_hand", offset)],
    )


@pytest.fixture(scope="module")
def arm() -> Arm:
    return Arm.load(panda_robot(), "fingertip", np.eye(4))


def transform(rotation: np.ndarray | None = None, translation: tuple[float, float, float] = (0, 0, 0)) -> np.ndarray:
    m = np.eye(4)
    if rotation is not None:
        m[:3, :3] = rotation
    m[:3, 3] = translation
    return m


def dh_effector(q: np.ndarray) -> np.ndarray:
    """The effector frame from the DH table: links, flange, hand at -45 deg, fingertip, Rx(180 deg)."""
    pose = np.eye(4)
    for (a, d, alpha), theta in zip(DH, [*q, 0.0]):
        pose = (
            pose
            @ transform(Rotation.from_euler("x", alpha).as_matrix())
            @ transform(translation=(a, 0, 0))
            @ transform(Rotation.from_euler("z", theta).as_matrix())
            @ transform(translation=(0, 0, d))
        )
    hand = pose @ transform(Rotation.from_euler("z", -math.pi / 4).as_matrix())
    return hand @ transform(translation=(0, 0, FINGERTIP)) @ transform(Rotation.from_euler("x", math.pi).as_matrix())


def hand_down(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """An effector pose with z up (the hand pointing down) at (x, y, z), turned by `yaw`."""
    return transform(Rotation.from_euler("z", yaw).as_matrix(), (x, y, z))


def pose_error(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """(position error m, rotation angle rad) between two poses."""
    angle = Rotation.from_matrix(a[:3, :3] @ b[:3, :3].T).magnitude()
    return float(np.linalg.norm(a[:3, 3] - b[:3, 3])), float(angle)


# ---------------------------------------------------------------- the URDF


def test_dart_loads_the_urdf_with_the_published_joints_and_limits() -> None:
    skeleton = load_skeleton(URDF)
    names = [skeleton.getBodyNode(i).getName() for i in range(skeleton.getNumBodyNodes())]
    assert [f"panda_link{i}" for i in range(9)] + ["panda_hand"] == names
    assert skeleton.getNumDofs() == 7
    assert [skeleton.getDof(i).getName() for i in range(7)] == [f"panda_joint{i}" for i in range(1, 8)]
    np.testing.assert_allclose(skeleton.getPositionLowerLimits(), LOWER)
    np.testing.assert_allclose(skeleton.getPositionUpperLimits(), UPPER)
    assert all(skeleton.getBodyNode(i).getMass() > 0 for i in range(skeleton.getNumBodyNodes()))
    assert all(skeleton.getBodyNode(i).getNumShapeNodes() > 0 for i in range(8))  # links 0-7 have shapes
    assert 15.0 < skeleton.getMass() < 25.0  # the real arm weighs about 18 kg


def test_fk_matches_the_dh_table_at_zero_and_at_random_joints(arm: Arm) -> None:
    rng = np.random.default_rng(7)
    for q in [np.zeros(7), *rng.uniform(LOWER, UPPER, (20, 7))]:
        np.testing.assert_allclose(arm.fk(q), dh_effector(q), atol=1e-9)


def test_fk_at_zero_is_the_known_panda_pose(arm: Arm) -> None:
    # All joints at zero: the arm stands straight up, the flange 0.926 m high and 8.8 cm forward,
    # pointing down; the effector frame is 10.3 cm lower with its z axis up.
    pose = arm.fk(np.zeros(7))
    np.testing.assert_allclose(pose[:3, 3], [0.088, 0.0, 0.926 - FINGERTIP], atol=1e-9)
    np.testing.assert_allclose(pose[:3, 2], [0, 0, 1], atol=1e-9)


def test_fk_applies_the_base_pose() -> None:
    base = transform(Rotation.from_euler("z", 90, degrees=True).as_matrix(), (0.1, -0.2, 0.05))
    moved = Arm.load(panda_robot(), "fingertip", base)
    q = np.array([0.3, -0.2, 0.1, -2.0, 0.2, 1.9, 0.5])
    np.testing.assert_allclose(moved.fk(q), base @ dh_effector(q), atol=1e-9)


def test_jacobian_is_the_derivative_of_fk(arm: Arm) -> None:
    q = np.array([0.2, -0.4, 0.3, -2.1, 0.1, 1.8, 0.4])
    jac = arm.jacobian(q)
    step = 1e-6
    for k in range(7):
        dq = np.zeros(7)
        dq[k] = step
        ahead, behind = arm.fk(q + dq), arm.fk(q - dq)
        np.testing.assert_allclose(jac[:3, k], (ahead[:3, 3] - behind[:3, 3]) / (2 * step), atol=1e-6)
        spin = Rotation.from_matrix(ahead[:3, :3] @ behind[:3, :3].T).as_rotvec() / (2 * step)
        np.testing.assert_allclose(jac[3:, k], spin, atol=1e-6)


def test_home_is_a_ready_pose_with_the_hand_down(arm: Arm) -> None:
    assert arm.joint_names == [f"panda_joint{i}" for i in range(1, 8)]
    assert np.all(arm.lower <= arm.home) and np.all(arm.home <= arm.upper)
    pose = arm.fk(arm.home)
    np.testing.assert_allclose(pose[:3, :3], np.eye(3), atol=1e-4)  # z up, x forward
    assert abs(pose[1, 3]) < 1e-4 and 0.3 < pose[0, 3] < 0.7 and pose[2, 3] > 0.2


# ---------------------------------------------------------------- inverse kinematics


def test_ik_round_trips_random_reachable_targets_within_the_limits(arm: Arm) -> None:
    rng = np.random.default_rng(11)
    for q in rng.uniform(LOWER, UPPER, (25, 7)):
        target = arm.fk(q)
        found = arm.ik(target)
        assert found is not None, f"no IK for the FK of {q}"
        assert np.all(arm.lower <= found) and np.all(found <= arm.upper)
        position, angle = pose_error(arm.fk(found), target)
        assert position < 1e-3 and angle < math.radians(0.5)


def test_ik_solves_hand_down_pushes_all_over_the_table(arm: Arm) -> None:
    # (how fast: bench/bench_robot.py)
    rng = np.random.default_rng(3)
    for _ in range(40):
        radius, azimuth, yaw = rng.uniform(0.3, 0.75), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi)
        target = hand_down(radius * math.cos(azimuth), radius * math.sin(azimuth), 0.025, yaw)
        found = arm.ik(target)
        assert found is not None
        position, angle = pose_error(arm.fk(found), target)
        assert position < 1e-3 and angle < math.radians(0.5)


def test_ik_warm_started_follows_a_path_without_jumps(arm: Arm) -> None:
    q = arm.ik(hand_down(0.45, 0.0, 0.03))
    for step in range(1, 21):
        nxt = arm.ik(hand_down(0.45 + 0.01 * step, 0.0, 0.03), q0=q)
        assert nxt is not None
        assert np.max(np.abs(nxt - q)) < 0.2  # 1 cm of motion: a small joint step, not another branch
        q = nxt


def test_ik_with_yaw_free_matches_position_and_z_axis_only(arm: Arm) -> None:
    tilted = transform(Rotation.from_euler("xz", [20, 70], degrees=True).as_matrix(), (0.5, 0.15, 0.1))
    found = arm.ik(tilted, yaw_free=True)
    assert found is not None
    pose = arm.fk(found)
    assert np.linalg.norm(pose[:3, 3] - tilted[:3, 3]) < 1e-3
    assert math.acos(min(1.0, pose[:3, 2] @ tilted[:3, 2])) < math.radians(0.5)
    # a hand-down target at any yaw is the same problem when the yaw is free
    for yaw in (0.0, 1.0, 2.5, -2.0):
        found = arm.ik(hand_down(0.55, -0.1, 0.03, yaw), yaw_free=True)
        assert found is not None
        assert arm.fk(found)[2, 2] > math.cos(math.radians(0.5))


def test_ik_of_an_unreachable_target_is_none_and_quick(arm: Arm) -> None:
    start = time.perf_counter()
    assert arm.ik(hand_down(2.0, 0.0, 0.03)) is None
    assert time.perf_counter() - start < 0.05  # rejected by its distance, without optimising (which takes ~0.1 s)
    # within the chain's length but beyond a hand-down pose's reach: the optimiser must say no
    start = time.perf_counter()
    assert arm.ik(hand_down(0.95, 0.0, 0.03), yaw_free=True) is None
    assert time.perf_counter() - start < 1.0


def test_ik_is_deterministic() -> None:
    import vkgl.robot.arm

    one = Arm.load(panda_robot(), "fingertip", np.eye(4))
    vkgl.robot.arm._READY_POSES.clear()  # compute the ready pose again, not from the cache
    two = Arm.load(panda_robot(), "fingertip", np.eye(4))
    target = hand_down(0.6, -0.2, 0.05, 0.7)
    np.testing.assert_array_equal(one.home, two.home)
    np.testing.assert_array_equal(one.ik(target), two.ik(target))


# ---------------------------------------------------------------- reach


def test_reach_at_table_height_is_the_pandas(arm: Arm) -> None:
    r_min, r_max = arm.reach(0.03)
    # Franka quotes 855 mm of reach, measured from joint 2's axis (0.333 m high)
    assert math.hypot(r_max, 0.333 - 0.03) == pytest.approx(0.855, abs=0.02)
    assert 0.05 < r_min < 0.2
    assert arm.reach(0.0302) == (r_min, r_max)  # cached to the mm


def test_reach_interval_is_what_ik_reaches(arm: Arm) -> None:
    height = 0.03
    r_min, r_max = arm.reach(height)
    rng = np.random.default_rng(5)
    for _ in range(20):
        radius, azimuth = rng.uniform(r_min, r_max), rng.uniform(-math.pi, math.pi)
        target = hand_down(radius * math.cos(azimuth), radius * math.sin(azimuth), height)
        assert arm.ik(target, yaw_free=True) is not None
    for azimuth in (0.0, 2.0, math.pi, -1.0):
        for radius in (r_max + 0.01, r_min - 0.01):
            point = (radius * math.cos(azimuth), radius * math.sin(azimuth), height)
            assert arm.ik(hand_down(*point), yaw_free=True) is None
    # the bisection along one azimuth agrees with the optimised extremes (IK's 1 mm tolerance aside)
    bisected = arm.radial_interval(height, 0.5)
    assert bisected is not None
    assert bisected[0] == pytest.approx(r_min, abs=0.005) and bisected[1] == pytest.approx(r_max, abs=0.005)


def test_reachable_uses_the_reach_around_the_base() -> None:
    base = transform(translation=(0.2, 0.1, 0.0))
    moved = Arm.load(panda_robot(), "fingertip", base)
    assert moved.reachable((0.2 + 0.5, 0.1, 0.03))
    assert moved.reachable((0.2, 0.1 - 0.6, 0.03))
    assert not moved.reachable((0.2 + 0.9, 0.1, 0.03))
    assert not moved.reachable((0.2 + 0.02, 0.1, 0.03))
    assert not moved.reachable((0.2, 0.1, 1.5))
    assert moved.reach(1.5) == (0.0, 0.0)


def test_reach_depends_on_the_effector_offset(arm: Arm) -> None:
    longer = Arm.load(panda_robot(offset=0.2), "fingertip", np.eye(4))
    # hand down, an effector 9.7 cm further along the approach axis holds the hand 9.7 cm higher:
    # its reach at table height is the fingertip's 9.7 cm above it (not the cached fingertip's)
    np.testing.assert_allclose(longer.reach(0.03), arm.reach(0.03 + 0.097), atol=0.003)
    assert abs(longer.reach(0.03)[0] - arm.reach(0.03)[0]) > 0.01


# ---------------------------------------------------------------- errors and scenes


def test_load_errors_say_what_is_wrong(tmp_path) -> None:
    with pytest.raises(InputError, match="no effector `gripper`.*fingertip"):
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
    compiler = pytest.importorskip("vkgl.lang.compiler")
    program = compiler.compile_file(str(STDLIB / "robots" / "panda.vkg"))
    robot = program.robots["Panda"]
    assert robot.effector("fingertip").offset.position.values == pytest.approx((0, 0, FINGERTIP))
    assert program.root.doc
    arm = Arm.load(robot, "fingertip", np.eye(4))
    assert arm.urdf == str(URDF.resolve())
