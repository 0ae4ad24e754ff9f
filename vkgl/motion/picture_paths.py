"""The arm's planned paths in plan pictures: where the effector goes along each `ArmSegment`, one style per phase.

A segment's joints are waypoints joined by straight joint-space lines
(`vkgl.formats.plan.ArmSegment`), so between two waypoints the effector
follows a curve, not a straight line: a transit with two waypoints can swing
the hand up and over. `joint_samples` therefore samples every line at most
`MAX_JOINT_STEP` rad apart (in the joint that moves most), the waypoints
themselves included, and `effector_track` puts the samples through the arm's
forward kinematics (`Arm.fk`): the effector frame's origin, in world
coordinates, exactly where the executor drives the arm (it follows the same
lines, docs/execution.md).

    tracks = step_tracks(plan.problem.arm.fk, plan.steps[0])   # [(phase, (m, 3) points), ...]
    draw_tracks(ax, tracks, (0, 1), step=1)                     # top view; (0, 2) for the side view
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

import numpy as np

MAX_JOINT_STEP = 0.02
"""rad between two samples of a joint-space line (the joint that moves most): the Panda's hand moves < 2.5 cm."""

ARM_COLOR = "#6a3d9a"
"""The arm's paths are dark purple (no body's colour, not the goal's red, not the black of the hand in contact)."""

PHASE_STYLES: dict[str, dict[str, Any]] = {
    "transit": {"linestyle": "--", "linewidth": 1.0, "color": ARM_COLOR},
    "approach": {"linestyle": "-", "linewidth": 2.2, "color": ARM_COLOR},
    "lift": {"linestyle": ":", "linewidth": 2.0, "color": ARM_COLOR},
    "retreat": {"linestyle": ":", "linewidth": 2.0, "color": ARM_COLOR},
}
"""How each phase is drawn: the long collision-free transits thin and dashed, the short straight moves into a
contact solid, the straight moves away from one (lift, retreat) dotted."""

PHASE_LABELS = {
    "transit": "arm: transit",
    "approach": "arm: approach",
    "lift": "arm: lift / retreat",
    "retreat": "arm: lift / retreat",
}
"""The legend's words for each phase (lift and retreat share a style, and an entry)."""

GID_PREFIX = "arm-path"
"""Every track's line has the gid `arm-path <step> <segment> <phase>` (step from 1): tests and SVG readers find it."""

Fk = Callable[[np.ndarray], np.ndarray]


def joint_samples(joints: np.ndarray, max_step: float = MAX_JOINT_STEP) -> np.ndarray:
    """Points of the polyline through the waypoints `joints` (k x n), at most `max_step` apart in every joint.

    Each straight joint-space line is cut into equal pieces (as few as keep
    every joint within `max_step`); every waypoint is a sample, the first and
    the last included.
    """
    joints = np.asarray(joints, dtype=float)
    out = [joints[:1]]
    for a, b in itertools.pairwise(joints):
        pieces = max(1, int(np.ceil(float(np.abs(b - a).max()) / max_step - 1e-9)))
        s = np.arange(1, pieces + 1)[:, None] / pieces
        out.append(a + (b - a) * s)
    return np.vstack(out)


def effector_track(fk: Fk, joints: np.ndarray, max_step: float = MAX_JOINT_STEP) -> np.ndarray:
    """The effector's positions (m x 3, world, m) along the joint polyline `joints`, by forward kinematics."""
    return np.array([fk(q)[:3, 3] for q in joint_samples(joints, max_step)])


def step_tracks(fk: Fk, step: Any) -> list[tuple[str, np.ndarray]]:
    """`(phase, positions)` of each planned arm segment of a plan step (its `path`), in order."""
    return [(segment.phase, effector_track(fk, segment.joints)) for segment in step.path]


def draw_tracks(ax: Any, tracks: list[tuple[str, np.ndarray]], axes: tuple[int, int], *, step: int) -> list[Any]:
    """Draw the tracks of plan step `step` (from 1) on `ax`, coordinates `axes` (0 x, 1 y, 2 z); their lines.

    A hollow circle marks where the arm starts (the first track's first point), under the tracks: a 3 cm
    retreat is about as long as the circle is wide.
    """
    lines = []
    for i, (phase, points) in enumerate(tracks):
        (line,) = ax.plot(points[:, axes[0]], points[:, axes[1]], zorder=4, **PHASE_STYLES[phase])
        line.set_gid(f"{GID_PREFIX} {step} {i} {phase}")
        lines.append(line)
    if tracks:
        first = tracks[0][1][0]
        ax.plot(first[axes[0]], first[axes[1]], marker="o", mfc="white", mec=ARM_COLOR, ms=3.5, zorder=3.5)
    return lines


def legend_handles() -> list[Any]:
    """One legend entry per drawn style: the arm's phases, then the hand in contact."""
    from matplotlib.lines import Line2D

    handles = []
    seen = set()
    for phase, label in PHASE_LABELS.items():
        if label not in seen:
            seen.add(label)
            handles.append(Line2D([], [], label=label, **PHASE_STYLES[phase]))
    handles.append(Line2D([], [], color=ARM_COLOR, marker="o", mfc="white", ls="none", ms=4, label="arm: start"))
    handles.append(Line2D([], [], color="black", marker=".", ms=5, lw=1, label="hand in contact"))
    return handles
