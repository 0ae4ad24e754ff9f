"""The planning problem: what the search needs to know about a task, read once from the IR.

`build_problem(program, task)` gathers the scene's bodies with their resting
poses and usable affordances, the robot's arm (URDF, effector, base), the
effectors (the robot's own and every tool frame with a correspondence), the
goals in SI and the table. Everything here is plain numpy; the search and the
feasibility checks never look at the IR again.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from vkgl.errors import InputError
from vkgl.lang.ir.geometry import (
    joint_axis,
    joint_coordinate,
    resting_height,
    scene_body_anchor,
    scene_body_pose,
    scene_table,
    table_top,
)
from vkgl.lang.ir.nodes import (
    Affordance,
    Body,
    FixedC,
    Goal,
    Robot,
    Scene,
    SceneBody,
    Task,
)
from vkgl.lang.ir.program import Program
from vkgl.motion.collision import TOUCH_TOL, CollisionScene
from vkgl.plan.problem.avoid import Avoid
from vkgl.robot import Arm

DEFAULT_MAX_DEPTH = 10
"""Graphs in the longest sequence searched (G0 included) when the task says nothing."""

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
    scene starts it `open Q`).
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
    """

    body: str
    position: np.ndarray | None
    yaw: float | None
    tol_position: float
    tol_yaw: float
    opening: float | None = None
    tol_opening: float = 0.0


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
    arm_start: np.ndarray | None = None
    """The arm's joints before the first step (None: its home configuration)."""
    _affordances: dict[tuple[str, str], Affordance] = field(default_factory=dict, repr=False)
    _effectors: dict[str, EffectorSpec] = field(default_factory=dict, repr=False)
    _actions: dict[tuple[str, str], np.ndarray] = field(default_factory=dict, repr=False)

    @property
    def robot_effector(self) -> EffectorSpec:
        """The robot's own effector (always the first)."""
        return self.effectors[0]

    def affordance(self, body: str, name: str) -> Affordance:
        """The affordance `name` of scene body `body`."""
        key = (body, name)
        if key not in self._affordances:  # looked up in every rollout: keep it a dict access
            self._affordances[key] = next(a for a in self.bodies[body].affordances if a.name == name)
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
    )


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
    usable = tuple(a for a in program.affordances.get(body.name, []) if isinstance(a.action, FixedC))
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
    )


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


def collision_scene(problem: Problem, tol: float = TOUCH_TOL, margin: float = 0.0) -> CollisionScene:
    """The collision scene of `problem`: its bodies' shapes and its table (if the scene has one)."""
    shapes = {name: body.type.shape for name, body in problem.bodies.items()}
    return CollisionScene(
        shapes,
        table_center=problem.table_center,
        table_size=problem.table_size,
        table_z=problem.table_z,
        tol=tol,
        margin=margin,
    )
