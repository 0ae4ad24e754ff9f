"""Pictures of plans (matplotlib): `plot_plan(plan, path)` for `vkgc solve --plot F.png`.

One column per mode of the plan (G0, G1, ...): on top a top view of the
table with the arm's reach at the hand's height (the annulus computed from the
URDF), every body where the mode starts (dashed) and ends (filled), the goal
(red outline: at the goal's pose, or with the body's joint at the goal's
opening), the hand's path during the mode (black dots) and the arm's planned
paths into the mode (`vkgl.motion.picture_paths`: transit, approach, lift or
retreat, one style each); below it a side view (x, z) of the same, at the
same scale, since a transit up over a body and down again is a line back
and forth in the top view; at the bottom the mode's kinematic graph
(networkx), each edge labelled with its type. A legend under the columns
names the styles.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.errors import InputError
from vkgl.figure_colors import body_color
from vkgl.figure_text import fit_lines
from vkgl.motion.picture_paths import draw_tracks, legend_handles, step_tracks

_COLUMN_WIDTH = 3.6  # inches per mode
_TITLE_ROOM = 0.92  # of a column's (or the figure's) width a title's line may span: a gap between neighbours
_EDGE_STYLE = {"fixed": "solid", "prismatic": "dashed", "revolute": "dashdot", "free": "dotted"}


def plot_plan(plan: Any, path: str | Path) -> None:
    """Draw a solved plan (one panel per mode, with its graph) to `path` (PNG, SVG, PDF: by extension), atomically."""
    from vkgl.atomic import write_bytes

    suffix = Path(path).suffix.lstrip(".").lower() or "png"
    try:
        data = plan_image(plan, suffix)
    except ValueError as exc:  # matplotlib: a format it cannot write
        raise InputError(f"cannot write the picture {path}: {exc}") from None
    write_bytes(path, data)


def plan_image(plan: Any, image_format: str = "png") -> bytes:
    """The picture of a solved plan as bytes of `image_format` (png, svg, pdf, ...)."""
    fig = plan_figure(plan)
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format=image_format, dpi=110)
    finally:
        plt.close(fig)
    return buffer.getvalue()


def plan_figure(plan: Any) -> Any:
    """The matplotlib Figure of a solved plan (the caller closes it: `matplotlib.pyplot.close(fig)`).

    Its axes are, column by column (one column per mode): the top view, the
    side view and the graph. The arm's paths are lines whose gid starts with
    `picture_paths.GID_PREFIX`.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    if plan.status != "solved":
        summary = plan.reason.splitlines()[0] if plan.reason else ""
        raise InputError(f"task {plan.task} has no plan to draw ({plan.status}: {summary})")
    modes = _modes(plan)
    tracks = _tracks(plan)
    solids = _solids(plan)
    outlines = {name: [_hull(part[:, :2]) for part in parts] for name, parts in solids.items()}
    limits = _limits(plan, modes)
    heights = _heights(plan, modes, tracks, solids)
    # Rows as tall as their views at one scale (both have equal axes and the same x range); the graph below.
    width = limits[0][1] - limits[0][0]
    rows = [(limits[1][1] - limits[1][0]) / width, (heights[1] - heights[0]) / width, 0.6]
    fig, axes = plt.subplots(
        3,
        len(modes),
        figsize=(_COLUMN_WIDTH * len(modes), _COLUMN_WIDTH * 0.85 * sum(rows) + 1.4),
        squeeze=False,
        gridspec_kw={"height_ratios": rows},
    )
    colors = {name: body_color(i) for i, name in enumerate(plan.start)}
    for k, (title, start, end, hand) in enumerate(modes):
        _draw_scene(axes[0][k], plan, start, end, hand, colors, outlines, limits)
        draw_tracks(axes[0][k], tracks[k], (0, 1), step=k)
        axes[0][k].set_title(fit_lines(title, _TITLE_ROOM * _COLUMN_WIDTH * 72, 9), fontsize=9)
        _draw_side(axes[1][k], plan, start, end, hand, colors, solids, (limits[0], heights))
        draw_tracks(axes[1][k], tracks[k], (0, 2), step=k)
        _draw_graph(axes[2][k], plan.graphs[k], colors)
    axes[1][0].set_ylabel("z (m)", fontsize=7)
    steps = f"{len(plan.steps)} step{'s' if len(plan.steps) != 1 else ''}"
    heading = f"{plan.task}: {plan.depth} graphs, {steps}"
    fig.suptitle(fit_lines(heading, _TITLE_ROOM * _COLUMN_WIDTH * len(modes) * 72, 11), fontsize=11)
    handles = [*legend_handles(), Line2D([], [], color="red", ls="--", lw=1, label="goal")]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    return fig


