"""Graph sequences and their rollout: body and hand poses from the motion values (task space).

A sequence G0 .. G_{D-1} has one mode per graph. The transition into mode k
(the sequence's k-th action) happens at a configuration where the constraints
of both graphs hold; during mode k every engaged prismatic or revolute
affordance moves its body by a value >= 0 (one variable each), and whatever is
fixed to it follows. `rollout(problem, seq, values)` composes those
constraints as matrix products (paper §2.3: task space ignores the arm) and
returns per mode the poses at its start and end and the hand's poses along it.

Motions are object-centric: the affordance's parameters are in the body's
frame, so a body at `P` moved by value `v` ends at `P @ motion_matrix(c, v)`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from vkgl.lang.ir.families import member_name
from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.plan.graphs.carry import CARRY_VALUES, carriable, carried_pose, carry_bounds
from vkgl.plan.graphs.graph import Action, Engagement, KGraph, g0, is_grasp, motion_type
from vkgl.plan.graphs.members import action_at, arc_seed, contact_band, has_family
from vkgl.plan.graphs.mode_shapes import (
    CACHED_OFFSETS,
    HAND_FREE,
    HAND_HELD,
    HAND_RETURNED,
    ModeShape,
    mode_shapes,
)
from vkgl.plan.graphs.motions import member_motions
from vkgl.plan.graphs.tool_faces import slide_band
from vkgl.plan.problem.problem import Problem
from vkgl.rotations import yaw_matrix

PRISMATIC_MAX = 2.0
"""m: the longest slide of one mode (beyond any table the examples use)."""

REVOLUTE_MAX = math.pi
"""rad: the largest turn of one mode (a turn about a fixed contact beyond half a revolution is not a push)."""


@dataclass(frozen=True)
class Sequence:
    """A graph sequence as the search builds it, with what its prefix already knows.

    `variables[i] = (mode, engagement)`: the motion value i moves the
    engagement's body during that mode. `dependent`: bodies whose current pose
    depends on some motion value (the others are where the rollout with all
    values 0 puts them, exactly). `zero_poses`: the poses after the last mode
    with every value 0. `offsets[j] = (mode, engagement)`: the engagement
    added at the transition into that mode has a family, and task-space
    value `len(variables) + j` is its contact's offset along the face (m);
    a rollout given only the motion values puts every offset at 0.
    `carries[j] = (mode, grasp)`: the grasped body is carried during that
    mode and set down where values `len(variables) + len(offsets) + 3 j ..
    + 3` put it (`vkgl.plan.graphs.carry`). `returns[j] = (mode, pose)`: the
    tool let go of at the transition into that mode is set down at that world
    pose (where it was picked up: `vkgl.plan.graphs.put_back`), not where it
    was used, and the hand lets go of it there.
    """

    actions: tuple[Action, ...] = ()
    graphs: tuple[KGraph, ...] = (g0(),)
    variables: tuple[tuple[int, Engagement], ...] = ()
    offsets: tuple[tuple[int, Engagement], ...] = ()
    dependent: frozenset[str] = frozenset()
    zero_poses: dict[str, np.ndarray] = field(default_factory=dict, compare=False)
    carries: tuple[tuple[int, Engagement], ...] = ()
    returns: tuple[tuple[int, np.ndarray], ...] = field(default=(), compare=False)

    @property
    def size(self) -> int:
        """How many values the sequence has: its motion values, its contacts' offsets, then three per carry."""
        return len(self.variables) + len(self.offsets) + CARRY_VALUES * len(self.carries)

    @property
    def depth(self) -> int:
        """Graphs in the sequence, G0 included."""
        return len(self.graphs)

    @property
    def last(self) -> Action | None:
        """The last action, or None for G0 alone."""
        return self.actions[-1] if self.actions else None


def start_sequence(problem: Problem) -> Sequence:
    """The sequence made of G0 alone."""
    return Sequence(zero_poses={n: b.rest.copy() for n, b in problem.bodies.items()})


