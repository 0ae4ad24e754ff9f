"""Contact families in the task space: the action and the motion of an engagement at an offset along its face.

An engagement of an affordance with a `family` (docs/language.md, "Families")
has one more variable in the task-space optimisation: the offset of its
contact along the face, fixed from its ADD to its REMOVE (`Sequence.offsets`).
At offset `s` the effector's frame is the action's pose moved by `s * along`
and a turn's pivot is moved by `s * drift` (`vkgl.lang.ir.families.at_offset`,
here as matrices, for the rollouts' inner loop). Once the optimiser has chosen
the offsets, the sequence is rewritten with the members' names
(`push_center_px@+3.12cm`, `rollout.materialise`) and every later stage reads
a point affordance.

A member of a slide's arc family (`NAME@+0.32cm`, offered by
`vkgl.plan.problem.arcs`) is a turn whose pivot the offset places
(`vkgl.lang.ir.arcs`): it is an `ArcSeed`. Its offset is a variable too, the
change `d` from the member's own offset `s0` (so `d = 0` is the member as
named), within its band (`ArcSeed.band`, `ARC_BAND`): the same side of the centre (the same turning
sense: the mode's edge type stays a turn), between half and twice `s0`'s
distance from the centre and inside the family's explored band. At `s0 + d`
the contact moves by `d * along` and the pivot to where the arc law puts it
for `s0 + d` (not linear in `d`: `pivot_shift`). The solution is named by the
member at `s0 + d` (`rollout.materialise`), which the executor resolves by the
same law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.families import OVER_MARK, is_straight_member, member_offset, offset_bounds
from vkgl.lang.ir.nodes import Affordance, FixedC, PrismaticC, RevoluteC
from vkgl.plan.problem.problem import Problem

_VECTORS: dict[int, tuple[Affordance, np.ndarray, np.ndarray | None]] = {}


def family_vectors(affordance: Affordance) -> tuple[np.ndarray, np.ndarray | None]:
    """(unit `along`, a turn's `drift` or None) of a family; zeros and None without one (cached by identity)."""
    cached = _VECTORS.get(id(affordance))
    if cached is not None and cached[0] is affordance:
        return cached[1], cached[2]
    family = affordance.family
    along, drift = np.zeros(3), None
    if family is not None:
        along = family.along.array() / np.linalg.norm(family.along.array())
        if family.drift is not None and isinstance(affordance.motion, RevoluteC):
            drift = family.drift.array()
    _VECTORS[id(affordance)] = (affordance, along, drift)  # kept so that its id stays its own
    return along, drift


def has_family(problem: Problem, body: str, name: str) -> bool:
    """Whether the planner may move the affordance's contact along its face: a turn whose band is wider than a
    point.

    A slide's family is not used (yet): it was learned from exploration's force-limited pushes, which DART's
    friction holds straight off the centre, but the arm pushes by position, and that push turns the body
    (the stdlib Block pushed 10 cm by the arm 1.1, 2.2 and 3.3 cm off its centre turned 2, 17 and 24 deg;
    docs/planning.md, "Contacts along a face"). A turn's member executes as predicted (7.7 cm off the
    centre, between two explored contacts: 1.5 deg off over a 20 deg turn).
    """
    affordance = problem.affordance(body, name)
    lower, upper = offset_bounds(affordance)
    if upper > lower and isinstance(affordance.motion, RevoluteC):
        return True
    return arc_seed(problem, body, name) is not None


def contact_band(problem: Problem, body: str, name: str) -> tuple[float, float]:
    """The offsets (m) the planner may move the contact of affordance `name` by: a turn's family band, an arc
    member's `ArcSeed.band` (relative to its own offset), (0, 0) otherwise."""
    seed = arc_seed(problem, body, name)
    if seed is not None:
        return seed.band
    return offset_bounds(problem.affordance(body, name)) if has_family(problem, body, name) else (0.0, 0.0)


def contact_direction(problem: Problem, body: str, name: str) -> np.ndarray:
    """The unit direction (body frame) its contact moves along with the offset; zeros without a family."""
    seed = arc_seed(problem, body, name)
    return seed.along if seed is not None else family_vectors(problem.affordance(body, name))[0]


def pivot_travel(problem: Problem, body: str, name: str) -> float:
    """The farthest (m) a turn's pivot moves over its contact band: `|drift|` times the band's farthest end, an arc
    member's at its band's ends (the pivot moves along a line, monotonically in the offset); 0 otherwise."""
    seed = arc_seed(problem, body, name)
    if seed is not None:
        return max(float(np.linalg.norm(seed.shift(d))) for d in seed.band)
    affordance = problem.affordance(body, name)
    _, drift = family_vectors(affordance)
    if drift is None or not has_family(problem, body, name):
        return 0.0
    return max(abs(v) for v in offset_bounds(affordance)) * float(np.linalg.norm(drift))


ARC_BAND = (0.5, 2.0)
"""An arc member's contact may move from half to twice its distance from the face's centre (within the family's
explored band): the pivot then lies between about twice and half its member's distance. Bounded so that the
search's bounds (`vkgl.plan.search`) know how far one such turn can move a body, and kept to where the law
interpolates between the contacts it was fitted on."""


@dataclass(frozen=True)
class ArcSeed:
    """A member of a slide's arc family as a turn whose offset the task space may change: `offset` its own (m, not
    0), `band` the changes allowed (m, `d_low <= 0 <= d_high`), `along` the face's direction (unit, body frame);
    the pivot at offset `s` lies at `base - sign(s) * (lever**2 / |s| + bias) * along`."""

    slide: str
    offset: float
    band: tuple[float, float]
    along: np.ndarray
    lever_sq: float
    bias: float
    ahead: float
    travel: float  # the slide's range (m): a turn goes as far as the contact travels that far; inf when `open`

    def radius(self, offset: float) -> float:
        """The pivot's distance across the push (m) at `offset` (same side as the member's)."""
        return self.lever_sq / abs(offset) + self.bias

    def shift(self, change: float) -> np.ndarray:
        """How far the pivot moves (body frame, m) when the contact moves by `change` from the member's offset."""
        side = 1.0 if self.offset > 0 else -1.0
        return -side * (self.radius(self.offset + change) - self.radius(self.offset)) * self.along


_SEEDS: dict[int, tuple[Affordance, ArcSeed | None]] = {}


def arc_seed(problem: Problem, body: str, name: str) -> ArcSeed | None:
    """The `ArcSeed` of affordance `name` when it is a member of a slide's arc family (`NAME@+0.32cm`), else None
    (cached by the member's identity: `Problem.affordance` keeps it)."""
    if "@" not in name:
        return None
    member = problem.affordance(body, name)
    cached = _SEEDS.get(id(member))
    if cached is not None and cached[0] is member:
        return cached[1]
    seed = _arc_seed(problem, body, name)
    _SEEDS[id(member)] = (member, seed)  # kept so that its id stays its own
    return seed


def _arc_seed(problem: Problem, body: str, name: str) -> ArcSeed | None:
    return arc_seed_in(problem.bodies[body].affordances, problem.affordance(body, name), name)


def arc_seed_in(affordances: tuple[Affordance, ...], member: Affordance, name: str | None = None) -> ArcSeed | None:
    """`arc_seed` of `member` (called `name`, by default its own) among its body's `affordances`, where its
    slide is (no Problem needed: the search's bounds ask it per body)."""
    name = member.name if name is None else name
    # A rolled tool's member (`NAME@-1.74cm/over+20deg+0.50cm`) keeps its offset: its roll and lift were found
    # for that contact alone (vkgl.plan.problem.over).
    if is_straight_member(name) or OVER_MARK in name or not isinstance(member.motion, RevoluteC):
        return None
    base, offset = member_offset(name)
    if base == name or offset == 0.0:
        return None
    slide = next((a for a in affordances if a.name == base), None)
    family = None if slide is None else slide.family
    if slide is None or family is None or family.arc is None:
        return None
    if not isinstance(slide.motion, PrismaticC) or not isinstance(slide.action, FixedC):
        return None
    side = 1.0 if offset > 0 else -1.0
    end = family.upper.value if side > 0 else -family.lower.value  # the band's end on the member's side
    near, far = ARC_BAND[0] * abs(offset), min(ARC_BAND[1] * abs(offset), end)
    if far <= near:
        return None
    band = (near - abs(offset), far - abs(offset)) if side > 0 else (abs(offset) - far, abs(offset) - near)
    along = family.along.array() / np.linalg.norm(family.along.array())
    arc = family.arc
    rng = slide.motion.range
    travel = math.inf if rng is None or rng.open else float(rng.upper.value)
    return ArcSeed(base, offset, band, along, arc.lever.value**2, arc.bias.value, arc.ahead.value, travel)


def turn_cap(problem: Problem, body: str, name: str) -> float:
    """The largest turn (rad) an arc member may make anywhere in its band: the slide's range as travel along the
    arc at the band's end nearest the centre (the longest lever: `vkgl.lang.ir.arcs`); inf for an `open` slide
    and for anything but an arc member."""
    seed = arc_seed(problem, body, name)
    if seed is None or math.isinf(seed.travel):
        return math.inf
    nearest = min(abs(seed.offset + d) for d in seed.band)
    return seed.travel / math.hypot(seed.radius(nearest), seed.ahead)


def action_at(problem: Problem, body: str, name: str, offset: float) -> np.ndarray:
    """The effector frame in the body's frame at `offset` (m) along the family of affordance `name`."""
    base = problem.action(body, name)
    if offset == 0.0:
        return base
    affordance = problem.affordance(body, name)
    seed = arc_seed(problem, body, name)
    if seed is not None:
        along = seed.along
    elif isinstance(affordance.motion, PrismaticC):  # a slide a tool's flat face enacts off the centre (`tool_faces`)
        along = base[:3, 1]
    else:
        along, _ = family_vectors(affordance)
    out = base.copy()
    out[:3, 3] += offset * along
    return out


def pivot_shift(problem: Problem, body: str, name: str, offset: float) -> np.ndarray | None:
    """How far a turn's pivot moves at `offset` (None when it does not: a slide, no drift, offset 0)."""
    if offset == 0.0:
        return None
    seed = arc_seed(problem, body, name)
    if seed is not None:
        return seed.shift(offset)
    _, drift = family_vectors(problem.affordance(body, name))
    return None if drift is None else offset * drift
