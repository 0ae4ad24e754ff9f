"""Diagnostic codes of grasps (E46x): a grasp affordance's action and a body's `explore grasps` policy."""

from __future__ import annotations

from vkgl.lang.diagnostics.registry import register as _code

GRASP_NOT_ACTION = _code(
    "E460",
    "a grasp that is not an affordance's action",
    (
        "`grasp at POSE width W force F` says how the robot's fingers hold a body: it is an affordance's "
        "`action`. A `motion` says how the body moves while held: `motion free` for a free body carried in "
        "the hand, the joint's `prismatic along ...` or `revolute about ...` for a handle on a drawer or a "
        "door. Move the grasp to `action`."
    ),
)
GRASP_WIDTH_OUT_OF_HAND = _code(
    "E461",
    "a grasp width the hand cannot open to",
    (
        "A grasp's `width` is the opening across the finger pads where they hold the body (the body's width "
        "there); `max_width` in `explore grasps` bounds the widths tried. Both are positive and at most "
        "8 cm, as wide as the Panda's fingers open (4 cm each). A body wider than that cannot be grasped "
        "there: grasp it across a narrower part, or push it."
    ),
)
UNKNOWN_APPROACH = _code(
    "E462",
    "an unknown grasp approach",
    (
        "`approach` in `explore grasps` names how the hand comes to the body: `top` (from above, the hand "
        "pointing down) and `side` (level, from any side), one or both; `approach none` alone learns no "
        "grasps for the body."
    ),
)
