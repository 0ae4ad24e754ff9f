"""The kinds of plan step, carried out by the arm in the scene's world (`vkgl.execute.replay`).

Every step first carries out its planned arm path (`step.path`, vkg-plan/3 and later:
lift, retreat, transit, approach; `ArmMoves.follow_path`), then its action,
from the step's `op` and the affordance's motion:
- push (add, prismatic/revolute): the path ends in contact; move the effector
  with the body's planned motion (planned poses_start -> poses_end), settle;
- let go (remove of a push): the path is the retreat out of the contact
  (outside a plan, at its end or before a re-solve, `let_go` leaves the
  contact by the rule of the way the plan's approach came into it,
  `vkgl.motion.moves.way_out`, as the planner checked: straight back,
  straight up from a hook behind a handle's bar, or back out the way it
  came from the side of a bar);
- grasp (add, free motion, e.g. Stick.wield): the path comes down onto the
  tool's grasp frame; hold the tool, with the grip of the fingers' friction
  (`vkgl.execute.grip`: a load beyond it breaks the grip, a slip beyond the
  tolerance fails the step);
- release (remove of a grasp): lower the tool onto the table and let go (the
  next step's path lifts the hand).

The bodies move only through contact and friction with the fingertip or a
held tool: their poses are never set after the start.
"""

from __future__ import annotations

import numpy as np

from vkgl.errors import InputError, SimulationError
from vkgl.execute import effector_path as paths
from vkgl.execute.arm_moves import ArmMoves
from vkgl.execute.grip.fingers import FINGER_CLEARANCE, TOUCH_GAP
from vkgl.execute.grip.model import grip_for
from vkgl.execute.scene_world import SceneWorld
from vkgl.execute.world_arm import ArmStuck
from vkgl.formats.plan import PlanStepRecord
from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.nodes import Affordance, Body, FixedC
from vkgl.motion.moves import LIFT, STANDOFF, WayOut, way_out
from vkgl.robot.grip import tool_width
from vkgl.robot.pad import pad_front

PLAN_CONTACT_TOL = 0.01  # m the plan's effector at a contact may be from the affordance's contact (a leaned hand)
SETTLE = 0.3  # s of stillness after a push, before observing


def contact_offset(hand: np.ndarray, wanted: np.ndarray) -> float:
    """How far (m) the arm's pad, its hand at `hand` (the effector frame, world), is from the contact `wanted` (the
    frame the affordance puts the effector at, its x the push): from its face (the frame's origin) or from its front
    along the push (a hand turned about its axis pushes with the pad's rounded end, `vkgl.robot.pad.pad_front`),
    whichever is nearer."""
    front = pad_front(hand, wanted[:3, 0])
    return float(min(np.linalg.norm(hand[:3, 3] - wanted[:3, 3]), np.linalg.norm(front - wanted[:3, 3])))


