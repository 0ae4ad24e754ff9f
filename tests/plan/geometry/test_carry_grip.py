"""A body carried in the hand loads the grip with its own weight at its centre of mass (`grip_load.carry_rejection`):
an L-shaped body held on its long leg, its centre of mass 3.9 cm behind the fingers, twists the grip beyond what
the pads hold (in DART the grip broke as the hand lifted it: 175 %); held in line with its centre of mass it passes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vkgl.lang.compiler import compile_file
from vkgl.plan.geometry.grip_load import GRIP_MARGIN, carry_rejection
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.problem.rejection import Kind

TASK = """
use stdlib.robots.panda

body Ell {
    shape union {
        box (24, 6, 6) cm at (0, 0, 0) cm
        box (6, 14, 6) cm at (-9, 10, 0) cm
    }
    mass 0.6 kg
    friction 0.5
}

affordances Ell {
    affordance grasp_leg_end {
        action grasp at (0.6, 0, 0.5) cm yaw 0deg width 6 cm force 20 N
        motion free
    }
    affordance grasp_in_line {
        action grasp at (-3.3, 0, 0.5) cm yaw 0deg width 6 cm force 20 N
        motion free
    }
}

scene bench {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    ell : Ell on table at (0.45, 0.05) m yaw 0deg
}

task carry {
    scene bench
    goal ell at (0.55, 0) m yaw 30deg within 1 cm, 3 deg
}
"""


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> Problem:
    path = Path(tmp_path_factory.mktemp("carry")) / "carry.vkg"
    path.write_text(TASK)
    program = compile_file(str(path))
    return build_problem(program, program.task())


def _carried(problem: Problem, grasp: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the body's start, its end, the hand at the start) for a carry 10 cm along +x, turning 30 deg."""
    start = problem.bodies["ell"].rest
    end = start.copy()
    end[:3, :3] = Rotation.from_euler("z", 30, degrees=True).as_matrix() @ start[:3, :3]
    end[0, 3] += 0.1
    return start, end, start @ problem.action("ell", grasp)


def test_a_hold_off_the_centre_of_mass_is_refused_for_the_twist_of_its_weight(problem: Problem) -> None:
    rejection = carry_rejection(problem, "ell", "grasp_leg_end", *_carried(problem, "grasp_leg_end"))
    assert rejection is not None
    assert rejection.kind is Kind.GRIP
    assert "as it is carried" in rejection.why and "twists the grip" in rejection.why
    # 0.6 kg, 3.9 cm behind the fingers: 0.23 N m where 2 x 20 N at mu 0.5 hold 0.13 N m
    assert rejection.excess == pytest.approx(1.77 * GRIP_MARGIN - 1.0, abs=0.1)
    assert "nearer its centre of mass" in rejection.advice


def test_a_hold_in_line_with_the_centre_of_mass_carries_it(problem: Problem) -> None:
    assert carry_rejection(problem, "ell", "grasp_in_line", *_carried(problem, "grasp_in_line")) is None


def test_the_centre_of_mass_is_the_union_s_not_its_frame_origin(problem: Problem) -> None:
    """Judged at the frame's origin, 0.6 cm from the fingers, the hold off the centre would have passed."""
    from vkgl.plan.geometry.grip_load import _centre_of_mass

    centre = _centre_of_mass(problem, "ell")
    volumes = np.array([24 * 6 * 6, 6 * 14 * 6], dtype=float)
    expected = (volumes[0] * np.zeros(3) + volumes[1] * np.array([-0.09, 0.10, 0.0])) / volumes.sum()
    assert np.allclose(centre, expected, atol=1e-4)