def extend(problem: Problem, seq: Sequence, action: Action) -> tuple[Sequence, np.ndarray | None]:
    """`seq` followed by `action`, and the hand's pose at the new transition when no motion value affects it.

    The second result is None when the hand is not attached at the transition
    or its pose depends on motion values (then only the optimisation knows it).
    """
    graph = seq.graphs[-1].apply(action)
    mode = len(seq.graphs)
    poses = dict(seq.zero_poses)
    _transition(problem, poses, action)
    dependent = set(seq.dependent)
    e = action.engagement
    effector = problem.effector(e.effector)
    if action.op == "add" and effector.tool is not None:
        dependent.discard(effector.tool)
        if e.body in dependent:
            dependent.add(effector.tool)
    hand = None
    if action.op == "add" and e.body not in dependent:
        hand = hand_pose_at(problem, graph, poses, action.engagement)
    carries = seq.carries
    if is_carry(problem, seq, action):
        carries += ((mode - 1, e),)
        dependent.add(e.body)
    variables = list(seq.variables)
    for engaged in graph.engaged:
        if motion_type(problem, engaged) in ("prismatic", "revolute"):
            variables.append((mode, engaged))
            dependent.add(engaged.body)
            for other in graph.engaged:  # a tool acting on a moving body moves with it
                tool = problem.effector(other.effector).tool
                if tool is not None and other.body == engaged.body:
                    dependent.add(tool)
    offsets = seq.offsets
    if action.op == "add" and (has_family(problem, e.body, e.affordance) or slide_band(problem, e) is not None):
        offsets += ((mode, e),)
    child = Sequence(
        seq.actions + (action,),
        seq.graphs + (graph,),
        tuple(variables),
        offsets,
        frozenset(dependent),
        poses,
        carries,
        seq.returns,  # a prefix's tools put back stay so (`put_back`; its modes are the prefix's)
    )
    return child, hand


def renamed(problem: Problem, seq: Sequence, member: Callable[[int, Engagement], str | None]) -> Sequence:
    """`seq` built again with each engagement added at transition `k` renamed to `member(k, e)` (None: kept) from
    its ADD to its REMOVE, keeping the tools it puts back (`returns`): the one way a sequence is rebuilt with other
    members, so that nothing a rebuild does not know of is dropped."""
    names: dict[Engagement, Engagement] = {}
    out = start_sequence(problem)
    for k, action in enumerate(seq.actions, start=1):
        e = action.engagement
        if action.op == "add" and (name := member(k, e)) is not None:
            names[e] = Engagement(e.effector, e.body, name)
        engaged = names.get(e, e)
        if action.op == "remove":
            names.pop(e, None)
        out, _ = extend(problem, out, Action(action.op, engaged))
    return replace(out, returns=seq.returns)


def is_carry(problem: Problem, seq: Sequence, action: Action) -> bool:
    """Whether `action` lets go of a body grasped by the action just before it (pick and place): the body is
    carried in between and set down where the carry's values put it."""
    e = action.engagement
    last = seq.last
    return (
        action.op == "remove"
        and last is not None
        and last.op == "add"
        and last.engagement == e
        and motion_type(problem, e) == "free"
        and carriable(problem, e.body)
    )


def _transition(problem: Problem, poses: dict[str, np.ndarray], action: Action, offset: float = 0.0) -> None:
    """Apply what happens at a transition: a tool jumps to its contact (at `offset` along a family); a released
    tool is put down."""
    e = action.engagement
    tool = problem.effector(e.effector).tool
    if action.op == "add" and tool is not None:
        poses[tool] = tool_pose_on(problem, e, poses[e.body], offset)
    elif action.op == "remove" and motion_type(problem, e) == "free":
        poses[e.body] = put_down(poses[e.body], problem.bodies[e.body].rest_z)


def tool_pose_on(problem: Problem, engagement: Engagement, target_pose: np.ndarray, offset: float = 0.0) -> np.ndarray:
    """Where a tool is when its frame enacts `engagement` (at `offset` along its family) on a target at
    `target_pose`."""
    effector = problem.effector(engagement.effector)
    return target_pose @ action_at(problem, engagement.body, engagement.affordance, offset) @ effector.frame_inverse


def put_down(pose: np.ndarray, rest_z: float) -> np.ndarray:
    """`pose` lowered onto the table: same x, y and heading, level, its frame at `rest_z`."""
    out = np.eye(4)
    yaw = math.atan2(pose[1, 0], pose[0, 0])
    out[:3, :3] = yaw_matrix(yaw)
    out[:3, 3] = (pose[0, 3], pose[1, 3], rest_z)
    return out


