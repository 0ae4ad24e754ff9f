"""An independent collision check of a plan: do its motions push bodies through one another?

The planner's own checks are not used here (nothing from `vkgl.plan` is
imported): the scene comes from the compiled IR (`vkgl.lang`), the motions
from the plan's `vkg-plan/8` JSON only. For every step, each body's pose is
interpolated between `poses_start` and `poses_end` along the screw motion
between the two (a slide is a straight line, a turn an arc about its pivot,
a held tool moves with what it pushes), at `samples` evenly spaced points,
both ends included; all bodies (held tools included) and the table are placed
in a DART collision world (`FCLCollisionDetector`, primitive shapes) and every
contact deeper than `tolerance` is a finding, except between two bodies that
the plan joins by an edge in the graph before or after the step (the tool and
the body it pushes, the hand and the tool it holds may touch).

    findings = check_plan(program, "a_push", plan.to_json())
    for f in findings:
        print(f.text)   # "step 2: block overlaps block2 by 1.3 cm at sample 7/20"
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import dartpy as dart
import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.geometry import scene_body_pose, shape_mesh, table_top
from vkgl.lang.ir.nodes import Body, BoxShape, CylinderShape, Pose, Scene, Shape, UnionShape
from vkgl.lang.ir.program import Program

TABLE = "table"
TABLE_THICKNESS = 0.05  # m, below the table top
SAMPLES = 20
TOLERANCE = 0.002  # m: contacts shallower than this are touching, not overlapping


@dataclass(frozen=True)
class Finding:
    """Two things overlapping: at which step (0 = the start scene) and sample, and how deep (m)."""

    step: int
    a: str
    b: str
    depth: float
    sample: int = 1
    samples: int = 1

    @property
    def text(self) -> str:
        """One line: "step 2: block overlaps block2 by 1.3 cm at sample 7/20"."""
        where = "start" if self.step == 0 else f"step {self.step}"
        what = f"penetrates the table by {self.depth * 100:.1f} cm" if self.b == TABLE else None
        what = what or f"overlaps {self.b} by {self.depth * 100:.1f} cm"
        sample = f" at sample {self.sample}/{self.samples}" if self.samples > 1 else ""
        return f"{where}: {self.a} {what}{sample}"


class SceneGeometry:
    """The scene's bodies and table as DART collision frames; place them and list overlaps."""

    def __init__(self, program: Program, scene: Scene) -> None:
        self.program = program
        self.scene = scene
        self.detector = dart.collision.FCLCollisionDetector()
        self.group = self.detector.createCollisionGroup()
        self.frames: dict[str, dart.dynamics.SimpleFrame] = {}
        self.owner: dict[str, str] = {}  # collision frame name -> body name (or "table")
        self._keep: list[Any] = []  # the part frames and shapes must outlive the group
        world = dart.dynamics.Frame.World()
        for scene_body in scene.bodies:
            body = program.bodies[scene_body.type.name]
            frame = dart.dynamics.SimpleFrame(world, f"{scene_body.name}")
            self.frames[scene_body.name] = frame
            for k, (shape, offset) in enumerate(_primitives(body)):
                part = dart.dynamics.SimpleFrame(frame, f"{scene_body.name}#{k}", _isometry(offset))
                part.setShape(shape)
                self._add(part, scene_body.name)
        if scene.table is not None:
            size = scene.table.size.values
            top = table_top(scene)
            centre = np.eye(4)
            centre[:3, 3] = [scene.table.position.values[0], scene.table.position.values[1], top - TABLE_THICKNESS / 2]
            table = dart.dynamics.SimpleFrame(world, TABLE, _isometry(centre))
            table.setShape(dart.dynamics.BoxShape(np.array([size[0], size[1], TABLE_THICKNESS])))
            self._add(table, TABLE)

    def _add(self, frame: dart.dynamics.SimpleFrame, owner: str) -> None:
        self._keep.append(frame)
        self.owner[frame.getName()] = owner
        self.group.addShapeFrame(frame)

    def start_poses(self) -> dict[str, np.ndarray]:
        """Where the scene puts its bodies (4x4 world poses)."""
        return {sb.name: scene_body_pose(self.scene, sb, self.program.bodies[sb.type.name]) for sb in self.scene.bodies}

    def overlaps(
        self, poses: Mapping[str, np.ndarray], allowed: Iterable[frozenset[str]] = ()
    ) -> dict[tuple[str, str], float]:
        """The deepest contact per pair of things at these poses, pairs in `allowed` left out.

        A pair is ordered as the scene lists its bodies, the table last.
        """
        for name, pose in poses.items():
            if name in self.frames:
                self.frames[name].setRelativeTransform(_isometry(np.asarray(pose, dtype=float)))
        option = dart.collision.CollisionOption()
        option.enableContact = True
        option.maxNumContacts = 10000
        result = dart.collision.CollisionResult()
        self.group.collide(option, result)
        skip = set(allowed)
        order = {name: i for i, name in enumerate([*self.frames, TABLE])}
        deepest: dict[tuple[str, str], float] = {}
        for i in range(result.getNumContacts()):
            contact = result.getContact(i)
            a = self.owner[contact.collisionObject1.getShapeFrame().getName()]
            b = self.owner[contact.collisionObject2.getShapeFrame().getName()]
            if a == b or frozenset((a, b)) in skip:
                continue
            pair = (a, b) if order[a] < order[b] else (b, a)
            deepest[pair] = max(deepest.get(pair, 0.0), float(contact.penetrationDepth))
        return deepest


