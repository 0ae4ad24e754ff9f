"""The distances and speeds of the arm's straight moves around contacts: one definition for planner and executor.

The planner checks a plan's straight moves with these (`vkgl.plan.arm.straight_moves`), and execution carries
them out with the same numbers (`vkgl.execute.steps`, `vkgl.execute.effector_path`): a move the planner found
clear is the move the executor makes.
"""

from __future__ import annotations

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

__all__ = ["CARTESIAN_SPEED", "GRASP_STANDOFF", "LIFT", "STANDOFF", "TOOL_DESCENT"]
