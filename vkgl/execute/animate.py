"""A top-view animation of an execution: real bodies filled, planned (ghost) poses dashed, the arm and its hand.

    report = execute(program, task, plan, record=True)
    animate(report, "a_push.gif")

The arm is drawn as the line through its links' origins, the effector as a
black dot trailing its path over the last `TRACE_SECONDS` of simulated time,
in the plan picture's style for each phase (`vkgl.motion.picture_paths`:
transit dashed, approach solid, lift and retreat dotted; the contact motion
black); the title says which phase it is and how high the hand is above the
table (a transit goes up over the bodies, which a top view does not show).

GIFs are written with Pillow (a dependency of matplotlib), drawing only what
moves and with one palette (`vkgl.execute.gif`); `.mp4` needs ffmpeg on the
PATH (matplotlib's FFMpegWriter, every frame drawn whole).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import ConvexHull

from vkgl.atomic import writing
from vkgl.errors import InputError
from vkgl.execute.gif import write_gif
from vkgl.figure_colors import body_color
from vkgl.figure_text import fit_lines
from vkgl.formats.execution_report import ExecutionReport, joint_value_text
from vkgl.lang.ir.geometry import shape_mesh
from vkgl.lang.ir.nodes import Body, UnionShape
from vkgl.motion.picture_paths import PHASE_STYLES

MAX_FRAMES = 240  # longer executions are sped up to keep the file small
FPS = 20
_TITLE_ROOM = 0.95  # of the figure's width a line of the title may span
TRACE_SECONDS = 4.0
"""s of simulated time: how much of the effector's path trails behind it."""

_TRACE_STYLES: dict[str, dict[str, Any]] = {
    "transit": PHASE_STYLES["transit"],
    "approach": PHASE_STYLES["approach"],
    "lift / retreat": PHASE_STYLES["lift"],
    "contact": {"linestyle": "-", "linewidth": 1.5, "color": "black"},
    "other": {"linestyle": "-", "linewidth": 0.8, "color": "0.45"},
}
"""The trace's styles, by what the arm does (`trace_group` of a frame's label); the legend names the first four."""


def footprints(body: Body) -> list[np.ndarray]:
    """The body's outline seen from above, in its own frame: one convex polygon (k, 2) per shape part."""
    parts = body.shape.parts if isinstance(body.shape, UnionShape) else None
    meshes = []
    if parts is None:
        meshes.append(shape_mesh(body.shape))
    else:
        for part in parts:
            mesh = shape_mesh(part.shape)
            mesh.apply_transform(part.pose.matrix())
            meshes.append(mesh)
    outlines = []
    for mesh in meshes:
        xy = mesh.vertices[:, :2]
        hull = ConvexHull(xy)
        outlines.append(xy[hull.vertices])
    return outlines


def _place(outline: np.ndarray, pose: np.ndarray) -> np.ndarray:
    return outline @ pose[:2, :2].T + pose[:2, 3]


