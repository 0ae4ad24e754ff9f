"""Exploration in DART on reduced grids: what the simulated pushes and grasps do to the stdlib bodies."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from sim_bodies import stdlib_body, with_durations, with_joint_limits, with_policy

from vkgl.formats.trials import Trials
from vkgl.lang.ir.nodes import Body
from vkgl.sim.explore import explore


def yaw_deg(T: np.ndarray) -> float:
    """The heading of a 4x4 pose, degrees."""
    return float(np.degrees(np.arctan2(T[1, 0], T[0, 0])))


def last(trials: Trials, i: int) -> np.ndarray:
    """The last recorded body pose of trial i."""
    return trials.T_ow[i, trials.samples(i) - 1]


def fixed_point(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """The point of the table plane that a planar motion start -> end leaves where it was (its centre)."""
    motion = end @ np.linalg.inv(start)
    return np.linalg.solve(np.eye(2) - motion[:2, :2], motion[:2, 3])


# `block_pushes` (tests/conftest.py): the Block pushed at the 9 points of its -x face (its grid, one face), 2 s
# each, explored once for this file and tests/infer/test_ending.py


def test_every_block_trial_ran_and_was_sampled_at_50_hz(block_pushes: Trials) -> None:
    assert len(block_pushes) == 9 and block_pushes.ok.all()
    assert block_pushes.samples(0) == 101
    assert np.allclose(np.diff(block_pushes.t[0]), 0.02)


def test_push_through_the_face_centre_slides_the_block_along_the_normal(block_pushes: Trials) -> None:
    start, end = block_pushes.T_ow[4, 0], last(block_pushes, 4)
    moved = end[:3, 3] - start[:3, 3]
    assert moved[0] > 0.03  # along the inward normal of -x
    assert abs(moved[1]) < 0.002 and abs(moved[2]) < 0.001
    assert abs(yaw_deg(end) - yaw_deg(start)) < 2.0
    contact_path = block_pushes.T_ro[4, 5 : block_pushes.samples(4), :3, 3]
    assert np.ptp(contact_path, axis=0).max() < 0.003  # the fingertip stays where it touched


def test_push_near_either_end_turns_the_block_about_a_point_near_the_other_end(block_pushes: Trials) -> None:
    for i, sign in ((0, -1.0), (8, 1.0)):  # contact at y < 0, then at y > 0
        start, end = block_pushes.T_ow[i, 0], last(block_pushes, i)
        turn = yaw_deg(end) - yaw_deg(start)
        assert abs(turn) > 10.0
        assert np.sign(turn) == -sign  # pushing +x at the +y end turns it clockwise
        centre = np.linalg.solve(start, np.append(fixed_point(start, end), [start[2, 3], 1.0]))[:3]
        assert -sign * centre[1] > 0.08  # beyond 8 cm from the middle, on the far side of the contact
        assert abs(centre[0]) < 0.05


def one_push(body: Body) -> Body:
    """A jointed body with its pushes cut to the centre of the face, and its pull kept."""
    _, pull = body.explores
    return body.model_copy(update={"explores": [with_policy(body, steps=1).explores[0], pull]})


def test_drawer_is_pushed_shut_and_pulled_open_from_both_ends_of_its_slide() -> None:
    drawer = with_durations(with_joint_limits(one_push(stdlib_body("Drawer")), 0.0, 0.02), 1.0)
    trials = explore(drawer, jobs=2)
    # pushes (the handle's bar, its outer face) from the closed end, then from the open end; then the pulls (behind
    # the bar's middle and its overhang), likewise
    assert list(trials.force[:, 0]) == [-1.0, -1.0, 1.0, 1.0, 1.0, 1.0]
    assert np.allclose(trials.contact, [[0.20, 0, 0]] * 2 + [[0.19, 0, 0], [0.19, 0.105, 0]] * 2)
    closed = trials.T_ow[0, 0]  # the body at the lower limit of its slide
    opening = []
    for i in range(6):
        T = trials.T_ow[i, : trials.samples(i)]
        assert np.allclose(T[:, :3, :3], np.eye(3), atol=1e-9)
        assert np.ptp(T[:, 1, 3]) < 1e-9 and np.ptp(T[:, 2, 3]) < 1e-9  # only along its slide
        opening.append(T[:, 0, 3] - closed[0, 3])
    assert opening[0] == pytest.approx(0.0, abs=1e-4)  # pushed against its closed stop: does not move
    assert opening[1][0] == pytest.approx(0.02, abs=1e-4) and opening[1][-1] == pytest.approx(0.0, abs=0.001)  # shut
    for pulled in (2, 3):  # at either frame
        assert opening[pulled][-1] == pytest.approx(0.02, abs=0.001)  # pulled open to its upper limit ...
        assert np.abs(opening[pulled][-10:] - 0.02).max() < 0.001  # ... where it stays
        hooked = trials.T_ro[pulled, : trials.samples(pulled), :3, 3]
        assert np.ptp(hooked, axis=0).max() < 0.002  # the fingertip stays hooked behind the bar
    for stopped in (4, 5):
        assert np.abs(opening[stopped] - 0.02).max() < 1e-3  # pulled against its open stop: does not move


def test_door_is_pushed_shut_and_pulled_open_about_its_hinge() -> None:
    door = with_durations(one_push(stdlib_body("Door")), 2.0)
    trials = explore(door, jobs=2)
    assert list(trials.force[:, 0]) == [-1.0, -1.0, 1.0, 1.0]  # pushes on the outside, then the pull at the handle
    hinge = np.array([0.0, -0.20, 0.0, 1.0])  # body frame
    turned = []
    for i in range(len(trials)):
        T = trials.T_ow[i, : trials.samples(i)]
        hinge_world = T @ hinge
        assert np.ptp(hinge_world[:, :3], axis=0).max() < 1e-4
        relative = np.linalg.inv(T[0]) @ T
        rotvec = Rotation.from_matrix(relative[:, :3, :3]).as_rotvec()
        assert np.abs(rotvec[:, :2]).max() < 1e-6  # about z only
        turned.append(-np.degrees(rotvec[-1, 2]))  # its hinge opens it about -z
    assert abs(turned[0]) < 0.5 and abs(turned[3]) < 0.5  # against its stops (shut, wide open): nothing
    assert -90.0 < turned[1] < -10.0  # pushed from wide open: it swings shut (its angle falls)
    assert 10.0 < turned[2] < 90.0  # pulled by the handle from shut: it swings open
    hooked = trials.T_ro[2, : trials.samples(2), :3, 3]
    assert np.ptp(hooked, axis=0).max() < 0.005  # the fingertip stays behind the bar, between its posts


def test_held_stick_moves_freely_over_the_direction_grid(stick_trials: Trials) -> None:
    stick = stdlib_body("Stick")
    trials = stick_trials  # `explore(stick, jobs=2)`, once per run (tests/conftest.py)
    assert len(trials) == 26 and trials.ok.all()
    handle = stick.frame("handle").pose.matrix()
    moves = []
    for i in range(len(trials)):
        n = trials.samples(i)
        assert np.abs(trials.T_ro[i, :n] - handle).max() < 1e-6  # held rigidly at the handle
        relative = np.linalg.inv(trials.T_ow[i, 0]) @ trials.T_ow[i, n - 1]
        moves.append(np.concatenate([relative[:3, 3], np.degrees(Rotation.from_matrix(relative[:3, :3]).as_rotvec())]))
    span = np.ptp(np.array(moves), axis=0)
    assert (span[:3] > 0.02).all(), span  # x, y, z
    assert (span[3:] > 2.0).all(), span  # roll, pitch, yaw
    lowest = min(trials.T_ow[i, : trials.samples(i), 2, 3].min() for i in range(len(trials)))
    assert lowest > 0.3  # it floats: never near the table


def test_trials_round_trip_through_a_file(tmp_path) -> None:
    block = stdlib_body("Block")
    short = with_policy(block, faces=["+x"], steps=2, duration=0.1).explores[0]
    longer = with_policy(block, faces=["-x"], steps=1, duration=0.2).explores[0].model_copy(update={"name": "long"})
    trials = explore(block.model_copy(update={"explores": [short, longer]}), jobs=1)
    assert trials.samples(0) == 6 and trials.samples(2) == 11 and np.isnan(trials.t[0, 6:]).all()
    path = tmp_path / "block.npz"
    trials.save(path)
    back = Trials.load(path)
    assert back.body == "Block"
    for key in ("t", "T_ro", "T_ow", "contact", "force", "ok", "reason"):
        np.testing.assert_array_equal(getattr(back, key), getattr(trials, key))


def test_output_bytes_do_not_depend_on_the_number_of_jobs(tmp_path) -> None:
    """The trials' bytes depend on the seed, not on the worker processes.

    Both runs on one machine: determinism, not a golden value, so CPU differences cannot enter.
    """
    block = with_policy(stdlib_body("Block"), steps=3, duration=0.3)
    data = []
    for jobs, seed in ((1, 0), (2, 0), (2, 1)):
        path = tmp_path / f"jobs{jobs}-seed{seed}.npz"
        explore(block, jobs=jobs, seed=seed).save(path)
        data.append(path.read_bytes())
    assert data[0] == data[1]
    assert data[1] != data[2]  # the seed is used (it jitters where the fingertip starts)


def _abort_on_second_trial(spec, seed=0):
    """Stands in for a simulator that aborts its process on one trial (as ODE does on a blown-up world)."""
    import os

    from vkgl.sim import explore as module

    if spec.index == 1:
        os._exit(134)
    return module.TRUE_RUN_TRIAL(spec, seed)


def test_a_trial_that_kills_its_process_is_marked_failed_and_the_others_are_kept(monkeypatch) -> None:
    from vkgl.sim import explore as module

    monkeypatch.setattr(module, "TRUE_RUN_TRIAL", module.run_trial, raising=False)
    monkeypatch.setattr(module, "run_trial", _abort_on_second_trial)
    trials = explore(with_policy(stdlib_body("Block"), steps=2, duration=0.1), jobs=2)
    assert list(trials.ok) == [True, False, True, True]
    assert "aborted" in trials.reason[1] and trials.samples(1) == 0
    assert trials.samples(0) == trials.samples(3) == 6
