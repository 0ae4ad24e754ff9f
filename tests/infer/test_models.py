"""The four constraint models: fits recover known parameters, signs follow the push, posteriors pick the type."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vkgl.infer.data import edge_data
from vkgl.infer.ending import END_WINDOW
from vkgl.infer.select import end_offset, infer_edge, moved_off_start

RNG = np.random.default_rng(7)


def _edge(T: np.ndarray, noise_p: float = 0.0, noise_r: float = 0.0, rotations: bool = True):
    """EdgeData of a trajectory of 4x4 poses, relative to its first pose, with optional noise."""
    n = len(T)
    p = T[:, :3, 3] + RNG.normal(scale=noise_p, size=(n, 3)) * (noise_p > 0)
    rot = Rotation.from_matrix(T[:, :3, :3])
    if noise_r > 0:
        rot = rot * Rotation.from_rotvec(RNG.normal(scale=noise_r, size=(n, 3)))
    has_rot = np.full(n, rotations)
    return edge_data(p, rot, has_rot)


def _slide(axis, length=0.2, n=80) -> np.ndarray:
    T = np.tile(np.eye(4), (n, 1, 1))
    T[:, :3, 3] = np.outer(np.linspace(0, length, n), axis)
    return T


def _turn(axis, center, angle=float(np.deg2rad(60)), n=80) -> np.ndarray:  # noqa: B008 - a constant
    axis, center = np.asarray(axis, float), np.asarray(center, float)
    rot = Rotation.from_rotvec(np.outer(np.linspace(0, angle, n), axis)).as_matrix()
    T = np.tile(np.eye(4), (n, 1, 1))
    T[:, :3, :3] = rot
    T[:, :3, 3] = center - rot @ center
    return T


def test_prismatic_recovers_axis_and_starts_at_origin() -> None:
    axis = np.array([0.6, 0.0, 0.8])
    edge = infer_edge(_edge(_slide(axis), 0.002, np.deg2rad(0.5)), relative=True)
    assert edge.type == "prismatic"
    assert edge.posterior["prismatic"] > 0.99
    assert np.degrees(np.arccos(edge.params["axis"] @ axis)) < 1.0
    assert np.linalg.norm(edge.params["origin"]) < 0.005


def test_prismatic_axis_points_where_the_body_went() -> None:
    axis = np.array([0.0, -1.0, 0.0])
    edge = infer_edge(_edge(_slide(axis)), relative=True)
    assert edge.params["axis"] @ axis > 0.999
    states = edge.best.states
    assert states[-1] > states[0] and states[0] == pytest.approx(0.0, abs=1e-9)


def test_revolute_recovers_axis_and_centre_with_angle_increasing() -> None:
    axis = np.array([0.0, 0.0, -1.0])
    center = np.array([0.05, -0.10, 0.0])
    edge = infer_edge(_edge(_turn(axis, center), 0.002, np.deg2rad(1)), relative=True)
    assert edge.type == "revolute"
    assert edge.params["axis"] @ axis > np.cos(np.deg2rad(1.0))
    d = edge.params["center"] - center
    assert np.linalg.norm(d - (d @ axis) * axis) < 0.005
    assert edge.best.states[-1] == pytest.approx(np.deg2rad(60), abs=np.deg2rad(4))  # two noisy samples


def test_revolute_from_positions_alone() -> None:
    axis = np.array([0.0, 0.0, 1.0])
    center = np.array([0.3, 0.0, 0.0])
    edge = infer_edge(_edge(_turn(axis, center, np.deg2rad(80)), 0.001, rotations=False), relative=True)
    assert edge.type == "revolute"
    assert abs(edge.params["axis"] @ axis) > 0.999
    d = edge.params["center"] - center
    assert np.linalg.norm(d - (d @ axis) * axis) < 0.01


def test_a_body_turning_in_place_is_revolute_from_its_orientation() -> None:
    """Positions do not move (the axis goes through the body's origin): orientations tell."""
    edge = infer_edge(_edge(_turn([0, 0, 1], [0, 0, 0]), 0.0005, np.deg2rad(0.5)), relative=True)
    assert edge.type == "revolute"
    assert edge.params["axis"] @ np.array([0, 0, 1.0]) > 0.999
    assert np.linalg.norm(edge.params["center"][:2]) < 0.01


def test_fixed_when_nothing_moves_beyond_noise() -> None:
    T = np.tile(np.eye(4), (80, 1, 1))
    edge = infer_edge(_edge(T, 0.003, np.deg2rad(1)), relative=True)
    assert edge.type == "fixed"


def test_free_when_no_joint_explains_the_motion() -> None:
    n = 80
    s = np.linspace(0, 1, n)
    T = np.tile(np.eye(4), (n, 1, 1))
    T[:, :3, 3] = np.column_stack([0.3 * s, 0.2 * np.sin(4 * s), 0.15 * s**2])
    tumble = Rotation.from_rotvec(np.outer(s, [1.2, 0, 0])) * Rotation.from_rotvec(np.outer(s**2, [0, 1.0, 0.5]))
    T[:, :3, :3] = tumble.as_matrix()
    edge = infer_edge(_edge(T, 0.001, np.deg2rad(0.5)), relative=True)
    assert edge.type == "free"


def test_a_fixed_action_keeps_its_pose_in_the_body_frame() -> None:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_euler("z", 30, degrees=True).as_matrix()
    pose[:3, 3] = (-0.05, 0.02, 0.0)
    edge = infer_edge(_edge(np.tile(pose, (60, 1, 1)), 0.001, np.deg2rad(0.5)), relative=False)
    assert edge.type == "fixed"
    assert np.allclose(edge.params["pose"][:3, 3], pose[:3, 3], atol=0.002)
    assert np.allclose(edge.params["pose"][:3, :3], pose[:3, :3], atol=0.01)


def test_outliers_do_not_bend_the_axis() -> None:
    axis = np.array([1.0, 0.0, 0.0])
    T = _slide(axis, n=100)
    bad = RNG.choice(100, size=5, replace=False)
    T[bad, :3, 3] += RNG.uniform(-0.2, 0.2, (5, 3))
    T[bad, :3, :3] = Rotation.random(5, random_state=1).as_matrix()
    edge = infer_edge(_edge(T, 0.001, np.deg2rad(0.5)), relative=True)
    assert edge.type == "prismatic"
    assert np.degrees(np.arccos(edge.params["axis"] @ axis)) < 0.5


def test_posterior_is_a_distribution_over_the_four_types() -> None:
    edge = infer_edge(_edge(_slide([0, 1, 0]), 0.002), relative=True)
    assert set(edge.posterior) == {"fixed", "prismatic", "revolute", "free"}
    assert sum(edge.posterior.values()) == pytest.approx(1.0)
    assert all(0.0 <= p <= 1.0 for p in edge.posterior.values())


def _steady_slide(length: float, seconds: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """Poses of a body slid `length` m along x at a steady speed for `seconds` s, at 50 Hz; and the times."""
    t = np.arange(0.0, seconds + 1e-9, 0.02)
    T = np.tile(np.eye(4), (len(t), 1, 1))
    T[:, 0, 3] = length * t / seconds
    return T, t


def test_a_slide_of_three_tolerances_is_not_fixed() -> None:
    # a 16 x 30 x 6 cm slab pushed with 1 N slides 3.7 cm in 3 s; its state costs the prismatic model more
    # nats than its residuals cost the at-rest one, so by the scores alone the body stayed where it was ...
    poses, t = _steady_slide(0.03)
    data = _edge(poses, 0.0002, np.deg2rad(0.05))
    assert infer_edge(data, relative=True).type == "fixed"
    # ... but its pose ended 3 tolerances from its start: it moved, and the slide is the MAP motion
    edge = infer_edge(data, relative=True, t=t)
    assert edge.type == "prismatic" and edge.posterior["fixed"] == 0.0
    assert edge.params["axis"] @ np.array([1.0, 0.0, 0.0]) > 0.999
    assert edge.best.states[-1] == pytest.approx(0.03, abs=0.002)


def test_a_body_that_stays_within_its_tolerance_is_still_fixed() -> None:
    poses, t = _steady_slide(0.0)
    assert infer_edge(_edge(poses, 0.003, np.deg2rad(1.0)), relative=True, t=t).type == "fixed"
    creep, t = _steady_slide(0.012)  # a 1.2 cm creep ends inside twice the 1 cm tolerance
    assert infer_edge(_edge(creep, 0.0002), relative=True, t=t).type == "fixed"


def _at_rest_trials(count: int, noise_p: float, noise_r: float) -> list:
    """`count` seeded trials of 3 s at 50 Hz of a body that never moved, seen with white noise."""
    t = np.arange(0.0, 3.0 + 1e-9, 0.02)
    data = []
    for seed in range(count):
        rng = np.random.default_rng(seed)
        rot = Rotation.from_rotvec(rng.normal(scale=noise_r, size=(t.size, 3)))
        data.append((edge_data(rng.normal(scale=noise_p, size=(t.size, 3)), rot, np.ones(t.size, bool)), t))
    return data


@pytest.mark.parametrize(("noise_p", "noise_r"), [(0.01, np.deg2rad(0.25)), (0.0005, np.deg2rad(2.0))])
def test_a_body_at_rest_with_noise_at_its_tolerance_rarely_ends_off_its_start(noise_p, noise_r) -> None:
    # the start (a median of 5 samples) errs by half a tolerance, shared by the whole end window: a median of the
    # window's distances kept that error and called 12 % of these trials moved (7 % in orientation); the window's
    # own position does not (measured 1.0 % and 0.1 % over 1,000 seeds; docs/inference.md, "Did the body move?")
    trials = _at_rest_trials(300, noise_p, noise_r)
    moved = sum(moved_off_start(data, t) for data, t in trials)
    assert moved <= 9  # 3 %: a third of the old rate


def test_the_end_offset_of_a_steady_slide_is_its_length_at_the_window() -> None:
    poses, t = _steady_slide(0.03)
    offset = end_offset(_edge(poses), t)
    assert offset is not None
    distance, angle = offset
    assert distance == pytest.approx(0.03 * (3.0 - END_WINDOW / 2) / 3.0, abs=1e-3)  # the window's middle
    assert angle == pytest.approx(0.0, abs=1e-6)
