"""The syntax of grasps: `action grasp at POSE width W force F`, `slip` in evidence, `explore grasps { ... }`."""

from __future__ import annotations

import pytest

from vkgl.lang.ir import nodes as ir
from vkgl.lang.syntax.parser import parse_module
from vkgl.lang.syntax.printer import print_module
from vkgl.resources import stdlib_dir

LEARNED = """body Carton {
    shape box (6, 6, 12) cm
    mass 0.3 kg
    explore grasps {
        approach top, side
        max_width 6 cm
        force 20 N
        lift 10 cm
        slip 5 mm
        trials 3
    }
}

affordances Carton {
    affordance grasp_top_y {
        action grasp at (0.6, 0, 3.2) cm yaw 0deg width 60 mm force 20 N
        motion free
        evidence trials 3 loglik 0 posterior 1 slip 0.4 mm
    }
    affordance grasp_side {
        action grasp at (-3, 0, 0) cm rpy (0, -90, 0) deg width 6 cm force 20 N
        motion prismatic along (1, 0, 0)
    }
}
"""


def test_a_grasp_module_prints_as_written_and_parses_back_to_the_same_ir() -> None:
    text = LEARNED
    module = parse_module(text, "carton.vkg")
    assert print_module(module) == text
    assert parse_module(print_module(module), "carton.vkg") == module


def test_a_grasp_is_an_action_with_a_pose_a_width_and_a_force_in_si() -> None:
    module = parse_module(LEARNED, "carton.vkg")
    sets = [d for d in module.decls if isinstance(d, ir.AffordanceSet)]
    top = sets[0].affordances[0]
    assert isinstance(top.action, ir.GraspC) and top.action.type == "grasp"
    assert top.action.width == pytest.approx(0.06) and top.action.force == pytest.approx(20.0)
    assert top.action.pose.position.values == pytest.approx((0.006, 0.0, 0.032))  # read as `fixed at POSE` is
    assert top.evidence is not None and top.evidence.slip == pytest.approx(0.0004)
    body = module.decls[0]
    assert isinstance(body, ir.Body) and body.grasps is not None and body.explores == []
    assert body.grasps.approaches == ["top", "side"] and body.grasps.trials == 3
    assert body.grasps.max_width is not None and body.grasps.max_width.value == pytest.approx(0.06)


def test_grasps_is_a_keyword_only_after_explore() -> None:
    text = "body grasps { shape box (1, 1, 1) cm mass 1 kg explore grasps2 { duration 1 s } }\n"
    body = parse_module(text, "x.vkg").decls[0]
    assert isinstance(body, ir.Body) and body.name == "grasps" and body.explores[0].name == "grasps2"
    assert body.grasps is None


def test_evidence_without_slip_prints_as_before() -> None:
    for path in sorted((stdlib_dir() / "affordances").glob("*.vkg")):
        text = path.read_text(encoding="utf-8")
        module = parse_module(text, path.name)
        evidences = [a.evidence for d in module.decls if isinstance(d, ir.AffordanceSet) for a in d.affordances]
        if all(e is None or e.slip is None for e in evidences):
            assert "slip" not in print_module(module)
