"""The typed intermediate representation (IR) of VKG programs.

The IR is the only thing the back ends (sim, infer, plan) see. Every node is a
frozen pydantic model with a source span. All physical values are stored in SI
units (m, rad, kg, N, s); the unit the user wrote is kept as a display hint
(`unit`) so that the printer can give back what the user wrote.

Equality ignores source spans, so `parse(print(ir)) == ir` is meaningful.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field
from scipy.spatial.transform import Rotation


class Span(BaseModel):
    """A region of a source file. Lines and columns are 1-based; `end_col` is exclusive."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    file: str
    line: int
    col: int
    end_line: int
    end_col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


class Node(BaseModel):
    """Base of every IR node: frozen, no extra fields, a span that equality ignores."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    span: Span | None = Field(default=None, exclude=True, repr=False)

    def __eq__(self, other: object) -> bool:
        # Spans are where a node was written, not what it means.
        if not isinstance(other, Node) or type(self) is not type(other):
            return NotImplemented
        return self.model_dump() == other.model_dump()

    def __hash__(self) -> int:
        return hash(repr(self.model_dump()))


# ---------------------------------------------------------------- values


class Quantity(Node):
    """A scalar with a dimension. `value` is SI; `unit` is how it was written (e.g. "cm")."""

    value: float
    unit: str = ""


class Vector(Node):
    """2 or 3 components in SI, one unit for all (`unit == ""` for dimensionless)."""

    values: tuple[float, ...]
    unit: str = ""

    def array(self) -> np.ndarray:
        """The components as a float numpy array."""
        return np.asarray(self.values, dtype=float)


class Pose(Node):
    """A position, optionally with a yaw or a roll-pitch-yaw orientation.

    At most one of `yaw` and `rpy` is set; neither means identity rotation.
    """

    position: Vector
    yaw: Quantity | None = None
    rpy: Vector | None = None

    def rotation(self) -> Rotation:
        """The orientation as a scipy Rotation (extrinsic xyz = roll, pitch, yaw)."""
        if self.rpy is not None:
            return Rotation.from_euler("xyz", self.rpy.values)
        if self.yaw is not None:
            return Rotation.from_euler("z", self.yaw.value)
        return Rotation.identity()

    def matrix(self) -> np.ndarray:
        """The pose as a 4x4 homogeneous transform (position padded with z = 0 if 2-d)."""
        m = np.eye(4)
        m[:3, :3] = self.rotation().as_matrix()
        p = list(self.position.values) + [0.0] * (3 - len(self.position.values))
        m[:3, 3] = p
        return m


class Ref(Node):
    """A reference to a declared name (resolved by the checker)."""

    name: str


class FrameRef(Node):
    """`Body.frame` (used in correspondences)."""

    body: str
    frame: str


# ---------------------------------------------------------------- shapes


class BoxShape(Node):
    """`box (x, y, z) UNIT`: a box centred on the body frame."""

    kind: Literal["box"] = "box"
    size: Vector


class CylinderShape(Node):
    """`cylinder radius Q height Q`: axis along the body's z, centred on the body frame."""

    kind: Literal["cylinder"] = "cylinder"
    radius: Quantity
    height: Quantity


class MeshShape(Node):
    """`mesh "file.stl" [scale K]`; `path` as written, `resolved` absolute (set by the checker)."""

    kind: Literal["mesh"] = "mesh"
    path: str
    scale: float = 1.0
    resolved: str | None = None


class ShapePart(Node):
    """One member of a union: a shape placed at a pose in the body frame."""

    shape: Shape
    pose: Pose


class UnionShape(Node):
    """`union { SHAPE at POSE ... }`."""

    kind: Literal["union"] = "union"
    parts: list[ShapePart]


Shape = Annotated[BoxShape | CylinderShape | MeshShape | UnionShape, Field(discriminator="kind")]


# ---------------------------------------------------------------- bodies


class Frame(Node):
    """`frame NAME = POSE`: a named frame in the body frame."""

    name: str
    pose: Pose
    name_span: Span | None = Field(default=None, exclude=True, repr=False)


class Joint(Node):
    """`joint prismatic|revolute axis V [through P] limits (lo, hi) UNIT [damping Q] [friction Q]`.

    A physical joint to the world. `damping` (N*s/m for a prismatic joint,
    N*m*s/rad for a revolute one) and `friction` (Coulomb: N or N*m) resist its
    motion in simulation; None means none.
    """

    type: Literal["prismatic", "revolute"]
    axis: Vector
    through: Vector | None = None
    lower: Quantity
    upper: Quantity
    damping: Quantity | None = None
    friction: Quantity | None = None


