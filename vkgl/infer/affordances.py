"""From per-trial graphs to a body's affordances: grouping, naming, IR.

Trials are grouped by where and how the robot acted and by what the body did:

- a PUSH trial (contact on a face, force along its inward normal) is keyed by
  its push direction (`px` = along +x, ...), where along the face the contact
  was (`center`, or near the `left` / `right` end, left being the side to the
  left of the push direction, z up), the action type, the motion type, the
  sense of rotation, and whether it pushed or pulled. Each group keeps its
  highest-likelihood trial.
- a PULL is a push whose contact lies beyond the body's origin in the
  direction of the force (by more than 1 mm): the fingertip pushed a surface
  that faces the body, such as the inner face of a handle's bar it hooked
  behind, and the body followed it. Pulls at different places are not
  merged: each is a handle frame the body declares (`contacts at`), and a
  tool may fit behind one and not another.
- a WIELD exploration (one grasp, many force directions: the contact point is
  shared by trials whose forces differ) is one group whose constraint must
  explain every trial at once: its models are fitted to all its trials
  together, so a tool swung in every direction comes out `free`.

Groups whose body did not move (`motion fixed`) are dropped: nothing to plan
with. Names: `push_center_px`, `push_px_left`, `turn_px_left`, `move_px_right`
(free), `pull_center_px` (a pull, whatever its motion), `wield`; a clash gets
a numeric suffix.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.formats.trials import Trials
from vkgl.infer.data import EdgeData, edge_data, trial_edges
from vkgl.infer.faces.arc import ArcFit, fit_arc
from vkgl.infer.faces.family import FamilyFit, fit_family, with_arc
from vkgl.infer.select import EdgeInference, infer_edge
from vkgl.infer.trial import TrialInference
from vkgl.lang.ir.nodes import (
    Affordance,
    Arc,
    Evidence,
    Family,
    FixedC,
    FreeC,
    MotionRange,
    Pose,
    PrismaticC,
    Quantity,
    RevoluteC,
    Vector,
)
from vkgl.lang.ir.units import SCALE, to_si

_SAME_POINT = 1e-3  # m: contacts closer than this are the same grasp
_SAME_DIRECTION = np.deg2rad(10.0)
_AXIS_LABEL = np.deg2rad(30.0)  # a push within this of a body axis is named after it
_CENTER_FRACTION = 1.0 / 3.0  # |lateral| below this share of the face's explored half-width is "center"
_SAME_AXIS = np.deg2rad(5.0)  # motions whose axes differ less are one constraint ...
_SAME_LINE = 0.01  # ... and, for turns, whose axis lines pass within this (m)
_TIE = 1.0  # nats: log-likelihoods this close are a tie
_VERBS = {"prismatic": "push", "revolute": "turn", "free": "move"}
_PULL_MARGIN = 0.001  # m a pull's contact lies beyond the body's origin along the force, at least


@dataclass
class Group:
    """Trials that make one affordance, and the graph that represents them."""

    name: str
    members: list[int]
    action: EdgeInference | None
    motion: EdgeInference
    loglik: float
    posterior: float
    kept: int | None = None  # the representative trial (None for a joint fit over all members)
    key: tuple = field(default_factory=tuple)
    state_range: tuple[float, float] | None = None  # the motion's states over all members (m or rad)
    still_moving: bool = False  # the member that went furthest was still moving when its trial ended
    family: FamilyFit | None = None  # where along the face the contact may be (vkgl/infer/faces/family.py)

    @property
    def open_range(self) -> bool:
        """Whether the range is written `open`: a slide still going when exploration ended (never a turn)."""
        return self.still_moving and self.motion.type == "prismatic"


def group_trials(trials: Trials, results: list[TrialInference]) -> list[Group]:
    """The affordance groups of a dataset, in reading order (see `_reading_order`)."""
    usable = [r for r in results if r.skipped is None and r.motion is not None]
    wield_sets, pushes = _split_wield(usable)
    groups = [_joint_group(trials, members) for members in wield_sets]
    groups += _push_groups(trials, pushes)
    groups = [g for g in groups if g.motion.type != "fixed"]
    groups.sort(key=_reading_order)
    _name(groups)
    return groups


_DIRECTIONS = ("px", "nx", "py", "ny", "pz", "nz", "any")
_PLACES = ("center", "left", "right", "")
_MOTIONS = ("prismatic", "revolute", "free")
_KINDS = ("push", "pull")


def _reading_order(g: Group) -> tuple:
    """Wielding first; then by direction (+x, -x, ...), push before pull, motion (push, turn, move), place, trial."""
    if g.key == ("wield",):
        return (0, g.members[0])
    label, place, _, motion, _, kind = g.key
    return (1, _DIRECTIONS.index(label), _KINDS.index(kind), _MOTIONS.index(motion), _PLACES.index(place), g.members[0])


# ---------------------------------------------------------------- wield (one grasp, many directions)


def _split_wield(results: list[TrialInference]) -> tuple[list[list[int]], list[TrialInference]]:
    """Clusters of trials at one contact point with differing forces; the rest are pushes."""
    clusters: list[list[TrialInference]] = []
    for r in results:
        if not np.all(np.isfinite(r.contact)):
            clusters.append([r])
            continue
        for cluster in clusters:
            head = cluster[0]
            if np.all(np.isfinite(head.contact)) and np.linalg.norm(head.contact - r.contact) < _SAME_POINT:
                cluster.append(r)
                break
        else:
            clusters.append([r])
    wield, pushes = [], []
    for cluster in clusters:
        if len(cluster) >= 2 and _directions_differ([r.force for r in cluster]):
            wield.append([r.index for r in cluster])
        else:
            pushes.extend(cluster)
    pushes.sort(key=lambda r: r.index)
    return wield, pushes


def _directions_differ(forces: list[np.ndarray]) -> bool:
    units = [f / np.linalg.norm(f) for f in forces if np.all(np.isfinite(f)) and np.linalg.norm(f) > 0]
    return any(np.arccos(np.clip(u @ v, -1.0, 1.0)) > _SAME_DIRECTION for u in units for v in units)


def _joint_group(trials: Trials, members: list[int]) -> Group:
    """One constraint for all the trials of a grasp: models fitted to their samples together."""
    edges = [trial_edges(trials, i) for i in members]
    motion = infer_edge(_stack([e.motion for e in edges]), relative=True)
    actions = [e.action for e in edges if e.action is not None]
    action = infer_edge(_stack(actions), relative=False) if len(actions) == len(edges) else None
    loglik = motion.loglik + (action.loglik if action is not None else 0.0)
    posterior = motion.posterior[motion.type] * (action.posterior[action.type] if action is not None else 1.0)
    return Group(
        name="wield", members=members, action=action, motion=motion, loglik=loglik, posterior=posterior, key=("wield",)
    )


def _stack(parts: list[EdgeData]) -> EdgeData:
    """Several trajectories as one (each keeps its own start), with the noise re-estimated."""
    p = np.concatenate([d.p for d in parts])
    rot = Rotation.concatenate([d.rot for d in parts])
    has_rot = np.concatenate([d.has_rot for d in parts])
    return edge_data(p, rot, has_rot)


# ---------------------------------------------------------------- pushes


def _push_groups(trials: Trials, pushes: list[TrialInference]) -> list[Group]:
    by_direction: dict[tuple[str, str], list[TrialInference]] = defaultdict(list)
    for r in pushes:
        by_direction[(_direction_label(r.force), "pull" if _pulls(r) else "push")].append(r)
    keyed: dict[tuple, list[TrialInference]] = defaultdict(list)
    place_of: dict[int, str] = {}
    for (label, kind), members in by_direction.items():
        for r, place in zip(members, _places(members)):
            assert r.motion is not None
            place_of[r.index] = place
            action_type = r.action.type if r.action is not None else None
            keyed[(label, place, action_type, r.motion.type, _sense(r.motion), kind)].append(r)
    groups = []
    for members in _merge_equivalent(keyed):
        best = _representative(members)
        assert best.motion is not None
        posterior = best.motion.posterior[best.motion.type]
        if best.action is not None:
            posterior *= best.action.posterior[best.action.type]
        label, _, action_type, motion_type, sense, kind = next(k for k, v in keyed.items() if best in v)
        groups.append(
            Group(
                name="",
                members=sorted(r.index for r in members),
                action=best.action,
                motion=best.motion,
                loglik=best.loglik,
                posterior=posterior,
                kept=best.index,
                key=(label, place_of[best.index], action_type, motion_type, sense, kind),
                state_range=_state_range(members),
                still_moving=_still_moving(members),
                family=None if kind == "pull" else _family(members, best),
            )
        )
        if kind == "push" and motion_type == "prismatic" and place_of[best.index] == "center":
            arc = fit_arc(trials, by_direction[(label, kind)], best, _left_of(best.force))
            groups[-1].family = with_arc(groups[-1].family, arc, _left_of(best.force))
    return groups


def _family(members: list[TrialInference], best: TrialInference) -> FamilyFit | None:
    """The group's family along its face (None for one contact, or when the push direction is unknown)."""
    ok = np.all(np.isfinite(best.force)) and np.linalg.norm(best.force) > 0
    return fit_family(members, best, _left_of(best.force)) if ok else None