def hand_chain(
    problem: Problem, graph: KGraph, engagement: Engagement, offset: float = 0.0
) -> tuple[np.ndarray, bool] | None:
    """The robot effector's pose in the target body's frame while `engagement` holds (at `offset` along its
    family), and whether its yaw is free.

    The robot's own effector: the action pose (a round fingertip pushes the
    same at any yaw, so yaw is free unless it grasps: `is_grasp`). A tool frame: the
    action, back to the tool's frame, then the grasp by which the hand holds
    the tool (exact pose). None when the tool is not held.
    """
    effector = problem.effector(engagement.effector)
    action = action_at(problem, engagement.body, engagement.affordance, offset)
    if effector.tool is None:
        return action, not is_grasp(problem, engagement.body, engagement.affordance)
    held = graph.engaging(effector.tool)
    if held is None:
        return None
    return action @ effector.frame_inverse @ problem.action(held.body, held.affordance), False


def hand_pose_at(problem: Problem, graph: KGraph, poses: dict[str, np.ndarray], e: Engagement) -> np.ndarray | None:
    """The hand's world pose when engagement `e` holds with the bodies at `poses` (None if not attached)."""
    chain = hand_chain(problem, graph, e)
    return None if chain is None else poses[e.body] @ chain[0]


RANGE_MARGIN = 0.0
"""m or rad: how far past its `range` upper bound one mode may move a motion (none: learned bounds are rounded down)."""


def value_bounds(constraint: object) -> tuple[float, float]:
    """The values one mode may give a motion: [0, cap] (`PRISMATIC_MAX` / `REVOLUTE_MAX`) within its `range`.

    An `open` range (a slide that was still going when its exploration ended)
    bounds the motion from below only: it may slide as far as the cap, and the
    table (`body_limits._stay_constraints`), the body's physical joint, if it has
    one, and the collision checks of its sweep decide how far it really goes.
    """
    cap = REVOLUTE_MAX if isinstance(constraint, RevoluteC) else PRISMATIC_MAX
    bounds = constraint.range if isinstance(constraint, (PrismaticC, RevoluteC)) else None
    if bounds is None:
        return 0.0, cap
    if bounds.open:  # a slide, or the turn of an open slide's arc member (`vkgl.lang.ir.arcs`)
        return min(max(0.0, bounds.lower.value), cap), cap
    upper = min(cap, bounds.upper.value + RANGE_MARGIN)
    return min(max(0.0, bounds.lower.value), upper), upper


def bounds(problem: Problem, seq: Sequence, *, offsets: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the sequence's motion values (`value_bounds` of each one's motion); with
    `offsets`, followed by those of its contacts' offsets (each family's band)."""
    pairs = [value_bounds(problem.affordance(e.body, e.affordance).motion) for _, e in seq.variables]
    if offsets:
        pairs += [_band(problem, e) for _, e in seq.offsets]
    lower = np.asarray([p[0] for p in pairs], dtype=float)
    upper = np.asarray([p[1] for p in pairs], dtype=float)
    pinned = problem.pinned[: len(seq.variables)]  # a prefix's values, kept (`Problem.pinned`)
    lower[: len(pinned)] = upper[: len(pinned)] = pinned
    carry_low, carry_high = carry_bounds(len(seq.carries))
    return np.concatenate([lower, carry_low]), np.concatenate([upper, carry_high])


def _band(problem: Problem, e: Engagement) -> tuple[float, float]:
    """The offsets an engagement's contact may take: a tool's slide off the centre (`tool_faces`), else its
    family's band (an arc member's: `members.ArcSeed.band`, relative to its own offset)."""
    return slide_band(problem, e) or contact_band(problem, e.body, e.affordance)


def materialise(problem: Problem, seq: Sequence, values: np.ndarray) -> tuple[Sequence, np.ndarray]:
    """`seq` with each family engagement renamed to its member at the offset `values` gives it (to 0.01 cm,
    `push_center_px@+3.12cm`), and the values without the offsets (the motions, then the carries): what every
    stage after the task space reads.

    The engagement keeps its member's name from its ADD to its REMOVE. A sequence without offsets comes back
    as it is.
    """
    n, m = len(seq.variables), len(seq.offsets)
    kept = np.concatenate([values[:n], values[n + m :]])  # the motions and the carries
    if not seq.offsets:
        return seq, kept
    offset_of = {key: float(v) for key, v in zip(seq.offsets, values[n : n + m])}

    def at_offset(k: int, e: Engagement) -> str | None:
        return _member_at(problem, e, offset_of[(k, e)]) if (k, e) in offset_of else None

    return renamed(problem, seq, at_offset), kept


def _member_at(problem: Problem, e: Engagement, offset: float) -> str:
    """The name of engagement `e`'s member at `offset` along its face: an arc member's at its own offset plus
    `offset` (`push@+0.32cm` moved by 0.05 cm: `push@+0.37cm`), a family's `NAME@+S.SScm`."""
    seed = arc_seed(problem, e.body, e.affordance)
    if seed is not None:
        name = member_name(seed.slide, seed.offset + offset)
        return name if name != seed.slide else e.affordance  # (never 0: the band keeps the member's side)
    return member_name(e.affordance, offset, straight=slide_band(problem, e) is not None)


