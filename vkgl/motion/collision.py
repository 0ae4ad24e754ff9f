"""Collision geometry for planning: which bodies overlap at given poses (DART's FCL detector).

A `CollisionScene` is built once per planning problem from the bodies' real
shapes and the table; a query only moves frames and asks the detector. The
shapes are the simulator's (`vkgl.shapes.dart_shapes`): boxes and cylinders
as primitives, a mesh as DART loads it, a union as one shape per part. The
table is a slab of the table's footprint whose top is the table's z and which
reaches `TABLE_DEPTH` below it, so that nothing can hide under the top.

Overlap means penetration: two bodies overlap when FCL reports a contact
between them deeper than `TOUCH_TOL` (1 mm). Touching (a pushed block against
the fingertip's face, a body resting on the table) is allowed; that is what
the tolerance is for, and it is also the accuracy asked of the geometry.

Why DART's FCL and not coal or python-fcl: docs/collision.md has the numbers
(bench/robot/bench_collision.py). In short, the same answers, no new dependency, and
the per-query work stays in C++ (one `collide` of a group against a group,
FCL's own broad phase) where the other libraries need a Python loop over pairs.

The boundary is plain numpy: poses are 4x4 world matrices keyed by body name.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import dartpy as dart
import numpy as np

from vkgl.lang.ir.geometry import scene_table, shape_mesh, shape_vertices, table_top
from vkgl.lang.ir.nodes import Scene, Shape
from vkgl.shapes import dart_shapes

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

    Built once (from a problem's bodies, or from a compiled scene); every query sets the world
    poses of the bodies it is given and collides groups of shape frames. Groups
    are cached per set of bodies, so that checking one body against "all the
    others" is one call to FCL after the first time.
    """

    def __init__(
        self,
        shapes: Mapping[str, Shape],
        *,
        table_center: np.ndarray | None = None,
        table_size: np.ndarray | None = None,
        table_z: float = 0.0,
        tol: float = TOUCH_TOL,
        margin: float = 0.0,
        lifts: Mapping[str, float] | None = None,
        exact: Iterable[str] = (),
        margins: Mapping[str, float] | None = None,
    ) -> None:
        """Bodies named by `shapes` (IR shapes, body frame).

        `lifts` (m, by body) raises bodies above the poses they are given: the planner's bodies on physical
        joints, which the simulator hangs `vkgl.lang.ir.geometry.JOINT_LIFT` above where they are placed
        (poses read back from the simulator need none).

        A table too, when `table_center` and `table_size` (x, y) are given.
        `margin` (m) grows every box and cylinder of the bodies (not the table)
        by that much on each side: a scene in which "free" means at least that
        clear of them (meshes keep their size); the bodies named in `exact` keep
        their own size, those in `margins` are grown by their own margin.
        """
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
        self.lifts = {name: float(lift) for name, lift in (lifts or {}).items() if lift}
        self._support: dict[str, list[tuple[str, np.ndarray, np.ndarray]]] = {}  # body -> parts' (kind, size, pose)
        kept = set(exact)
        for name, shape in shapes.items():
            grow = (margins or {}).get(name, margin if name not in kept else 0.0)
            parts = [(_grown(part, grow), local) for part, local in dart_shapes(shape)] if grow else dart_shapes(shape)
            # the mesh's round parts are inscribed polygons (32 sides): 0.5 % more, and the tolerance, cover them;
            # a grown box's corner lies its margin further out along each of its three axes
            reach = _extent(shape) * 1.005 + tol + self.lifts.get(name, 0.0) + grow * math.sqrt(3.0)
            self._add(name, parts, reach)
            self._support[name] = [_support(part, local, shape) for part, local in parts]
        self.table_box: tuple[np.ndarray, np.ndarray] | None = None  # (lower, upper) corners of the slab
        self.table_top = float(table_z)
        if table_center is not None and table_size is not None:
            size = np.array([table_size[0], table_size[1], TABLE_DEPTH])
            centre = np.array([table_center[0], table_center[1], table_z - TABLE_DEPTH / 2])
            self._add(TABLE, [(dart.dynamics.BoxShape(size), np.eye(4))], float(np.linalg.norm(size)) / 2)
            self._place(TABLE, _translation(centre))
            self.table_box = (centre - size / 2, centre + size / 2)
        self._groups: dict[tuple[str, ...], Any] = {}
        self._table_memo: dict[tuple[str, bytes], bool] = {}

    @classmethod
    def from_scene(
        cls, scene: Scene, shapes: Mapping[str, Shape], tol: float = TOUCH_TOL, margin: float = 0.0
    ) -> CollisionScene:
        """The bodies `shapes` (by scene body name) and the table of a compiled `scene`."""
        center, size = scene_table(scene)
        return cls(shapes, table_center=center, table_size=size, table_z=table_top(scene), tol=tol, margin=margin)

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
        given = tuple(names)
        group = self._groups.get(given)  # the same names in the same order: no sorting (the hot path)
        if group is not None:
            return group
        key = tuple(sorted(set(given)))
        group = self._groups.get(key)
        if group is None:
            group = self.detector.createCollisionGroup()
            for name in key:
                for frame, _ in self._frames[name]:
                    group.addShapeFrame(frame)
            self._groups[key] = group
        self._groups[given] = group
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
        lift = self.lifts.get(name)
        if lift:
            pose = _translation(np.array([0.0, 0.0, lift])) @ pose
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

    def collides(self, group_a: Any, group_b: Any) -> bool:
        """Whether two groups overlap deeper than the tolerance (stops at the first such contact: the fast check)."""
        result = dart.collision.CollisionResult()
        if not group_a.collide(group_b, self.option, result):
            return False
        return any(result.getContact(i).penetrationDepth > self.tol for i in range(result.getNumContacts()))

    def _name(self, frame_name: str, names: dict[str, str] | None) -> str:
        owner = self._owner.get(frame_name)
        if owner is not None:
            return owner
        return names.get(frame_name, frame_name) if names else frame_name

    def hits(self, name: str, pose: np.ndarray, others: Iterable[str]) -> bool:
        """Whether body `name` at `pose` overlaps any of `others` where they were last placed (no Contacts built)."""
        others = [o for o in others if o != name]
        if not others:
            return False
        self._place(name, pose)
        return self.collides(self.group([name]), self.group(others))

    def against(self, name: str, pose: np.ndarray, others: Iterable[str]) -> list[Contact]:
        """Overlaps of body `name` at `pose` with the bodies `others` where they were last placed."""
        others = [o for o in others if o != name]
        if not others:
            return []
        self._place(name, pose)
        mine, theirs = self.group([name]), self.group(others)
        return self.collide(mine, theirs) if self.collides(mine, theirs) else []

    def overlap(
        self, poses: Mapping[str, np.ndarray], ignore: Iterable[frozenset[str]] = (), table: bool = True
    ) -> list[Contact]:
        """Every pair of the bodies in `poses` (and the table, if `table`) that overlaps, but the `ignore` pairs.

        `ignore`: unordered pairs (`pair(a, b)`) allowed to overlap, e.g. a tool
        and the body it acts on. Bodies whose bounding balls (or the table's
        slab) are apart are not handed to FCL at all.
        """
        self.place(poses)
        skip = set(ignore)
        names = [n for n in poses if n != TABLE]
        centres = np.array([np.asarray(poses[n], dtype=float)[:3, 3] for n in names]).reshape(-1, 3)
        radii = np.array([self.radius[n] for n in names])
        apart = np.linalg.norm(centres[:, None] - centres[None], axis=2) >= radii[:, None] + radii[None]
        out: list[Contact] = []
        for i, a in enumerate(names):
            near = [b for j, b in enumerate(names[i + 1 :], i + 1) if not apart[i, j] and pair(a, b) not in skip]
            if table and self.table_box is not None and pair(a, TABLE) not in skip and self._on_table(a, poses[a]):
                near.append(TABLE)
            if near:
                mine, theirs = self.group([a]), self.group(near)
                if self.collides(mine, theirs):
                    out.extend(self.collide(mine, theirs))
        return out

    def _on_table(self, name: str, pose: np.ndarray) -> bool:
        """`near_table` at one pose, remembered: still bodies are asked about the same pose again and again."""
        key = (name, np.asarray(pose, dtype=float).tobytes())
        known = self._table_memo.get(key)
        if known is None:
            if len(self._table_memo) > 4096:
                self._table_memo.clear()
            known = self._table_memo[key] = bool(self.near_table(name, np.asarray(pose, dtype=float)[None])[0])
        return known

    def part_boxes(self, name: str) -> list[tuple[np.ndarray, np.ndarray]]:
        """World boxes (pose 4x4, half sides) that contain the parts of body `name` where it was last placed
        (`part_boxes_local` placed with the body)."""
        frame, local = self._frames[name][0]
        body = np.asarray(frame.getTransform().matrix()) @ np.linalg.inv(local)
        return [(body @ pose, half) for pose, half in self.part_boxes_local(name)]

    def part_boxes_local(self, name: str) -> list[tuple[np.ndarray, np.ndarray]]:
        """Boxes (pose 4x4 in the body's frame, half sides) that contain the parts of body `name`, as grown by
        the scene's margin: boxes as they are, cylinders in their bounding boxes, other shapes in the box
        around the body's hull. For bounds on distances (`vkgl.motion.clearance`)."""
        out = []
        for kind, size, pose in self._support[name]:
            if kind == "box":
                out.append((pose, np.asarray(size, dtype=float)))
            elif kind == "cylinder":
                out.append((pose, np.array([size[0], size[0], size[1]], dtype=float)))
            else:
                low, high = size.min(axis=0), size.max(axis=0)
                out.append((_translation((low + high) / 2), (high - low) / 2))
        return out

    def near_table(self, name: str, poses: np.ndarray) -> np.ndarray:
        """For each of `poses` (n x 4 x 4) of body `name`, whether it may sink into the table deeper than the tolerance.

        False is certain: either the body's bounding ball stays out of the slab,
        or its lowest point (exact for boxes and cylinders, a mesh's vertices)
        is at most the tolerance below the top; then FCL need not be asked.
        A body sliding on the table top is the common case this saves.
        """
        if self.table_box is None:
            return np.zeros(len(poses), dtype=bool)
        lower, upper = self.table_box
        centres = poses[:, :3, 3]
        gap = np.maximum(np.maximum(lower - centres, centres - upper), 0.0)
        near = np.einsum("ij,ij->i", gap, gap) < self.radius[name] ** 2
        if near.any():
            near &= self.lowest(name, poses) < self.table_top - self.tol
        return near

    def lowest(self, name: str, poses: np.ndarray) -> np.ndarray:
        """The world z of the lowest point of body `name` at each of `poses` (n x 4 x 4)."""
        out = np.full(len(poses), np.inf)
        if self.lifts.get(name):
            poses = poses.copy()
            poses[:, 2, 3] += self.lifts[name]
        for kind, size, local in self._support[name]:
            world = poses @ local
            z_row, z = world[:, 2, :3], world[:, 2, 3]
            if kind == "box":
                low = z - np.abs(z_row) @ size
            elif kind == "cylinder":
                tilt = np.abs(z_row[:, 2])
                low = z - tilt * size[1] - size[0] * np.sqrt(np.clip(1.0 - tilt * tilt, 0.0, None))
            else:
                low = (z_row @ size.T).min(axis=1) + z
            out = np.minimum(out, low)
        return out