def animate(report: ExecutionReport, path: str | Path, *, max_frames: int = MAX_FRAMES) -> Path:
    """Write a top-view animation of a recorded execution to `path` (.gif, or .mp4 with ffmpeg).

    The report must come from `execute(..., record=True)`. Executions longer
    than `max_frames` recorded frames are sped up (every k-th frame is kept).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import animation
    from matplotlib.patches import Polygon, Rectangle

    frames = report.frames
    if frames is None or not frames.t:
        raise InputError("the execution was not recorded: call execute(..., record=True) before animate()")
    path = Path(path)
    writer = _writer(path, animation)
    stride = max(1, int(np.ceil(len(frames.t) / max(1, max_frames))))
    indices = list(range(0, len(frames.t), stride))
    if indices[-1] != len(frames.t) - 1:
        indices.append(len(frames.t) - 1)

    fig, ax = plt.subplots(figsize=(7.0, 5.6), dpi=80)
    _draw_table(ax, report.table, Rectangle)
    outlines = {name: footprints(report.bodies[name]) for name in frames.bodies}
    real_patches: dict[str, list[Polygon]] = {}
    ghost_patches: dict[str, list[Polygon]] = {}
    for k, name in enumerate(frames.bodies):
        color = body_color(k)
        real_patches[name] = [
            Polygon(o, closed=True, fc=color, ec="black", lw=0.8, alpha=0.75, label=name if i == 0 else None)
            for i, o in enumerate(outlines[name])
        ]
        ghost_patches[name] = [Polygon(o, closed=True, fill=False, ec=color, lw=1.2, ls="--") for o in outlines[name]]
        for patch in (*real_patches[name], *ghost_patches[name]):
            ax.add_patch(patch)
    (arm_line,) = ax.plot([], [], "-o", color="0.35", lw=3, ms=3, zorder=5)
    traces = {group: ax.plot([], [], zorder=5.5, **style)[0] for group, style in _TRACE_STYLES.items()}
    (tip,) = ax.plot([], [], "o", color="black", ms=5, zorder=6)
    title = ax.set_title("", fontsize=10)
    _frame_limits(ax, report, frames)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.add_artist(ax.legend(loc="upper right", fontsize=8, title="filled: real, dashed: planned", title_fontsize=7))
    named = [traces[g] for g in list(_TRACE_STYLES)[:4]]
    ax.legend(named, list(_TRACE_STYLES)[:4], loc="lower right", fontsize=7, title="the hand's path", title_fontsize=7)
    effector = np.array([e[:3, 3] for e in frames.effector])
    groups = [trace_group(label) for label in frames.label]
    times = np.asarray(frames.t)
    table_z = _table_top(report.table)

    def draw(i: int) -> None:
        for b, name in enumerate(frames.bodies):
            for patch, outline in zip(real_patches[name], outlines[name]):
                patch.set_xy(_place(outline, frames.real[i][b]))
            for patch, outline in zip(ghost_patches[name], outlines[name]):
                patch.set_xy(_place(outline, frames.planned[i][b]))
        links = frames.arm[i]
        arm_line.set_data(links[:, 0], links[:, 1])
        tip.set_data([effector[i, 0]], [effector[i, 1]])
        first = int(np.searchsorted(times, times[i] - TRACE_SECONDS - 1e-9))
        for group, (xs, ys) in trace_lines(effector[:, :2], groups, first, i).items():
            traces[group].set_data(xs, ys)
        shoved = f" ({', '.join(d.body for d in report.disturbed)})" if report.disturbed else ""
        status = f"  —  {report.status}{shoved}{_openings(report)}" if i == indices[-1] else ""
        height = f"   hand {(effector[i, 2] - table_z) * 100:3.0f} cm up"
        # the last frame's status (goal openings, bodies shoved) made the line wider than the figure: wrapped
        text = f"{report.task}   t = {frames.t[i]:5.2f} s   {frames.label[i]}{height}{status}"
        title.set_text(fit_lines(text, _TITLE_ROOM * fig.get_figwidth() * 72, 10))

    moving: list[Any] = [patch for patches in (*real_patches.values(), *ghost_patches.values()) for patch in patches]
    moving += [arm_line, *traces.values(), tip, title]
    try:
        if path.suffix.lower() == ".gif":
            write_gif(fig, moving, draw, indices, path, fps=FPS)
        else:  # One draw per frame: grab_frame renders the figure itself (FuncAnimation.save would draw twice).
            assert writer is not None
            with writing(path) as temporary, writer.saving(fig, str(temporary), dpi=fig.dpi):
                for i in indices:
                    draw(i)
                    writer.grab_frame()
    finally:
        plt.close(fig)
    return path


def trace_group(label: str) -> str:
    """How a frame's effector path is drawn, from the frame's label (`step 2 transit`: its last word is the phase)."""
    phase = label.rpartition(" ")[2]
    if phase in ("lift", "retreat"):
        return "lift / retreat"
    if phase == "motion":
        return "contact"
    return phase if phase in ("transit", "approach") else "other"


def trace_lines(points: np.ndarray, groups: list[str], first: int, last: int) -> dict[str, tuple[list, list]]:
    """The trace from frame `first` to frame `last` (both included) as x and y data per group of `_TRACE_STYLES`.

    The move from frame j - 1 to frame j is drawn in frame j's group (the
    label says what the arm did to get there); runs of one group are joined,
    runs apart are separated by NaN (a break in the line).
    """
    out: dict[str, tuple[list, list]] = {group: ([], []) for group in _TRACE_STYLES}
    previous = None
    for j in range(first + 1, last + 1):
        xs, ys = out[groups[j]]
        if groups[j] != previous:
            if xs:
                xs.append(np.nan)
                ys.append(np.nan)
            xs.append(points[j - 1, 0])
            ys.append(points[j - 1, 1])
        xs.append(points[j, 0])
        ys.append(points[j, 1])
        previous = groups[j]
    return out


def _openings(report: ExecutionReport) -> str:
    """The joint goals at the end, for the last frame's title: `, drawer open 19.9 cm (goal 20.0 cm)`."""
    parts = [
        f"{g.body} open {joint_value_text(g.opening.joint, g.opening.real)} "
        f"(goal {joint_value_text(g.opening.joint, g.opening.target)})"
        for g in report.goals
        if g.opening is not None
    ]
    return f", {', '.join(parts)}" if parts else ""


def check_animation_path(path: str | Path) -> None:
    """Raise InputError unless an animation can be written to `path` (.gif, or .mp4 with ffmpeg)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import animation

    _writer(Path(path), animation)


def _writer(path: Path, animation: Any) -> Any:
    """matplotlib's writer for an MP4, None for a GIF (`vkgl.execute.gif` writes it); InputError if neither works."""
    suffix = path.suffix.lower()
    if suffix == ".gif":
        try:
            import PIL  # noqa: F401  (pillow comes with matplotlib; vkgl.execute.gif writes with it)
        except ImportError as exc:
            raise InputError(f"{path}: writing a GIF needs pillow, which is not installed") from exc
        return None
    if suffix == ".mp4":
        if not animation.writers.is_available("ffmpeg"):
            raise InputError(f"{path}: writing an MP4 needs ffmpeg on the PATH; write a .gif instead")
        return animation.FFMpegWriter(fps=FPS)
    raise InputError(f"{path}: the animation must be a .gif or .mp4 file")


def _draw_table(ax: Any, table: Any, rectangle: Any) -> None:
    if table is None:
        return
    sx, sy = table.size.values[:2]
    cx, cy = table.position.values[:2]
    ax.add_patch(rectangle((cx - sx / 2, cy - sy / 2), sx, sy, fc="0.93", ec="0.6", zorder=0))


def _table_top(table: Any) -> float:
    """The z of the table's top (its position's z, 0 without one: as `vkgl.lang.ir.geometry.table_top`)."""
    if table is None:
        return 0.0
    values = table.position.values
    return float(values[2]) if len(values) > 2 else 0.0


def _frame_limits(ax: Any, report: ExecutionReport, frames: Any) -> None:
    points = [np.array([[0.0, 0.0]])]
    if report.table is not None:
        sx, sy = report.table.size.values[:2]
        cx, cy = report.table.position.values[:2]
        points.append(np.array([[cx - sx / 2, cy - sy / 2], [cx + sx / 2, cy + sy / 2]]))
    points.append(np.array([e[:2, 3] for e in frames.effector]))
    allp = np.vstack(points)
    lo, hi = allp.min(axis=0) - 0.05, allp.max(axis=0) + 0.05
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
