"""The arc law of a face: how a push off the face's centre slides and turns the body at once.

Quasi-static pushing turns a body pushed at offset d from its centre line about
a pivot on the other side of that line, at a distance that shrinks as d grows
(docs/planning.md, "Arcs", measured it in DART). Across the push the pivot lies

    r(d) = lever**2 / |d| + bias        (beyond the centre line, away from the contact)

and along the push it lies `ahead` of the contact (a constant: the mean of the
pivots the turning pushes made). At d = 0 the radius is infinite: the pure
slide. The law is fitted on every push of one face, the centre's slides and the
off-centre pushes that turned (the trials behind the face's `turn_*`
affordances), from the body's pose at the start and at the end of each trial:

- each push that turned by 1 deg or more gives a pivot (the point the start
  and the end pose share), its turn counted along the trial's track (a long
  push may turn a body past half a turn: from its ends alone, 206 deg reads
  -154 deg); `r = lever**2 / |d| + bias` is fitted by least
  squares on those pivots (with pushes at only one |d|, `bias` is 0: the
  textbook `c**2 / d`), `ahead` is their mean;
- the uncertainty is leave-one-out: each off-centre push (the slides among
  them) is predicted from a law fitted on the others, the turn it makes over
  its own travel against the turn DART made, scaled to 10 cm of travel;
  `sigma` is the RMS of those errors (None when no push can be left out);
- where the law holds: from the centre to the innermost explored push the law
  interpolates between the slide (the pivot at infinity) and that push, which
  only its `lever**2 / |d|` term shapes. When that term makes up less than
  `SEEN` of the innermost push's pivot distance, the pushes pivoted about one
  place (a tall crate's far corner) and never showed how the pivot comes in
  from the slide's infinity: the law holds from that push out (`beyond`),
  where its sigma was measured (CrateT: 14 deg wrong over 10 cm 0.75 cm off its
  centre, 0.34 deg at its explored pushes; docs/inference.md, "Arcs"); nearer
  the centre the planner does not know its members' turn.

The law is symmetric in d: a body pushed at -d turns the other way about the
mirrored pivot (the faces of the explored bodies are symmetric; the
leave-one-out error says how far that holds).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from vkgl.formats.trials import Trials
from vkgl.infer.trial import TrialInference
from vkgl.lang.ir.arcs import SIGMA_TRAVEL

_TURNED = math.radians(1.0)  # a push that turned less than this gives no pivot (its chord pivot is noise)
_SAME_FACE = 0.005  # m: a push this far off the face plane (or the contact's height) is another face's
_SAME_OFFSET = 1e-3  # m: |d| values closer than this are one offset of the fit
_UPRIGHT = math.cos(math.radians(5.0))  # a turn whose axis leans more from the face's normal axis is no arc
SEEN = 1.0 / 3.0
"""The least share of the innermost explored push's pivot distance that the law's `lever**2 / |d|` term must make
up for the law to hold nearer the centre than that push (`ArcFit.beyond`): the explored bodies' laws make 54 to 95 %
(the Block's 55 %, held out within 1.13 deg near its centre), CrateT's 13 to 23 % (held out 14 deg wrong)."""
CHECK_TRAVEL = SIGMA_TRAVEL  # m: sigma is the turn's error over this much of the contact's travel


@dataclass(frozen=True)
class ArcFit:
    """A face's arc law (m): `lever`, `bias`, `ahead`; offsets `lower..upper` (m) of the pushes it was fitted on;
    `sigma` the RMS leave-one-out error of the turn over 10 cm of travel (rad), None when nothing could be left
    out; `pushes` how many pushes it rests on; `beyond` the offset (m, from the centre) where the law starts to
    hold, 0 when it holds up to the centre (`SEEN`)."""

    lever: float
    bias: float
    ahead: float
    lower: float
    upper: float
    sigma: float | None
    pushes: int
    beyond: float = 0.0


@dataclass(frozen=True)
class _Push:
    """One explored push: its offset `d` (m), the contact's travel (m, along its arc), the turn (rad, positive in the
    law's sense: away from the contact's side) and, when it turned, its pivot across (`r`) and along (`ahead`)."""

    d: float
    travel: float
    turn: float
    r: float | None
    ahead: float | None


def fit_arc(trials: Trials, members: list[TrialInference], kept: TrialInference, along: np.ndarray) -> ArcFit | None:
    """The arc law of the face that `kept` (the centre's slide) pushes, from the pushes `members` of that face.

    `along` is the face's direction (unit, body frame; the family's). None when no push of the face turned the
    right way, or the centre's push has no direction.
    """
    if not (np.all(np.isfinite(kept.contact)) and np.all(np.isfinite(kept.force)) and np.linalg.norm(kept.force)):
        return None
    normal = kept.force / np.linalg.norm(kept.force)
    up = np.cross(normal, along)
    pushes = [p for r in members if (p := _measured(trials, r, kept.contact, normal, along, up)) is not None]
    law = _fit(pushes)
    if law is None:
        return None
    used = [p for p in pushes if p.r is None or p.r > 0]
    offsets = [p.d for p in used]
    return ArcFit(
        lever=law[0],
        bias=law[1],
        ahead=law[2],
        lower=min(min(offsets), 0.0),
        upper=max(max(offsets), 0.0),
        sigma=_leave_one_out(used),
        pushes=len(used),
        beyond=_holds_from(law, used),
    )


def radius(lever: float, bias: float, offset: float) -> float:
    """The pivot's distance across the push from the centre line (m) at `offset`; inf at the centre."""
    return math.inf if offset == 0.0 else lever * lever / abs(offset) + bias


