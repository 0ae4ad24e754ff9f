"""The planning problem: what the search needs to know about a task, read once from the IR.

`build_problem(program, task)` gathers the scene's bodies with their resting
poses and usable affordances, the robot's arm (URDF, effector, base), the
effectors (the robot's own and every tool frame with a correspondence), the
goals in SI and the table. Everything here is plain numpy; the search and the
feasibility checks never look at the IR again.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from vkgl.errors import InputError
from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.geometry import (
    JOINT_LIFT,
    joint_axis,
    joint_coordinate,
    resting_height,
    scene_body_anchor,
    scene_body_pose,
    scene_table,
    shape_vertices,
    table_top,
)
from vkgl.lang.ir.nodes import Affordance, Body, FixedC, Goal, Robot, Scene, SceneBody, Task
from vkgl.lang.ir.program import Program
from vkgl.lang.ir.regions import KeepOut, excess, footprint
from vkgl.motion.collision import TOUCH_TOL, CollisionScene
from vkgl.plan.problem.arcs import arc_members
from vkgl.plan.problem.avoid import Avoid
from vkgl.plan.problem.hulls import hull_vertices, outline_corners
from vkgl.plan.problem.over import clearing_height, over_members
from vkgl.plan.problem.reach_members import reach_members
from vkgl.plan.problem.tipping import TooHigh, split_by_tipping
from vkgl.robot import Arm

DEFAULT_MAX_DEPTH = 6
"""Graphs in the longest sequence searched (G0 included) when the task says nothing. Not 10: with the guided
search, tasks that are "no plan" at 6 mostly time out at 10 on scenes with clutter (the bound is weak where
bodies slide far, and deeper sequences moving clutter and tools reach the optimiser: docs/physical_bench.md,
"Guided search"); a user who wants deeper writes `max_depth`, and the hint says when it could help."""

DEFAULT_TIMEOUT = 60.0
"""s: the search gives up after this long when the task says nothing."""

_ARMS: dict[tuple[str, str, bytes], Arm] = {}  # loaded arms, per URDF, effector and base: loading costs ~0.5 s


@dataclass(frozen=True)
class PlanBody:
    """A scene body as the planner sees it.

    `rest`: world pose at the start; `rest_z`: the height of its frame when it
    lies on the table (where a released tool is put down); `affordances`: the
    affordances of its type with a fixed action (the only ones an effector can
    enact); `joint`: the type of its physical joint to the world, if any, with
    `joint_axis` (body frame), `joint_limits` and `joint_zero`, the world pose
    where its coordinate is 0 (where the scene places it: `rest` unless the
    scene starts it `open Q`). `outline`: the corners of its convex hull (body
    frame, k x 3), which must all stay over the table when it is moved.
    `too_high`: the affordances left out because they push it where it tips
    (`vkgl.plan.problem.tipping`), with the reason. `tool_members`: the
    members that one tool effector alone may enact.
    """

    name: str
    type: Body
    rest: np.ndarray
    rest_z: float
    on_table: bool
    affordances: tuple[Affordance, ...]
    joint: str | None = None
    joint_axis: np.ndarray | None = None
    joint_limits: tuple[float, float] | None = None
    joint_zero: np.ndarray | None = None
    outline: np.ndarray = field(default_factory=lambda: np.zeros((1, 3)))
    too_high: tuple[TooHigh, ...] = ()
    tool_members: frozenset[tuple[str, str]] = frozenset()
    """(affordance, effector): the members only that tool effector may enact (`vkgl.plan.problem.over`)."""
    arc_seeds: frozenset[str] = frozenset()
    """Arc members offered as seeds only: their turn from rest misses the goal; task space moves their offset."""

    def joint_state(self, pose: np.ndarray) -> float:
        """The coordinate of the physical joint at world `pose` (m or rad), 0 at `joint_zero`; the body needs a joint.

        Prismatic: the displacement from `joint_zero` along the axis. Revolute:
        the rotation from it about the axis (its rotation vector's component),
        exact up to half a turn. Goals and joint limits are measured alike.
        """
        assert self.joint is not None and self.joint_axis is not None, f"{self.name} has no physical joint"
        zero = self.rest if self.joint_zero is None else self.joint_zero
        return joint_coordinate(self.joint, self.joint_axis, zero, pose)

    @property
    def start_state(self) -> float:
        """The joint's coordinate at the start (m or rad): 0 unless the scene starts it `open Q`."""
        return self.joint_state(self.rest)


@dataclass(frozen=True)
class EffectorSpec:
    """Something that can enact an affordance: the robot's effector, or a tool frame (`Stick.tip ~ fingertip`).

    `name` is what plans print (`arm.fingertip`, `stick.tip`); `tool` is the
    scene body that carries the frame (None for the robot); `frame` is the
    frame in the tool's body frame (identity for the robot).
    """

    name: str
    tool: str | None
    frame: np.ndarray

    @property
    def frame_inverse(self) -> np.ndarray:
        """The inverse of `frame` (cached: rollouts use it in every evaluation)."""
        cached = self.__dict__.get("_inverse")
        if cached is None:
            cached = np.linalg.inv(self.frame)
            object.__setattr__(self, "_inverse", cached)
        return cached


@dataclass(frozen=True)
class GoalSpec:
    """One goal in SI: `position` (2 or 3 components, or None), `yaw` (rad, or None) and the tolerances.

    A joint goal sets `opening` instead (the coordinate of the body's physical
    joint, m or rad, `PlanBody.joint_state`) with its tolerance `tol_opening`.
    A region goal sets `region`, its half-planes (rows `nx, ny, d`, inside when
    `n . p <= d`), and `footprint`, the body-frame points (n x 3) of the body's
    convex hull: it holds when no point of the footprint passes an edge by
    more than `tol_position`; `region_words` names the region for messages.
    """

    body: str
    position: np.ndarray | None
    yaw: float | None
    tol_position: float
    tol_yaw: float
    opening: float | None = None
    tol_opening: float = 0.0
    region: np.ndarray | None = None
    footprint: np.ndarray | None = None
    region_words: str = ""

    def region_excess(self, pose: np.ndarray) -> np.ndarray:
        """Per edge of the goal's region, how far the body's footprint at `pose` passes it (m; <= 0 inside)."""
        assert self.region is not None and self.footprint is not None, "not a region goal"
        return excess(self.region, footprint(self.footprint, pose))


@dataclass(frozen=True)
class KeepOutSpec:
    """A keep-out region of the task: `region` its vertices (k x 2, m, counterclockwise), `body` the one body it
    keeps out (None: every body), `words` how messages name it (`region sink`, `region (0.6, 0.2) to ... m`)."""

    region: np.ndarray
    body: str | None
    words: str

    def applies_to(self, name: str) -> bool:
        """Whether the region keeps out body `name`."""
        return self.body is None or self.body == name


@dataclass(frozen=True)
class Problem:
    """Everything the search and the feasibility checks need about one task; built once (`build_problem`) and
    never changed (its private lookups only fill caches)."""

    program: Program
    task: Task
    scene: Scene
    bodies: dict[str, PlanBody]
    robot_name: str
    arm: Arm
    effectors: list[EffectorSpec]
    goals: list[GoalSpec]
    table_center: np.ndarray | None
    table_size: np.ndarray | None
    table_z: float
    max_depth: int
    timeout: float
    avoid: Avoid | None = None  # what a re-solve must not repeat (`vkgl.plan.problem.avoid`); None: nothing
    arm_start: np.ndarray | None = None  # the arm's joints before the first step (None: its home configuration)
    keep_out: tuple[KeepOutSpec, ...] = ()
    """The task's keep-out regions: no body they apply to may enter one, along any motion."""
    pinned: tuple[float, ...] = ()
    """The first motion values of every sequence, fixed: those of a plan every sequence searched extends (a
    plan that cleared a body in the way, `vkgl.plan.search.clutter.clear_first`); none by default."""
    least: frozenset[str] = frozenset()
    """Bodies moved only to make room (`clear_first`'s goal bodies): their motions kept least (`least_room`)."""
    moves_once: int | None = None
    """Modes after the first `moves_once` graphs move each body at most once (`clear_first`'s narrow try)."""
    _footprints: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    _affordances: dict[tuple[str, str], Affordance] = field(default_factory=dict, repr=False)
    _effectors: dict[str, EffectorSpec] = field(default_factory=dict, repr=False)
    _actions: dict[tuple[str, str], np.ndarray] = field(default_factory=dict, repr=False)

    @property
    def robot_effector(self) -> EffectorSpec:
        """The robot's own effector (always the first)."""
        return self.effectors[0]

    def footprint_points(self, body: str) -> np.ndarray:
        """The body-frame points (n x 3) of `body`'s convex hull: its footprint on the table at any pose."""
        if body not in self._footprints:
            self._footprints[body] = _hull_points(self.bodies[body].type)
        return self._footprints[body]

    def affordance(self, body: str, name: str) -> Affordance:
        """The affordance `name` of scene body `body`, or the member of a family that `name` names (`push@+3.12cm`,
        `vkgl.lang.ir.families.find_member`)."""
        key = (body, name)
        if key not in self._affordances:  # looked up in every rollout: keep it a dict access
            found = find_member(self.bodies[body].affordances, name)  # a family's member: `push@+3.12cm`
            if found is None:
                raise KeyError(f"{body} has no affordance {name}")
            self._affordances[key] = found
        return self._affordances[key]

    def effector(self, name: str) -> EffectorSpec:
        """The effector called `name`."""
        if name not in self._effectors:
            self._effectors[name] = next(e for e in self.effectors if e.name == name)
        return self._effectors[name]

    def action(self, body: str, name: str) -> np.ndarray:
        """The effector frame in `body`'s frame while its affordance `name` holds (read-only)."""
        key = (body, name)
        if key not in self._actions:
            self._actions[key] = action_pose(self.affordance(body, name))
        return self._actions[key]


def build_problem(
    program: Program,
    task: Task,
    *,
    max_depth: int | None = None,
    timeout: float | None = None,
    avoid: Avoid | None = None,
    arm_start: Sequence[float] | np.ndarray | None = None,
) -> Problem:
    """The planning problem of `task` in `program`; command-line limits override the task's `search` block.
    `avoid` names what a re-solve must not repeat; `arm_start` are the arm's joints before the first step
    (default: its home configuration).

    Raises InputError (saying where and what to change) when the task's scene,
    robot or a goal body does not exist, or a limit is not positive.
    """
    scene = program.scenes.get(task.scene.name)
    if scene is None:
        raise InputError(f"{_where(task)}task {task.name}: no scene `{task.scene.name}` in the program")
    if not scene.robots:
        raise InputError(f"{_where(scene)}scene {scene.name} has no robot: add `robot arm : Panda at (0, 0, 0) m`")
    placed = scene.robots[0]
    robot = program.robots.get(placed.type.name)
    if robot is None:
        raise InputError(f"{_where(placed)}robot {placed.name} has the unknown type `{placed.type.name}`")
    effector_name = _robot_effector_name(program, robot)
    arm = _load_arm(robot, effector_name, placed.pose.matrix())
    bodies = {sb.name: _plan_body(program, scene, sb) for sb in scene.bodies}
    effectors = [EffectorSpec(f"{placed.name}.{effector_name}", None, np.eye(4))]
    effectors += _tool_effectors(program, scene, effector_name)
    goals = [_goal_spec(task, g, bodies) for g in task.goals]
    for goal in goals:
        arcs = _with_arc_members(bodies[goal.body], goal)
        bodies[goal.body] = _with_over_members(arcs, bodies, effectors, table_top(scene), arm, goal)
    search = task.search
    depth = max_depth if max_depth is not None else (search.max_depth if search and search.max_depth else None)
    limit = timeout if timeout is not None else (search.timeout.value if search and search.timeout else None)
    depth = DEFAULT_MAX_DEPTH if depth is None else int(depth)
    limit = DEFAULT_TIMEOUT if limit is None else float(limit)
    if depth < 1:
        raise InputError(f"max_depth must be at least 1 (graphs in a sequence, G0 included), got {depth}")
    if not limit > 0:
        raise InputError(f"the timeout must be positive, got {limit} s")
    center, size = scene_table(scene)
    start = None if arm_start is None else np.asarray(arm_start, dtype=float)
    return Problem(
        program,
        task,
        scene,
        bodies,
        placed.name,
        arm,
        effectors,
        goals,
        center,
        size,
        table_top(scene),
        depth,
        limit,
        avoid or None,
        start,
        tuple(_keep_out_spec(task, keep, bodies) for keep in task.keep_out),
    )


def _with_arc_members(body: PlanBody, goal: GoalSpec) -> PlanBody:
    """`body` with the members of its arc families that reach a place goal, with its heading or any, in one push
    (`vkgl.plan.problem.arcs`)."""
    if goal.position is None or goal.region is not None or goal.opening is not None:
        return body
    where, tolerances = goal.position[:2], (goal.tol_position, goal.tol_yaw)
    members = arc_members(body.affordances, body.rest, where, goal.yaw, tolerances)
    known = {a.name for a in body.affordances}  # two goals on one body may pick the same member
    members = tuple(m for m in members if m.name not in known)
    if not members:
        return body
    exact = {m.name for m in arc_members(body.affordances, body.rest, where, goal.yaw, tolerances, reach=1.0)}
    seeds = frozenset(m.name for m in members if m.name not in exact)
    return replace(body, affordances=body.affordances + members, arc_seeds=body.arc_seeds | seeds)


def _with_over_members(
    body: PlanBody, bodies: dict[str, PlanBody], effectors: list[EffectorSpec], table: float, arm: Arm, goal: GoalSpec
) -> PlanBody:
    """`body` with its slides enacted by a tool rolled over its top, where the tool lying flat would stand in it,
    its arcs' members rolled over the low bodies beside it (`vkgl.plan.problem.over`), and its slides a tool
    enacts with the hand out of `arm`'s reach on its way to `goal` enacted nearer the arm
    (`vkgl.plan.problem.reach_members`); only a body lying on the table (`table`: the table top's height)."""
    if not body.on_table or body.joint is not None or abs(body.rest[2, 2]) < 0.99:
        return body
    tools = [(e.name, bodies[e.tool].type, e.frame) for e in effectors if e.tool is not None and e.tool != body.name]
    points, kinds = _hull_points(body.type), {tool.name for _, tool, _ in tools}
    near = [b for b in bodies.values() if b is not body and b.on_table and b.type.name not in kinds]  # not tools
    others = [(b.rest, _hull_points(b.type)) for b in near]
    beside = clearing_height(body.rest, points, [tool for _, tool, _ in tools], others, table) if tools else 0.0
    members, pairs = over_members(body.affordances, points, tools, beside, body.type.friction)
    far, far_pairs = reach_members(body, bodies, effectors, points, arm, goal)
    members, pairs = members + far, pairs | far_pairs
    known = {a.name for a in body.affordances}
    fresh = tuple(m for m in members if m.name not in known)
    if not fresh:
        return body
    return replace(body, affordances=body.affordances + fresh, tool_members=body.tool_members | pairs)


def _where(node: object) -> str:
    span = getattr(node, "span", None)
    return f"{span}: " if span is not None else ""


def _robot_effector_name(program: Program, robot: Robot) -> str:
    """The effector the plans use: the first one that tools correspond to, else the robot's first."""
    names = [e.name for e in robot.effectors]
    if not names:
        raise InputError(f"{_where(robot)}robot {robot.name} declares no effector")
    for corr in program.correspondences:
        if corr.effector.name in names:
            return corr.effector.name
    return names[0]


def _load_arm(robot: Robot, effector: str, base: np.ndarray) -> Arm:
    """The arm of `robot` at `base`, loaded once per process (per URDF, effector and base)."""
    key = (robot.urdf_resolved or robot.urdf, effector, base.tobytes())
    if key not in _ARMS:
        _ARMS[key] = Arm.load(robot, effector, base)
    return _ARMS[key]


def _plan_body(program: Program, scene: Scene, scene_body: SceneBody) -> PlanBody:
    body = program.bodies.get(scene_body.type.name)
    if body is None:
        raise InputError(
            f"{_where(scene_body)}scene body {scene_body.name} has the unknown type `{scene_body.type.name}`"
        )
    rest = scene_body_pose(scene, scene_body, body)
    yaw = math.atan2(rest[1, 0], rest[0, 0])
    # a fixed action (a push, a tool's wield) or a grasp: both put the effector at a pose on the body
    fixed = tuple(
        a for a in program.affordances.get(body.name, []) if isinstance(a.action, FixedC) or a.action.type == "grasp"
    )
    usable, too_high = split_by_tipping(body, fixed, program.tipping.get(body.name, []))
    joint = body.joint
    return PlanBody(
        name=scene_body.name,
        type=body,
        rest=rest,
        rest_z=resting_height(body, yaw, table_top(scene)),
        on_table=scene_body.placement.on_table,
        affordances=usable,
        joint=None if joint is None else joint.type,
        joint_axis=None if joint is None else joint_axis(joint),
        joint_limits=None if joint is None else (joint.lower.value, joint.upper.value),
        joint_zero=None if joint is None else scene_body_anchor(scene, scene_body, body),
        outline=hull_corners(shape_vertices(body.shape)),
        too_high=too_high,
    )


def hull_corners(vertices: np.ndarray) -> np.ndarray:
    """The vertices of the convex hull of `vertices` (k x 3): what can first pass a table's edge."""
    return outline_corners(vertices)  # flat: every point counts


def action_pose(affordance: Affordance) -> np.ndarray:
    """The effector frame in the body's frame of a fixed action (identity when it gives no pose)."""
    pose = affordance.action.pose  # type: ignore[union-attr]
    return np.eye(4) if pose is None else pose.matrix()


def _tool_effectors(program: Program, scene: Scene, effector_name: str) -> list[EffectorSpec]:
    """Every scene body frame with a correspondence to the robot's effector, in correspondence then scene order."""
    out = []
    for corr in program.correspondences:
        if corr.effector.name != effector_name:
            continue
        body_type = program.bodies.get(corr.frame.body)
        if body_type is None:
            continue
        frame = body_type.frame(corr.frame.frame)
        if frame is None:
            raise InputError(
                f"{_where(corr)}correspondence {corr.frame.body}.{corr.frame.frame}: "
                f"body {corr.frame.body} has no frame `{corr.frame.frame}`"
            )
        for sb in scene.bodies:
            if sb.type.name == corr.frame.body:
                out.append(EffectorSpec(f"{sb.name}.{corr.frame.frame}", sb.name, frame.pose.matrix()))
    return out


def _goal_spec(task: Task, goal: Goal, bodies: dict[str, PlanBody]) -> GoalSpec:
    name = goal.body.name
    if name not in bodies:
        known = ", ".join(bodies) or "none"
        raise InputError(
            f"{_where(goal)}task {task.name}: the goal names `{name}`, which is not a body of the "
            f"scene (its bodies: {known})"
        )
    position = goal.position.array() if goal.position is not None else None
    yaw = goal.yaw.value if goal.yaw is not None else None
    tol_p, tol_y = goal.tolerance()
    if goal.region is not None:
        hull = _hull_points(bodies[name].type)
        words = goal.region.words()
        return GoalSpec(name, None, yaw, float(tol_p), float(tol_y), None, 0.0, goal.region.halfplanes(), hull, words)
    if goal.relative and position is None and yaw is None:  # what `vkgc check` fills in, for goals made without it
        raise InputError(f"{_where(goal)}task {task.name}: the relative goal on `{name}` was not placed by the checker")
    if goal.opening is None:
        return GoalSpec(name, position, yaw, float(tol_p), float(tol_y))
    body = bodies[name]
    wanted = {"prismatic": ("m", "cm", "mm"), "revolute": ("deg", "rad")}.get(body.joint or "", ())
    if goal.opening.unit not in wanted:  # what `vkgc check` reports (E441, E201), for goals made without it
        kind = "a length" if body.joint == "prismatic" else "an angle"
        has = f"a {body.joint} joint, which opens by {kind}" if body.joint else "no physical joint to open"
        raise InputError(f"{_where(goal)}task {task.name}: the joint goal on `{name}` cannot hold: `{name}` has {has}")
    tolerance = goal.opening_tolerance()
    if not tolerance > 0:  # what `vkgc check` reports (E411)
        raise InputError(f"{_where(goal)}task {task.name}: the joint goal on `{name}` needs a positive tolerance")
    return GoalSpec(name, position, yaw, float(tol_p), float(tol_y), goal.opening.value, tolerance)


def _hull_points(body: Body) -> np.ndarray:
    points = shape_vertices(body.shape)
    return points[hull_vertices(points)] if len(points) > 4 else points


def _keep_out_spec(task: Task, keep: KeepOut, bodies: dict[str, PlanBody]) -> KeepOutSpec:
    if keep.region is None or (keep.body is not None and keep.body.name not in bodies):  # what `vkgc check` reports
        raise InputError(f"{_where(keep)}task {task.name}: a keep-out region that `vkgc check` has not resolved")
    return KeepOutSpec(keep.region.points(), keep.body.name if keep.body is not None else None, keep.region.words())


def collision_scene(
    problem: Problem,
    tol: float = TOUCH_TOL,
    margin: float = 0.0,
    exact: Iterable[str] = (),
    margins: Mapping[str, float] | None = None,
) -> CollisionScene:
    """The collision scene of `problem`: its bodies' shapes (grown by `margin`, but those named in `exact`, and
    those in `margins` by their own) and its table (if the scene has one).

    A body on a physical joint is where the simulator hangs it: `JOINT_LIFT` above its planned pose.
    """
    shapes = {name: body.type.shape for name, body in problem.bodies.items()}
    lifts = {name: JOINT_LIFT for name, body in problem.bodies.items() if body.joint_limits is not None}
    return CollisionScene(
        shapes,
        table_center=problem.table_center,
        table_size=problem.table_size,
        table_z=problem.table_z,
        tol=tol,
        margin=margin,
        lifts=lifts,
        exact=exact,
        margins=margins,
    )