def check_start(program: Program, scene_name: str, *, tolerance: float = TOLERANCE) -> list[Finding]:
    """Overlaps in a scene as it starts (step 0)."""
    geometry = SceneGeometry(program, program.scenes[scene_name])
    found = geometry.overlaps(geometry.start_poses())
    return [Finding(0, a, b, d) for (a, b), d in sorted(found.items()) if d > tolerance]


def check_plan(
    program: Program,
    task_name: str,
    plan_json: Mapping[str, Any],
    *,
    samples: int = SAMPLES,
    tolerance: float = TOLERANCE,
) -> list[Finding]:
    """Every overlap deeper than `tolerance` along the plan's motions: the deepest per step and pair.

    `plan_json` is the plan's `vkg-plan/8` document (`plan.to_json()`); a
    plan that is not solved has no steps and no findings.
    """
    task = program.tasks[task_name]
    geometry = SceneGeometry(program, program.scenes[task.scene.name])
    graphs = plan_json.get("graphs") or []
    resting = geometry.start_poses()  # a body the plan leaves out stays where the scene puts it
    findings = []
    for k, step in enumerate(plan_json.get("steps") or []):
        allowed = _joined(graphs[k : k + 2])
        start = {b: np.asarray(p, dtype=float) for b, p in step["poses_start"].items()}
        end = {b: np.asarray(p, dtype=float) for b, p in step["poses_end"].items()}
        worst: dict[tuple[str, str], tuple[float, int]] = {}
        for i in range(samples):
            s = i / (samples - 1) if samples > 1 else 1.0
            poses = {**resting, **{b: screw_interpolate(start[b], end.get(b, start[b]), s) for b in start}}
            for pair, depth in geometry.overlaps(poses, allowed).items():
                if depth > tolerance and depth > worst.get(pair, (0.0, 0))[0]:
                    worst[pair] = (depth, i + 1)
        for (a, b), (depth, sample) in sorted(worst.items()):
            a, b = _mover_first(a, b, start, end)
            findings.append(Finding(k + 1, a, b, depth, sample, samples))
    return findings


def _joined(graphs: list[Mapping[str, Any]]) -> set[frozenset[str]]:
    """The pairs of bodies that an edge of these graphs joins (world and robot edges aside: they name no body pair)."""
    pairs = set()
    for graph in graphs:
        for a, b, *_ in graph.get("edges", []):
            pairs.add(frozenset((a, b)))
    return pairs


def _mover_first(a: str, b: str, start: Mapping[str, np.ndarray], end: Mapping[str, np.ndarray]) -> tuple[str, str]:
    """Name the body that moves in the step first ("block overlaps block2"), the table last."""
    if b == TABLE:
        return a, b

    def moves(name: str) -> bool:
        return name in end and not np.allclose(start[name], end[name], atol=1e-9)

    return (b, a) if moves(b) and not moves(a) else (a, b)


def screw_interpolate(start: np.ndarray, end: np.ndarray, s: float) -> np.ndarray:
    """The pose a fraction `s` of the way from `start` to `end` along the screw motion between them.

    The world-frame displacement D = end @ start^-1 is a rotation by angle
    theta about an axis through a pivot c plus a slide along the axis; the
    pose at `s` turns by s * theta about the same axis through c and slides
    s times as far. A pure slide is a straight line; a turn about a pivot
    (a revolute motion) an arc about that pivot.
    """
    displacement = end @ np.linalg.inv(start)
    rotation, translation = displacement[:3, :3], displacement[:3, 3]
    rotvec = Rotation.from_matrix(rotation).as_rotvec()
    theta = float(np.linalg.norm(rotvec))
    partial = np.eye(4)
    if theta < 1e-9:
        partial[:3, 3] = s * translation
    else:
        axis = rotvec / theta
        along = float(translation @ axis) * axis
        # the pivot: (I - R) c = t - along, solved in the plane normal to the axis
        pivot = np.linalg.lstsq(np.eye(3) - rotation, translation - along, rcond=None)[0]
        turn = Rotation.from_rotvec(s * rotvec).as_matrix()
        partial[:3, :3] = turn
        partial[:3, 3] = pivot - turn @ pivot + s * along
    return partial @ start


def _primitives(body: Body) -> list[tuple[Any, np.ndarray]]:
    """The body's shape as DART primitives with their poses in the body frame."""
    return _shape_primitives(body.shape, np.eye(4))


def _shape_primitives(shape: Shape, offset: np.ndarray) -> list[tuple[Any, np.ndarray]]:
    if isinstance(shape, BoxShape):
        return [(dart.dynamics.BoxShape(np.array(shape.size.values, dtype=float)), offset)]
    if isinstance(shape, CylinderShape):
        return [(dart.dynamics.CylinderShape(shape.radius.value, shape.height.value), offset)]
    if isinstance(shape, UnionShape):
        parts = []
        for part in shape.parts:
            parts += _shape_primitives(part.shape, offset @ _pose_matrix(part.pose))
        return parts
    # a mesh: its axis-aligned bounding box in the body frame (conservative)
    lower, upper = shape_mesh(shape).bounds
    box = np.eye(4)
    box[:3, 3] = (lower + upper) / 2
    return [(dart.dynamics.BoxShape(np.asarray(upper - lower, dtype=float)), offset @ box)]


def _pose_matrix(pose: Pose) -> np.ndarray:
    return np.asarray(pose.matrix(), dtype=float)


def _isometry(matrix: np.ndarray) -> dart.math.Isometry3:
    iso = dart.math.Isometry3()
    iso.set_matrix(np.asarray(matrix, dtype=float))
    return iso
