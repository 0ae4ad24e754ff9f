"""The DART world of a task's scene, in which a plan is carried out (`vkgl.execute.replay`).

`SceneWorld` holds one simulated world: the table, every scene body with its
physics (built by `vkgl.sim.world`, exactly as for exploration), and the arm
(`vkgl.execute.world_arm`). It steps the physics, records frames for the
animation, watches for touches while the arm moves through free space, and
answers where the bodies are and how high the arm must travel to clear them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from vkgl.errors import InputError, SimulationError
from vkgl.execute.grip.fingers import Fingers
from vkgl.execute.grip.watch import GripWatch
from vkgl.execute.world_arm import FINGERTIP_RADIUS, ArmStuck, WorldArm, rx_pi
from vkgl.formats.execution_report import Frames
from vkgl.formats.plan import PlanRobot
from vkgl.lang.ir.geometry import body_mesh, joint_axis, joint_coordinate, scene_body_anchor, table_top
from vkgl.lang.ir.nodes import Body, Scene
from vkgl.lang.ir.program import Program

TIME_STEP = 0.001  # s, fixed physics step
CLEARANCE = 0.04  # m above the highest body when travelling
FRAME_PERIOD = 0.04  # s between recorded frames (25 frames per simulated second)


class SceneWorld:
    """A DART world of one task's scene with the plan's robot in it; the bodies move only through contact."""

    def __init__(self, program: Program, scene: Scene, robot: PlanRobot, *, record: bool) -> None:
        from vkgl.robot import Arm
        from vkgl.sim import world as sim_world

        self.program = program
        self.scene = scene
        self.types: dict[str, Body] = {sb.name: program.bodies[sb.type.name] for sb in scene.bodies}
        self.table_z = table_top(scene)
        # the physics exploration learned the models in (its solver's stop too: vkgl.sim.world)
        self.world = sim_world.new_world(TIME_STEP, tolerance=sim_world.EXECUTION_SOLVER_TOLERANCE)
        self.table = sim_world.add_table(self.world, scene.table)[1] if scene.table is not None else None
        self.nodes: dict[str, tuple[Any, Any]] = {}
        self.anchors: dict[str, np.ndarray] = {}  # bodies on physical joints: where their coordinate is 0
        for sb in scene.bodies:
            # a body on a physical joint is anchored where it is placed and starts at its `open Q`
            anchor = scene_body_anchor(scene, sb, self.types[sb.name])
            joint_start = None
            if self.types[sb.name].joint is not None:
                self.anchors[sb.name] = anchor
                joint_start = sb.start_opening()
            self.nodes[sb.name] = sim_world.add_body(self.world, sb.name, self.types[sb.name], anchor, joint_start)
        self.robot_name, robot_ir, base = self._robot(robot)
        self.base_xy = base[:2, 3].copy()
        self.effector_name = robot.effector
        effector = robot_ir.effector(self.effector_name)
        if effector is None:
            raise InputError(f"robot {robot_ir.name} has no effector `{self.effector_name}`")
        self.arm_model = Arm.load(robot_ir, self.effector_name, base)
        skeleton = _world_skeleton(self.arm_model, robot_ir)
        self.arm = WorldArm(
            self.world,
            self.arm_model,
            skeleton,
            effector.link,
            effector.offset.matrix() @ rx_pi(),
            base,
            np.asarray(self.arm_model.home, dtype=float),
            table=self.table,
        )
        self.grip = GripWatch(self.arm)  # the load on the grip and the slip of a held tool
        self.fingers = Fingers(self.arm)  # the hand's finger joints, if its URDF has them
        self.meshes = {name: body_mesh(body) for name, body in self.types.items()}
        self.skeleton_names = {skeleton.getName(): name for name, (skeleton, _) in self.nodes.items()}
        self._owners: dict[int, str] = {}  # shape id -> the name of the skeleton it is on (`_owner`)
        self.guarded = False  # True while moving through free space: touching a body there is a failure
        self.planned = self.poses()  # the ghost: where the current plan wants every body now
        self.frames = Frames(list(self.nodes)) if record else None
        self.label = "start"
        self.on_advance: Callable[[], None] | None = None  # told after every `advance` (live progress)
        self._next_frame = 0.0
        self.record()

    def _robot(self, entry: PlanRobot) -> tuple[str, Any, np.ndarray]:
        name = entry.name
        scene_robot = next((r for r in self.scene.robots if r.name == name), None)
        if scene_robot is None:
            raise InputError(f"the plan's robot `{name}` is not in scene {self.scene.name}")
        robot_ir = self.program.robots[scene_robot.type.name]
        return name, robot_ir, scene_robot.pose.matrix()

    # ------------------------------------------------------------ observation

    @property
    def time(self) -> float:
        """Simulated time since the start (s)."""
        return float(self.world.getTime())

    def poses(self) -> dict[str, np.ndarray]:
        """The real world poses of every scene body now."""
        return {name: node.getWorldTransform().matrix().copy() for name, (_, node) in self.nodes.items()}

    def holding(self) -> str | None:
        """The name of the tool in the hand, if any."""
        return None if self.arm.held is None else self.arm.held.name

    def openings(self) -> dict[str, float]:
        """The coordinate of every body's physical joint now, as DART's joint has it (m or rad, 0 at the anchor)."""
        return {name: float(self.nodes[name][0].getPosition(0)) for name in self.anchors}

    def opening_at(self, name: str, pose: np.ndarray) -> float:
        """The coordinate of body `name`'s physical joint when the body is at world `pose` (a planned pose)."""
        joint = self.types[name].joint
        assert joint is not None, f"{name} has no physical joint"
        return joint_coordinate(joint.type, joint_axis(joint), self.anchors[name], pose)

    # ------------------------------------------------------------ running

    def advance(self, n: int) -> None:
        """Run `n` physics steps with the arm's current commands (recording frames, watching for touches and
        the grip on a held tool)."""
        watching = self.grip.held is not None
        for _ in range(n):
            self.world.step(False)  # keep the arm's velocity commands for the whole control period
            if watching:
                self.grip.after_physics_step(self.world)
            if self.frames is not None and self.time >= self._next_frame - 1e-9:
                self.record()
        if watching:
            self.grip.after_period(n * self.world.getTimeStep())  # may break the grip, or fail on a slip
        self.arm.update_letting_go()  # a tool let go of is touched again once the hand has left it
        if self.guarded:  # once per control period is enough to stop in time
            self._check_clear()
        if self.on_advance is not None:
            self.on_advance()

    def _check_clear(self) -> None:
        """Stop a move through free space as soon as the robot or what it holds touches a body."""
        robot = {self.arm.skeleton.getName()}
        if self.arm.held is not None:
            robot.add(self.arm.held.skeleton.getName())
        for contact in self.world.getLastCollisionResult().getContacts():
            # pairs kept apart (the switched-off pad, a held tool) are not reported
            a = self._owner(contact.collisionObject1)
            b = self._owner(contact.collisionObject2)
            for mine, other in ((a, b), (b, a)):
                if mine in robot and other in self.skeleton_names and other not in robot:  # not arm vs. held tool
                    what = "the fingertip" if mine == self.arm.skeleton.getName() else f"the held {self.holding()}"
                    raise ArmStuck(
                        f"{what} touched {self.skeleton_names[other]} on its planned way through free space "
                        "(the planner found it clear: is the body where the plan expects it?)"
                    )

    def _owner(self, collision_object: Any) -> str:
        """The name of the skeleton a contact's collision object is on, looked up once per shape: by its shape's
        id (unique among the shapes alive, never reused), three calls where the skeleton's name took five."""
        key = int(collision_object.getShape().getID())
        name = self._owners.get(key)
        if name is None:
            name = self._owners[key] = _skeleton_name(collision_object)
        return name

    def record(self) -> None:
        """Keep a frame of the world now (nothing unless recording)."""
        if self.frames is None:
            return
        f = self.frames
        real = self.poses()
        f.t.append(self.time)
        f.real.append(np.stack([real[n] for n in f.bodies]))
        f.planned.append(np.stack([self.planned[n] for n in f.bodies]))
        f.effector.append(self.arm.effector_pose())
        skel = self.arm.skeleton
        f.arm.append(
            np.array([skel.getBodyNode(i).getWorldTransform().translation() for i in range(skel.getNumBodyNodes())])
        )
        f.label.append(self.label)
        self._next_frame = self.time + FRAME_PERIOD

    def lowest_offset(self) -> float:
        """How far below the effector frame the lowest point of what the robot holds is (m)."""
        hand = self.arm.effector_pose()
        if self.arm.held is None:
            return FINGERTIP_RADIUS
        tool_pose = self.arm.held.body_node.getWorldTransform().matrix()
        vertices = self.meshes[self.arm.held.name].vertices @ tool_pose[:3, :3].T + tool_pose[:3, 3]
        return float(hand[2, 3] - vertices[:, 2].min())

    def safe_height(self) -> float:
        """The effector height at which what the robot holds clears every other body."""
        tops = [self.table_z]
        held = self.holding()
        for name, (_, node) in self.nodes.items():
            if name == held:
                continue
            pose = node.getWorldTransform().matrix()
            vertices = self.meshes[name].vertices @ pose[:3, :3].T + pose[:3, 3]
            tops.append(float(vertices[:, 2].max()))
        return max(tops) + CLEARANCE + self.lowest_offset()


def _skeleton_name(collision_object: Any) -> str:
    return collision_object.getShapeFrame().asShapeNode().getBodyNodePtr().getSkeleton().getName()


def _world_skeleton(arm: Any, robot_ir: Any) -> Any:
    """A fresh DART skeleton of the arm for the world (a clone of the arm model's, if it has one)."""
    skeleton = getattr(arm, "skeleton", None)
    if skeleton is not None:
        return skeleton.clone()
    import dartpy as dart

    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
    loader.setOptions(options)
    skeleton = loader.parseSkeleton(robot_ir.urdf_resolved or robot_ir.urdf)
    if skeleton is None:
        raise SimulationError(f"DART cannot load the URDF {robot_ir.urdf_resolved or robot_ir.urdf}")
    return skeleton


__all__ = ["CLEARANCE", "TIME_STEP", "SceneWorld"]
