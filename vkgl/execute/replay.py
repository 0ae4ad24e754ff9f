"""Carry out the steps of a `vkg-plan/1` plan in a DART world of the task's scene.

`Replay` holds one simulated world: the table, every scene body with its
physics (built by `vkgl.sim.world`), and the arm (`vkgl.execute.world_arm`). Each
plan step becomes an effector path (`vkgl.execute.effector_path`) that the arm
follows; the bodies move only through contact and friction with the
fingertip or a held tool — their poses are never set after the start.

Step kinds, from the step's `op` and the affordance's motion:
- push (add, prismatic/revolute): travel above the table to a point behind
  the contact, approach, make contact, move the effector with the body's
  planned motion (planned poses_start -> poses_end), settle;
- let go (remove of a push): back off along the push direction and lift;
- grasp (add, free motion, e.g. Stick.wield): come down onto the tool's grasp
  frame, hold the tool;
- release (remove of a grasp): lower the tool to the table and let go.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vkgl.errors import InputError, SimulationError
from vkgl.execute import effector_path as paths
from vkgl.execute.world_arm import FINGERTIP_RADIUS, ArmStuck, WorldArm, rx_pi
from vkgl.lang.geometry import body_mesh, scene_body_pose, table_top
from vkgl.lang.ir import Affordance, Body, FixedC, Scene
from vkgl.lang.program import Program

PLAN_FORMAT = "vkg-plan/1"
TIME_STEP = 0.001  # s, fixed physics step
STANDOFF = 0.01  # m behind the contact where the descent from above ends and the approach starts
CLEARANCE = 0.04  # m above the highest body when travelling
LIFT = 0.04  # m the effector rises after letting go
SETTLE = 0.3  # s of stillness after a push, before observing
MAX_CHAIN_JUMP = 0.05  # m a link may move between IK solutions 2 cm apart on the way down
CHAIN_SPACING = 0.01  # m of hand travel between two IK solutions of a contact motion solved beforehand
MOTION_LEVER = 0.2  # m: a turn of the hand counts as this lever arm times its angle, for that spacing
WAYPOINT_TOL = 0.002  # m the effector may leave its straight way down between two joint waypoints
WAYPOINT_TOL_ANGLE = np.radians(1.0)  # rad it may turn away from it
MAX_SPLITS = 5  # halvings of one joint move at most
RAISED_TOPS = (0.0, 0.1, 0.2)  # m above the safe height where the way down may start
FRAME_PERIOD = 0.04  # s between recorded frames (25 frames per simulated second)


@dataclass(frozen=True)
class PlannedStep:
    """One step of a `vkg-plan/1` plan, with poses as numpy arrays."""

    index: int
    op: str
    affordance: str
    body: str
    effector: str
    motion: str
    value: float
    poses_start: dict[str, np.ndarray]
    poses_end: dict[str, np.ndarray]
    q_start: np.ndarray | None
    q_end: np.ndarray | None

    def title(self) -> str:
        """`add Block.push_center_px with arm.fingertip (prismatic 15.0 cm)`."""
        amount = f"{self.value * 100:.1f} cm" if self.motion == "prismatic" else f"{np.degrees(self.value):.1f} deg"
        motion = f" ({self.motion} {amount})" if self.op == "add" and self.motion in ("prismatic", "revolute") else ""
        return f"{self.op} {self.affordance} with {self.effector}{motion}"


def read_plan(plan: dict[str, Any]) -> tuple[list[PlannedStep], dict[str, Any]]:
    """The steps and the `robot` entry of a `vkg-plan/1` plan; InputError if it is not one."""
    if not isinstance(plan, dict) or plan.get("format") != PLAN_FORMAT:
        raise InputError(
            f"not a {PLAN_FORMAT} plan (its `format` is {plan.get('format')!r})"
            if isinstance(plan, dict)
            else f"a {PLAN_FORMAT} plan must be a JSON object"
        )
    if plan.get("status") != "solved":
        raise InputError(f"plan for `{plan.get('task')}` is {plan.get('status')!r}: there is nothing to execute")
    try:
        steps = [_read_step(i + 1, s) for i, s in enumerate(plan["steps"])]
        robot = plan["robot"]
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"malformed {PLAN_FORMAT} plan: {type(exc).__name__}: {exc}") from exc
    return steps, robot


def _read_step(index: int, raw: dict[str, Any]) -> PlannedStep:
    def poses(key: str) -> dict[str, np.ndarray]:
        out = {name: np.asarray(m, dtype=float) for name, m in raw[key].items()}
        for name, m in out.items():
            if m.shape != (4, 4):
                raise ValueError(f"step {index}: {key}.{name} is not a 4x4 matrix")
        return out

    def joints(key: str) -> np.ndarray | None:
        value = raw.get(key)
        return None if value is None else np.asarray(value, dtype=float)

    return PlannedStep(
        index=index,
        op=raw["op"],
        affordance=raw["affordance"],
        body=raw["body"],
        effector=raw["effector"],
        motion=raw["motion"],
        value=float(raw.get("value", 0.0) or 0.0),
        poses_start=poses("poses_start"),
        poses_end=poses("poses_end"),
        q_start=joints("q_start"),
        q_end=joints("q_end"),
    )


@dataclass
class Frames:
    """What the simulation looked like, sampled every FRAME_PERIOD (for the animation)."""

    bodies: list[str]
    t: list[float] = field(default_factory=list)
    real: list[np.ndarray] = field(default_factory=list)  # (n_bodies, 4, 4) per frame
    planned: list[np.ndarray] = field(default_factory=list)  # (n_bodies, 4, 4) per frame
    effector: list[np.ndarray] = field(default_factory=list)  # (4, 4) per frame
    arm: list[np.ndarray] = field(default_factory=list)  # (n_links, 3) link origins per frame
    label: list[str] = field(default_factory=list)  # "step 2 motion" etc.


class Replay:
    """A DART world of one task's scene, in which plan steps are carried out one after another."""

    def __init__(self, program: Program, scene: Scene, robot_entry: dict[str, Any], *, record: bool) -> None:
        from vkgl.robot import Arm
        from vkgl.sim import world as sim_world

        self.program = program
        self.scene = scene
        self.types: dict[str, Body] = {sb.name: program.bodies[sb.type.name] for sb in scene.bodies}
        self.table_z = table_top(scene)
        self.world = sim_world.new_world(TIME_STEP)
        use_coulomb_friction(self.world)
        self.table = sim_world.add_table(self.world, scene.table)[1] if scene.table is not None else None
        self.nodes: dict[str, tuple[Any, Any]] = {}
        for sb in scene.bodies:
            pose = scene_body_pose(scene, sb, self.types[sb.name])
            self.nodes[sb.name] = sim_world.add_body(self.world, sb.name, self.types[sb.name], pose)
        self.robot_name, robot_ir, base = self._robot(robot_entry)
        self.base_xy = base[:2, 3].copy()
        self.effector_name = robot_entry["effector"]
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
        self.meshes = {name: body_mesh(body) for name, body in self.types.items()}
        self.skeleton_names = {skeleton.getName(): name for name, (skeleton, _) in self.nodes.items()}
        self.guarded = False  # True while moving through free space: touching a body there is a failure
        self.planned = self.poses()  # the ghost: where the current plan wants every body now
        self.grasp_planned: np.ndarray | None = None  # effector frame in the held tool's frame, as planned
        self.push_direction: np.ndarray | None = None  # x axis of the pushing frame while in contact
        self.frames = Frames(list(self.nodes)) if record else None
        self.label = "start"
        self._next_frame = 0.0
        self._record()

    def _robot(self, entry: dict[str, Any]) -> tuple[str, Any, np.ndarray]:
        name = entry["name"]
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

    # ------------------------------------------------------------ running

    def _step(self, n: int) -> None:
        for _ in range(n):
            self.world.step(False)  # keep the arm's velocity commands for the whole control period
            if self.frames is not None and self.time >= self._next_frame - 1e-9:
                self._record()
        if self.guarded:  # once per control period is enough to stop in time
            self._check_clear()

    def _check_clear(self) -> None:
        """Stop a move through free space as soon as the robot or what it holds touches a body."""
        robot = {self.arm.skeleton.getName()}
        if self.arm.held is not None:
            robot.add(self.arm.held.skeleton.getName())
        result = self.world.getLastCollisionResult()
        for i in range(result.getNumContacts()):
            contact = result.getContact(i)
            if not (_collidable(contact.collisionObject1) and _collidable(contact.collisionObject2)):
                continue  # DART reports them, but makes no contact force (fingertip switched off)
            a = _skeleton_name(contact.collisionObject1)
            b = _skeleton_name(contact.collisionObject2)
            for mine, other in ((a, b), (b, a)):
                if mine in robot and other in self.skeleton_names and other not in robot:  # not arm vs. held tool
                    what = "the fingertip" if mine == self.arm.skeleton.getName() else f"the held {self.holding()}"
                    raise ArmStuck(
                        f"{what} touched {self.skeleton_names[other]} on its way to the contact "
                        "(the way down from above must be clear: is the body where the plan expects it?)"
                    )

    def _record(self) -> None:
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

    def _run(
        self,
        segments: list[paths.Segment],
        label: str,
        *,
        ghost: Callable[[float], None] | None = None,
        q_hint: np.ndarray | None = None,
        q_path: list[np.ndarray] | None = None,
    ) -> None:
        for i, segment in enumerate(segments):
            self.label = f"{label} {segment.phase}"

            def step(n: int, s: float, _ghost: Callable[[float], None] | None = ghost) -> None:
                if _ghost is not None and segment.motion is not None:
                    _ghost(s)
                self._step(n)

            self.arm.follow(segment, step, q_hint=q_hint if i == 0 else None, q_path=q_path if i == 0 else None)

    def _travel(
        self, target: np.ndarray, label: str, seeds: list[np.ndarray | None], contact: np.ndarray | None = None
    ) -> None:
        """Through free space to `target`: straight up to the safe height, across, straight down; then to `contact`.

        The way down is solved backwards first: IK of the pose the step is
        about (`contact`, else `target`) from the plan's joints, then
        warm-started IK every 2 cm up to the top of the way down. The arm
        crosses in joint space to that top and comes down through the chain's
        joints in reverse, so it arrives in the configuration the planner
        checked. When the straight joint-space line would dip below the safe
        height, the way down starts higher (10 or 20 cm above the safe
        height); if it still dips, the arm swings about the robot's base and
        changes configuration in place. Touching a body on the way is a
        failure (ArmStuck); the last move, from `target` to `contact`, is
        the approach and may touch.
        """
        safe_z = self.safe_height()
        seeds = [*seeds, self.arm.q, getattr(self.arm_model, "home", None)]
        self.guarded = True
        try:
            self._lift(safe_z, label)
            crossed, at_safe_height = False, None
            for extra in RAISED_TOPS:
                over = paths.at_height(target, max(safe_z, target[2, 3]) + extra)
                chain = ([contact] if contact is not None else []) + [target] + _steps_up(target, over[2, 3])
                try:
                    joints = self._solve_chain(chain, seeds)
                except ArmStuck:
                    if extra == 0.0:
                        raise
                    break  # higher is out of reach here (close to the base)
                at_safe_height = at_safe_height or (over, chain, joints)
                if self._joint_line_clears(self.arm.q, joints[-1], safe_z - CLEARANCE / 2):
                    distance = float(np.linalg.norm(over[:3, 3] - self.arm.effector_pose()[:3, 3]))
                    self.label = f"{label} transit"
                    self.arm.move_joints(
                        joints[-1], lambda n, s: self._step(n), min_duration=distance / paths.TRANSIT_SPEED
                    )
                    crossed = True
                    break
            if not crossed:
                assert at_safe_height is not None
                over, chain, joints = at_safe_height
                if not self._cross_via_home(joints[-1], safe_z - CLEARANCE / 2, label):
                    self._swing(over, joints[-1], label)
            down = len(chain) - (contact is not None)
            self._through(chain[::-1][1:down], joints[::-1][1:down], paths.TRANSIT_SPEED, f"{label} transit")
        finally:
            self.guarded = False
        if contact is not None:
            self._through([contact], [joints[0]], paths.APPROACH_SPEED, f"{label} approach")

    def _cross_via_home(self, q_top: np.ndarray, z_min: float, label: str) -> bool:
        """Cross through the arm's home configuration (hand high above its base) to `q_top`, when both
        joint-space lines keep the effector above `z_min`. Returns whether it did."""
        home = getattr(self.arm_model, "home", None)
        if home is None or not (
            self._joint_line_clears(self.arm.q, home, z_min) and self._joint_line_clears(home, q_top, z_min)
        ):
            return False
        self.label = f"{label} transit"
        for q in (home, q_top):
            self.arm.move_joints(np.asarray(q, dtype=float), lambda n, s: self._step(n))
        return True

    def _lift(self, safe_z: float, label: str) -> None:
        """Straight up from where the effector is to `safe_z` (nothing if it is higher already)."""
        start = self.arm.effector_pose()
        up = paths.at_height(start, max(safe_z, start[2, 3]))
        if up[2, 3] - start[2, 3] > 1e-6:
            self._run([paths.line("transit", start, up)], label)

    def _swing(self, over: np.ndarray, q_over: np.ndarray, label: str) -> None:
        """Across to `over` about the robot's base, then into the configuration `q_over` in place."""
        self._run([paths.swing("transit", self.arm.effector_pose(), over, self.base_xy)], label)
        # The swing's IK may end in another configuration than the way down starts from.
        self._through([over], [q_over], paths.TRANSIT_SPEED, f"{label} transit")

    def _through(self, poses: list[np.ndarray], joints: list[np.ndarray], speed: float, label: str) -> None:
        """Visit `joints` in turn (IK solutions of `poses`) at `speed` of the effector."""
        self.label = label
        for q in joints:
            for q_next in self._straight_waypoints(self.arm.q, q):
                distance = float(np.linalg.norm(self.arm_model.fk(q_next)[:3, 3] - self.arm.effector_pose()[:3, 3]))
                self.arm.move_joints(q_next, lambda n, s: self._step(n), min_duration=distance / speed)

    def _straight_waypoints(self, q_a: np.ndarray, q_b: np.ndarray, depth: int = 0) -> list[np.ndarray]:
        """Joint waypoints from q_a to q_b (q_b last) between which the effector stays on the straight line.

        Near the shoulder singularity two IK solutions 2 cm apart may differ by
        a large, mutually compensating turn of joints 1 and 3; halfway along the
        joint line the effector is then off its path and tilted (a held stick
        dips by centimetres). Such a move is split at the IK solution of the
        midpoint pose until the halfway effector error is small.
        """
        pose_a, pose_b = self.arm_model.fk(q_a), self.arm_model.fk(q_b)
        wanted = paths.line("probe", pose_a, pose_b).pose(0.5)
        q_mid = (q_a + q_b) / 2
        halfway = self.arm_model.fk(q_mid)
        off = float(np.linalg.norm(halfway[:3, 3] - wanted[:3, 3]))
        if depth >= MAX_SPLITS or (off < WAYPOINT_TOL and paths.rotation_angle(halfway, wanted) < WAYPOINT_TOL_ANGLE):
            return [q_b]
        solved = self.arm_model.ik(wanted, q0=q_mid)
        if solved is None:
            return [q_b]
        q_mid = np.asarray(solved, dtype=float)
        return self._straight_waypoints(q_a, q_mid, depth + 1) + self._straight_waypoints(q_mid, q_b, depth + 1)

    def _motion_chain(self, segment: paths.Segment, seeds: list[np.ndarray | None]) -> list[np.ndarray]:
        """Joints every `CHAIN_SPACING` along a contact motion, without a switch of configuration.

        A long push can carry the hand from near the base to the edge of the
        workspace; IK warm-started period by period may then run into a joint
        limit halfway and find only another configuration (a jump the arm
        cannot make while in contact). Solving the whole path beforehand, from
        the start or else backwards from the end, picks a configuration at the
        contact that lasts the whole motion. Raises ArmStuck when none does.
        """
        length = float(np.linalg.norm(segment.end[:3, 3] - segment.start[:3, 3]))
        turn = paths.rotation_angle(segment.start, segment.end)
        count = max(2, int(np.ceil(max(length, turn * MOTION_LEVER) / CHAIN_SPACING)) + 1)
        poses = [segment.pose(s) for s in np.linspace(0.0, 1.0, count)]
        try:
            return self._solve_chain(poses, seeds)
        except ArmStuck as stuck:
            first = stuck
        # The arm is redundant: another elbow position at the contact may last the whole way.
        for start in self._other_configurations(poses[0]):
            try:
                return self._continue(poses, start)
            except ArmStuck:
                continue
        raise ArmStuck(f"no single arm configuration carries the whole motion ({first})")

    def _other_configurations(self, pose: np.ndarray) -> list[np.ndarray]:
        """IK solutions of `pose` from the arm model's fixed spread of seeds, distinct from each other."""
        found: list[np.ndarray] = []
        for seed in self.arm_model.spread_seeds():
            q = self.arm_model.ik(pose, q0=seed)
            if q is not None and all(self.arm.link_travel(q, other) > MAX_CHAIN_JUMP for other in found):
                found.append(np.asarray(q, dtype=float))
        return found

    def _solve_chain(self, poses: list[np.ndarray], seeds: list[np.ndarray | None]) -> list[np.ndarray]:
        """IK solutions of `poses` (contact first, then up), each warm-started at its neighbour's.

        Solved upwards from the contact (whose IK starts from `seeds`, the
        plan's joints first); if that breaks (neighbouring poses would need a
        jump between joint configurations), downwards from the top instead.
        Raises ArmStuck when neither gives a continuous way down.
        """
        try:
            return self._continue(poses, self.arm.solve(poses[0], seeds))
        except ArmStuck as upwards:
            top = self.arm.solve(poses[-1], [*seeds[1:], seeds[0]] if seeds else [])
            try:
                return self._continue(poses[::-1], top)[::-1]
            except ArmStuck:
                raise upwards from None

    def _continue(self, poses: list[np.ndarray], q0: np.ndarray) -> list[np.ndarray]:
        joints = [q0]
        for pose in poses[1:]:
            q = self.arm.solve(pose, [joints[-1]])
            jump = self.arm.link_travel(joints[-1], q)
            if jump > MAX_CHAIN_JUMP:
                xyz = ", ".join(f"{v:.3f}" for v in pose[:3, 3])
                raise ArmStuck(
                    f"the arm cannot come straight down to the contact: near ({xyz}) m a link "
                    f"would jump {jump * 100:.1f} cm (another joint configuration)"
                )
            joints.append(q)
        return joints

    def _joint_line_clears(self, q_a: np.ndarray, q_b: np.ndarray, z_min: float) -> bool:
        """True when the effector stays above `z_min` all along the joint-space line from q_a to q_b."""
        return all(self.arm_model.fk(q_a + (q_b - q_a) * s)[2, 3] >= z_min for s in np.linspace(0.0, 1.0, 12))

    # ------------------------------------------------------------ geometry helpers

    def _lowest_offset(self) -> float:
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
        return max(tops) + CLEARANCE + self._lowest_offset()

    def _frame_of(self, body_type: Body, frame: str, where: str) -> np.ndarray:
        found = body_type.frame(frame)
        if found is None:
            raise InputError(f"{where}: body {body_type.name} has no frame `{frame}`")
        return found.pose.matrix()

    def _affordance(self, step: PlannedStep) -> Affordance:
        type_name, _, name = step.affordance.partition(".")
        for aff in self.program.affordances.get(type_name, []):
            if aff.name == name:
                return aff
        raise InputError(f"step {step.index}: the program has no affordance {step.affordance}")

    def _action_pose(self, step: PlannedStep) -> np.ndarray:
        action = self._affordance(step).action
        if not isinstance(action, FixedC):
            raise SimulationError(
                f"step {step.index}: only fixed actions can be executed, {step.affordance} has a {action.type} action"
            )
        return np.eye(4) if action.pose is None else action.pose.matrix()

    def _hand_from_pusher(self, step: PlannedStep, pusher_pose: np.ndarray) -> np.ndarray:
        """The effector pose that puts the pushing frame (fingertip or tool frame) at `pusher_pose`."""
        owner, _, frame = step.effector.partition(".")
        if owner == self.robot_name:
            if frame != self.effector_name:
                raise SimulationError(f"step {step.index}: the arm's effector is {self.effector_name}, not {frame}")
            return pusher_pose
        if self.holding() != owner or self.grasp_planned is None:
            raise SimulationError(f"step {step.index} pushes with {step.effector} but the robot does not hold {owner}")
        tool_frame = self._frame_of(self.types[owner], frame, f"step {step.index}")
        return pusher_pose @ np.linalg.inv(tool_frame) @ self.grasp_planned

    # ------------------------------------------------------------ step kinds

    def run_step(self, step: PlannedStep) -> None:
        """Carry out one plan step. Raises ArmStuck if the arm cannot follow the path."""
        label = f"step {step.index}"
        self.planned = {**self.planned, **step.poses_start}
        if step.motion == "free":
            (self._grasp if step.op == "add" else self._release)(step, label)
        elif step.op == "add":
            self._push(step, label)
        else:
            self.let_go(label)
        self.planned = {**self.planned, **step.poses_end}

    def _push(self, step: PlannedStep, label: str) -> None:
        if step.body not in self.nodes:
            raise InputError(f"step {step.index}: no body `{step.body}` in scene {self.scene.name}")
        body_start, body_end = step.poses_start[step.body], step.poses_end[step.body]
        pusher = body_start @ self._action_pose(step)
        hand = self._hand_from_pusher(step, pusher)
        direction = pusher[:3, 0].copy()
        before = paths.backed_off(hand, STANDOFF, direction)
        motion = paths.screw_motion(body_start, body_end)
        moving = [
            n
            for n in step.poses_start
            if n in step.poses_end and np.abs(step.poses_start[n] - step.poses_end[n]).max() > 1e-9
        ]

        def ghost(s: float) -> None:
            now = motion.at(s)
            self.planned = {**self.planned, **{n: now @ step.poses_start[n] for n in moving}}

        self.arm.fingertip_collides(self.arm.held is None)
        if self.push_direction is not None:
            self.let_go(label)
        push = paths.screw("motion", hand, motion)
        chain = self._motion_chain(push, [step.q_start, step.q_end])
        self._travel(before, label, [chain[0], step.q_start, step.q_end], contact=hand)
        self.push_direction = direction
        self._run([push], label, ghost=ghost, q_hint=chain[0], q_path=chain)
        end = self.arm.effector_pose()
        self.push_direction = motion.at(1.0)[:3, :3] @ direction
        self._run([paths.hold("settle", end, SETTLE)], label)

    def let_go(self, label: str = "end") -> None:
        """Break contact: back off against the push direction, then lift. Nothing if not in contact."""
        if self.push_direction is None:
            return
        start = self.arm.effector_pose()
        back = paths.backed_off(start, STANDOFF, self.push_direction)
        up = paths.at_height(back, back[2, 3] + LIFT)
        self._run([paths.line("retreat", start, back, paths.APPROACH_SPEED), paths.line("retreat", back, up)], label)
        self.push_direction = None

    def _grasp(self, step: PlannedStep, label: str) -> None:
        tool = step.body
        if tool not in self.nodes:
            raise InputError(f"step {step.index}: no body `{tool}` in scene {self.scene.name}")
        if self.holding() is not None:
            raise SimulationError(f"step {step.index}: the robot already holds {self.holding()}")
        self.let_go(label)
        grasp = self._action_pose(step)
        hand = step.poses_start[tool] @ grasp
        self.arm.fingertip_collides(False)  # the open gripper closes around the tool, it does not push it
        self._travel(hand, label, [step.q_start, step.q_end])
        _, node = self.nodes[tool]
        self.arm.grasp(tool, self.nodes[tool][0], node)
        self.grasp_planned = grasp

    def _release(self, step: PlannedStep, label: str) -> None:
        self.put_down(label)

    def put_down(self, label: str) -> None:
        """Lower the held tool onto the table and let go of it; then lift the empty hand."""
        if self.arm.held is None:
            return
        self.let_go(label)
        start = self.arm.effector_pose()
        drop = self._lowest_offset() - 0.002
        low = paths.at_height(start, self.table_z + drop) if start[2, 3] > self.table_z + drop else start
        self._run([paths.line("release", start, low, paths.APPROACH_SPEED)], label)
        self.arm.release()
        self.grasp_planned = None
        up = paths.at_height(low, low[2, 3] + LIFT)
        self._run([paths.line("release", low, up), paths.hold("settle", up, SETTLE)], label)
        self.arm.fingertip_collides(True)

    def settle(self, seconds: float, label: str = "settle") -> None:
        """Let the world run with the arm still."""
        pose = self.arm.effector_pose()
        self._run([paths.hold("settle", pose, seconds)], label)


