"""The family of an affordance: where along its face its contact may be, and how the motion changes with it.

A push group (vkgl/infer/affordances.py) holds the trials of one face that
made the same constraint at different contacts: the Block's pushes at the
five middle points of a face all slide it straight, its pushes at the two
outer points of one end both turn it about a pivot beyond the far end. The
family is that set of contacts as a band of offsets along the face, measured
from the group's representative contact (the affordance's action), and the
motion as a function of the offset:

- a slide is the same at every offset (what the group's members share);
  `sigma` is the RMS angle between the members' directions and the
  representative's;
- a turn's pivot moves linearly with the offset: `pivot(s) = pivot(0) + s *
  drift`, drift fitted by least squares over the members' pivots (across the
  turn's axis); `sigma` is the RMS leave-one-out error of that fit, each
  member's pivot predicted from the others (with one other member, the drift
  is unknown and the prediction is the representative's pivot: a
  pessimistic spread).

The band holds only explored offsets: between two bands (the Block's slide
ends at 4.4 cm from the centre, its turn starts at 6.7 cm) what the body does
was not seen, and no family claims it. A pull is never a family (it is made at
a frame the body declares, `contacts at`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vkgl.infer.faces.arc import ArcFit
from vkgl.infer.trial import TrialInference

_SAME_POINT = 1e-3  # m: a band narrower than this is one contact, not a family


@dataclass(frozen=True)
class FamilyFit:
    """A fitted family: `along` (unit, body frame), offsets `lower..upper` (m), a turn's `drift` (or None), `sigma`
    (m for a turn's pivot, rad for a slide's direction; None when no other member tells); a slide's `arc` law
    (`vkgl.infer.faces.arc`: then sigma is the law's, rad of turn over 10 cm)."""

    along: np.ndarray
    lower: float
    upper: float
    drift: np.ndarray | None
    sigma: float | None
    arc: ArcFit | None = None


def fit_family(members: list[TrialInference], kept: TrialInference, along: np.ndarray) -> FamilyFit | None:
    """The family of a push group whose representative is `kept`, along the face direction `along` (unit).

    None when the members' contacts span less than a millimetre, or the motion is neither a slide nor a turn.
    """
    motion = kept.motion
    if motion is None or motion.type not in ("prismatic", "revolute") or not np.all(np.isfinite(kept.contact)):
        return None
    usable = [
        r for r in members if r.motion is not None and r.motion.type == motion.type and np.all(np.isfinite(r.contact))
    ]
    offsets = np.array([float((r.contact - kept.contact) @ along) for r in usable])
    if offsets.size == 0 or float(offsets.max() - offsets.min()) < _SAME_POINT:
        return None
    lower, upper = float(min(offsets.min(), 0.0)), float(max(offsets.max(), 0.0))
    if motion.type == "prismatic":
        return FamilyFit(along, lower, upper, None, _direction_spread(usable, kept))
    axis = np.asarray(motion.params["axis"], dtype=float)
    pivots = np.array([_across(np.asarray(r.motion.params["center"], dtype=float), axis) for r in usable])  # type: ignore[union-attr]
    origin = _across(np.asarray(motion.params["center"], dtype=float), axis)
    drift = _drift(offsets, pivots - origin)
    return FamilyFit(along, lower, upper, _across(drift, axis), _pivot_spread(offsets, pivots - origin))


def _across(v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """`v` without its component along the turn's axis (the pivot is a line: only its trace matters)."""
    return v - (v @ axis) * axis


def _drift(offsets: np.ndarray, moves: np.ndarray) -> np.ndarray:
    """Least squares `moves ~ offsets * drift` through the representative (offset 0, move 0)."""
    weight = float(offsets @ offsets)
    return (offsets @ moves) / weight if weight > 0 else np.zeros(3)


def _pivot_spread(offsets: np.ndarray, moves: np.ndarray) -> float | None:
    """RMS leave-one-out error of the pivot (m) over the members other than the representative."""
    errors = []
    for i in range(len(offsets)):
        if abs(offsets[i]) < _SAME_POINT:
            continue  # the representative itself (or a member at its contact)
        keep = np.arange(len(offsets)) != i
        predicted = offsets[i] * _drift(offsets[keep], moves[keep])
        errors.append(float(np.linalg.norm(moves[i] - predicted)))
    return float(np.sqrt(np.mean(np.square(errors)))) if errors else None


def _direction_spread(members: list[TrialInference], kept: TrialInference) -> float | None:
    """RMS angle (rad) between the members' slide directions and the representative's."""
    assert kept.motion is not None
    reference = np.asarray(kept.motion.params["axis"], dtype=np.float64)
    angles = []
    for r in members:
        if r is kept:
            continue
        assert r.motion is not None
        axis = np.asarray(r.motion.params["axis"], dtype=np.float64)
        angles.append(float(np.arccos(np.clip(axis @ reference, -1.0, 1.0))))
    return float(np.sqrt(np.mean(np.square(angles)))) if angles else None


def with_arc(family: FamilyFit | None, arc: ArcFit | None, along: np.ndarray) -> FamilyFit | None:
    """A centre slide's family with the face's arc law: the band every push of the face covers, the law's sigma."""
    if arc is None:
        return family
    lower, upper = arc.lower, arc.upper
    if family is not None:
        lower, upper = min(lower, family.lower), max(upper, family.upper)
    return FamilyFit(along, lower, upper, None, arc.sigma, arc)