class _Fractions(dict):
    """`_FRACTIONS[n]`: n evenly spaced fractions from 0 to 1 (cached)."""

    def __missing__(self, n: int) -> np.ndarray:
        self[n] = np.linspace(0.0, 1.0, n)
        return self[n]


_FRACTIONS = _Fractions()


@dataclass
class ModeTrace:
    """One mode of a rollout: poses at its start and end, and the hand along it.

    `hand`: the hand's world poses at evenly spaced fractions of the mode's
    motion (one pose when it only touches at the start, e.g. a grasp; empty
    when the hand is free); `yaw_free`: whether only its position and z axis
    matter; `values`: the motion value of each engagement of the mode;
    `carried`: the grasps whose bodies the hand carries during the mode, with
    their carry values (dx, dy, dyaw).
    """

    start: dict[str, np.ndarray]
    end: dict[str, np.ndarray]
    hand: list[np.ndarray]
    yaw_free: bool
    values: dict[Engagement, float]
    carried: dict[Engagement, np.ndarray] = field(default_factory=dict)

    @property
    def moved(self) -> set[str]:
        """The bodies the mode moves: by a motion value, or carried."""
        moved = {e.body for e in self.values}
        return moved | {e.body for e in self.carried} if self.carried else moved


@dataclass(frozen=True)
class ModeValues:
    """What a vector of values gives each mode: `moves[k]` the (engagement, value) pairs of mode k's motions,
    `offsets[(k, e)]` the offset of the contact `e` added at the transition into mode k, `carries[k]` the carry
    values of the grasps carried during mode k."""

    moves: dict[int, list[tuple[Engagement, float]]]
    offsets: dict[tuple[int, Engagement], float]
    carries: dict[int, dict[Engagement, np.ndarray]]


def mode_values(seq: Sequence, values: np.ndarray) -> ModeValues:
    """`values` (the motions, then the contacts' offsets (absent once `materialise` named the members), then the
    carries) sorted by the mode each one acts in."""
    moves: dict[int, list[tuple[Engagement, float]]] = {}
    for (mode, e), v in zip(seq.variables, values):
        moves.setdefault(mode, []).append((e, float(v)))
    first_carry = len(values) - CARRY_VALUES * len(seq.carries)
    offsets = dict(zip(seq.offsets, (float(v) for v in values[len(seq.variables) : first_carry])))
    carries: dict[int, dict[Engagement, np.ndarray]] = {}
    if seq.carries:  # (the optimiser's hot path: nothing to do for the sequences that carry nothing)
        carry_values = np.asarray(values[first_carry:], dtype=float).reshape(-1, CARRY_VALUES)
        for (mode, e), c in zip(seq.carries, carry_values):
            carries.setdefault(mode, {})[e] = c
    return ModeValues(moves, offsets, carries)


def rest_poses(problem: Problem) -> dict[str, np.ndarray]:
    """Every body at its rest pose (copies): where a rollout starts."""
    return {n: b.rest.copy() for n, b in problem.bodies.items()}


def rollout(problem: Problem, seq: Sequence, values: np.ndarray, samples: int = 5) -> list[ModeTrace]:
    """Every mode of `seq` with motion values `values` (`samples` hand poses along each moving mode)."""
    given = mode_values(seq, values)
    poses = rest_poses(problem)
    live: dict[Engagement, float] = {}  # the offsets of the family engagements in force
    return [roll_mode(problem, seq, k, poses, live, given, samples) for k in range(len(seq.graphs))]


