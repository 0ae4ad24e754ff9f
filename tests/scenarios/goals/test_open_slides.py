"""An open slide is planned past its explored range and carried out in DART to the goal.

An 8 cm cube explored as the paper explores (the 2 s push grid, no long
slides) slides 8.7 cm in its 2 s pushes and was still sliding when they ended,
so `vkgc learn` writes its slides `range 0 to 8.7 cm open`. Pushed 27.6 cm with
the stick, beyond the fingertip's reach: with the range closed that was "no
sequence of at most 6 graphs" (each stick push at most 8.7 cm); open, it is one
stick push of 27.6 cm, and the cube gets there in physics.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import vkgl

# The affordances below are what `vkgc learn` wrote for this body (DART exploration, seed 0).
CUBE_TASK = """
use stdlib.robots.panda
use stdlib.bodies.stick
use stdlib.affordances.stick
use stdlib.tools

body Cube {
    shape box (8, 8, 8) cm
    mass 0.256 kg
    friction 0.5
    explore pushes {
        contacts on faces +x, -x steps 9
        force normal 1 N
        duration 2 s
    }
}

affordances Cube {
    affordance push_center_px {
        action fixed at (-4, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 8.7 cm open
        evidence trials 9 loglik 3699.8 posterior 0.99
    }
    affordance push_center_nx {
        action fixed at (4, 0, 0) cm yaw 180deg
        motion prismatic along (-1, 0, 0) from (0, 0, 0) cm range 0 to 8.7 cm open
        evidence trials 9 loglik 3699.8 posterior 0.99
    }
}

scene far {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    cube : Cube on table at (0.7, 0) m yaw 0deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
}

task far_push {
    scene far
    goal cube at (0.976, 0) m within 1 cm
    search { max_depth 6  timeout 30 s }
}
"""


def test_an_open_slide_is_pushed_past_its_explored_range_with_the_stick_and_reaches_the_goal(tmp_path: Path) -> None:
    path = tmp_path / "cube.vkg"
    path.write_text(CUBE_TASK, encoding="utf-8")
    program = vkgl.compile(path)
    plan = vkgl.solve(program, "far_push")
    assert plan.status == "solved", plan.reason
    steps = plan.to_json()["steps"]
    assert [(s["affordance"], s["effector"]) for s in steps] == [
        ("Stick.wield", "arm.fingertip"),
        ("Cube.push_center_px", "stick.tip"),
    ]
    assert steps[1]["value"] == pytest.approx(0.276, abs=0.01)  # past the 8.7 cm it was explored over
    report = vkgl.execute(program, "far_push", plan)
    assert report.status == "reached", report.text()
