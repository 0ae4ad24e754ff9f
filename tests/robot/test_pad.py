"""The fingertip pad's geometry: its front along a push, and the hand turned about its axis with the pad's end at
the contact (`vkgl.robot.pad`)."""

from __future__ import annotations

import numpy as np
import pytest

from vkgl.robot.pad import FINGER_PAD_WIDTH, FINGERTIP_RADIUS, pad_front, pad_lies_along, turned_pad

PUSH = np.array([1.0, 0.0, 0.0])


def test_the_front_of_a_pad_along_the_face_is_the_effector_frames_origin() -> None:
    assert np.allclose(pad_front(np.eye(4), PUSH), 0.0)


def test_a_pad_turned_by_nothing_is_the_written_frame() -> None:
    assert np.allclose(turned_pad(0.0), np.eye(4))


@pytest.mark.parametrize("degrees", [30.0, 60.0, 90.0, 120.0, 150.0, -30.0, -90.0, -150.0])
def test_a_turned_hand_keeps_its_pad_front_on_the_contact_and_its_axis_upright(degrees: float) -> None:
    turned = turned_pad(np.radians(degrees))
    assert np.allclose(pad_front(turned, PUSH), 0.0, atol=1e-12)
    assert np.allclose(turned[:3, 2], [0.0, 0.0, 1.0])
    # the pad's axis (the frame's y) turned by the angle: across the face no longer
    assert turned[:3, 1] @ PUSH == pytest.approx(-np.sin(np.radians(degrees)))


def test_a_quarter_turn_stands_the_hand_back_by_half_the_pad_and_its_radius() -> None:
    turned = turned_pad(np.pi / 2)
    assert turned[0, 3] == pytest.approx(-(FINGER_PAD_WIDTH / 2 + FINGERTIP_RADIUS))
    assert abs(turned[1, 3]) == pytest.approx(FINGERTIP_RADIUS)


def test_the_front_follows_the_pad_wherever_the_hand_stands() -> None:
    hand = np.eye(4)
    hand[:3, 3] = (0.4, -0.1, 0.05)
    hand[:3, :3] = turned_pad(np.radians(120.0))[:3, :3]
    moved = hand @ np.linalg.inv(turned_pad(np.radians(120.0)))  # the frame before the turn, at the same pad
    assert np.allclose(pad_front(hand, moved[:3, 0]), moved[:3, 3])


@pytest.mark.parametrize("degrees", [0.0, 20.0, -20.0])
def test_a_pad_leaned_back_or_rolled_still_lies_along_the_face(degrees: float) -> None:
    """A lean turns the hand about the pad's axis, a roll about the push: the pad stays a 2 cm line on the face."""
    angle = np.radians(degrees)
    lean, roll = np.eye(4), np.eye(4)
    lean[:3, :3] = [[np.cos(angle), 0.0, -np.sin(angle)], [0.0, 1.0, 0.0], [np.sin(angle), 0.0, np.cos(angle)]]
    roll[:3, :3] = [[1.0, 0.0, 0.0], [0.0, np.cos(angle), -np.sin(angle)], [0.0, np.sin(angle), np.cos(angle)]]
    assert pad_lies_along(lean, PUSH) and pad_lies_along(roll, PUSH)


@pytest.mark.parametrize("degrees", [60.0, 90.0, 120.0, -60.0, -90.0, -120.0])
def test_a_hand_turned_about_its_axis_pushes_with_a_point(degrees: float) -> None:
    assert not pad_lies_along(turned_pad(np.radians(degrees)), PUSH)