class ContactSpec(Node):
    """`contacts on faces +x, -x steps K`, or `contacts at FRAME, FRAME` (then `faces` is empty)."""

    faces: list[str] = []
    steps: int = 1
    frames: list[Ref] = []  # `contacts at`: push at each frame's origin, along its x axis


class ForceSpec(Node):
    """`force normal Q` or `force directions I x J x K Q`."""

    mode: Literal["normal", "directions"]
    grid: tuple[int, int, int] | None = None
    magnitude: Quantity


class Explore(Node):
    """`explore NAME { ... }`: a grid-search exploration policy."""

    name: str
    contacts: ContactSpec | None = None
    grasp: Ref | None = None
    force: ForceSpec | None = None
    duration: Quantity | None = None


class Body(Node):
    """`body NAME { ... }`."""

    kind: Literal["body"] = "body"
    name: str
    shape: Shape
    mass: Quantity
    friction: float | None = None
    frames: list[Frame] = []
    joint: Joint | None = None
    explores: list[Explore] = []
    name_span: Span | None = Field(default=None, exclude=True, repr=False)
    friction_span: Span | None = Field(default=None, exclude=True, repr=False)

    def frame(self, name: str) -> Frame | None:
        """The frame called `name`, or None."""
        return next((f for f in self.frames if f.name == name), None)


# ---------------------------------------------------------------- robots


class Effector(Node):
    """`effector NAME = link L offset POSE`."""

    name: str
    link: str
    offset: Pose


class Robot(Node):
    """`robot NAME { urdf "..."; effector ... }`."""

    kind: Literal["robot"] = "robot"
    name: str
    urdf: str
    urdf_resolved: str | None = None
    effectors: list[Effector] = []
    name_span: Span | None = Field(default=None, exclude=True, repr=False)
    urdf_span: Span | None = Field(default=None, exclude=True, repr=False)

    def effector(self, name: str) -> Effector | None:
        """The effector called `name`, or None."""
        return next((e for e in self.effectors if e.name == name), None)


# ---------------------------------------------------------------- affordances


class FixedC(Node):
    """`fixed [at POSE]`: rigid; the pose (if given) is the effector frame in the body frame."""

    type: Literal["fixed"] = "fixed"
    pose: Pose | None = None


class MotionRange(Node):
    """`range LO to HI UNIT [open]` on a motion: the values of its state it was explored over (SI: m or rad).

    A length for a slide, an angle for a turn; the checker wants `0 <= lower <= upper`.
    Plans keep each value inside it, but `open` (slides only, E433; else closed, as
    before `open` existed) says the body was still moving when exploration ended:
    `upper` is how far it was seen to go, not a bound.
    """

    lower: Quantity
    upper: Quantity
    open: bool = False


class PrismaticC(Node):
    """`prismatic along DIR [from POINT] [range LO to HI UNIT]`: translation along a unit direction.

    `range` (motions only) bounds the displacement; None means unbounded.
    """

    type: Literal["prismatic"] = "prismatic"
    axis: Vector
    origin: Vector | None = None
    range: MotionRange | None = None


class RevoluteC(Node):
    """`revolute about POINT axis DIR [range LO to HI UNIT]`: rotation about a line.

    `range` (motions only) bounds the angle; None means unbounded.
    """

    type: Literal["revolute"] = "revolute"
    center: Vector
    axis: Vector
    range: MotionRange | None = None


class FreeC(Node):
    """`free`: no constraint."""

    type: Literal["free"] = "free"


Constraint = Annotated[FixedC | PrismaticC | RevoluteC | FreeC, Field(discriminator="type")]


class Evidence(Node):
    """`evidence trials N loglik L posterior P`: how an affordance was inferred."""

    trials: int
    loglik: float
    posterior: float


class Affordance(Node):
    """`affordance NAME { action C; motion C; [evidence ...] }`."""

    name: str
    action: Constraint
    motion: Constraint
    evidence: Evidence | None = None


class AffordanceSet(Node):
    """`affordances BODY { affordance ... }`."""

    kind: Literal["affordances"] = "affordances"
    body: Ref
    affordances: list[Affordance]


# ---------------------------------------------------------------- correspondences


class Correspondence(Node):
    """`Body.frame ~ effector`."""

    frame: FrameRef
    effector: Ref


class Correspondences(Node):
    """`correspondences { ... }`."""

    kind: Literal["correspondences"] = "correspondences"
    items: list[Correspondence]


# ---------------------------------------------------------------- scenes


