"""The plan picture (`vkgc solve --plot`) draws the arm's planned paths: the effector's track along every segment.

The tracks are checked against the arm's forward kinematics of the plan's own
joints (`vkg-plan/8` `steps[k].path`), in the top view (x, y) and in the side
view (x, z), one line per segment, in its phase's style.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.api import solve
from vkgl.motion.picture_paths import GID_PREFIX, MAX_JOINT_STEP, PHASE_STYLES, joint_samples
from vkgl.plan.result.picture import plan_figure, plan_image

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def plans(compiled):
    """b: grasp the stick (transit, approach), push with it (lift, transit, approach); d: a retreat in between."""
    return {name: solve(compiled(name)) for name in ("b_stick_push", "d_rotate_push")}


def _path_lines(fig) -> dict[tuple[int, int, str], list]:
    """The arm-path lines of a figure by (step, segment, phase): one per view."""
    out: dict[tuple[int, int, str], list] = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            gid = line.get_gid() or ""
            if gid.startswith(GID_PREFIX + " "):
                step, segment, phase = gid.split()[1:]
                out.setdefault((int(step), int(segment), phase), []).append(line)
    return out


def test_joint_samples_keep_the_waypoints_and_the_step() -> None:
    waypoints = np.array([[0.0, 0.0], [0.1, -0.05], [0.1, -0.05], [0.1, 0.3]])
    samples = joint_samples(waypoints, max_step=0.02)
    assert np.abs(np.diff(samples, axis=0)).max() <= 0.02 + 1e-12
    assert len(samples) == 1 + 5 + 1 + 18  # ceil(0.1 / 0.02), a repeated waypoint, ceil(0.35 / 0.02)
    for waypoint in waypoints:
        assert np.abs(samples - waypoint).max(axis=1).min() == 0.0
    assert (samples[0] == waypoints[0]).all() and (samples[-1] == waypoints[-1]).all()


@pytest.mark.parametrize("name", ["b_stick_push", "d_rotate_push"])
def test_the_picture_draws_every_segment_through_the_arms_fk(plans, name) -> None:
    import matplotlib.pyplot as plt

    plan = plans[name]
    fig = plan_figure(plan)
    try:
        lines = _path_lines(fig)
        expected = {(k, i, seg.phase) for k, step in enumerate(plan.steps, 1) for i, seg in enumerate(step.path)}
        assert set(lines) == expected
        fk = plan.problem.arm.fk
        for (k, i, phase), (top, side) in lines.items():
            segment = plan.steps[k - 1].path[i]
            samples = joint_samples(segment.joints)
            points = np.array([fk(q)[:3, 3] for q in samples])
            assert len(top.get_xdata()) == len(samples) >= len(segment.joints)
            np.testing.assert_allclose(np.column_stack([top.get_xdata(), top.get_ydata()]), points[:, :2])
            np.testing.assert_allclose(np.column_stack([side.get_xdata(), side.get_ydata()]), points[:, [0, 2]])
            # the ends are the plan's joints: where the segment starts, and where it ends
            np.testing.assert_allclose(points[0], fk(segment.joints[0])[:3, 3])
            np.testing.assert_allclose(points[-1], fk(segment.joints[-1])[:3, 3])
            assert top.get_linestyle() == side.get_linestyle()
            assert top.get_linewidth() == pytest.approx(PHASE_STYLES[phase]["linewidth"])
    finally:
        plt.close(fig)


def test_each_path_ends_where_the_step_starts_and_the_phases_look_different(plans) -> None:
    import matplotlib.pyplot as plt

    plan = plans["b_stick_push"]
    fig = plan_figure(plan)
    try:
        lines = _path_lines(fig)
        fk = plan.problem.arm.fk
        for k, step in enumerate(plan.steps, 1):
            last = max(i for (s, i, _) in lines if s == k)
            top = next(v for (s, i, _), v in lines.items() if s == k and i == last)[0]
            end = fk(step.q_start)[:3, 3]
            assert (top.get_xdata()[-1], top.get_ydata()[-1]) == pytest.approx((end[0], end[1]), abs=1e-9)
        styles = {phase: v[0].get_linestyle() for (_, _, phase), v in lines.items()}
        assert set(styles) == {"lift", "transit", "approach"}
        assert len(set(styles.values())) == 3
        legend = [t.get_text() for t in fig.legends[0].get_texts()]
        assert {"arm: transit", "arm: approach", "arm: lift / retreat"} <= set(legend)
    finally:
        plt.close(fig)


def test_the_side_view_shows_a_transit_going_up_over_what_lies_between(plans) -> None:
    """Task d's first transit goes up, across and down (its straight joint-space line is blocked): the side view
    shows it rise, and its axes hold it."""
    import matplotlib.pyplot as plt

    fig = plan_figure(plans["d_rotate_push"])
    try:
        risen = [
            side
            for (_, _, phase), (_, side) in _path_lines(fig).items()
            if phase == "transit" and side.get_ydata().max() > max(side.get_ydata()[[0, -1]]) + 0.05
        ]
        assert risen
        assert all(side.axes.get_ylim()[1] >= side.get_ydata().max() for side in risen)
    finally:
        plt.close(fig)


def test_the_picture_is_the_same_bytes_every_time(plans) -> None:
    """Both runs on one machine: determinism, not a golden value, so CPU differences cannot enter."""
    plan = plans["b_stick_push"]
    assert plan_image(plan, "png") == plan_image(plan, "png")


def test_the_sampling_is_fine_enough_for_the_panda(plans) -> None:
    """At MAX_JOINT_STEP the effector moves at most 2.5 cm between two samples of a path (docstring's promise)."""
    plan = plans["b_stick_push"]
    fk = plan.problem.arm.fk
    for step in plan.steps:
        for segment in step.path:
            points = np.array([fk(q)[:3, 3] for q in joint_samples(segment.joints, MAX_JOINT_STEP)])
            assert np.linalg.norm(np.diff(points, axis=0), axis=1).max() < 0.025


def test_long_titles_wrap_within_their_columns_and_the_figure(plans) -> None:
    """A long task name and a family member's long affordance name: every title stays inside the figure and
    clear of its neighbours' (they were drawn on one line, over each other and cut at the figure's edge)."""
    from dataclasses import replace
    from itertools import pairwise

    import matplotlib.pyplot as plt

    plan = plans["b_stick_push"]
    member = "turn_px_right_family_member@+2.63cm/over+20deg+1.00cm"
    steps = [replace(s, affordance=s.affordance.replace("push_center_px", member)) for s in plan.steps]
    long = replace(plan, task="push_the_block_beyond_the_fingertips_reach_" * 3, steps=steps)
    fig = plan_figure(long)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        figure = fig.bbox
        titles = [ax.title for ax in fig.axes if ax.get_title()]
        boxes = [t.get_window_extent(renderer) for t in [*titles, fig._suptitle]]
        assert all(figure.x0 <= b.x0 and b.x1 <= figure.x1 and b.y1 <= figure.y1 for b in boxes)
        for left, right in pairwise(boxes[: len(titles)]):
            assert left.x1 < right.x0
        assert boxes[-1].y0 > max(b.y1 for b in boxes[:-1])  # the heading above the column titles
        assert fig._suptitle.get_text().endswith("3 graphs, 2 steps")
    finally:
        plt.close(fig)