def _still_moving(members: list[TrialInference]) -> bool:
    """Whether the member whose motion went furthest was still moving when its trial ended.

    That member saw the end of the explored range: if it had stopped (a
    limit, a wall, a stall) the range ends at a bound, whatever shorter
    trials did; if it was still moving, exploration ended before the motion.
    """
    moved = [r for r in members if r.motion is not None and r.motion.best.states.size]
    if not moved:
        return False
    furthest = max(moved, key=lambda r: (float(np.nanmax(r.motion.best.states)), -r.index))  # type: ignore[union-attr]
    return furthest.ending is not None and furthest.ending.moving


def _state_range(members: list[TrialInference]) -> tuple[float, float] | None:
    """The lowest and highest state of the members' MAP motions (m or rad), None when they have none."""
    states = [r.motion.best.states for r in members if r.motion is not None and r.motion.best.states.size]
    finite = np.concatenate(states) if states else np.zeros(0)
    finite = finite[np.isfinite(finite)]
    return (float(finite.min()), float(finite.max())) if finite.size else None


def _merge_equivalent(keyed: dict[tuple, list[TrialInference]]) -> list[list[TrialInference]]:
    """Groups of one push direction that produce the same constraint at different places, merged.

    Pushing a drawer at either end slides it along the same rail, pushing a door
    anywhere turns it about the same hinge: one affordance, not three. Turns
    about different centres (the Block's two ends) stay apart, and so do pulls
    at different places: they were made at frames the body declares to be
    pulled at (`contacts at`), and what fits behind one handle (a hook's
    cross-piece at a bar's overhang) may not fit behind another.
    """
    order = sorted(keyed, key=lambda k: (k[0], str(k[2]), k[3], k[4], k[5], _PLACES.index(k[1])))
    merged: list[tuple[tuple, TrialInference, list[TrialInference]]] = []
    for key in order:
        members = keyed[key]
        head = _representative(members)
        for other_key, other_head, other_members in merged:
            same_kind = (other_key[0], *other_key[2:]) == (key[0], *key[2:])
            apart = key[5] == "pull" and other_key[1] != key[1]
            if same_kind and not apart and _same_constraint(head.motion, other_head.motion):
                other_members.extend(members)
                break
        else:
            merged.append((key, head, list(members)))
    return [members for _, _, members in merged]


