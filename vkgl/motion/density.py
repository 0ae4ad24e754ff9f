"""How densely a joint-space motion must be checked, and checking it that densely.

A straight joint-space segment is collision-free only if the configurations
between its checked samples are too: the samples must be close enough that no
point of the arm (or of a held tool) moves more than a tolerance between two of
them. For a point p beyond joint i, |dp| <= sum_i r_i |dq_i| <= |r|_2 |dq|_2
(Cauchy-Schwarz), where r_i bounds p's distance from joint i's axis. So a
Euclidean joint step of `tolerance / |r|_2` moves no point more than
`tolerance`.

`link_reach(arm)` computes r from the URDF (triangle inequality: the lengths of
the joint offsets after joint i, plus the extent of each link's collision
shapes about its origin, plus the effector and an optional tool reach beyond
it). For the Panda with the fingertip and no tool, r is about
(1.11, 1.11, 0.79, 0.71, 0.31, 0.31, 0.23) m, |r| = 1.95 m, so a 1 cm tolerance
gives a Euclidean joint step of 0.0051 rad; with a tool reaching 12 cm beyond
the fingertip 0.0046 rad (see `DEFAULT_RESOLUTION`), 30 cm 0.0038 rad.

The helpers below check segments with the same Euclidean step OMPL's
`DiscreteMotionValidator` uses (`ceil(distance / step)` pieces), the interior
samples in bisection order (the middle first: a collision is usually found
after few checks).
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from vkgl.robot import Arm

DEFAULT_TOLERANCE = 0.01
"""m: no point of the arm moves more than this between two checked configurations."""

DEFAULT_RESOLUTION = 0.0045
"""rad (Euclidean joint step): `DEFAULT_TOLERANCE` / |r| for the Panda with its fingertip and a tool reaching
12 cm beyond it (0.0051 rad without a tool); `edge_resolution(arm, ...)` computes it for any arm and tool."""

Validity = Callable[[np.ndarray], bool]

Advance = tuple[Callable[[np.ndarray], float], np.ndarray]
"""(clearance, reach): a lower bound (m) on the arm's distance to everything at a configuration
(`vkgl.motion.clearance`) and `link_reach` of the arm (and tool): conservative advancement along segments."""

PROBES = 7
"""Dense samples checked first, coarse to fine, before the walk of conservative advancement (the first three
levels of the bisection order)."""

SKIP_MIN = 4
"""Dense steps a skip must save to be taken: a clearance bound costs about as much as two or three checks."""

FINE_RUN = 8
"""Dense checks made in a row where the clearance bound is not positive, before the bound is asked again (near a
body the bound stays at zero for a while, and asking it costs about a check)."""


def _shape_extent(body: Any) -> float:
    """The largest distance from `body`'s origin of a corner of its collision shapes' bounding boxes (m)."""
    extent = 0.0
    for node in body.getShapeNodes():
        if not node.hasCollisionAspect():
            continue
        box = node.getShape().getBoundingBox()
        low, high = np.asarray(box.getMin()), np.asarray(box.getMax())
        transform = node.getRelativeTransform()
        rotation, translation = np.asarray(transform.rotation()), np.asarray(transform.translation())
        for corner in np.array(np.meshgrid(*zip(low, high))).T.reshape(-1, 3):
            extent = max(extent, float(np.linalg.norm(rotation @ corner + translation)))
    return extent


_SKELETON_REACHES: dict[tuple[str, str, bytes], tuple[np.ndarray, np.ndarray]] = {}
_REACHES: dict[tuple[str, str, bytes, float], np.ndarray] = {}


def link_reach(arm: Arm, tool_reach: float = 0.0) -> np.ndarray:
    """r_i (m, one per joint of `arm.joint_names`): a bound on the distance from joint i's axis of any point
    of the arm that joint i moves, of the effector, and of a held tool reaching `tool_reach` beyond the effector.

    Triangle inequality along the chain: from joint i's origin, the lengths of
    every later joint offset to a link's origin, plus that link's shape extent.
    The walk over the URDF is done once per process for each URDF and effector;
    each tool reach only extends the effector's term (a read-only array).
    """
    key = (arm.urdf, arm.effector_link, np.asarray(arm.link_offset, dtype=float).tobytes())
    found = _REACHES.get((*key, float(tool_reach)))
    if found is None:
        if key not in _SKELETON_REACHES:
            _SKELETON_REACHES[key] = _link_reach(arm)
        links, to_effector = _SKELETON_REACHES[key]
        effector_extent = float(np.linalg.norm(arm.link_offset[:3, 3])) + tool_reach
        found = np.maximum(links, to_effector + effector_extent)
        found.flags.writeable = False
        _REACHES[(*key, float(tool_reach))] = found
    return found


def _link_reach(arm: Arm) -> tuple[np.ndarray, np.ndarray]:
    """Per joint: the bound over the links' shapes, and the chain length to the effector link's origin
    (-inf where the joint does not move the effector)."""
    skeleton = arm.skeleton
    joints = [skeleton.getJoint(name) for name in arm.joint_names]
    effector_body = skeleton.getBodyNode(arm.effector_link)
    reach = np.zeros(len(joints))
    to_effector = np.full(len(joints), -np.inf)
    extents: dict[str, float] = {}  # each link's shape extent, measured once
    for i, joint in enumerate(joints):
        # breadth-first over the links below joint i, with the chain length from the joint's origin
        start = joint.getChildBodyNode()
        stack = [(start, float(np.linalg.norm(joint.getTransformFromChildBodyNode().translation())))]
        best = 0.0
        while stack:
            body, length = stack.pop()
            name = body.getName()
            if name not in extents:
                extents[name] = _shape_extent(body)
            best = max(best, length + extents[name])
            if name == effector_body.getName():
                to_effector[i] = max(to_effector[i], length)
            for k in range(body.getNumChildBodyNodes()):
                child = body.getChildBodyNode(k)
                below = child.getParentJoint()
                offset = float(np.linalg.norm(below.getTransformFromParentBodyNode().translation()))
                offset += float(np.linalg.norm(below.getTransformFromChildBodyNode().translation()))
                stack.append((child, length + offset))
        reach[i] = best
    return reach, to_effector


def edge_resolution(arm: Arm, tolerance: float = DEFAULT_TOLERANCE, tool_reach: float = 0.0) -> float:
    """The Euclidean joint step (rad) at which no point of `arm` (and of a tool reaching `tool_reach` beyond
    its effector) moves more than `tolerance` (m) between two checked configurations."""
    return tolerance / float(np.linalg.norm(link_reach(arm, tool_reach)))


def pieces(a: np.ndarray, b: np.ndarray, resolution: float) -> int:
    """How many pieces the segment a-b is cut into: `ceil(|b - a| / resolution)`, at least 1 (as OMPL does)."""
    return max(1, math.ceil(float(np.linalg.norm(b - a)) / resolution))


def _bisection_order(count: int) -> Iterator[int]:
    """1 .. count - 1 (the interior samples of `count` pieces), coarse to fine: the middle first."""
    queue = deque([(0, count)])
    while queue:
        low, high = queue.popleft()
        if high - low < 2:
            continue
        middle = (low + high) // 2
        yield middle
        queue.append((low, middle))
        queue.append((middle, high))


class CountingChecker:
    """`is_valid` with a count of its calls (the work measure of the planner)."""

    def __init__(self, is_valid: Validity) -> None:
        """Wrap `is_valid`."""
        self.is_valid = is_valid
        self.calls = 0

    def __call__(self, q: np.ndarray) -> bool:
        """Whether `q` is valid (one call of the wrapped function)."""
        self.calls += 1
        return bool(self.is_valid(q))


def segment_is_valid(
    a: np.ndarray, b: np.ndarray, is_valid: Validity, resolution: float, advance: Advance | None = None
) -> bool:
    """Whether every sample of the straight segment a-b, `resolution` apart, is valid (ends not checked).

    With `advance` (a clearance bound and the arm's link reach), stretches the
    bound proves clear are skipped (`advanced_segment_is_valid`).
    """
    if advance is not None:
        return advanced_segment_is_valid(a, b, is_valid, resolution, advance)
    count = pieces(a, b, resolution)
    delta = b - a
    return all(is_valid(a + delta * (k / count)) for k in _bisection_order(count))


def advanced_segment_is_valid(
    a: np.ndarray, b: np.ndarray, is_valid: Validity, resolution: float, advance: Advance
) -> bool:
    """`segment_is_valid` by conservative advancement: from a to b, where the clearance bound `d` (m) is
    positive, no arm point touches anything, and none can until it has moved `d`: the walk skips that far
    (`sum_i r_i |dq_i|` bounds the motion of every point, see the module's docstring). Where the bound is not
    positive, the configurations are checked `resolution` apart as without it, `FINE_RUN` at a time."""
    clearance, reach = advance
    delta = b - a
    length = float(np.linalg.norm(delta))
    if length == 0.0:
        return True
    # a blocked segment is usually blocked in a stretch that the dense samples' coarsest levels hit (the
    # middle first): a few of them find it sooner than a walk from one end
    count = pieces(a, b, resolution)
    if not all(is_valid(a + delta * (k / count)) for k in itertools.islice(_bisection_order(count), PROBES)):
        return False
    travel = float(reach @ np.abs(delta))  # the farthest any arm point moves from a to b (m)
    fine = resolution / length  # one sample of the dense check, as a fraction of the segment
    s = 0.0
    while s < 1.0:
        room = clearance(a + s * delta)
        if travel <= 0.0 and room > 0.0:
            return True
        if room > 0.0 and room / travel >= SKIP_MIN * fine:  # a short skip costs more than the checks it saves
            s += room / travel
            continue
        for _ in range(FINE_RUN):
            if s > 0.0 and not is_valid(a + s * delta):
                return False
            s += fine
            if s >= 1.0:
                break
    return True


def path_is_valid(waypoints: np.ndarray, is_valid: Validity, resolution: float, advance: Advance | None = None) -> bool:
    """Whether every waypoint and every dense sample of every segment of `waypoints` (k x n) is valid."""
    if not all(is_valid(q) for q in waypoints):
        return False
    return all(segment_is_valid(a, b, is_valid, resolution, advance) for a, b in itertools.pairwise(waypoints))


def densify(waypoints: np.ndarray, resolution: float) -> np.ndarray:
    """Every sample of `waypoints` (k x n) as checked: each segment cut into `pieces`, waypoints included."""
    rows = [waypoints[:1]]
    for a, b in itertools.pairwise(waypoints):
        count = pieces(a, b, resolution)
        rows.append(a + np.outer(np.arange(1, count + 1) / count, b - a))
    return np.vstack(rows)


__all__ = [
    "DEFAULT_RESOLUTION",
    "DEFAULT_TOLERANCE",
    "CountingChecker",
    "Validity",
    "densify",
    "edge_resolution",
    "link_reach",
    "path_is_valid",
    "pieces",
    "segment_is_valid",
]