def turn_per_travel(lever: float, bias: float, ahead: float, offset: float) -> float:
    """The turn (rad) per metre of the contact's travel at `offset`, positive away from the contact's side."""
    r = radius(lever, bias, offset)
    return 0.0 if math.isinf(r) or r <= 0.0 else 1.0 / math.hypot(r, ahead)


def _measured(
    trials: Trials, r: TrialInference, origin: np.ndarray, normal: np.ndarray, along: np.ndarray, up: np.ndarray
) -> _Push | None:
    """What trial `r` did, in the law's terms; None for a push elsewhere, a skipped trial or a tilted turn."""
    if r.skipped is not None or r.motion is None or r.motion.type not in ("prismatic", "revolute"):
        return None
    if not (np.all(np.isfinite(r.contact)) and np.all(np.isfinite(r.force))):
        return None
    offset = r.contact - origin
    if abs(float(offset @ normal)) > _SAME_FACE or abs(float(offset @ up)) > _SAME_FACE:
        return None
    poses = _ordered_poses(trials, r.index)
    if poses is None:
        return None
    relative = np.linalg.inv(poses[0]) @ poses[-1]  # the end pose in the body's frame at the start
    rotvec = _rotation_vector(relative[:3, :3])
    if np.linalg.norm(rotvec) > 0 and abs(float(rotvec @ up)) < _UPRIGHT * float(np.linalg.norm(rotvec)):
        return None  # the body tilted, not turned
    d = float(offset @ along)
    side = 1.0 if d >= 0 else -1.0
    # a push at +d turns the body about -up (away from the contact's side)
    turn = -side * _unwrapped(float(rotvec @ up), poses, normal, along)
    chord = float(np.linalg.norm(relative[:3, :3] @ origin + relative[:3, 3] - origin))
    travel = chord * _arc_over_chord(turn)
    if abs(turn) < _TURNED:
        return _Push(d, travel, turn, None, None)
    pivot = _pivot(relative, normal, along)
    return _Push(d, travel, turn, -side * float((pivot - origin) @ along), float((pivot - origin) @ normal))


def _ordered_poses(trials: Trials, i: int) -> np.ndarray | None:
    """The body's observed poses of trial `i` in time order; None with fewer than two."""
    t, poses = trials.t[i], trials.T_ow[i]
    seen = np.isfinite(t) & np.isfinite(poses.reshape(len(poses), -1)).all(axis=1)
    if seen.sum() < 2:
        return None
    order = np.argsort(t[seen], kind="stable")
    return np.asarray(poses[seen][order])


