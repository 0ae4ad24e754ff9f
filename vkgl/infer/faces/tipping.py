"""Where pushing tips a body over: the `tips above Q on faces F` clauses of a learned module.

Exploration ends a push whose lying body tilts more than 5 deg and says so in
the trial's `reason` (`vkgl.formats.trials.TIPPED`). Per pushed side face,
inference takes the lowest contact height at which a push tipped the body and
records the highest explored height below it at which every push kept the
body upright (0 when none did): pushes on that face up to that height are
known not to tip it, and the planner pushes no higher (docs/inference.md,
"Tipping"). Faces with the same height share one clause.

Heights are over the table: the contact's z in the body frame plus the body
origin's height at the start of its trial (a lying body starts upright, its
lowest point on the exploration table's top at z = 0).
"""

from __future__ import annotations

import numpy as np

from vkgl.formats.trials import TIPPED, Trials
from vkgl.lang.ir.geometry import SIDE_FACES, pushed_face
from vkgl.lang.ir.nodes import Quantity, Tipping
from vkgl.lang.ir.units import to_si

SAME_HEIGHT = 1e-4  # m: contact heights closer than this are one explored height (0.1 mm, as printed)


def trial_height(trials: Trials, i: int) -> float:
    """The height (m) of trial `i`'s contact over the table, from the body's pose at its start."""
    return float(trials.contact[i, 2] + trials.T_ow[i, 0, 2, 3])


def tipped(trials: Trials, i: int) -> bool:
    """Did exploration end trial `i` because its body tipped over?"""
    return str(trials.reason[i]).startswith(TIPPED)


def safe_heights(trials: Trials) -> dict[str, float]:
    """Per side face that some push tipped: the highest explored height below every tipping one that no push
    tipped (0 when there is none)."""
    seen: dict[str, list[tuple[float, bool]]] = {}
    for i in range(len(trials)):
        face = pushed_face(trials.force[i])
        if face is None or not np.isfinite(trials.T_ow[i, 0, 2, 3]):
            continue
        if tipped(trials, i) or bool(trials.ok[i]):  # a trial that failed otherwise says nothing about tipping
            seen.setdefault(face, []).append((trial_height(trials, i), tipped(trials, i)))
    safe: dict[str, float] = {}
    for face, pushes in seen.items():
        lowest_tip = min((h for h, tip in pushes if tip), default=None)
        if lowest_tip is None:
            continue
        below = [h for h, tip in pushes if not tip and h < lowest_tip - SAME_HEIGHT]
        safe[face] = max(below, default=0.0)
    return safe


def tipping_ir(trials: Trials) -> list[Tipping]:
    """The `tips above` clauses of the dataset (empty when no push tipped the body), lowest height first."""
    by_height: dict[float, list[str]] = {}
    for face, height in safe_heights(trials).items():
        shown = float(f"{100 * height:.1f}")  # cm, 1 mm: heights are only as exact as the explored grid
        by_height.setdefault(shown, []).append(face)
    order = list(SIDE_FACES)
    return [
        Tipping(height=Quantity(value=to_si(f"{h:.1f}", "cm"), unit="cm"), faces=sorted(faces, key=order.index))
        for h, faces in sorted(by_height.items())
    ]
