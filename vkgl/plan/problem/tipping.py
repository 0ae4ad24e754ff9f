"""Never push a body where it tips: the affordances a `tips above` clause rules out.

Inference writes `tips above Q on faces F` (docs/inference.md, "Tipping"): a
push on side face F higher than Q over the table tipped the body in
exploration. An affordance's contact height is its action pose's z in the body
frame plus the height of the body's frame over the table as it lies there; its
face is the one its action's x axis (the push direction, into the body)
presses. The planner drops every affordance that pushes a face higher than
that face's Q (docs/planning.md, "Tipping"), and keeps a sentence for each, so
that a task that needed one gets "no plan" with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.geometry import pushed_face, resting_height
from vkgl.lang.ir.nodes import Affordance, AffordanceSet, Body, FixedC, Ref, Tipping

TOLERANCE = 5e-4  # m: a contact printed at the recorded height (0.1 mm and 1 mm roundings) is at it, not above


@dataclass(frozen=True)
class TooHigh:
    """An affordance left out because it would tip its body: its name and why, in words."""

    affordance: str
    why: str


def split_by_tipping(
    body: Body, affordances: tuple[Affordance, ...], clauses: list[Tipping]
) -> tuple[tuple[Affordance, ...], tuple[TooHigh, ...]]:
    """(the affordances that do not tip `body`, those left out with the reason), in their order.

    Only a body that lies on the table can tip; an affordance that moves
    nothing (`fixed` or `free` motion: a grasp held still) is never left out.
    """
    if not clauses or body.joint is not None:
        return affordances, ()
    table = AffordanceSet(body=Ref(name=body.name), affordances=[], tipping=clauses)
    origin = resting_height(body, 0.0, 0.0)  # the body frame's height over the table, lying upright
    kept: list[Affordance] = []
    left: list[TooHigh] = []
    for affordance in affordances:
        why = _tips(affordance, table, origin, body.name)
        if why:
            left.append(TooHigh(affordance.name, why))
        else:
            kept.append(affordance)
    return tuple(kept), tuple(left)


def _tips(affordance: Affordance, table: AffordanceSet, origin: float, body: str) -> str:
    action = affordance.action
    if not isinstance(action, FixedC) or action.pose is None or affordance.motion.type not in ("prismatic", "revolute"):
        return ""
    pose = action.pose.matrix()
    face = pushed_face(pose[:3, 0])
    if face is None:
        return ""
    limit = table.tipping_height(face)
    height = float(pose[2, 3]) + origin
    if limit is None or height <= limit + TOLERANCE or not np.isfinite(height):
        return ""
    return (
        f"{affordance.name} pushes {body} {100 * height:.1f} cm over the table on its {face} face, above the "
        f"{100 * limit:.1f} cm it tips over at (`tips above`)"
    )
