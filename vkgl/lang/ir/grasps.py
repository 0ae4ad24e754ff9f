"""The IR of grasps: a grasp affordance's action (`action grasp at POSE width W force F`) and a body's
`explore grasps { ... }` policy, which narrows or widens the grasps `vkgc learn` tries.

`vkgl.lang.ir.nodes` re-exports every name here; import them from there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from pydantic import Field

from vkgl.lang.ir.values import Node, Pose, Quantity, Span

HAND_OPENING = 0.08
"""m: the widest a parallel gripper's fingers open (the Panda's: 4 cm each, stdlib/robots/panda.urdf). A grasp's
`width` is at most this; `vkgc learn` uses the robot's own URDF when it tries grasps."""

GRASP_APPROACHES = ("top", "side")
"""The approaches `explore grasps { approach ... }` can name: from above (the hand pointing down, fingers closing
horizontally) and from the side (the hand level, pointing at the body)."""

NO_APPROACH = "none"
"""`approach none`: learn no grasps for the body."""


class GraspC(Node):
    """`grasp at POSE width W force F` (actions only): the fingers close on the body and hold it.

    `pose` is the robot's effector frame in the body frame while it holds the
    body (as `fixed at POSE`: planners read `action.pose` of both); the fingers
    close along its y axis. `width` (m) is the opening across the finger pads
    there, `force` (N) the closing force. `width_unit` and `force_unit` are how
    they were written (display only: equality ignores them).
    """

    type: Literal["grasp"] = "grasp"
    pose: Pose
    width: float
    force: float
    width_unit: str = Field(default="cm", exclude=True, repr=False)
    force_unit: str = Field(default="N", exclude=True, repr=False)


class GraspPolicy(Node):
    """`explore grasps { approach top, side  max_width Q  force Q  lift Q  slip Q  trials N }` on a body.

    Every item is optional (None: the learner's default, docs/language.md "Grasps").
    `approaches` are words of GRASP_APPROACHES, or [NO_APPROACH]; `approach_spans`
    say where each was written.
    """

    approaches: list[str] | None = None
    max_width: Quantity | None = None
    force: Quantity | None = None
    lift: Quantity | None = None
    slip: Quantity | None = None
    trials: int | None = None
    approach_spans: list[Span] = Field(default_factory=list, exclude=True, repr=False)
    trials_span: Span | None = Field(default=None, exclude=True, repr=False)


DEFAULT_MAX_WIDTH = 0.07
"""m: the widest part tried without `max_width`: the hand's 8 cm less 5 mm of room on each side."""
DEFAULT_FORCE = 20.0
"""N: the closing force tried without `force`."""
DEFAULT_LIFT = 0.10
"""m: how far a free body is lifted (a handle pulled along its joint) without `lift`."""
DEFAULT_SLIP = 0.005
"""m: the most a body may move in the hand over a trial, without `slip`, for the grasp to be kept."""
DEFAULT_TRIALS = 3
"""Trials per grasp without `trials`."""


@dataclass(frozen=True)
class GraspSettings:
    """What `vkgc learn` tries for a body: a `GraspPolicy` with the defaults filled in (SI)."""

    approaches: tuple[str, ...] = GRASP_APPROACHES
    max_width: float = DEFAULT_MAX_WIDTH
    force: float = DEFAULT_FORCE
    lift: float = DEFAULT_LIFT
    slip: float = DEFAULT_SLIP
    trials: int = DEFAULT_TRIALS

    @classmethod
    def of(cls, policy: GraspPolicy | None) -> GraspSettings:
        """The settings of a body's `explore grasps` block (None: all defaults); `approach none` tries nothing."""
        if policy is None:
            return cls()
        approaches = GRASP_APPROACHES if policy.approaches is None else tuple(policy.approaches)
        return cls(
            approaches=tuple(a for a in approaches if a != NO_APPROACH),
            max_width=DEFAULT_MAX_WIDTH if policy.max_width is None else float(policy.max_width.value),
            force=DEFAULT_FORCE if policy.force is None else float(policy.force.value),
            lift=DEFAULT_LIFT if policy.lift is None else float(policy.lift.value),
            slip=DEFAULT_SLIP if policy.slip is None else float(policy.slip.value),
            trials=DEFAULT_TRIALS if policy.trials is None else int(policy.trials),
        )


__all__ = ["GRASP_APPROACHES", "HAND_OPENING", "NO_APPROACH", "GraspC", "GraspPolicy", "GraspSettings"]
