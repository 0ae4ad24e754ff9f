"""The executor's check that a plan's hand is at its contact (`vkgl.execute.steps.contact_offset`): the pad's face
or, for a hand turned about its axis, the pad's rounded end."""

from __future__ import annotations

import numpy as np

from vkgl.execute.steps import PLAN_CONTACT_TOL, contact_offset
from vkgl.robot.pad import turned_pad


def _contact(x: float, y: float, yaw_deg: float) -> np.ndarray:
    pose = np.eye(4)
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    pose[:2, :2] = [[c, -s], [s, c]]
    pose[:3, 3] = (x, y, 0.04)
    return pose


def test_a_hand_at_the_contact_is_there() -> None:
    contact = _contact(0.5, -0.1, 30.0)
    assert contact_offset(contact, contact) < 1e-12


def test_a_hand_turned_about_its_axis_pushes_with_the_pads_end_at_the_contact() -> None:
    contact = _contact(0.5, -0.1, 30.0)
    for degrees in (60.0, 90.0, 120.0, -90.0, -150.0):
        hand = contact @ turned_pad(np.radians(degrees))
        assert np.linalg.norm(hand[:3, 3] - contact[:3, 3]) > PLAN_CONTACT_TOL / 2  # its origin stands back
        assert contact_offset(hand, contact) < 1e-9


def test_a_hand_beside_the_contact_is_refused() -> None:
    contact = _contact(0.5, -0.1, 30.0)
    hand = contact.copy()
    hand[:3, 3] += 2.0 * PLAN_CONTACT_TOL * contact[:3, 1]  # 2 cm along the face
    assert contact_offset(hand, contact) > PLAN_CONTACT_TOL
    turned = contact @ turned_pad(np.pi / 2)
    turned[:3, 3] -= 2.0 * PLAN_CONTACT_TOL * contact[:3, 0]  # turned, but 2 cm short of the face
    assert contact_offset(turned, contact) > PLAN_CONTACT_TOL
