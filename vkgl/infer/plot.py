"""`vkgc infer --plot`: the posterior over motion types against the contact position.

As in the paper's Figure 1 (centre panel): for each push direction, one panel
whose x axis is where along the face the robot pushed (cm, positive to the
left of the push) and whose stacked bars are the posterior of each motion type
of that trial. Trials without a known contact (tools held at one grasp, real
recordings) are drawn against their trial number.
"""

from __future__ import annotations

import io
from collections import defaultdict
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from vkgl.atomic import write_bytes
from vkgl.figure_text import fit_lines
from vkgl.infer.affordances import _direction_label, _left_of
from vkgl.infer.models import TYPES

if TYPE_CHECKING:
    from vkgl.infer.library import InferenceResult

COLORS = {"fixed": "#8c8c8c", "prismatic": "#1f77b4", "revolute": "#d62728", "free": "#2ca02c"}


def plot_posteriors(result: InferenceResult, path: str | Path) -> None:
    """Write a PNG of the motion posterior of every trial against where it pushed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = _panels(result)
    if not panels:
        panels = {"no usable trial": []}
    fig, axes = plt.subplots(1, len(panels), figsize=(4.5 * len(panels), 3.6), squeeze=False, sharey=True)
    for ax, (title, points) in zip(axes[0], panels.items()):
        _draw_panel(ax, title, points)
    axes[0][0].set_ylabel("posterior of the motion type")
    handles = [plt.Rectangle((0, 0), 1, 1, color=COLORS[k]) for k in TYPES]
    fig.legend(handles, TYPES, loc="upper center", ncol=len(TYPES), frameon=False)
    heading = fit_lines(f"{result.body}: what the body did, by where it was pushed", 0.95 * 4.5 * len(panels) * 72, 9)
    fig.suptitle(heading, y=0.02, va="bottom", fontsize=9)
    fig.tight_layout(rect=(0, 0.05, 1, 0.9))
    buffer = io.BytesIO()
    try:  # rendered in memory, then written by the one writer (never over a device, never half a file)
        fig.savefig(buffer, format=Path(path).suffix.lstrip(".").lower() or "png", dpi=120, metadata={"Software": None})
    finally:
        plt.close(fig)
    write_bytes(path, buffer.getvalue())


def _panels(result: InferenceResult) -> dict[str, list[tuple[float, dict[str, float], str]]]:
    """Per panel: (x, motion posterior, x-axis label) of each usable trial."""
    wielded = {i for g in result.groups if g.key == ("wield",) for i in g.members}
    panels: dict[str, list[tuple[float, dict[str, float], str]]] = defaultdict(list)
    for r in result.trials:
        if r.skipped is not None or r.motion is None:
            continue
        label = _direction_label(r.force)
        known = label != "any" and np.all(np.isfinite(r.contact)) and r.index not in wielded
        if known:
            x = 100.0 * float(r.contact @ _left_of(r.force))
            panels[f"push {label}"].append((x, r.motion.posterior, "contact along the face, cm (+ = left)"))
        else:
            title = "held (one grasp)" if r.index in wielded else "trials"
            panels[title].append((float(r.index), r.motion.posterior, "trial"))
    return dict(sorted(panels.items()))


def _draw_panel(ax: object, title: str, points: list[tuple[float, dict[str, float], str]]) -> None:
    ax.set_title(title, fontsize=10)  # type: ignore[attr-defined]
    if not points:
        return
    xs = np.array([p[0] for p in points])
    spacing = np.min(np.diff(np.unique(xs))) if len(np.unique(xs)) > 1 else 1.0
    width = 0.8 * spacing
    bottom = np.zeros(len(points))
    for kind in TYPES:
        heights = np.array([p[1][kind] for p in points])
        ax.bar(xs, heights, width=width, bottom=bottom, color=COLORS[kind])  # type: ignore[attr-defined]
        bottom += heights
    ax.set_xlabel(points[0][2])  # type: ignore[attr-defined]
    ax.set_ylim(0, 1)  # type: ignore[attr-defined]