def _extent(shape: Shape) -> float:
    """How far the body's mesh reaches from its frame's origin (m)."""
    return float(np.linalg.norm(shape_vertices(shape), axis=1).max())


def _support(part: Any, local: np.ndarray, shape: Shape) -> tuple[str, np.ndarray, np.ndarray]:
    """(kind, size, pose in the body frame) of a DART part for `lowest`: a box's half sides, a cylinder's
    (radius, half height), else the body's whole hull vertices (body frame: a lower bound for the part)."""
    kind = part.getType()
    if kind == "BoxShape":
        return "box", np.asarray(part.getSize(), dtype=float) / 2, local
    if kind == "CylinderShape":
        return "cylinder", np.array([part.getRadius(), part.getHeight() / 2]), local
    return "points", np.asarray(shape_mesh(shape).convex_hull.vertices, dtype=float), np.eye(4)


def _grown(shape: Any, margin: float) -> Any:
    """A DART box or cylinder `margin` larger on every side (other shapes as they are)."""
    kind = shape.getType()
    if kind == "BoxShape":
        return dart.dynamics.BoxShape(np.asarray(shape.getSize(), dtype=float) + 2 * margin)
    if kind == "CylinderShape":
        return dart.dynamics.CylinderShape(shape.getRadius() + margin, shape.getHeight() + 2 * margin)
    return shape


def _isometry(matrix: np.ndarray) -> Any:
    iso = dart.math.Isometry3()
    iso.set_matrix(matrix)
    return iso


def _translation(p: np.ndarray) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = p
    return m
