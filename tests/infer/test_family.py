"""Contact families: fitting a band and a pivot's drift from a push group, and the member at an offset."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vkgl.infer.faces.family import fit_family
from vkgl.infer.select import EdgeInference
from vkgl.infer.trial import TrialInference
from vkgl.lang.ir.families import at_offset, offset_bounds
from vkgl.lang.ir.nodes import AffordanceSet, PrismaticC, RevoluteC
from vkgl.lang.syntax.parser import parse_module

REPO = Path(__file__).resolve().parents[2]
LEFT = np.array([0.0, 1.0, 0.0])


def _trial(index: int, y: float, motion_type: str, **params: object) -> TrialInference:
    edge = EdgeInference(type=motion_type, posterior={motion_type: 1.0}, fits={}, params=dict(params))
    return TrialInference(index=index, contact=np.array([-0.05, y, 0.0]), force=np.array([1.0, 0.0, 0.0]), motion=edge)


def test_a_slide_family_spans_the_explored_offsets_and_the_spread_of_the_directions() -> None:
    axes = [np.array([1.0, 0.0, 0.0]), np.array([np.cos(0.002), np.sin(0.002), 0.0])]
    members = [
        _trial(i, y, "prismatic", axis=axes[i % 2], origin=np.zeros(3)) for i, y in enumerate((0.0, 0.02, -0.04))
    ]
    fit = fit_family(members, members[0], LEFT)
    assert fit is not None and fit.drift is None
    assert (fit.lower, fit.upper) == pytest.approx((-0.04, 0.02))
    assert fit.sigma == pytest.approx(np.sqrt(0.002**2 / 2))  # one of the two others leans 0.002 rad


def test_a_turn_family_fits_the_pivots_drift_and_its_leave_one_out_spread() -> None:
    axis = np.array([0.0, 0.0, -1.0])
    drift = np.array([0.1, -0.05, 0.0])
    members = [
        _trial(i, 0.06 + s, "revolute", axis=axis, center=np.array([0.0, -0.11, 0.3]) + s * drift)
        for i, s in enumerate((0.0, 0.01, 0.02, 0.03))
    ]
    fit = fit_family(members, members[0], LEFT)
    assert fit is not None
    assert (fit.lower, fit.upper) == pytest.approx((0.0, 0.03))
    assert fit.drift == pytest.approx(drift)  # the height along the turn's axis does not count
    assert fit.sigma == pytest.approx(0.0, abs=1e-12)  # a straight line: every member is predicted by the others


def test_one_contact_or_a_grasp_is_no_family() -> None:
    single = [_trial(0, 0.0, "prismatic", axis=np.array([1.0, 0.0, 0.0]), origin=np.zeros(3))]
    assert fit_family(single, single[0], LEFT) is None
    free = [_trial(i, y, "free") for i, y in enumerate((0.0, 0.02))]
    assert fit_family(free, free[0], LEFT) is None


FAMILIES = """affordances Block {
    affordance push_center_px {
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 49.1 cm open
        family along (0, 1, 0) from -4.44 to 4.44 cm sigma 0.08deg
    }
    affordance turn_px_left {
        action fixed at (-5, 6.56, 0) cm yaw 0.1deg
        motion revolute about (-0.54, -11.1, 0) cm axis (0, 0, -1) range 0 to 25deg
        family along (0, 1, 0) from 0 to 2.22 cm drift (0.136, -0.002, 0) sigma 0.3 cm
    }
}
"""


def test_the_member_at_an_offset_moves_the_contact_and_a_turns_pivot() -> None:
    # a slide's family and a turn's, as inference writes them (the stdlib Block's under the boxed LCP: under the
    # friction cone only its centre pushes slide, so its slides have no family now)
    module = parse_module(FAMILIES, "block.vkg")
    block = next(d for d in module.decls if isinstance(d, AffordanceSet))
    slide = next(a for a in block.affordances if a.name == "push_center_px")
    turn = next(a for a in block.affordances if a.name == "turn_px_left")
    assert offset_bounds(slide) == pytest.approx((-0.0444, 0.0444))
    moved = at_offset(slide, 0.03)
    assert moved.family is None and isinstance(moved.motion, PrismaticC)
    assert moved.action.pose.position.values == pytest.approx((-0.05, 0.03, 0.0))  # type: ignore[union-attr]
    assert moved.motion == slide.motion
    member = at_offset(turn, 0.02)
    assert isinstance(member.motion, RevoluteC) and isinstance(turn.motion, RevoluteC)
    expected = turn.motion.center.array() + 0.02 * turn.family.drift.array()  # type: ignore[union-attr]
    assert member.motion.center.array() == pytest.approx(expected)
    assert at_offset(turn, 0.0) == turn.model_copy(update={"family": None})
    with pytest.raises(ValueError, match="outside the family's band"):
        at_offset(turn, -0.01)