class Table(Node):
    """`table size (x, y) UNIT at (x, y, z) UNIT`: the support surface; its top is at the given z."""

    size: Vector
    position: Vector


class Placement(Node):
    """Where a scene body starts: `on table at (x, y) UNIT [yaw Q]` or `at POSE`."""

    on_table: bool
    pose: Pose


class SceneRobot(Node):
    """`robot NAME : TYPE at POSE`."""

    name: str
    type: Ref
    pose: Pose


class SceneBody(Node):
    """`NAME : TYPE [open Q] on table at (x, y) UNIT yaw Q` or `NAME : TYPE [open Q] at POSE`.

    A body with a physical joint is hung on it where `placement` puts it: that
    is where its joint's coordinate is 0 (its limits and joint goals are
    measured from there). `opening` (a length for a prismatic joint, an angle
    for a revolute one) is the coordinate the joint starts at; None is 0, the
    body then starts where it is placed.
    """

    name: str
    type: Ref
    placement: Placement
    opening: Quantity | None = None

    def start_opening(self) -> float:
        """The joint coordinate the body starts at, SI (m or rad): `opening`, or 0."""
        return float(self.opening.value) if self.opening is not None else 0.0


class Scene(Node):
    """`scene NAME { table ...; robot ...; bodies... }`."""

    kind: Literal["scene"] = "scene"
    name: str
    table: Table | None = None
    robots: list[SceneRobot] = []
    bodies: list[SceneBody] = []
    name_span: Span | None = Field(default=None, exclude=True, repr=False)


# ---------------------------------------------------------------- tasks


DEFAULT_TOL_POSITION = 0.01
DEFAULT_TOL_YAW = 0.05235987755982988  # 3 deg


class Goal(Node):
    """`B at POSE within Q_len[, Q_ang]`, `B yaw Q within Q_ang` or `B open Q within Q`.

    `position` None = position free; `yaw` None = heading free. A tolerance left
    out (None) means the default: 1 cm for position, 3 deg for yaw (see
    `DEFAULT_TOL_POSITION`, `DEFAULT_TOL_YAW`); `tolerance()` gives both in SI.
    `opening` (a joint goal) is the coordinate of the body's physical joint, 0
    where the body starts: a length for a prismatic joint, an angle for a
    revolute one; `opening_tolerance()` gives its tolerance in SI.
    """

    body: Ref
    position: Vector | None = None
    yaw: Quantity | None = None
    tol_position: Quantity | None = None
    tol_yaw: Quantity | None = None
    opening: Quantity | None = None
    tol_opening: Quantity | None = None

    def opening_tolerance(self) -> float:
        """The joint goal's tolerance in SI: as given, else 1 cm for a length and 3 deg for an angle."""
        if self.tol_opening is not None:
            return float(self.tol_opening.value)
        angle = self.opening is not None and self.opening.unit in ("deg", "rad")
        return float(DEFAULT_TOL_YAW if angle else DEFAULT_TOL_POSITION)

    def tolerance(self) -> tuple[float, float]:
        """The goal's tolerances in SI, `(metres, radians)`, with the defaults for those left out."""
        position = self.tol_position.value if self.tol_position is not None else DEFAULT_TOL_POSITION
        yaw = self.tol_yaw.value if self.tol_yaw is not None else DEFAULT_TOL_YAW
        return float(position), float(yaw)

    @staticmethod
    def default_tolerance() -> tuple[float, float]:
        """The tolerances of a goal that gives none, `(metres, radians)`."""
        return float(DEFAULT_TOL_POSITION), float(DEFAULT_TOL_YAW)


class SearchSpec(Node):
    """`search { max_depth N  timeout Q }`."""

    max_depth: int | None = None
    timeout: Quantity | None = None


class Task(Node):
    """`task NAME { scene S; goal ...; [search {...}] }`."""

    kind: Literal["task"] = "task"
    name: str
    scene: Ref
    goals: list[Goal]
    search: SearchSpec | None = None
    name_span: Span | None = Field(default=None, exclude=True, repr=False)


# ---------------------------------------------------------------- modules


class Use(Node):
    """`use a.b.c` (dotted) or `use "path.vkg"` (path)."""

    target: str
    by_path: bool
    resolved: str | None = None


Decl = Annotated[Body | Robot | AffordanceSet | Correspondences | Scene | Task, Field(discriminator="kind")]


class Module(Node):
    """One `.vkg` file: its leading doc comment, its imports and its declarations."""

    path: str
    doc: str | None = None
    uses: list[Use] = []
    decls: list[Decl] = []


ShapePart.model_rebuild()
UnionShape.model_rebuild()