def roll_mode(
    problem: Problem,
    seq: Sequence,
    k: int,
    poses: dict[str, np.ndarray],
    live: dict[Engagement, float],
    given: ModeValues,
    samples: int,
) -> ModeTrace:
    """Mode k of a rollout: the transition into it, then its motions, from the bodies at `poses` after mode
    k - 1 with the family offsets `live` in force then (both advanced in place, to after mode k; the pose arrays
    are replaced, never written to). What it reads of the sequence is found once (`mode_shapes`)."""
    shape = mode_shapes(problem, seq)[k]
    action = shape.action
    if action is not None:  # the transition (`_transition`, with what it reads found once)
        e = action.engagement
        if action.op == "add":
            live[e] = given.offsets.get((k, e), 0.0)
            if shape.jump is not None:  # a tool jumps to its contact
                tool, inverse = shape.jump
                poses[tool] = poses[e.body] @ shape.contact(problem, e, live.get(e, 0.0)) @ inverse
        else:
            if shape.put_down is not None:
                poses[e.body] = put_down(poses[e.body], shape.put_down)
            live.pop(e, None)
            if shape.returned is not None:  # a tool set down where it was picked up
                poses[e.body] = shape.returned
    start = dict(poses)
    moves = given.moves.get(k, _NO_MOVES)
    paths = {}  # the body's motion at `samples` fractions of its value, for the hand path
    for e, v in moves:
        paths[e] = member_motions(problem, e, live.get(e, 0.0), _FRACTIONS[samples] * v)
        poses[e.body] = start[e.body] @ paths[e][-1]
    carried = given.carries.get(k, _NOTHING_CARRIED)
    for e, c in carried.items():
        poses[e.body] = carried_pose(start[e.body], c)
    for e, tool, inverse in shape.tools:
        poses[tool] = poses[e.body] @ shape.contact(problem, e, live.get(e, 0.0)) @ inverse
    if carried:
        hand, yaw_free = _carry_hand_path(problem, carried, start, poses), False
    else:
        hand, yaw_free = _hand_path(problem, shape, start, paths, live)
    return ModeTrace(start, dict(poses), hand, yaw_free, {e: v for e, v in moves}, carried)


_NO_MOVES: list[tuple[Engagement, float]] = []
"""The `moves` of a mode that moves nothing (shared: never written to)."""

_NOTHING_CARRIED: dict[Engagement, np.ndarray] = {}
"""The `carried` of a mode that carries nothing (shared: never written to)."""


def _carry_hand_path(
    problem: Problem, carried: dict[Engagement, np.ndarray], start: dict[str, np.ndarray], end: dict[str, np.ndarray]
) -> list[np.ndarray]:
    """The hand while it carries a body: at the grasp where the body is picked up and where it is set down (the
    way between is lifted over the other bodies, planned with the arm's paths)."""
    (e,) = carried  # one hand, one grasp
    grasp = problem.action(e.body, e.affordance)
    return [start[e.body] @ grasp, end[e.body] @ grasp]


def _hand_path(
    problem: Problem,
    shape: ModeShape,
    start: dict[str, np.ndarray],
    paths: dict[Engagement, np.ndarray],
    live: dict[Engagement, float],
) -> tuple[list[np.ndarray], bool]:
    """The hand's poses during a mode: along the motion of what it pushes, at a grasp, or none (free)."""
    if shape.hand == HAND_FREE:
        return [], True
    e = shape.hand_engagement
    assert e is not None
    if shape.hand == HAND_RETURNED:  # the hand lets go of the tool where it set it down (`put_back`)
        return [start[e.body] @ shape.hand_action], False
    if shape.hand == HAND_HELD:  # a tool free in the hand: only a grasp made at this transition pins the hand
        return ([start[e.body] @ shape.hand_action] if shape.just_grasped else []), False
    offset = live.get(e, 0.0)
    found = shape.chains.get(offset)
    if found is None:
        if len(shape.chains) >= CACHED_OFFSETS:
            shape.chains.clear()
        chained = hand_chain(problem, shape.graph, e, offset)
        assert chained is not None  # a tool frame acts only while its tool is held (`acting_engagement`)
        found = shape.chains[offset] = chained
    chain, yaw_free = found
    if e not in paths:
        return [start[e.body] @ chain], yaw_free
    return list(start[e.body] @ paths[e] @ chain), yaw_free