def _same_constraint(a: EdgeInference | None, b: EdgeInference | None) -> bool:
    """Whether two MAP motions are one constraint: same axis (5 deg) and, for turns, same axis line (1 cm)."""
    if a is None or b is None or a.type != b.type:
        return False
    if a.type in ("fixed", "free"):
        return True
    axis_a, axis_b = np.asarray(a.params["axis"]), np.asarray(b.params["axis"])
    if np.arccos(np.clip(axis_a @ axis_b, -1.0, 1.0)) > _SAME_AXIS:
        return False
    if a.type == "prismatic":
        return True
    d = np.asarray(b.params["center"]) - np.asarray(a.params["center"])
    return bool(np.linalg.norm(d - (d @ axis_a) * axis_a) < _SAME_LINE)


def _representative(members: list[TrialInference]) -> TrialInference:
    """The highest-likelihood trial; among near ties (physics is symmetric) the most central contact."""
    top = max(r.loglik for r in members)
    tied = [r for r in members if r.loglik >= top - _TIE]
    return min(tied, key=lambda r: (_lateral_distance(r), -r.loglik, r.index))


def _lateral_distance(r: TrialInference) -> float:
    ok = np.all(np.isfinite(r.contact)) and np.all(np.isfinite(r.force)) and np.linalg.norm(r.force) > 0
    return abs(float(r.contact @ _left_of(r.force))) if ok else 0.0


def _pulls(r: TrialInference) -> bool:
    """Whether the contact lies beyond the body's origin along the force: the fingertip pulled it."""
    ok = np.all(np.isfinite(r.contact)) and np.all(np.isfinite(r.force)) and np.linalg.norm(r.force) > 0
    return bool(ok and float(r.contact @ r.force) / float(np.linalg.norm(r.force)) > _PULL_MARGIN)


