"""Draw docs/img/pipeline.png: the data flow from a `.vkg` file to a plan and an execution report.

Run from the repository root: `python docs/pipeline_picture.py`.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import FancyBboxPatch

STAGE = "#dbe9f6"
DATA = "#fdf1d6"
SHARED = "#e6e6e6"

# (x, y) centres; width/height in axes units
BOXES = {
    "source": ((0.08, 0.80), ".vkg files\n(tasks, scenes,\nbodies, stdlib)", DATA),
    "lang": ((0.27, 0.80), "vkgl/lang\nparse · resolve ·\ncheck (one validator)", STAGE),
    "program": ((0.46, 0.80), "Program\n(checked IR)", DATA),
    "sim": ((0.27, 0.45), "vkgl/sim\nDART world ·\nexploration grid", STAGE),
    "trials": ((0.27, 0.18), "vkg-trials/1\n(.npz)", DATA),
    "infer": ((0.50, 0.18), "vkgl/infer\nconstraint models ·\nmodel selection", STAGE),
    "module": ((0.50, 0.45), "affordance module\n(.vkg, via the printer)", DATA),
    "plan": ((0.67, 0.80), "vkgl/plan\ngraph search · task space ·\njoint space (IK)", STAGE),
    "planout": ((0.87, 0.80), "Plan\n→ text · vkg-plan/8 · PNG", DATA),
    "execute": ((0.77, 0.45), "vkgl/execute\nDART replay ·\nclosed loop", STAGE),
    "report": ((0.77, 0.18), "vkg-execution/5\nreport · GIF", DATA),
    "api": ((0.08, 0.45), "vkgl/api.py\nthe driver\n(vkgc, notebooks)", SHARED),
}

ARROWS = [
    ("source", "lang"),
    ("lang", "program"),
    ("program", "sim"),
    ("sim", "trials"),
    ("trials", "infer"),
    ("infer", "module"),
    ("module", "lang"),
    ("program", "plan"),
    ("plan", "planout"),
    ("planout", "execute"),
    ("execute", "report"),
    ("execute", "plan"),
]


def _on_edge(centre: tuple[float, float], towards: tuple[float, float], w: float, h: float) -> tuple[float, float]:
    """Where the line from a box's centre towards another point leaves the box (with a small gap)."""
    dx, dy = towards[0] - centre[0], towards[1] - centre[1]
    scale = min((w / 2 + 0.008) / abs(dx) if dx else float("inf"), (h / 2 + 0.015) / abs(dy) if dy else float("inf"))
    return centre[0] + dx * scale, centre[1] + dy * scale


def draw(path: Path) -> None:
    """Draw the picture into `path`."""
    fig, ax = plt.subplots(figsize=(11, 5.2))
    ax.set_xlim(0, 1)
    ax.set_ylim(0.02, 0.98)
    ax.axis("off")
    w, h = 0.15, 0.17
    for (x, y), text, colour in BOXES.values():
        ax.add_patch(
            FancyBboxPatch((x - w / 2, y - h / 2), w, h, boxstyle="round,pad=0.01", fc=colour, ec="0.35", lw=1)
        )
        ax.text(x, y, text, ha="center", va="center", fontsize=8.5)
    for a, b in ARROWS:
        (xa, ya), (xb, yb) = BOXES[a][0], BOXES[b][0]
        start = _on_edge((xa, ya), (xb, yb), w, h)
        end = _on_edge((xb, yb), (xa, ya), w, h)
        ax.annotate("", xy=end, xytext=start, arrowprops={"arrowstyle": "-|>", "color": "0.3", "lw": 1.2})
    ax.text(0.735, 0.62, "re-solve from the\nobserved scene", fontsize=7.5, color="0.3", ha="right")
    ax.text(0.86, 0.62, "carry out", fontsize=7.5, color="0.3")
    ax.text(0.20, 0.60, "`vkgc learn`: explore, infer", fontsize=7.5, color="0.3")
    ax.text(0.08, 0.22, "blue: stages (vkgl/…)\nyellow: data and\nexternal formats\n(vkgl/formats)", fontsize=7.5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    draw(Path(__file__).resolve().parent / "img" / "pipeline.png")
