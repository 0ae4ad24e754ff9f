"""Draw docs/img/layout.png: vkgl's packages by layer (with their rooms), and the data flow of
`vkgc solve --execute`.

The left panel is read from the code: the layers are the import contract in pyproject.toml and each package's
rooms are its sub-folders, so the picture cannot drift from the layout. Run from the repository root:
`python docs/layout_picture.py`.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.axes import Axes
from matplotlib.patches import FancyBboxPatch

REPO = Path(__file__).resolve().parents[1]
STAGE = "#dbe9f6"
DATA = "#fdf1d6"
SHARED = "#e6e6e6"


def layers() -> list[list[str]]:
    """The pipeline's layers, top first, as pyproject.toml's first import contract states them."""
    config = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    contract = config["tool"]["importlinter"]["contracts"][0]
    return [[m.strip() for m in layer.split("|")] for layer in contract["layers"]]


def rooms(package: str) -> list[str]:
    """The sub-packages of `package` (a folder with an __init__.py), or its modules when it has none."""
    folder = REPO / package.replace(".", "/")
    if not folder.is_dir():
        return []
    subs = sorted(p.name for p in folder.iterdir() if (p / "__init__.py").is_file())
    return [f"{s}/" for s in subs] + [p.stem for p in sorted(folder.glob("*.py")) if p.stem != "__init__"]


def _wrapped(names: list[str], per_line: int) -> str:
    return "\n".join(" · ".join(names[i : i + per_line]) for i in range(0, len(names), per_line))


def _box(ax: Axes, x: float, y: float, w: float, h: float, text: str, colour: str, size: float = 7.5) -> None:
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.004", fc=colour, ec="0.35", lw=0.9))
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=size)


def draw_layers(ax: Axes) -> None:
    """Packages by layer, top (the CLI) to bottom (errors, resources); rooms listed under each package."""
    ax.set_title("packages by layer (rooms/ and modules): imports only point down", fontsize=10)
    ax.axis("off")
    rows = layers()
    height = 1.0 / len(rows)
    for i, members in enumerate(rows):
        y = 1.0 - (i + 1) * height
        width = 0.96 / len(members)
        for j, member in enumerate(members):
            inner = rooms(member)
            label = member.replace("vkgl.", "vkgl/").replace(".", "/")
            if inner:
                label += "\n" + _wrapped(inner, max(2, int(7 * width / 0.96 * len(members) ** 0.3)))
            colour = SHARED if member.split(".")[-1] in {"errors", "resources", "se3", "callable_stage"} else STAGE
            _box(ax, 0.02 + j * width, y + 0.008, width - 0.01, height - 0.016, label, colour, 6.2)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)


FLOW = [
    ("vkgc solve T.vkg --execute", "vkgl/cli: arguments, exit codes", SHARED),
    ("compile", "lang: syntax → resolve → checks\n→ Program (checked IR)", STAGE),
    ("build the problem", "plan/problem: Problem (frozen)", STAGE),
    ("search", "plan/search: graph sequences\n(graphs: successors, rollout)", STAGE),
    ("feasible?", "plan/task_space: closed form, SLSQP;\nplan/geometry: sweeps (motion/collision)", STAGE),
    ("arm paths", "plan/arm: straight moves, contact chains;\ntransits (motion/transit, OMPL)", STAGE),
    ("the plan", "plan/result: Plan → text, vkg-plan/8, PNG", DATA),
    ("carry it out", "execute: scene world, the arm in it,\nsteps (motion/approach, moves)", STAGE),
    ("goal reached?", "execute/goal_checks; a re-solve\ngoes back to the driver (api)", STAGE),
    ("report", "formats: vkg-execution/5, GIF", DATA),
]


def draw_flow(ax: Axes) -> None:
    """The data flow of `vkgc solve --execute`, one box per stage, top to bottom."""
    ax.set_title("vkgc solve --execute, step by step", fontsize=10)
    ax.axis("off")
    n = len(FLOW)
    step = 1.0 / n
    for k, (what, where, colour) in enumerate(FLOW):
        y = 1.0 - (k + 1) * step
        ax.text(0.0, y + step / 2, what, ha="left", va="center", fontsize=8, weight="bold")
        _box(ax, 0.36, y + 0.012, 0.62, step - 0.03, where, colour, 7.2)
        if k < n - 1:
            ax.annotate(
                "", xy=(0.67, y + 0.004), xytext=(0.67, y + 0.016), arrowprops={"arrowstyle": "-|>", "color": "0.3"}
            )
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)


def draw(path: Path) -> None:
    """Draw both panels into `path`."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 9), gridspec_kw={"width_ratios": [1.25, 1]})
    draw_layers(left)
    draw_flow(right)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


if __name__ == "__main__":
    draw(REPO / "docs" / "img" / "layout.png")