def _direction_label(force: np.ndarray) -> str:
    """`px`, `ny`, ... for a push along a body axis; `any` when unknown or oblique."""
    norm = float(np.linalg.norm(force)) if np.all(np.isfinite(force)) else 0.0
    if norm == 0.0:
        return "any"
    d = force / norm
    k = int(np.argmax(np.abs(d)))
    if np.arccos(min(abs(d[k]), 1.0)) > _AXIS_LABEL:
        return "any"
    return ("p" if d[k] > 0 else "n") + "xyz"[k]


def _left_of(force: np.ndarray) -> np.ndarray:
    """The direction to the left of a push (z up); for vertical pushes, +y."""
    d = force / np.linalg.norm(force)
    left = np.cross([0.0, 0.0, 1.0], d)
    n = np.linalg.norm(left)
    return left / n if n > 0.1 else np.array([0.0, 1.0, 0.0])


def _places(members: list[TrialInference]) -> list[str]:
    """`center`, `left` or `right` of each trial's contact along its face ("" when unknown)."""
    lateral = []
    for r in members:
        ok = np.all(np.isfinite(r.contact)) and np.all(np.isfinite(r.force)) and np.linalg.norm(r.force) > 0
        lateral.append(float(r.contact @ _left_of(r.force)) if ok else np.nan)
    known = [abs(s) for s in lateral if np.isfinite(s)]
    half_width = max(known) if known else 0.0
    places = []
    for s in lateral:
        if not np.isfinite(s):
            places.append("")
        elif half_width < _SAME_POINT or abs(s) <= _CENTER_FRACTION * half_width:
            places.append("center")
        else:
            places.append("left" if s > 0 else "right")
    return places


def _sense(motion: EdgeInference) -> int:
    """The sense of a rotation (sign of its axis' largest component), 0 for other motions."""
    if motion.type != "revolute":
        return 0
    axis = np.asarray(motion.params["axis"])
    return 1 if axis[int(np.argmax(np.abs(axis)))] > 0 else -1


# ---------------------------------------------------------------- names


def _name(groups: list[Group]) -> None:
    taken: dict[str, int] = {}
    for g in groups:
        base = g.name if g.key == ("wield",) else _push_name(g)
        count = taken.get(base, 0) + 1
        taken[base] = count
        g.name = base if count == 1 else f"{base}_{count}"


def _push_name(g: Group) -> str:
    label, place = g.key[0], g.key[1]
    verb = "pull" if g.key[5] == "pull" else _VERBS.get(g.motion.type, "push")
    if label == "any":
        return verb
    if place == "center":
        return f"{verb}_center_{label}"
    if place in ("left", "right"):
        return f"{verb}_{label}_{place}"
    return f"{verb}_{label}"


# ---------------------------------------------------------------- IR


def affordance_ir(g: Group) -> Affordance:
    """The group as an `affordance NAME { action ...  motion ...  evidence ... }` IR node."""
    action = constraint_ir(g.action) if g.action is not None else FixedC()
    evidence = Evidence(trials=len(g.members), loglik=_round(g.loglik, 1), posterior=_round(g.posterior, 3))
    motion = constraint_ir(g.motion, g.state_range, open_range=g.open_range)
    family = _family_ir(g.family) if g.family is not None and isinstance(action, FixedC) else None
    return Affordance(name=g.name, action=action, motion=motion, family=family, evidence=evidence)


def _family_ir(f: FamilyFit) -> Family:
    """The family rounded for reading: offsets to 0.01 cm (inwards: never wider than explored), drift to 1e-3,
    sigma to 0.01 cm (a turn's pivot) or 0.01 deg (a slide's direction)."""
    lower = math.ceil(round(100.0 * f.lower * 100.0, 6)) / 100.0
    upper = math.floor(round(100.0 * f.upper * 100.0, 6)) / 100.0
    sigma = None
    if f.sigma is not None:
        unit = "cm" if f.drift is not None else "deg"
        shown = 100.0 * f.sigma if unit == "cm" else math.degrees(f.sigma)
        sigma = Quantity(value=_si(shown, 2, unit), unit=unit)
    return Family(
        along=direction_ir(f.along),
        lower=Quantity(value=_si(lower, 2, "cm"), unit="cm"),
        upper=Quantity(value=_si(upper, 2, "cm"), unit="cm"),
        drift=None if f.drift is None else Vector(values=tuple(_si(float(x), 3, "") for x in f.drift), unit=""),
        arc=None if f.arc is None else _arc_ir(f.arc),
        sigma=sigma,
    )


