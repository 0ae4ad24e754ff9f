"""A hook pull of a 30 cm wide slab from 1.0 m, planned and carried out in DART.

At the middle of SlabW's far face the hook's shaft (12 cm beside its tip) would lie 4 cm inside the slab, so the
hook pulls it off the centre, on the side its shaft clears. Under DART's friction cone that pull turns the slab
about a pivot on the other side; explored with long pushes at 5 points of each face (`slide_steps` 5) the slab
knows that turn over 119 deg. The goal (heading free) lies off the written contact's arc by 1.9 cm: the planner
moves the contact along its family, 5.9 cm farther from the centre (the pivot moves with it), and DART's slab
ends where the plan says.
"""

from __future__ import annotations

import math

import numpy as np
from task_makers import generated_tasks

import vkgl


def _far_pull(
    tmp_path, name: str, target: generated_tasks.Placement, goal: tuple, tolerance: float, slide_steps: int = 1
):
    """The program and the plan (at most 3 graphs) of a far pull of `target` to `goal`, the stdlib tools beside it,
    its body's learned fixture (explored with long pushes at `slide_steps` points a face)."""
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec(name, 0, 0, (target, *tools), goal, "far-pull", False, tolerance)
    library = generated_tasks.fixture_library((target.type,), slide_steps=slide_steps)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / name, library, slide_steps=slide_steps))
    return program, vkgl.solve(program, name, max_depth=3)


def test_the_hook_pulls_a_wide_slab_off_its_far_face_centre_and_it_ends_where_planned(tmp_path):
    target = generated_tasks.Placement("target", "SlabW", 1.0, 0.0, 0.0)
    steps = generated_tasks.WIDE_SLIDE_STEPS
    program, plan = _far_pull(tmp_path, "wide", target, (0.809, 0.1025, None), 0.22, slide_steps=steps)
    assert plan.status == "solved", plan.reason
    assert plan.steps[0].affordance == "Hook.wield"
    pull = plan.steps[1]
    # a member of the hook-side turn's family, moved along the face from the written contact (5.66 cm off the centre)
    assert pull.affordance.startswith("SlabW.turn_nx_left@+") and pull.effector == "hook.tip"
    assert 30 < math.degrees(pull.value) < 119
    hook = pull.poses_start["hook"]
    slab = pull.poses_start["target"]
    shaft = np.linalg.inv(slab) @ hook  # the hook in the slab's frame: its shaft beside the slab's -y end
    assert shaft[1, 3] < -0.15 - 0.01
    report = vkgl.execute(program, "wide", plan)
    assert report.status == "reached", report.reason
    planned, real = pull.poses_end["target"], report.final["target"]
    assert np.linalg.norm(planned[:2, 3] - real[:2, 3]) < 0.01
    yaw = math.degrees(math.atan2(planned[1, 0], planned[0, 0]) - math.atan2(real[1, 0], real[0, 0]))
    assert abs((yaw + 180) % 360 - 180) < 2.0


def test_the_hook_pulls_a_24_cm_crate_straight_back_off_its_far_face_centre_and_it_keeps_its_heading(tmp_path):
    """CrateT (16 x 24 x 25 cm): at the middle of its far face the hook's shaft would lie 1 cm inside it, and a
    pull off the centre by a point turns it. The cross-piece lies flat along the face, so 2 cm toward the shaft's
    side it still covers the crate's centre line by 1 cm, its shaft 1 cm clear: the slide as learned, heading kept
    (`vkgl.plan.graphs.tool_faces`); DART's crate ends where the plan says."""
    target = generated_tasks.Placement("target", "CrateT", 0.93, 0.05, 0.0)
    program, plan = _far_pull(tmp_path, "kept", target, (0.78, 0.05, 0.0), 0.15)
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "CrateT.push_center_nx@+2.00cm/straight"]
    pull = plan.steps[1]
    shaft = np.linalg.inv(pull.poses_start["target"]) @ pull.poses_start["hook"]  # the hook in the crate's frame
    assert shaft[1, 3] <= -0.12 - 0.01 - 0.005  # the shaft (2 cm thick) beside its -y side, 0.5 cm clear or more
    report = vkgl.execute(program, "kept", plan)
    assert report.status == "reached", report.reason
    planned, real = pull.poses_end["target"], report.final["target"]
    assert np.linalg.norm(planned[:2, 3] - real[:2, 3]) < 0.01
    yaw = math.degrees(math.atan2(real[1, 0], real[0, 0]))
    assert abs(yaw) < 2.0


def test_the_hook_rolled_over_a_30_cm_slab_pulls_it_straight_back_and_it_keeps_its_heading(tmp_path):
    """SlabW (16 x 30 x 6 cm): lying flat, the hook's shaft would stand 4 cm inside it at its far face's centre,
    and no contact along the face both clears it and keeps the cross-piece on the centre line. Rolled 20 deg about
    the pull, its shaft passes over the slab's top and the cross-piece slants down behind the far face, across the
    centre line (`vkgl.plan.problem.over`): the slide as learned, heading kept; DART's slab ends where planned."""
    target = generated_tasks.Placement("target", "SlabW", 0.95, -0.1, 5.0)
    goal = (round(0.95 - 0.1 * math.cos(math.radians(5)), 4), round(-0.1 - 0.1 * math.sin(math.radians(5)), 4), 5.0)
    program, plan = _far_pull(tmp_path, "over", target, goal, 0.1)
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "SlabW.push_center_nx/over+20deg+1.00cm"]
    pull = plan.steps[1]
    hook = np.linalg.inv(pull.poses_start["target"]) @ pull.poses_start["hook"]  # the hook in the slab's frame
    assert hook[2, 1] < -0.3  # rolled: the hook's y axis (its cross-piece, tip to shaft) leans down from the shaft
    report = vkgl.execute(program, "over", plan)
    assert report.status == "reached", report.reason
    planned, real = pull.poses_end["target"], report.final["target"]
    assert np.linalg.norm(planned[:2, 3] - real[:2, 3]) < 0.01
    yaw = math.degrees(math.atan2(real[1, 0], real[0, 0]))
    assert abs(yaw - 5.0) < 2.0
