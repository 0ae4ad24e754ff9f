"""A tall carton in DART: pushed high it tips and the trial ends there; pushed low it slides; inference
records the heights that tip it; the fingertip neither lifts nor pins the pushed face."""

from __future__ import annotations

import numpy as np
import pytest

from vkgl.formats.trials import TIP_ANGLE, TIPPED, Trials, tilt_deg
from vkgl.infer.library import infer_library
from vkgl.lang.compiler import compile_source
from vkgl.lang.ir.nodes import Body
from vkgl.sim.explore import explore
from vkgl.sim.policy import plan_trials


def carton(friction: float, contacts: str) -> Body:
    """A 6 x 6 x 12 cm, 200 g carton explored with `contacts`, 1 N, 2 s: it tips when friction x height > 3 cm."""
    source = f"""
body Carton {{
    shape box (6, 6, 12) cm
    mass 0.2 kg
    friction {friction}
    explore pushes {{
        {contacts}
        force normal 1 N
        duration 2 s
    }}
}}
"""
    return compile_source(source).bodies["Carton"]


@pytest.fixture(scope="module")
def three_heights() -> Trials:
    """Friction 0.8, pushed on +x at 2, 6 and 10 cm over the table."""
    return explore(carton(0.8, "contacts on faces +x steps 1 heights 3"), jobs=2)


def test_heights_put_the_contacts_at_the_centres_of_equal_cells_of_the_body_height() -> None:
    specs = plan_trials(carton(0.8, "contacts on faces +x, -y steps 2 heights 3"))
    assert len(specs) == 12
    up = sorted({round(float(s.contact[2]) + 0.06, 6) for s in specs})
    assert up == [0.02, 0.06, 0.1]
    assert specs[0].label == "pushes +x 1/2 at 2.0 cm" and specs[2].label == "pushes +x 1/2 at 6.0 cm"


def test_without_heights_the_contacts_stay_at_mid_height() -> None:
    specs = plan_trials(carton(0.8, "contacts on faces +x steps 3"))
    assert [float(s.contact[2]) for s in specs] == [0.0, 0.0, 0.0]
    assert [s.label for s in specs] == ["pushes +x 1/3", "pushes +x 2/3", "pushes +x 3/3"]


def test_a_low_push_slides_the_carton_upright(three_heights: Trials) -> None:
    assert three_heights.ok[0] and three_heights.reason[0] == ""
    poses = three_heights.T_ow[0, : three_heights.samples(0)]
    assert tilt_deg(poses).max() < 1.0
    assert np.linalg.norm(poses[-1, :2, 3] - poses[0, :2, 3]) > 0.05  # 7.7 cm in 2 s


@pytest.mark.parametrize("i", [1, 2])
def test_a_high_push_tips_the_carton_and_the_trial_ends_there(three_heights: Trials, i: int) -> None:
    assert not three_heights.ok[i]
    assert str(three_heights.reason[i]).startswith(TIPPED)
    n = three_heights.samples(i)
    assert n < 50  # stopped within 1 s of a 2 s push
    assert tilt_deg(three_heights.T_ow[i, n - 1]) > TIP_ANGLE
    assert tilt_deg(three_heights.T_ow[i, n - 2]) <= TIP_ANGLE  # the first sample past 5 deg ends it


def test_the_carton_with_less_friction_slides_where_the_other_tips() -> None:
    """Friction 0.4 at 6 cm: 0.4 x 6 cm = 2.4 cm < 3 cm, so it slides (the old fingertip slid both)."""
    trials = explore(carton(0.4, "contacts on faces +x steps 1"), jobs=1)
    assert trials.ok.all()
    assert tilt_deg(trials.T_ow[0, : trials.samples(0)]).max() < 1.0


def test_inference_records_the_heights_that_tip_and_learns_only_the_low_push(three_heights: Trials) -> None:
    result = infer_library(three_heights, body_use="carton.vkg", header="# test")
    assert "    tips above 2 cm on faces +x\n" in result.source
    [block] = result.module.decls
    assert block.tipping_height("+x") == pytest.approx(0.02)
    assert block.tipping_height("-y") is None
    [push] = block.affordances
    assert push.action.pose.position.values[2] == pytest.approx(-0.04)  # 2 cm over the table (SI)
    skipped = [t["skipped"] for t in result.report["trials"] if "skipped" in t]
    assert len(skipped) == 2 and all(s.startswith("not ok: the body tipped over") for s in skipped)
