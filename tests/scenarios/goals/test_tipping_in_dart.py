"""A tall carton that tips when pushed high is pushed low by the plan, and in DART it stays upright."""

from __future__ import annotations

import textwrap

import numpy as np

import vkgl
from vkgl.formats.trials import tilt_deg
from vkgl.lang.compiler import compile_source

CARTON = """
use stdlib.robots.panda

body Carton {
    shape box (6, 6, 12) cm
    mass 0.2 kg
    friction 0.8
}

# The clause and push_center_px as `vkgc learn` writes them for `contacts on faces +x, -x steps 1 heights 3`
# (tests/sim/test_explore_tipping.py), and a push at mid-height added by hand, listed first: never to be used.
affordances Carton {
    tips above 2 cm on faces +x, -x
    affordance push_mid_px {
        action fixed at (-3, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }
    affordance push_center_px {
        action fixed at (-3, 0, -4) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 7.6 cm open
    }
}

scene carton_scene {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    carton : Carton on table at (0.45, 0.05) m yaw 0deg
}

task push_carton {
    scene carton_scene
    goal carton at (0.55, 0.05) m yaw 0deg within 1 cm, 3deg
    search { max_depth 3  timeout 30 s }
}
"""


def test_the_tall_carton_is_pushed_low_and_stays_upright_in_dart() -> None:
    program = compile_source(textwrap.dedent(CARTON), "carton.vkg")
    plan = vkgl.solve(program, "push_carton")
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Carton.push_center_px"]
    report = vkgl.execute(program, "push_carton", plan.document())
    assert report.status == "reached", report.reason
    final = report.final["carton"]
    assert float(tilt_deg(final)) < 1.0
    assert np.linalg.norm(final[:2, 3] - [0.55, 0.05]) < 0.01