def _unwrapped(turn: float, poses: np.ndarray, normal: np.ndarray, along: np.ndarray) -> float:
    """`turn` (rad about up = normal x along, from the start and end poses alone: within +-pi) plus the whole turns
    the body made on the way, counted along the track `poses`: a long push that turned a body 206 deg reads -154 deg
    from its ends, and would fit, and check the law against, a turn the wrong way (CrateT's 17 s edge pushes)."""
    start = poses[0][:3, :3].T
    faced = np.einsum("ij,njk,k->ni", start, poses[:, :3, :3], normal)  # the start's normal, carried by the body
    track = np.unwrap(np.arctan2(faced @ along, faced @ normal))
    return turn + 2.0 * math.pi * round((float(track[-1]) - turn) / (2.0 * math.pi))


def _rotation_vector(rotation: np.ndarray) -> np.ndarray:
    """The rotation's axis times its angle (rad)."""
    from scipy.spatial.transform import Rotation

    return np.asarray(Rotation.from_matrix(rotation).as_rotvec())


def _arc_over_chord(turn: float) -> float:
    """An arc's length over its chord's for a turn (rad): 1 for a straight push."""
    half = abs(turn) / 2.0
    return 1.0 if half < 1e-9 else half / math.sin(half)


def _pivot(relative: np.ndarray, normal: np.ndarray, along: np.ndarray) -> np.ndarray:
    """The point of the face's plane of motion that the start and the end pose share (body frame at the start)."""
    frame = np.stack([normal, along])  # 2 x 3: the plane's axes
    rotation = frame @ relative[:3, :3] @ frame.T
    shift = frame @ relative[:3, 3]
    planar = np.linalg.solve(np.eye(2) - rotation, shift)
    return frame.T @ planar


def _fit(pushes: list[_Push]) -> tuple[float, float, float] | None:
    """(lever, bias, ahead) fitted on the pushes that turned the law's way; None without one."""
    turned = [p for p in pushes if p.r is not None and p.r > 0 and abs(p.d) >= _SAME_OFFSET]
    if not turned:
        return None
    inverse = np.array([1.0 / abs(p.d) for p in turned])
    radii = np.array([p.r for p in turned], dtype=float)
    ahead = float(np.mean([p.ahead for p in turned]))
    if float(np.ptp(inverse)) * _SAME_OFFSET < 1e-9 or _distinct_offsets(turned) < 2:
        square = float(inverse @ radii / (inverse @ inverse))  # r = lever**2 / |d|: one offset fixes one number
        bias = 0.0
    else:
        design = np.stack([inverse, np.ones_like(inverse)], axis=1)
        (square, bias), *_ = np.linalg.lstsq(design, radii, rcond=None)
        square, bias = float(square), float(bias)
    if square <= 0.0:
        return None  # the pivot would come closer as the push moves in: not an arc law
    return math.sqrt(square), bias, ahead


def _holds_from(law: tuple[float, float, float], pushes: list[_Push]) -> float:
    """The offset (m) from which the law holds: 0 when its `lever**2 / |d|` term makes up `SEEN` or more of the
    pivot's distance at the innermost off-centre push, that push's offset otherwise (the module's docstring)."""
    offsets = [abs(p.d) for p in pushes if abs(p.d) >= _SAME_OFFSET]
    if not offsets:
        return 0.0
    lever, bias, _ = law
    innermost = min(offsets)
    curve = lever * lever / innermost
    return 0.0 if curve >= SEEN * (curve + bias) else innermost


def _distinct_offsets(pushes: list[_Push]) -> int:
    values = sorted(abs(p.d) for p in pushes)
    return 1 + sum(1 for a, b in itertools.pairwise(values) if b - a >= _SAME_OFFSET)


def _leave_one_out(pushes: list[_Push]) -> float | None:
    """RMS error (rad) of each off-centre push's turn over 10 cm predicted by the law fitted on the others."""
    errors = []
    for i, push in enumerate(pushes):
        if abs(push.d) < _SAME_OFFSET or push.travel <= 0.0:
            continue
        law = _fit(pushes[:i] + pushes[i + 1 :])
        if law is None:
            continue
        predicted = turn_per_travel(*law, push.d) * push.travel
        errors.append((predicted - push.turn) * CHECK_TRAVEL / push.travel)
    return float(np.sqrt(np.mean(np.square(errors)))) if errors else None