class StepKinds:
    """Carries out plan steps one after another, remembering the contact and the grasp between them."""

    def __init__(self, sim: SceneWorld, moves: ArmMoves) -> None:
        self.sim = sim
        self.moves = moves
        self.grasp_planned: np.ndarray | None = None  # effector frame in the held tool's frame, as planned
        self.push_direction: np.ndarray | None = None  # x axis of the pushing frame while in contact
        self.way_in: np.ndarray | None = None  # world: the last move of the step's planned approach
        self.leaving: tuple[WayOut, np.ndarray | None] = ("back", None)  # how `let_go` leaves the contact
        self.tool_width = 0.0  # m across the grip of the tool being grasped or held

    def _frame_of(self, body_type: Body, frame: str, where: str) -> np.ndarray:
        found = body_type.frame(frame)
        if found is None:
            raise InputError(f"{where}: body {body_type.name} has no frame `{frame}`")
        return found.pose.matrix()

    def _affordance(self, step: PlanStepRecord, label: str) -> Affordance:
        type_name, _, name = step.affordance.partition(".")
        try:  # the affordance, or a member of its family: `push@+3.12cm`
            found = find_member(self.sim.program.affordances.get(type_name, []), name)
        except ValueError as exc:
            raise InputError(f"{label}: {exc}") from None
        if found is not None:
            return found
        raise InputError(f"{label}: the program has no affordance {step.affordance}")

    def _action_pose(self, step: PlanStepRecord, label: str) -> np.ndarray:
        action = self._affordance(step, label).action
        if not isinstance(action, FixedC) and action.type != "grasp":  # a grasp is a pose too (the fingers hold it)
            raise SimulationError(
                f"{label}: only fixed and grasp actions can be executed, {step.affordance} has a {action.type} action"
            )
        pose = getattr(action, "pose", None)
        return np.eye(4) if pose is None else pose.matrix()

    def _hand_from_pusher(self, step: PlanStepRecord, pusher_pose: np.ndarray, label: str) -> np.ndarray:
        """The effector pose that puts the pushing frame (fingertip or tool frame) at `pusher_pose`."""
        owner, _, frame = step.effector.partition(".")
        if owner == self.sim.robot_name:
            if frame != self.sim.effector_name:
                raise SimulationError(f"{label}: the arm's effector is {self.sim.effector_name}, not {frame}")
            return pusher_pose
        if self.sim.holding() != owner or self.grasp_planned is None:
            raise SimulationError(f"{label} pushes with {step.effector} but the robot does not hold {owner}")
        tool_frame = self._frame_of(self.sim.types[owner], frame, label)
        return pusher_pose @ np.linalg.inv(tool_frame) @ self.grasp_planned

    # ------------------------------------------------------------ step kinds

    def run_step(self, index: int, step: PlanStepRecord) -> None:
        """Carry out step `index` (from 1) of a plan. Raises ArmStuck if the arm cannot follow the path."""
        label = f"step {index}"
        self.sim.grip.begin_step()
        self.sim.planned = {**self.sim.planned, **step.poses_start}
        if step.op == "add" and step.body not in self.sim.nodes:
            raise InputError(f"{label}: no body `{step.body}` in scene {self.sim.scene.name}")
        # the fingertip pushes; an open gripper closing around a tool or a handle, or a hand holding one, does not
        handle = self._affordance(step, label).action.type == "grasp" and step.motion in ("prismatic", "revolute")
        grasping = step.op == "add" and (step.motion == "free" or handle)
        if step.op == "remove" and handle:
            self._let_go_of_handle()  # before the planned retreat out of the grip
        self.sim.arm.fingertip_collides(self.sim.arm.held is None and self.sim.arm.handle is None and not grasping)
        if grasping:  # the hand comes down onto the tool with its fingers open clear of the tool's faces
            self.tool_width = self._width(step, label)
            self._fingers(self.tool_width / 2 + FINGER_CLEARANCE)
        elif self.sim.arm.held is None and self.sim.arm.handle is None:  # closed fingers behind the pad push
            self._fingers(0.0)
        self.moves.follow_path(step.path, label)
        self.way_in = _way_in(self.sim, step)
        if step.motion == "free":
            (self._grasp if step.op == "add" else self._release)(step, label)
        elif step.op == "add":
            self._push(step, label, handle=handle)
        else:
            self.push_direction = None  # the path was the retreat out of the contact
        self.sim.planned = {**self.sim.planned, **step.poses_end}
        self.sim.grip.end_step()  # a grip that broke in the step fails it

    def _push(self, step: PlanStepRecord, label: str, *, handle: bool = False) -> None:
        """The body's planned motion, the hand pushing it (the fingertip, a held tool) or holding its handle."""
        body_start, body_end = step.poses_start[step.body], step.poses_end[step.body]
        pusher = body_start @ self._action_pose(step, label)
        wanted = self._hand_from_pusher(step, pusher, label)
        # the hand as planned at the contact (the planner may lean it back from upright to clear a tall face)
        hand = self.sim.arm_model.fk(step.q_start)
        own_pad = step.effector.partition(".")[0] == self.sim.robot_name
        off = contact_offset(hand, wanted) if own_pad else float(np.linalg.norm(hand[:3, 3] - wanted[:3, 3]))
        if off > PLAN_CONTACT_TOL:
            raise ArmStuck(
                f"the plan is inconsistent: its arm configuration at the contact puts the effector "
                f"{off * 100:.1f} cm from the contact of {step.affordance}"
            )
        direction = pusher[:3, 0].copy()
        motion = paths.screw_motion(body_start, body_end)
        moving = [
            n
            for n in step.poses_start
            if n in step.poses_end and np.abs(step.poses_start[n] - step.poses_end[n]).max() > 1e-9
        ]

        def ghost(s: float) -> None:
            now = motion.at(s)
            self.sim.planned = {**self.sim.planned, **{n: now @ step.poses_start[n] for n in moving}}

        push = paths.screw("motion", hand, motion)
        # the plan's own chain (vkg-plan/3 and later): the configuration the planner checked; older plans: solved here
        chain = (
            list(step.contact)
            if step.contact is not None
            else self.moves.motion_chain(push, [step.q_start, step.q_end])
        )
        self.push_direction = direction
        if handle:  # the fingers close on the handle where the path brought them
            self._fingers(self.tool_width / 2 + TOUCH_GAP)
            _, node = self.sim.nodes[step.body]
            self.sim.arm.hold_handle(step.body, node)
            action = self._affordance(step, label).action
            self.sim.grip.hold(step.body, node, grip_for(action, self.sim.types[step.body].friction), jointed=True)
        # the rule the planner checked for leaving this contact, from the way its approach came in
        self.leaving = ("back", None) if self.way_in is None else (way_out(self.way_in, direction), self.way_in)
        self.moves.run([push], label, ghost=ghost, q_hint=chain[0], q_path=chain)
        end = self.sim.arm.effector_pose()
        turn = motion.at(1.0)[:3, :3]
        self.push_direction = turn @ direction
        rule, way = self.leaving
        self.leaving = (rule, None if way is None else turn @ way)
        self.moves.run([paths.hold("settle", end, SETTLE)], label)

    def let_go(self, label: str = "end") -> None:
        """Break contact by the rule of the way the plan came into it (`vkgl.motion.moves.way_out`, as the
        planner checked it): back off against the push direction, then lift; straight up when the plan came
        into the contact from above (a hook behind a handle's bar: backing off would put the hand into the body
        it pulled); back out the way it came, then lift, when it came from elsewhere (from the side of a
        handle's bar). Nothing if not in contact."""
        self._let_go_of_handle()
        if self.push_direction is None:
            return
        up = np.array([0.0, 0.0, 1.0])
        rule, way = self.leaving
        self.leaving = ("back", None)
        if rule == "up":
            self.moves.straight("retreat", (STANDOFF + LIFT) * up, paths.APPROACH_SPEED, label)
            self.push_direction = None
            return
        if rule == "reverse" and way is not None:
            self.moves.straight("retreat", -STANDOFF * way, paths.APPROACH_SPEED, label)
            self.moves.straight("retreat", LIFT * up, paths.TRANSIT_SPEED, label)
            self.push_direction = None
            return
        start = self.sim.arm.effector_pose()
        back = paths.backed_off(start, STANDOFF, self.push_direction)
        # as the planner checked the last contact could be left (`vkgl.plan.arm.paths`): straight back out of
        # it, or straight up where no arm configuration goes back, then up
        if not self.moves.straight("retreat", back[:3, 3] - start[:3, 3], paths.APPROACH_SPEED, label, track=False):
            self.moves.straight("retreat", STANDOFF * up, paths.APPROACH_SPEED, label)
        self.moves.straight("retreat", LIFT * up, paths.TRANSIT_SPEED, label)
        self.push_direction = None

    def _grasp(self, step: PlanStepRecord, label: str) -> None:
        tool = step.body
        if self.sim.holding() is not None:
            raise SimulationError(f"{label}: the robot already holds {self.sim.holding()}")
        _, node = self.sim.nodes[tool]
        self._fingers(self.tool_width / 2 + TOUCH_GAP)  # the pads close onto the tool's faces
        self.sim.arm.grasp(tool, self.sim.nodes[tool][0], node)
        self.sim.grip.hold(tool, node, grip_for(self._affordance(step, label).action, self.sim.types[tool].friction))
        self.grasp_planned = self._action_pose(step, label)

    def _width(self, step: PlanStepRecord, label: str) -> float:
        """The tool's width across the grip (`vkgl.robot.grip.tool_width`: stated, else measured where the action
        holds it), as the planner has it when it checks the fingers around the tool."""
        action = self._affordance(step, label).action
        return tool_width(action, self.sim.meshes[step.body], self._action_pose(step, label))

    def _let_go_of_handle(self) -> None:
        """Open the fingers off a handle the hand holds (nothing if none)."""
        if self.sim.arm.handle is None:
            return
        self.sim.arm.let_go_of_handle()
        self.sim.grip.let_go()
        self._fingers(self.tool_width / 2 + FINGER_CLEARANCE)

    def _fingers(self, each: float) -> None:
        """Open or close the fingers to `each` m, the world running."""
        self.sim.fingers.move(each, self.sim.advance)

    def _release(self, step: PlanStepRecord, label: str) -> None:
        # the plan lets go where the hand is and lifts from there: the open hand goes back up the way it came
        # down, so that the next step's path starts where the plan expects the arm
        self._lower_and_release(label, back_up=True)

    def put_down(self, label: str) -> None:
        """Lower the held tool onto the table and let go of it; then lift the empty hand. A hand still around a
        tool that slipped out of its grip is lifted clear of it (a re-solve plans the arm from where it stands)."""
        if self.sim.arm.held is None:
            if self.sim.arm.leaving_a_tool:
                self.moves.straight(
                    "release", (STANDOFF + LIFT) * np.array([0.0, 0.0, 1.0]), paths.APPROACH_SPEED, label
                )
            return
        self.let_go(label)
        self._lower_and_release(label)
        start = self.sim.arm.effector_pose()
        up = paths.at_height(start, start[2, 3] + LIFT)
        self.moves.run([paths.line("release", start, up), paths.hold("settle", up, SETTLE)], label)

    def _lower_and_release(self, label: str, *, back_up: bool = False) -> None:
        """Lower the held tool until it rests on the table, and let go of it; the hand stays where it is, or with
        `back_up` returns to the joints it had before lowering (the fingers still open around the tool's grip)."""
        if self.sim.arm.held is None:
            return
        before = self.sim.arm.q
        start = self.sim.arm.effector_pose()
        # its lowest point onto the table's top, not into it: a kinematic tool pressed 2 mm into the table was
        # let go of 2 mm lower than the plan puts it down and came up only slowly (8.3 mm of 10 after 0.3 s)
        drop = self.sim.lowest_offset()
        low = paths.at_height(start, self.sim.table_z + drop) if start[2, 3] > self.sim.table_z + drop else start
        self.moves.run([paths.line("release", start, low, paths.APPROACH_SPEED)], label)
        self.sim.arm.release()
        self.sim.grip.let_go()
        self._fingers(self.tool_width / 2 + FINGER_CLEARANCE)  # the fingers open off the tool's faces
        self.grasp_planned = None
        self.moves.run([paths.hold("settle", low, SETTLE)], label)
        if back_up and float(np.abs(before - self.sim.arm.q).max()) > 1e-9:
            self.sim.label = f"{label} release"
            self.sim.arm.move_joints(before, lambda n, s: self.sim.advance(n))
        self.sim.arm.fingertip_collides(True)

    def settle(self, seconds: float, label: str = "settle") -> None:
        """Let the world run with the arm still."""
        pose = self.sim.arm.effector_pose()
        self.moves.run([paths.hold("settle", pose, seconds)], label)


def _way_in(sim: SceneWorld, step: PlanStepRecord) -> np.ndarray | None:
    """The direction (world, unit) of the last move of the step's planned approach into its contact (a held
    tool's approach comes down to its stand-off first, then goes its way in), or None without one."""
    approach = next((s for s in reversed(step.path) if s.phase == "approach"), None)
    if approach is None or len(approach.joints) < 2:
        return None
    way = sim.arm_model.fk(approach.joints[-1])[:3, 3] - sim.arm_model.fk(approach.joints[-2])[:3, 3]
    length = float(np.linalg.norm(way))
    return way / length if length > 1e-9 else None


__all__ = ["StepKinds", "contact_offset"]
