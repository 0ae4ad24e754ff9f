"""A compiled program: every module of one compilation, resolved into one flat namespace.

This is what `vkgl.compile(path)` returns and what the back ends consume.

Changing a problem without editing source: the IR is frozen, so `with_goal`,
`with_start` and `with_start_poses` return a new Program with one task's goal
or one scene's start poses replaced (in `tasks` / `scenes`; `root`, `modules`
and `sources` keep the source as written). Solve the new Program as usual:

    program = vkgl.compile("examples/tasks/a_push.vkg")
    moved = program.with_goal("a_push", "block", at=(0.6, 0.1), yaw=math.radians(30))
    moved = moved.with_start("a_push", "block", at=(0.45, -0.1), yaw=0.0)
    plan = vkgl.solve(moved)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from vkgl.errors import InputError, did_you_mean
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir.nodes import (
    Affordance,
    Body,
    Correspondence,
    Goal,
    MeshShape,
    Module,
    Placement,
    Pose,
    Quantity,
    Ref,
    Robot,
    Scene,
    SceneBody,
    Shape,
    Task,
    Tipping,
    UnionShape,
    Vector,
)
from vkgl.lang.ir.regions import KeepOut, Region, region_problem

if TYPE_CHECKING:  # imported where the numbers are wanted, so that `vkgc check` loads neither
    import numpy as np

# A body tilted less than this from level still counts as lying on the table (`with_start_poses`).
LEVEL_TILT = math.radians(2.0)


@dataclass
class Program:
    """The checked IR of a root module and everything it (transitively) uses.

    `affordances` maps a body type name to its affordances, in declaration order,
    merged over every `affordances BODY { ... }` block of the compilation;
    `tipping` its `tips above` clauses, merged the same way.
    `warnings` holds the non-fatal diagnostics of the compilation.
    """

    root: Module
    modules: dict[str, Module] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    robots: dict[str, Robot] = field(default_factory=dict)
    affordances: dict[str, list[Affordance]] = field(default_factory=dict)
    correspondences: list[Correspondence] = field(default_factory=list)
    tipping: dict[str, list[Tipping]] = field(default_factory=dict)
    scenes: dict[str, Scene] = field(default_factory=dict)
    tasks: dict[str, Task] = field(default_factory=dict)
    warnings: list[Diagnostic] = field(default_factory=list)
    sources: dict[str, str] = field(default_factory=dict)

    def body(self, name: str | None = None) -> Body:
        """The body called `name` (any in scope), or the only body the root module declares.

        Raises InputError (saying what there is) when there is no such body, or
        when `name` is None and the root module declares none or several.
        """
        where = self.root.path
        if name is not None:
            if name not in self.bodies:
                known = ", ".join(sorted(self.bodies)) or "none"
                hint = did_you_mean(name, self.bodies)
                raise InputError(
                    f"{where}: no body named `{name}` ({hint + ' ' if hint else ''}bodies in scope: {known})"
                )
            return self.bodies[name]
        own = [d for d in self.root.decls if isinstance(d, Body)]
        if not own:
            raise InputError(f"{where}: declares no body; give a file with a `body NAME {{ ... }}` declaration")
        if len(own) > 1:
            names = ", ".join(b.name for b in own)
            raise InputError(f"{where}: declares {len(own)} bodies ({names}); say which with --body NAME")
        return own[0]

    def task(self, name: str | None = None) -> Task:
        """The task called `name`; with no name, the only task of the root module (or of the program).

        Raises InputError listing the task names when `name` is unknown, or when it
        is None and there is no task or more than one.
        """
        where = self.root.path
        known = ", ".join(sorted(self.tasks)) or "none"
        if name is not None:
            if name not in self.tasks:
                hint = did_you_mean(name, self.tasks)
                raise InputError(f"{where}: no task `{name}` ({hint + ' ' if hint else ''}tasks: {known})")
            return self.tasks[name]
        own = [d.name for d in self.root.decls if isinstance(d, Task) and d.name in self.tasks]
        candidates = own or sorted(self.tasks)
        if not candidates:
            raise InputError(f"{where}: declares no task; give a file with a `task NAME {{ ... }}` declaration")
        if len(candidates) > 1:
            raise InputError(
                f"{where}: declares {len(candidates)} tasks ({', '.join(candidates)}); "
                "say which by name (`vkgc solve --task NAME`, or `program.task(NAME)`)"
            )
        return self.tasks[candidates[0]]

    def files(self) -> dict[Path, str]:
        """Every file this compilation read, by real path: its modules, meshes and URDFs, each saying what it is.

        What an output must never replace (`vkgc solve --json`, `explore -o`
        refuse them); the values are for messages, e.g. "the module
        `examples/scenes/tabletop.vkg`".
        """
        found: dict[Path, str] = {}
        for shown in self.modules:
            if not shown.startswith("<"):  # `compile_source`'s text has no file
                found.setdefault(Path(shown).resolve(), f"the module `{shown}`")
        for body in self.bodies.values():
            for mesh in _meshes(body.shape):
                found.setdefault(Path(mesh.resolved or mesh.path).resolve(), f"the mesh `{mesh.path}`")
        for robot in self.robots.values():
            found.setdefault(Path(robot.urdf_resolved or robot.urdf).resolve(), f"the URDF `{robot.urdf}`")
        return found

    def with_goal(
        self,
        task: str | Task | None,
        body: str,
        *,
        at: Sequence[float] | None = None,
        yaw: float | None = None,
        within: tuple[float, float] | float | None = None,
        open: float | None = None,  # the goal's keyword, as in `goal B open Q` (shadows the builtin here only)
        region: Sequence[Sequence[float]] | None = None,
    ) -> Program:
        """A copy whose `task` has the goal on `body` replaced (or added, if it had none).

        `at`: (x, y) or (x, y, z) in metres, None for a heading-only goal; `yaw`:
        radians, None for a free heading; `within`: (metres, radians) tolerances,
        None to keep those of the goal replaced (the defaults for a new goal).
        `open`: a joint goal instead (`goal B open Q`): the coordinate of the
        body's physical joint, metres for a prismatic joint and radians for a
        revolute one, 0 where the scene places the body; its `within` is one
        number of the same kind (None: the tolerance of the joint goal
        replaced, else 1 cm or 3 deg).
        Raises InputError for an unknown task or body, a goal that says nothing,
        a joint goal with a position or heading too, or on a body without a joint.
        `region`: a region goal instead of a position (`goal B in region ...`), two corners (x, y) in metres
        for a box (lower-left, upper-right) or three or more vertices of a convex polygon; `yaw` may be given
        with it. Raises InputError for a region that is not one (docs/language.md, "Regions").
        """
        chosen = self._task_of(task)
        scene = self._scene_of(chosen)
        placed = self._scene_body(scene, body)
        if region is not None:
            if at is not None or open is not None:
                raise InputError(f"a region goal on `{body}` takes no position (`at`) or opening (`open`)")
            return self._with_goal_on(chosen, _region_goal(chosen, body, region, yaw, within))
        if open is not None:
            if at is not None or yaw is not None:
                raise InputError(
                    f"a joint goal on `{body}` (`open`) takes no position or heading: give one or the other"
                )
            return self._with_joint_goal(chosen, placed, float(open), within)
        if at is None and yaw is None:
            raise InputError(f"a goal on `{body}` needs a position (`at`), a heading (`yaw`), or both")
        if at is not None and len(at) not in (2, 3):
            raise InputError(f"a goal position is (x, y) or (x, y, z) in metres, got {len(at)} values")
        old = [g for g in chosen.goals if g.body.name == body]
        if within is not None:
            if not isinstance(within, Sequence) or len(within) != 2:
                raise InputError(f"the tolerances of a pose goal are (metres, radians), got {within!r}")
            if not all(math.isfinite(t) and t > 0 for t in within):
                raise InputError(f"goal tolerances must be positive, got {tuple(within)}")
            tol_position: Quantity | None = Quantity(value=float(within[0]), unit="m")
            tol_yaw: Quantity | None = Quantity(value=float(within[1]), unit="rad")
        else:
            tol_position = old[0].tol_position if old else None
            tol_yaw = old[0].tol_yaw if old else None
        goal = Goal(
            body=Ref(name=body),
            position=Vector(values=tuple(float(v) for v in at), unit="m") if at is not None else None,
            yaw=Quantity(value=float(yaw), unit="rad") if yaw is not None else None,
            tol_position=tol_position if at is not None else None,
            tol_yaw=tol_yaw,
        )
        return self._with_goal_on(chosen, goal)

    def _with_joint_goal(
        self, task: Task, placed: SceneBody, value: float, within: tuple[float, float] | float | None
    ) -> Program:
        """`with_goal(..., open=value)`: the joint goal on `placed`, of its joint's kind (m or rad)."""
        name = placed.name
        kind = self.bodies.get(placed.type.name)
        joint = kind.joint if kind is not None else None
        if joint is None:
            raise InputError(
                f"`{name}` has no physical joint to open: its type `{placed.type.name}` declares no `joint` "
                "(give it a pose goal, `at=` and `yaw=`)"
            )
        unit = "m" if joint.type == "prismatic" else "rad"
        if not math.isfinite(value):
            raise InputError(f"a joint goal's opening must be a finite number of {unit}, got {value}")
        old = next((g for g in task.goals if g.body.name == name and g.opening is not None), None)
        tolerance = old.tol_opening if old is not None else None
        if within is not None:
            if isinstance(within, Sequence) or not (math.isfinite(within) and within > 0):
                raise InputError(f"a joint goal's tolerance is one positive number of {unit}, got {within!r}")
            tolerance = Quantity(value=float(within), unit=unit)
        elif tolerance is not None and tolerance.unit not in (("m", "cm", "mm") if unit == "m" else ("deg", "rad")):
            tolerance = None  # the old goal's was of the other kind: the default
        goal = Goal(body=Ref(name=name), opening=Quantity(value=value, unit=unit), tol_opening=tolerance)
        return self._with_goal_on(task, goal)

    def _with_goal_on(self, task: Task, goal: Goal) -> Program:
        """A copy whose `task` has `goal` in place of its goals on the same body (where the first was)."""
        body = goal.body.name
        old = [g for g in task.goals if g.body.name == body]
        goals = [g for g in task.goals if g.body.name != body]
        index = task.goals.index(old[0]) if old else len(task.goals)
        goals.insert(min(index, len(goals)), goal)
        return dataclasses.replace(self, tasks={**self.tasks, task.name: task.model_copy(update={"goals": goals})})

    def with_keep_out(
        self, task: str | Task | None, region: Sequence[Sequence[float]], body: str | None = None
    ) -> Program:
        """A copy whose `task` also keeps every body (or only `body`) out of `region` (`keep out region ...`,
        `keep B out of region ...`): two corners (x, y) in metres of a box, or the vertices of a convex polygon.

        Raises InputError for an unknown task or body, or a region that is not one. (`vkgc check`'s E452, a
        body that starts inside, is not checked here: the planner then finds no plan that moves that body.)
        """
        chosen = self._task_of(task)
        ref = Ref(name=self._scene_body(self._scene_of(chosen), body).name) if body is not None else None
        keep = KeepOut(body=ref, region=_region(region))
        updated = chosen.model_copy(update={"keep_out": [*chosen.keep_out, keep]})
        return dataclasses.replace(self, tasks={**self.tasks, chosen.name: updated})

    def with_start(
        self, scene_or_task: str | Task | Scene, body: str, *, at: Sequence[float], yaw: float = 0.0
    ) -> Program:
        """A copy where `body` of the scene (given by name, or by a task that uses it) starts
        `on table at (x, y)` metres with heading `yaw` radians.

        Raises InputError for an unknown scene, task or body.
        """
        scene = self._scene_named(scene_or_task)
        placed = self._scene_body(scene, body)
        if len(at) != 2:
            raise InputError(f"a start on the table is (x, y) in metres, got {len(at)} values")
        pose = Pose(
            position=Vector(values=(float(at[0]), float(at[1])), unit="m"), yaw=Quantity(value=float(yaw), unit="rad")
        )
        moved = placed.model_copy(update={"placement": Placement(on_table=True, pose=pose)})
        return self._with_scene_body(scene, moved)

    def with_start_poses(self, task: str | Task | None, poses: Mapping[str, np.ndarray]) -> Program:
        """A copy whose task scene starts where the bodies are (`poses`: scene body name -> 4x4 world pose).

        A body placed on the table that still lies level (tilt under 2 deg) is placed
        `on table at (x, y) yaw`; any other is placed at its full pose. A body on a
        physical joint stays where its joint is anchored (its placement, where the
        coordinate is 0) and starts `open` at the coordinate of its pose there, so
        that its limits and joint goals keep their meaning. Bodies not in
        `poses` keep their placement; names that are not scene bodies are ignored.
        This is what the closed-loop executor does with observed poses.
        """
        import numpy as np

        from vkgl.lang.ir.geometry import joint_axis, joint_coordinate, scene_body_anchor

        scene = self._scene_of(self._task_of(task))
        bodies = []
        for scene_body in scene.bodies:
            pose = poses.get(scene_body.name)
            if pose is None:
                bodies.append(scene_body)
                continue
            body = self.bodies.get(scene_body.type.name)
            joint = body.joint if body is not None else None
            if body is not None and joint is not None:
                anchor = scene_body_anchor(scene, scene_body, body)
                value = joint_coordinate(joint.type, joint_axis(joint), anchor, np.asarray(pose, dtype=float))
                value = min(max(value, joint.lower.value), joint.upper.value)  # a stop holds it within
                unit = "m" if joint.type == "prismatic" else "rad"
                bodies.append(scene_body.model_copy(update={"opening": Quantity(value=value, unit=unit)}))
                continue
            placement = observed_placement(np.asarray(pose, dtype=float), scene_body.placement.on_table)
            bodies.append(scene_body.model_copy(update={"placement": placement}))
        observed = scene.model_copy(update={"bodies": bodies})
        return dataclasses.replace(self, scenes={**self.scenes, scene.name: observed})

    # ------------------------------------------------------------ helpers of the edits

    def _task_of(self, task: str | Task | None) -> Task:
        if isinstance(task, Task):
            return self.task(task.name)
        return self.task(task)

    def _scene_of(self, task: Task) -> Scene:
        scene = self.scenes.get(task.scene.name)
        if scene is None:
            raise InputError(f"task `{task.name}` names no known scene (`{task.scene.name}`)")
        return scene

    def _scene_named(self, scene_or_task: str | Task | Scene) -> Scene:
        if isinstance(scene_or_task, Scene):
            return self._scene_named(scene_or_task.name)
        if isinstance(scene_or_task, Task):
            return self._scene_of(self._task_of(scene_or_task))
        if scene_or_task in self.scenes:
            return self.scenes[scene_or_task]
        if scene_or_task in self.tasks:
            return self._scene_of(self.tasks[scene_or_task])
        known = ", ".join(sorted(self.scenes) + sorted(self.tasks)) or "none"
        hint = did_you_mean(scene_or_task, [*self.scenes, *self.tasks])
        raise InputError(f"no scene or task `{scene_or_task}` ({hint + ' ' if hint else ''}scenes and tasks: {known})")

    @staticmethod
    def _scene_body(scene: Scene, name: str) -> SceneBody:
        for placed in scene.bodies:
            if placed.name == name:
                return placed
        known = ", ".join(b.name for b in scene.bodies) or "none"
        hint = did_you_mean(name, [b.name for b in scene.bodies])
        raise InputError(f"scene `{scene.name}` has no body `{name}` ({hint + ' ' if hint else ''}its bodies: {known})")

    def _with_scene_body(self, scene: Scene, moved: SceneBody) -> Program:
        bodies = [moved if b.name == moved.name else b for b in scene.bodies]
        return dataclasses.replace(
            self, scenes={**self.scenes, scene.name: scene.model_copy(update={"bodies": bodies})}
        )