def _modes(plan: Any) -> list[tuple[str, dict, dict, list]]:
    """(title, poses at start, poses at end, hand poses) of every mode; G0 is the scene at rest."""
    out: list[tuple[str, dict, dict, list]] = [("G0: start", plan.start, plan.start, [])]
    for k, step in enumerate(plan.steps, start=1):
        what = step.title().replace(" with ", "\nwith ", 1)
        out.append((f"G{k}: {what}", dict(step.poses_start), dict(step.poses_end), step.hand))
    return out


def _tracks(plan: Any) -> list[list[tuple[str, np.ndarray]]]:
    """Per mode, the effector's track along each planned arm segment into it (none into G0, none without an arm)."""
    if plan.problem is None:
        return [[] for _ in range(len(plan.steps) + 1)]
    fk = plan.problem.arm.fk
    return [[], *(step_tracks(fk, step) for step in plan.steps)]


def _solids(plan: Any) -> dict[str, list[np.ndarray]]:
    """Each body's shape in its own frame: the vertices (k x 3) of each part of its shape."""
    from vkgl.lang.ir.geometry import shape_mesh
    from vkgl.lang.ir.nodes import UnionShape

    out: dict[str, list[np.ndarray]] = {}
    problem = plan.problem
    if problem is None:
        return out
    for name, body in problem.bodies.items():
        shape = body.type.shape
        parts = [(p.shape, p.pose.matrix()) for p in shape.parts] if isinstance(shape, UnionShape) else [(shape, None)]
        out[name] = []
        for part, pose in parts:
            mesh = shape_mesh(part)
            if pose is not None:
                mesh.apply_transform(pose)
            out[name].append(np.asarray(mesh.vertices, dtype=float))
    return out


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex outline (k x 2, in order) of 2-d points."""
    from scipy.spatial import ConvexHull

    return points[ConvexHull(points).vertices]


def _heights(plan: Any, modes: list, tracks: list, solids: dict) -> tuple[float, float]:
    """The side views' common z range: the table top to the highest body, hand or arm path, with a margin."""
    problem = plan.problem
    low = problem.table_z if problem is not None else 0.0
    tops = [low + 0.1]
    for k, (_, start, end, hand) in enumerate(modes):
        tops += [float(p[2, 3]) for p in hand]
        tops += [float(points[:, 2].max()) for _, points in tracks[k]]
        for poses in (start, end):
            for name, pose in poses.items():
                tops += [float((part @ pose[2, :3]).max() + pose[2, 3]) for part in solids.get(name, [])]
    return low - 0.04, max(tops) + 0.05


def _limits(plan: Any, modes: list) -> tuple[tuple[float, float], tuple[float, float]]:
    """A common view for every panel: the table, or everything drawn, with a margin."""
    problem = plan.problem
    if problem is not None and problem.table_center is not None:
        low = problem.table_center - problem.table_size / 2
        high = problem.table_center + problem.table_size / 2
        base = problem.arm.base[:2, 3]
        low, high = np.minimum(low, base), np.maximum(high, base)
    else:
        points = np.array([p[:2, 3] for _, s, e, _ in modes for p in (*s.values(), *e.values())])
        low, high = points.min(axis=0) - 0.3, points.max(axis=0) + 0.3
    return (low[0] - 0.05, high[0] + 0.05), (low[1] - 0.05, high[1] + 0.05)


def _draw_scene(
    ax: Any, plan: Any, start: dict, end: dict, hand: list, colors: dict, outlines: dict, limits: tuple
) -> None:
    from matplotlib.patches import Circle, Polygon, Rectangle

    problem = plan.problem
    if problem is not None and problem.table_center is not None:
        corner = problem.table_center - problem.table_size / 2
        ax.add_patch(Rectangle(corner, *problem.table_size, facecolor="0.93", edgecolor="0.6"))
        height = float(hand[0][2, 3]) if hand else 0.025
        r_min, r_max = problem.arm.reach(height)
        base = problem.arm.base[:2, 3]
        ax.add_patch(Circle(base, r_max, fill=False, linestyle=":", color="0.45"))
        ax.add_patch(Circle(base, r_min, fill=False, linestyle=":", color="0.45"))
        ax.plot(*base, marker="s", color="0.3")
        for goal in problem.goals:
            if goal.region is not None:  # the region itself: where the body's footprint must end
                ax.add_patch(Polygon(_region_outline(goal.region), fill=False, edgecolor="red", linestyle="--"))
                continue
            pose = _goal_pose(problem, goal)
            if pose is not None and goal.body in outlines:
                for part in outlines[goal.body]:
                    ax.add_patch(Polygon(_placed(part, pose), fill=False, edgecolor="red", linestyle="--"))
    _draw_bodies(ax, start, end, colors, outlines, _placed)
    if hand:
        path = np.array([p[:2, 3] for p in hand])
        ax.plot(path[:, 0], path[:, 1], "k.-", markersize=3, linewidth=1)
        ax.plot(*path[-1], marker="o", color="k", markersize=4)
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    ax.set_aspect("equal")
    ax.tick_params(labelsize=7)


