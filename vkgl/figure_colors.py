"""The colours scene bodies are drawn in: the same body the same colour in a plan's picture and its animation.

`vkgc solve --plot` (vkgl/plan/result/picture.py) and `--animate` (vkgl/execute/animate.py) each colour the
bodies in scene order. They had a palette each, so a scene's fourth body, the hook of a scene with a block, a
stick and a hook, was purple in the plan and red in the animation. Red is left out: the picture draws goals in it.
"""

from __future__ import annotations

__all__ = ["BODY_COLORS", "body_color"]

BODY_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan")
"""Matplotlib colours, one per body in scene order, again from the first after the last."""


def body_color(index: int) -> str:
    """The colour of the body at `index` (0 first) in its scene's order."""
    return BODY_COLORS[index % len(BODY_COLORS)]