def observed_placement(pose: np.ndarray, was_on_table: bool) -> Placement:
    """The placement of a body seen at the 4x4 world `pose`: on the table if it was and still lies level."""
    import numpy as np
    from scipy.spatial.transform import Rotation

    yaw = math.atan2(pose[1, 0], pose[0, 0])
    tilt = float(np.arccos(np.clip(pose[2, 2], -1.0, 1.0)))
    if was_on_table and tilt < LEVEL_TILT:
        planar = Pose(
            position=Vector(values=(float(pose[0, 3]), float(pose[1, 3])), unit="m"),
            yaw=Quantity(value=yaw, unit="rad"),
        )
        return Placement(on_table=True, pose=planar)
    rpy = Rotation.from_matrix(pose[:3, :3]).as_euler("xyz")
    full = Pose(
        position=Vector(values=tuple(float(v) for v in pose[:3, 3]), unit="m"),
        rpy=Vector(values=tuple(float(v) for v in rpy), unit="rad"),
    )
    return Placement(on_table=False, pose=full)


def _meshes(shape: Shape) -> list[MeshShape]:
    """The mesh files of a shape (a union's parts included)."""
    if isinstance(shape, MeshShape):
        return [shape]
    if isinstance(shape, UnionShape):
        return [mesh for part in shape.parts for mesh in _meshes(part.shape)]
    return []


