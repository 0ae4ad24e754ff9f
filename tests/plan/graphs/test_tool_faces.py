"""Where along a face a tool's flat face may enact a slide (`vkgl.plan.graphs.tool_faces.slide_band`): the hook's
cross-piece covering the body's centre line, its shaft clear of the body; nothing for a point."""

from __future__ import annotations

import pytest
from task_makers import generated_tasks

import vkgl
from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.nodes import RevoluteC
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.members import action_at
from vkgl.plan.graphs.rollout import bounds, extend, start_sequence
from vkgl.plan.graphs.tool_faces import COVER_MARGIN, slide_band
from vkgl.plan.problem.problem import build_problem


def _problem(tmp_path, body: str):
    target = generated_tasks.Placement("target", body, 0.93, 0.05, 0.0)
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("band", 0, 0, (target, *tools), (0.78, 0.05, 0.0), "far-pull", False, 0.15)
    library = generated_tasks.fixture_library((body,))
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / body, library))
    return build_problem(program, program.tasks["band"])


PULL = Engagement("hook.tip", "target", "push_center_nx")


def test_the_hook_pulls_a_24_cm_crate_only_toward_its_shafts_side_by_the_cover_it_keeps(tmp_path):
    problem = _problem(tmp_path, "CrateT")
    # the shaft 12 cm beside the tip (2 cm thick) clears the 12 cm half width by 0.5 cm from 1.5 cm on; the
    # cross-piece reaches 3 cm past the tip, so the centre line stays 1 cm inside it up to 2 cm
    assert slide_band(problem, PULL) == pytest.approx((0.015, 0.03 - COVER_MARGIN))
    for effector in ("stick.tip", "arm.fingertip"):  # a 2 cm end, a point: no room off the centre
        assert slide_band(problem, Engagement(effector, "target", "push_center_px")) is None
    wield = Engagement("arm.fingertip", "hook", "wield")
    seq = start_sequence(problem)
    for action in (Action("add", wield), Action("add", PULL)):
        seq, _ = extend(problem, seq, action)
    assert seq.offsets == ((2, PULL),)
    lower, upper = bounds(problem, seq, offsets=True)
    assert (lower[-1], upper[-1]) == pytest.approx((0.015, 0.02))


def test_no_band_where_the_shaft_would_leave_the_cross_piece_short_of_the_centre_line(tmp_path):
    assert slide_band(_problem(tmp_path, "CrateM"), PULL) is None  # 30 cm wide: the shaft clears it 4.5 cm out


def test_a_slides_member_moves_its_contact_along_the_face_and_keeps_its_motion(tmp_path):
    problem = _problem(tmp_path, "CrateT")
    written = problem.affordance("target", "push_center_nx")
    member = find_member([written], "push_center_nx@+2.00cm/straight")
    assert member is not None and member.motion == written.motion
    moved = action_at(problem, "target", "push_center_nx", 0.02)
    along = problem.action("target", "push_center_nx")[:3, 1]  # the contact's y axis: the body's -y on its +x face
    assert moved[:3, 3] - problem.action("target", "push_center_nx")[:3, 3] == pytest.approx(0.02 * along)
    assert member.action.pose.matrix()[:3, 3] == pytest.approx(moved[:3, 3])
    # the same offset without `/straight` names the point's member of the slide's arc family: a turn
    assert written.family is not None and written.family.arc is not None
    assert isinstance(find_member([written], "push_center_nx@+2.00cm").motion, RevoluteC)
