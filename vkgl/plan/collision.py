"""Collision geometry for planning: which bodies overlap at given poses (DART's FCL detector).

A `CollisionScene` is built once per planning problem from the bodies' real
shapes and the table; a query only moves frames and asks the detector. The
shapes are the simulator's (`vkgl.sim.world.dart_shapes`): boxes and cylinders
as primitives, a mesh as DART loads it, a union as one shape per part. The
table is a slab of the table's footprint whose top is the table's z and which
reaches `TABLE_DEPTH` below it, so that nothing can hide under the top.

Overlap means penetration: two bodies overlap when FCL reports a contact
between them deeper than `TOUCH_TOL` (1 mm). Touching (a pushed block against
the fingertip's face, a body resting on the table) is allowed; that is what
the tolerance is for, and it is also the accuracy asked of the geometry.

Why DART's FCL and not coal or python-fcl: docs/collision.md has the numbers
(bench/bench_collision.py). In short, the same answers, no new dependency, and
the per-query work stays in C++ (one `collide` of a group against a group,
FCL's own broad phase) where the other libraries need a Python loop over pairs.

The boundary is plain numpy: poses are 4x4 world matrices keyed by body name.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import dartpy as dart
import numpy as np

from vkgl.lang.geometry import shape_mesh
from vkgl.lang.ir import Shape
from vkgl.sim.world import dart_shapes

TOUCH_TOL = 1e-3
"""m: penetration up to this depth counts as touching (allowed); deeper is an overlap."""

TABLE = "table"
"""The name under which the table appears in contacts and `ignore` pairs."""

TABLE_DEPTH = 1.0
"""m: how far the table slab reaches below its top (thick: whatever is under the top inside its footprint is in it)."""

MAX_CONTACTS = 256
"""Contacts FCL may report per query (4 per pair of shapes): enough that a deep one is never crowded out."""


@dataclass(frozen=True)
class Contact:
    """Two bodies overlapping: their names, the penetration depth (m) and a world point of the contact."""

    body_a: str
    body_b: str
    depth: float
    point: np.ndarray


def pair(a: str, b: str) -> frozenset[str]:
    """The unordered pair of two names, as `ignore` sets hold them."""
    return frozenset((a, b))


class CollisionScene:
    """The collision shapes of a planning problem's bodies and table, with DART's FCL detector.

    Built once (`from_problem`, or from shapes); every query sets the world
    poses of the bodies it is given and collides groups of shape frames. Groups
    are cached per set of bodies, so that checking one body against "all the
    others" is one call to FCL after the first time.
    """

    def __init__(self, shapes: Mapping[str, Shape], *, table_center: np.ndarray | None = None,
                 table_size: np.ndarray | None = None, table_z: float = 0.0, tol: float = TOUCH_TOL) -> None:
        """Bodies named by `shapes` (IR shapes, body frame), and a table when `table_center` and `table_size` (x, y) are given."""
        if TABLE in shapes:
            raise ValueError(f"a body may not be called `{TABLE}` in a collision scene: that name is the table's")
        self.tol = tol
        self.detector = dart.collision.FCLCollisionDetector()
        # FCL's own box / cylinder algorithms, not triangulated shapes: exact and faster
        self.detector.setPrimitiveShapeType(dart.collision.FCLCollisionDetector.PRIMITIVE)
        self.option = dart.collision.CollisionOption()
        self.option.enableContact = True
        self.option.maxNumContacts = MAX_CONTACTS
        self._frames: dict[str, list[tuple[Any, np.ndarray]]] = {}  # body -> [(frame, part pose in body frame)]
        self._owner: dict[str, str] = {}  # shape frame name -> body
        self.radius: dict[str, float] = {}  # body -> radius of a ball about its frame origin that holds it
        self._placed: dict[str, bytes] = {}
        for name, shape in shapes.items():
            self._add(name, dart_shapes(shape), float(np.linalg.norm(shape_mesh(shape).vertices, axis=1).max()))
        self.table_box: tuple[np.ndarray, np.ndarray] | None = None  # (lower, upper) corners of the slab
        if table_center is not None and table_size is not None:
            size = np.array([table_size[0], table_size[1], TABLE_DEPTH])
            centre = np.array([table_center[0], table_center[1], table_z - TABLE_DEPTH / 2])
            self._add(TABLE, [(dart.dynamics.BoxShape(size), np.eye(4))], float(np.linalg.norm(size)) / 2)
            self._place(TABLE, _translation(centre))
            self.table_box = (centre - size / 2, centre + size / 2)
        self._groups: dict[tuple[str, ...], Any] = {}

    @classmethod
    def from_problem(cls, problem: Any, tol: float = TOUCH_TOL) -> CollisionScene:
        """The scene of a `vkgl.plan.model.Problem`: its bodies' shapes and its table (if the scene has one)."""
        shapes = {name: body.type.shape for name, body in problem.bodies.items()}
        return cls(shapes, table_center=problem.table_center, table_size=problem.table_size,
                   table_z=problem.table_z, tol=tol)

    # ------------------------------------------------------------ building

    def _add(self, name: str, parts: list[tuple[Any, np.ndarray]], radius: float) -> None:
        frames = []
        for i, (shape, local) in enumerate(parts):
            frame = dart.dynamics.SimpleFrame(dart.dynamics.Frame.World(), f"{name}#{i}")
            frame.setShape(shape)
            frames.append((frame, np.asarray(local, dtype=float)))
            self._owner[frame.getName()] = name
        self._frames[name] = frames  # the groups keep raw pointers to these frames: this keeps them alive
        self.radius[name] = radius

    @property
    def names(self) -> tuple[str, ...]:
        """The bodies of the scene (the table last, if any)."""
        return tuple(self._frames)

    def group(self, names: Iterable[str]) -> Any:
        """The (cached) DART collision group of the shapes of `names`."""
        key = tuple(sorted(set(names)))
        group = self._groups.get(key)
        if group is None:
            group = self.detector.createCollisionGroup()
            for name in key:
                for frame, _ in self._frames[name]:
                    group.addShapeFrame(frame)
            self._groups[key] = group
        return group

    def owner(self, frame_name: str) -> str | None:
        """The body whose shape frame is called `frame_name` (None for frames of other groups, e.g. the arm)."""
        return self._owner.get(frame_name)

    # ------------------------------------------------------------ poses

    def place(self, poses: Mapping[str, np.ndarray]) -> None:
        """Put the bodies of `poses` at their 4x4 world poses (the others stay where they were)."""
        for name, pose in poses.items():
            if name != TABLE:
                self._place(name, pose)

    def _place(self, name: str, pose: np.ndarray) -> None:
        pose = np.asarray(pose, dtype=float)
        key = pose.tobytes()
        if self._placed.get(name) == key:
            return
        self._placed[name] = key
        for frame, local in self._frames[name]:
            frame.setTransform(_isometry(pose @ local))

    # ------------------------------------------------------------ queries

    def collide(self, group_a: Any, group_b: Any, names: dict[str, str] | None = None) -> list[Contact]:
        """The overlaps (deeper than the tolerance) between two groups, one deepest Contact per pair of bodies.

        A contact's `body_a` is in `group_a`, its `body_b` in `group_b`.

        Bodies are named by their frames' owners (`names` maps other frame names,
        e.g. the arm's links, to what contacts should call them).
        """
        result = dart.collision.CollisionResult()
        if not group_a.collide(group_b, self.option, result):
            return []
        deepest: dict[tuple[str, str], Contact] = {}
        for c in result.getContacts():
            if c.penetrationDepth <= self.tol:
                continue
            first, second = c.collisionObject1.getShapeFrame(), c.collisionObject2.getShapeFrame()
            if not group_a.hasShapeFrame(first):  # FCL may give the pair either way round
                first, second = second, first
            a, b = self._name(first.getName(), names), self._name(second.getName(), names)
            old = deepest.get((a, b))
            if old is None or c.penetrationDepth > old.depth:
                deepest[(a, b)] = Contact(a, b, float(c.penetrationDepth), np.array(c.point, dtype=float))
        return list(deepest.values())

    def _name(self, frame_name: str, names: dict[str, str] | None) -> str:
        owner = self._owner.get(frame_name)
        if owner is not None:
            return owner
        return names.get(frame_name, frame_name) if names else frame_name

    def against(self, name: str, pose: np.ndarray, others: Iterable[str]) -> list[Contact]:
        """Overlaps of body `name` at `pose` with the bodies `others` where they were last placed."""
        others = [o for o in others if o != name]
        if not others:
            return []
        self._place(name, pose)
        return self.collide(self.group([name]), self.group(others))

    def overlap(self, poses: Mapping[str, np.ndarray], ignore: Iterable[frozenset[str]] = (),
                table: bool = True) -> list[Contact]:
        """Every pair of the bodies in `poses` (and the table, if `table`) that overlaps, but the `ignore` pairs.

        `ignore`: unordered pairs (`pair(a, b)`) allowed to overlap, e.g. a tool
        and the body it acts on. Bodies whose bounding balls (or the table's
        slab) are apart are not handed to FCL at all.
        """
        self.place(poses)
        skip = set(ignore)
        names = [n for n in poses if n != TABLE]
        centres = {n: np.asarray(poses[n], dtype=float)[:3, 3] for n in names}
        out: list[Contact] = []
        for i, a in enumerate(names):
            near = [b for b in names[i + 1:] if pair(a, b) not in skip
                    and np.linalg.norm(centres[a] - centres[b]) < self.radius[a] + self.radius[b]]
            if table and self.table_box is not None and pair(a, TABLE) not in skip \
                    and self.near_table(centres[a][None], self.radius[a])[0]:
                near.append(TABLE)
            if near:
                out.extend(self.collide(self.group([a]), self.group(near)))
        return out

    def near_table(self, centres: np.ndarray, radius: float) -> np.ndarray:
        """For each of `centres` (n x 3), whether a ball of `radius` there reaches into the table slab."""
        if self.table_box is None:
            return np.zeros(len(centres), dtype=bool)
        lower, upper = self.table_box
        gap = np.maximum(np.maximum(lower - centres, centres - upper), 0.0)
        return np.einsum("ij,ij->i", gap, gap) < radius * radius


def _isometry(matrix: np.ndarray) -> Any:
    iso = dart.math.Isometry3()
    iso.set_matrix(matrix)
    return iso


def _translation(p: np.ndarray) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = p
    return m