def _region_goal(
    task: Task,
    body: str,
    corners: Sequence[Sequence[float]],
    yaw: float | None,
    within: tuple[float, float] | float | None,
) -> Goal:
    """`with_goal(..., region=corners)`: the region goal, its region checked as `vkgc check` checks one."""
    region = _region(corners)
    old = next((g for g in task.goals if g.body.name == body), None)
    tolerances = (old.tol_position, old.tol_yaw) if old is not None else (None, None)
    if within is not None:
        if not isinstance(within, Sequence) or len(within) != 2 or not all(math.isfinite(t) and t > 0 for t in within):
            raise InputError(
                f"the tolerances of a region goal are two positive numbers (metres, radians), got {within!r}"
            )
        tolerances = (Quantity(value=float(within[0]), unit="m"), Quantity(value=float(within[1]), unit="rad"))
    heading = Quantity(value=float(yaw), unit="rad") if yaw is not None else None
    return Goal(body=Ref(name=body), region=region, yaw=heading, tol_position=tolerances[0], tol_yaw=tolerances[1])


def _region(corners: Sequence[Sequence[float]]) -> Region:
    """The region of `corners` in metres (two: a box; more: a polygon), or InputError saying why it is none."""
    try:
        vectors = [Vector(values=tuple(float(v) for v in c), unit="m") for c in corners]
    except (TypeError, ValueError) as exc:
        raise InputError(f"a region's corners are (x, y) pairs of metres, got {corners!r}") from exc
    region = Region(kind="box", corners=vectors) if len(vectors) == 2 else Region(kind="polygon", corners=vectors)
    problem = region_problem(region)
    if problem is not None:
        raise InputError(f'the region {corners!r} is not a region ({problem}): see docs/language.md, "Regions"')
    return region