def _draw_bodies(ax: Any, start: dict, end: dict, colors: dict, parts: dict, outline: Any) -> None:
    """Each body's parts as `outline(part, pose)` polygons: filled where the mode ends, dashed where it
    started if it moved."""
    from matplotlib.patches import Polygon

    for name in end:
        moved = np.abs(start[name] - end[name]).max() > 1e-9
        for part in parts.get(name, []):
            if moved:
                ax.add_patch(Polygon(outline(part, start[name]), fill=False, edgecolor=colors[name], linestyle="--"))
            ax.add_patch(Polygon(outline(part, end[name]), facecolor=colors[name], alpha=0.6, edgecolor=colors[name]))


def _draw_side(
    ax: Any, plan: Any, start: dict, end: dict, hand: list, colors: dict, solids: dict, limits: tuple
) -> None:
    """The side view (x, z; seen from -y) of a mode: the table's edge, the bodies, the hand in contact."""
    from matplotlib.patches import Rectangle

    problem = plan.problem
    if problem is not None and problem.table_center is not None:
        left = problem.table_center[0] - problem.table_size[0] / 2
        ax.add_patch(
            Rectangle((left, problem.table_z - 0.03), problem.table_size[0], 0.03, facecolor="0.93", edgecolor="0.6")
        )
        ax.plot(problem.arm.base[0, 3], problem.arm.base[2, 3], marker="s", color="0.3")
    _draw_bodies(ax, start, end, colors, solids, _silhouette)
    if hand:
        path = np.array([p[:3, 3] for p in hand])
        ax.plot(path[:, 0], path[:, 2], "k.-", markersize=3, linewidth=1)
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    ax.set_aspect("equal")
    ax.tick_params(labelsize=7)


def _silhouette(vertices: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """The outline (x, z) of a part with body-frame `vertices` at world `pose`, seen from the side."""
    placed = vertices @ pose[:3, :3].T + pose[:3, 3]
    return _hull(placed[:, [0, 2]])


def _goal_pose(problem: Any, goal: Any) -> np.ndarray | None:
    """Where a goal puts its body, to draw it: the goal's position and yaw, or its joint at the goal's opening."""
    if goal.position is not None:
        pose = np.eye(4)
        yaw = goal.yaw if goal.yaw is not None else 0.0
        pose[:2, :2] = [[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]
        pose[:2, 3] = goal.position[:2]
        return pose
    body = problem.bodies[goal.body]
    if goal.opening is not None and body.type.joint is not None:
        from vkgl.lang.ir.geometry import joint_pose

        zero = body.rest if body.joint_zero is None else body.joint_zero
        return joint_pose(body.type.joint, zero, goal.opening)
    return None


def _region_outline(halfplanes: np.ndarray) -> np.ndarray:
    """The vertices of a convex region given by its half-planes (rows nx, ny, d), in order: consecutive edges meet."""
    following = np.roll(halfplanes, -1, axis=0)
    return np.array([np.linalg.solve(np.array([a[:2], b[:2]]), [a[2], b[2]]) for a, b in zip(halfplanes, following)])


def _placed(outline: np.ndarray, pose: np.ndarray) -> np.ndarray:
    return outline @ pose[:2, :2].T + pose[:2, 3]


def _draw_graph(ax: Any, edges: list, colors: dict) -> None:
    import networkx as nx

    graph = nx.MultiDiGraph()
    for parent, child, kind in edges:
        graph.add_edge(parent, child, type=kind)
    positions = nx.circular_layout(sorted(graph.nodes))
    node_colors = [colors.get(n, "0.75") for n in graph.nodes]
    nx.draw_networkx_nodes(graph, positions, ax=ax, node_color=node_colors, node_size=500, alpha=0.8)
    nx.draw_networkx_labels(graph, positions, ax=ax, font_size=7)
    for kind, style in _EDGE_STYLE.items():
        chosen = [(u, v) for u, v, d in graph.edges(data=True) if d["type"] == kind]
        nx.draw_networkx_edges(
            graph, positions, edgelist=chosen, ax=ax, style=style, arrows=True, node_size=500, width=1.2
        )
    labels = {(u, v): d["type"] for u, v, d in graph.edges(data=True)}
    nx.draw_networkx_edge_labels(graph, positions, edge_labels=labels, ax=ax, font_size=6)
    ax.set_axis_off()
