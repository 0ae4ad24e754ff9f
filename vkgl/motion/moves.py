"""The distances and speeds of the arm's straight moves around contacts: one definition for planner and executor.

The planner checks a plan's straight moves with these (`vkgl.plan.arm.straight_moves`), and execution carries
them out with the same numbers (`vkgl.execute.steps`, `vkgl.execute.effector_path`): a move the planner found
clear is the move the executor makes.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

STANDOFF = 0.03
"""m: the pre-contact pose is this far back from the contact, against its push direction; a contact is left by
backing out this far (or rising this far where backing out is blocked)."""

GRASP_STANDOFF = 0.05
"""m: a tool is grasped from this high above its grasp frame, straight down."""

LIFT = 0.04
"""m: the hand rises this much after a grasp, a release or a retreat, before it moves on."""

TOOL_DESCENT = 0.03
"""m: a held tool comes straight down this much to its stand-off before its straight approach."""

CARTESIAN_SPEED = 0.03
"""m/s of the effector on the straight moves (approach, retreat, lift): slow, as they start or end in contact."""

BACK_CONE = np.radians(35.0)
"""rad: a way in within this of the push direction (along it, or the planner's rule 30 deg below it) is left
straight back against the push; one farther off (from the side of a handle's bar, ...) back out the way it came."""

WayOut = Literal["up", "back", "reverse"]


def way_out(way_in: np.ndarray, push: np.ndarray) -> WayOut:
    """How the arm leaves a contact, from the way it came in (`way_in`, world: the direction the hand moved on
    the approach's last step) and the contact's push direction (world), both where the contact was made.

    - "up": it came down into the contact (more vertical than horizontal: a fingertip or a hook's cross-piece
      behind a handle's bar, where backing off would put it into the body it pulls): straight up by
      `STANDOFF` + `LIFT`;
    - "back": it came in within `BACK_CONE` of the push: straight back against the push by `STANDOFF` (or up
      where the arm has no straight path back), then up by `LIFT`;
    - "reverse": it came in from elsewhere (from the side along a handle's bar, ...): back out the way it came
      by `STANDOFF` (the way turned with the body while in contact), then up by `LIFT`.

    One rule for both: the planner checks this move (`vkgl.plan.arm.straight_moves`), execution makes it
    (`vkgl.execute.steps`).
    """
    way = np.asarray(way_in, dtype=float)
    if -way[2] > float(np.linalg.norm(way[:2])):
        return "up"
    cosine = float(way @ push) / max(float(np.linalg.norm(way) * np.linalg.norm(push)), 1e-12)
    return "back" if cosine >= np.cos(BACK_CONE) else "reverse"


__all__ = [
    "BACK_CONE",
    "CARTESIAN_SPEED",
    "GRASP_STANDOFF",
    "LIFT",
    "STANDOFF",
    "TOOL_DESCENT",
    "WayOut",
    "way_out",
]
