"""The typed intermediate representation (IR) of VKG programs.

The IR is the only thing the back ends (sim, infer, plan) see. Every node is a
frozen pydantic model with a source span. All physical values are stored in SI
units (m, rad, kg, N, s); the unit the user wrote is kept as a display hint
(`unit`) so that the printer can give back what the user wrote.

Equality ignores source spans, so `parse(print(ir)) == ir` is meaningful.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

# re-exported: the values (spans, the base node, quantities, vectors, poses, references), grasps, regions
from vkgl.lang.ir.grasps import GraspC as GraspC
from vkgl.lang.ir.grasps import GraspPolicy as GraspPolicy
from vkgl.lang.ir.regions import KeepOut as KeepOut
from vkgl.lang.ir.regions import Region as Region
from vkgl.lang.ir.values import FrameRef as FrameRef
from vkgl.lang.ir.values import Node as Node
from vkgl.lang.ir.values import Pose as Pose
from vkgl.lang.ir.values import Quantity as Quantity
from vkgl.lang.ir.values import Ref as Ref
from vkgl.lang.ir.values import Span as Span
from vkgl.lang.ir.values import Vector as Vector

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


JOINT_LIFT = 0.001
"""m: a body on a physical joint hangs this far above where the scene places it (so it does not rub on the
table); the simulator, the planner's collision geometry and the scene checks all put it there, to agree on its
room (a drawer 1 mm under its cabinet's top touches it once lifted, and drags it)."""


class ContactSpec(Node):
    """`contacts on faces +x, -x steps K`, or `contacts at FRAME, FRAME` (then `faces` is empty)."""

    faces: list[str] = Field(default_factory=list)
    steps: int = 1
    heights: int = 1  # `heights K`: K contact heights up each side face, at the centres of K equal cells
    frames: list[Ref] = Field(default_factory=list)  # `contacts at`: push at each frame's origin, along its x axis


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
    frames: list[Frame] = Field(default_factory=list)
    joint: Joint | None = None
    explores: list[Explore] = Field(default_factory=list)
    grasps: GraspPolicy | None = None  # `explore grasps { ... }`: which grasps `vkgc learn` tries
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
    effectors: list[Effector] = Field(default_factory=list)
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
    `upper` is how far it was seen to go, not a bound. The turn of an arc member of
    an open slide (`vkgl.lang.ir.arcs`, never written in a module) is open too.
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


Constraint = Annotated[FixedC | PrismaticC | RevoluteC | FreeC | GraspC, Field(discriminator="type")]


class Evidence(Node):
    """`evidence trials N loglik L posterior P [slip Q]`: how an affordance was inferred.

    `slip` (m, grasps): the largest slip of the body in the hand over the
    trials; `slip_unit` is how it was written (display only).
    """

    trials: int
    loglik: float
    posterior: float
    slip: float | None = None
    slip_unit: str = Field(default="mm", exclude=True, repr=False)


class Arc(Node):
    """`arc lever Q bias Q ahead Q [beyond Q]` (m): pushed at `s` off the centre, the body turns about a pivot `ahead`
    along the push and `lever**2 / |s| + bias` across it (`vkgl.lang.ir.arcs`), for `|s| >= beyond` only if set."""

    lever: Quantity
    bias: Quantity
    ahead: Quantity
    beyond: Quantity | None = None


class Family(Node):
    """`family along DIR from LO to HI UNIT [drift VEC] [arc ...] [sigma Q]`: an affordance's contacts on its face.

    The contact may be the action's pose moved by `s * along` for any offset `s` in [lower, upper] (SI m; 0,
    the action's own contact, lies inside). A slide is the same at every offset (with an `arc`, a turn off the
    centre); a turn's pivot moves by `s * drift` (m of pivot per m of offset). `sigma`: the spread of what the
    explored contacts did about that model (a length for a turn's pivot, an angle for a slide's direction or
    an arc's turn over 10 cm); None when not known.
    """

    along: Vector
    lower: Quantity
    upper: Quantity
    drift: Vector | None = None
    arc: Arc | None = None
    sigma: Quantity | None = None


class Affordance(Node):
    """`affordance NAME { action C; motion C; [family ...] [evidence ...] }`."""

    name: str
    action: Constraint
    motion: Constraint
    family: Family | None = None
    evidence: Evidence | None = None


class Tipping(Node):
    """`tips above Q [on faces F, ...]`: pushed higher than Q over the table on those faces, the body tips.

    `faces` empty: every side face. Written by inference (docs/inference.md, "Tipping").
    """

    height: Quantity
    faces: list[str] = Field(default_factory=list)


class AffordanceSet(Node):
    """`affordances BODY { affordance ... tips above Q ... }`."""

    kind: Literal["affordances"] = "affordances"
    body: Ref
    affordances: list[Affordance]
    tipping: list[Tipping] = Field(default_factory=list)

    def tipping_height(self, face: str) -> float | None:
        """The lowest height (m over the table) above which a push on `face` tips the body, or None."""
        heights = [t.height.value for t in self.tipping if not t.faces or face in t.faces]
        return min(heights) if heights else None


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


SLOT_FRAME = "slot"
"""The frame of a body's type that `B2 : T in B` places B2 at."""


class Placement(Node):
    """Where a scene body starts: `on table at (x, y) UNIT [yaw Q]`, `at POSE`, or relative to another scene
    body: `in B` (at the frame `slot` of B's type) or `at B.F` (`relative_to`, `inside` for the `in` form).
    For the relative forms the checker (vkgl/lang/checks/geometry/placement.py) fills `pose` with the world pose."""

    on_table: bool
    pose: Pose
    relative_to: FrameRef | None = None
    inside: bool = False


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
    robots: list[SceneRobot] = Field(default_factory=list)
    bodies: list[SceneBody] = Field(default_factory=list)
    regions: list[Region] = Field(default_factory=list)  # `region NAME = ...`: named regions of the table's plane
    name_span: Span | None = Field(default=None, exclude=True, repr=False)


# ---------------------------------------------------------------- tasks


DEFAULT_TOL_POSITION = 0.01
DEFAULT_TOL_YAW = 0.05235987755982988  # 3 deg


class Goal(Node):
    """`B at POSE within Q_len[, Q_ang]`, `B yaw Q within Q_ang` or `B open Q within Q`.

    `position` None = position free; `yaw` None = heading free. A tolerance left out (None) means the default:
    1 cm for position, 3 deg for yaw (`DEFAULT_TOL_POSITION`, `DEFAULT_TOL_YAW`); `tolerance()` gives both in
    SI. `opening` (a joint goal) is the coordinate of the body's physical joint, 0 where the body starts: a
    length for a prismatic joint, an angle for a revolute one; `opening_tolerance()` gives its tolerance in SI.

    A relative goal (`B moved by V [in F] [turned by Q]`, `B turned by Q`) keeps what was written in
    `moved_by` (a 2- or 3-vector), `moved_in` (the body whose frame at the start `moved_by` is in; None: the
    world) and `turned_by`; the checker (vkgl/lang/checks/geometry/relative.py) fills `position` and `yaw`
    with where that puts the body, from its start in the task's scene, so that every back end sees an
    ordinary pose goal, and a re-solve from an observed scene keeps the target of the original start.

    A region goal (`B in region ... [yaw Q]`, `B in R` for a region `R` of the scene) sets `region`: the
    body's footprint must lie inside it, passing its edges by at most the position tolerance; `region_ref`
    keeps the name written (the checker copies the scene's region into `region`).
    """

    body: Ref
    position: Vector | None = None
    yaw: Quantity | None = None
    tol_position: Quantity | None = None
    tol_yaw: Quantity | None = None
    opening: Quantity | None = None
    tol_opening: Quantity | None = None
    moved_by: Vector | None = None
    moved_in: Ref | None = None
    turned_by: Quantity | None = None
    region: Region | None = None
    region_ref: Ref | None = None

    @property
    def relative(self) -> bool:
        """Whether the goal is written relative to the body's start (`moved by`, `turned by`)."""
        return self.moved_by is not None or self.turned_by is not None

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
    keep_out: list[KeepOut] = Field(default_factory=list)  # `keep out R`, `keep B out of R`
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
    uses: list[Use] = Field(default_factory=list)
    decls: list[Decl] = Field(default_factory=list)