def use_coulomb_friction(world: Any) -> None:
    """Solve contacts with DART's friction-cone solver (NSGS, Coulomb law) instead of the boxed LCP.

    The boxed LCP bounds friction separately along two fixed tangent axes
    (world x and y on the table): a body pushed at an angle to them slides
    along the nearer axis instead of the way it is pushed (a block pushed
    10 cm along a heading of -20 deg ended 3.6 cm to the side). The cone
    treats every direction alike.
    """
    import dartpy as dart

    solver = dart.constraint.NsgsFrictionSolver()
    options = dart.constraint.NsgsFrictionSolver.Options()
    options.law = dart.constraint.NsgsFrictionSolver.Law.Coulomb
    solver.setOptions(options)
    world.getConstraintSolver().setBoxedLcpSolver(solver)


def _collidable(collision_object: Any) -> bool:
    aspect = collision_object.getShapeFrame().asShapeNode().getCollisionAspect()
    return aspect is None or aspect.isCollidable()


def _skeleton_name(collision_object: Any) -> str:
    return collision_object.getShapeFrame().asShapeNode().getBodyNodePtr().getSkeleton().getName()


def _steps_up(pose: np.ndarray, z: float, step: float = 0.02) -> list[np.ndarray]:
    """Poses straight above `pose` every `step` metres up to height `z` (z included)."""
    heights = np.arange(pose[2, 3] + step, z, step).tolist() + [z] if z > pose[2, 3] + 1e-9 else []
    return [paths.at_height(pose, h) for h in heights]


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


__all__ = ["ArmStuck", "Frames", "PlannedStep", "Replay", "read_plan"]