def _arc_ir(arc: ArcFit) -> Arc:
    """The arc law rounded to 0.01 cm; its `beyond` outwards (never nearer the centre than the push it names)."""
    beyond = None
    if arc.beyond > 0.0:
        shown = math.ceil(round(100.0 * arc.beyond * 100.0, 6)) / 100.0
        beyond = Quantity(value=_si(shown, 2, "cm"), unit="cm")
    return Arc(lever=_centimetres(arc.lever), bias=_centimetres(arc.bias), ahead=_centimetres(arc.ahead), beyond=beyond)


def _centimetres(metres: float) -> Quantity:
    return Quantity(value=_si(100.0 * metres, 2, "cm"), unit="cm")


def constraint_ir(
    edge: EdgeInference, state_range: tuple[float, float] | None = None, *, open_range: bool = False
) -> Any:
    """The MAP constraint of an edge as IR, rounded for reading (0.1 mm, 1e-3 in directions, 0.1 deg).

    A prismatic or revolute motion with a `state_range` gets the explored range (see `range_ir`);
    `open_range` marks a slide's range `open` (still moving when exploration ended).
    """
    params = edge.params
    if edge.type == "fixed":
        return FixedC(pose=pose_ir(np.asarray(params["pose"])))
    if edge.type == "prismatic":
        bounds = range_ir(state_range, "cm", open_range=open_range) if state_range is not None else None
        return PrismaticC(axis=direction_ir(params["axis"]), origin=point_ir(params["origin"]), range=bounds)
    if edge.type == "revolute":
        bounds = range_ir(state_range, "deg") if state_range is not None else None
        return RevoluteC(center=point_ir(params["center"]), axis=direction_ir(params["axis"]), range=bounds)
    return FreeC()


def range_ir(state_range: tuple[float, float], unit: str, *, open_range: bool = False) -> MotionRange:
    """The explored range of a motion's state, rounded inwards: never wider than what was seen.

    `unit` is `cm` (slides, to 0.1 cm = 1 mm) or `deg` (turns, to 0.1 deg).
    The upper bound is rounded down, the lower bound up and then to at least
    0 (plans use non-negative values only); an upper bound below that is 0.
    `open_range`: written `open` (the body was still moving at the upper bound).
    """
    low, high = (v / float(SCALE[unit]) for v in state_range)
    lower = max(0.0, math.ceil(round(low * 10.0, 9)) / 10.0)
    upper = max(lower, math.floor(round(high * 10.0, 9)) / 10.0)
    return MotionRange(
        lower=Quantity(value=_si(lower, 1, unit), unit=unit),
        upper=Quantity(value=_si(upper, 1, unit), unit=unit),
        open=open_range,
    )


def pose_ir(T: np.ndarray) -> Pose:
    """A 4x4 pose as IR: the position to 0.01 cm, a `yaw` when z stays up, else an `rpy`, to 0.1 deg."""
    roll, pitch, yaw = Rotation.from_matrix(T[:3, :3]).as_euler("xyz", degrees=True)
    if round(yaw, 1) <= -180.0:
        yaw += 360.0  # one way to write a half turn: 180deg
    position = point_ir(T[:3, 3])
    if max(abs(roll), abs(pitch)) < 1.0:  # degrees: the effector frame keeps z up
        return Pose(position=position, yaw=Quantity(value=_si(yaw, 1, "deg"), unit="deg"))
    values = tuple(_si(a, 1, "deg") for a in (roll, pitch, yaw))
    return Pose(position=position, rpy=Vector(values=values, unit="deg"))


def point_ir(p: Any) -> Vector:
    """A point in cm, to 0.01 cm (0.1 mm)."""
    return Vector(values=tuple(_si(100.0 * float(x), 2, "cm") for x in p), unit="cm")


def direction_ir(a: Any) -> Vector:
    """A unit direction to three decimals."""
    a = np.asarray(a, dtype=float)
    a = a / np.linalg.norm(a)
    return Vector(values=tuple(_si(float(x), 3, "") for x in a), unit="")


def _si(value_in_unit: float, decimals: int, unit: str) -> float:
    """`value_in_unit` rounded, as the SI float that the parser reads back from its printed text."""
    text = f"{value_in_unit:.{decimals}f}"
    if float(text) == 0.0:
        text = "0"  # no "-0"
    return to_si(text, unit)


def _round(x: float, decimals: int) -> float:
    value = float(f"{x:.{decimals}f}")
    return 0.0 if value == 0.0 else value
