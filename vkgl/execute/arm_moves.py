"""How the arm moves in the scene's world: along its planned paths, and with a contact's motion.

`ArmMoves` carries out, in a `SceneWorld`: a step's planned arm segments
(`vkgl.formats.plan.ArmSegment`: lift, retreat, transit, approach), joint
waypoints at their planned times, joined by a planned transit when the arm is
not where a path starts; effector paths (`vkgl.execute.effector_path`) such as
a contact's motion, followed by IK every control period; and solving a whole
contact motion beforehand, so that no configuration switch happens in contact.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from vkgl.execute import effector_path as paths
from vkgl.execute.scene_world import SceneWorld
from vkgl.execute.world_arm import ArmStuck
from vkgl.formats.plan import ArmSegment

JOIN_NEAR = 0.02  # rad: closer than this to where a path starts, the arm steps there directly
MAX_CHAIN_JUMP = 0.05  # m a link may move between IK solutions 1 cm apart along a contact motion
CHAIN_SPACING = 0.01  # m of hand travel between two IK solutions of a contact motion solved beforehand
MOTION_LEVER = 0.2  # m: a turn of the hand counts as this lever arm times its angle, for that spacing


class ArmMoves:
    """The arm's moves in one `SceneWorld` (the world advances while the arm moves)."""

    def __init__(self, sim: SceneWorld) -> None:
        self.sim = sim
        self._collision: Any = None  # the scene's collision world for joining transits, built when first needed

    def run(
        self,
        segments: list[paths.Segment],
        label: str,
        *,
        ghost: Callable[[float], None] | None = None,
        q_hint: np.ndarray | None = None,
        q_path: list[np.ndarray] | None = None,
    ) -> None:
        for i, segment in enumerate(segments):
            self.sim.label = f"{label} {segment.phase}"

            def step(
                n: int, s: float, _ghost: Callable[[float], None] | None = ghost, _segment: paths.Segment = segment
            ) -> None:
                if _ghost is not None and _segment.motion is not None:
                    _ghost(s)
                self.sim.advance(n)

            self.sim.arm.follow(segment, step, q_hint=q_hint if i == 0 else None, q_path=q_path if i == 0 else None)

    def follow_path(self, segments: Sequence[ArmSegment], label: str) -> None:
        """Carry out a step's planned arm segments (lift, retreat, transit, approach) exactly as planned.

        The arm first joins the path where it starts (`join`); while it
        transits, touching a body is a failure (ArmStuck): the planner checked
        that the way is clear, so a touch means the scene is not as planned.
        """
        for segment in segments:
            if segment.phase in ("retreat", "lift"):
                self._move_away(segment, label)
                continue
            self.join(segment.joints[0], label)
            self.sim.label = f"{label} {segment.phase}"
            self.sim.guarded = segment.phase in ("transit", "lift")
            try:
                self.sim.arm.follow_joints(segment.joints, segment.times, lambda n, s: self.sim.advance(n))
            finally:
                self.sim.guarded = False

    def _move_away(self, segment: ArmSegment, label: str) -> None:
        """A planned retreat's or lift's straight move: as planned where the arm is where the plan expects it,
        else from where the hand really is.

        After a contact followed along the plan's chain the arm is where the
        plan says, and the planned joints are followed. Elsewhere (a release
        lowers the tool by IK; an older plan without a contact chain) the
        move is carried out as the planned displacement of the effector from
        its real pose; the next segment joins the plan from there, clear of
        what the hand just touched.
        """
        if float(np.abs(self.sim.arm.q - segment.joints[0]).max()) < JOIN_NEAR:
            # where the plan expects it (a contact chain followed as planned): the planned joints themselves
            self.join(segment.joints[0], label)  # a step from close by, as any path is joined
            self.sim.label = f"{label} {segment.phase}"
            self.sim.arm.follow_joints(segment.joints, segment.times, lambda n, s: self.sim.advance(n))
            return
        model = self.sim.arm_model
        shift = model.fk(segment.joints[-1])[:3, 3] - model.fk(segment.joints[0])[:3, 3]
        self.straight(segment.phase, shift, paths.APPROACH_SPEED, label)

    def straight(self, phase: str, shift: np.ndarray, speed: float, label: str, *, track: bool = True) -> bool:
        """Move the hand by `shift` (m, world) in a straight line from where it really is, at `speed` (m/s).

        Solved as the planner solves its straight moves (`vkgl.motion.approach.
        follow_poses`: IK every 5 mm, each from the last, one configuration
        throughout) and followed in joint space, so that a move the planner
        checked is one the arm can make even where it stands at a joint limit
        (tracking the line by IK every control period would have to switch
        configuration there). When no such chain exists: tracked by IK if
        `track`, else nothing is done and False is returned.
        """
        from vkgl.motion.approach import APPROACH_STEP, CartesianFailure, follow_poses
        from vkgl.motion.timing import arm_velocity_limits, straight_times

        start = self.sim.arm.effector_pose()
        length = float(np.linalg.norm(shift))
        count = max(1, int(np.ceil(length / APPROACH_STEP)))
        poses = []
        for i in range(count + 1):
            pose = start.copy()
            pose[:3, 3] += shift * (i / count)
            poses.append(pose)
        chain = follow_poses(self.sim.arm_model, poses, self.sim.arm.q)
        if isinstance(chain, CartesianFailure):
            if not track:
                return False
            end = start.copy()
            end[:3, 3] += shift
            self.run([paths.line(phase, start, end, speed)], label)
            return True
        joints = chain.joints.copy()
        joints[0] = self.sim.arm.q
        self.sim.label = f"{label} {phase}"
        # at `speed`, slower where a joint would pass its share of its velocity limit (near a singularity)
        times = straight_times(joints, length, speed, arm_velocity_limits(self.sim.arm_model))
        self.sim.arm.follow_joints(joints, times, lambda n, s: self.sim.advance(n))
        return True

    def join(self, q_target: np.ndarray, label: str) -> None:
        """Bring the arm to `q_target` when it is not there: a step from close by, else a planned transit.

        A plan's path starts where the planner expected the arm to be (its
        home configuration for a fresh plan, where the previous step left it
        otherwise); after a re-solve or a stray move it is elsewhere, and the
        way from there is planned among the bodies as they really are.
        """
        q_target = np.asarray(q_target, dtype=float)
        gap = float(np.abs(self.sim.arm.q - q_target).max())
        if gap < JOIN_NEAR:
            if gap > 1e-9:
                self.sim.arm.move_joints(q_target, lambda n, s: self.sim.advance(n))
            return
        segment = self._joining_transit(q_target)
        self.sim.label = f"{label} transit"
        self.sim.guarded = True
        try:
            self.sim.arm.follow_joints(segment.joints, segment.times, lambda n, s: self.sim.advance(n))
        finally:
            self.sim.guarded = False

    def _joining_transit(self, q_target: np.ndarray) -> ArmSegment:
        from vkgl.motion.arm_collision import ArmCollision, Held
        from vkgl.motion.collision import CollisionScene
        from vkgl.motion.transit import TransitFailure
        from vkgl.motion.transit_segment import transit_segment

        if self._collision is None:
            shapes = {name: body.shape for name, body in self.sim.types.items()}
            # the exact geometry: the arm may start touching a body (where a contact motion left it)
            self._collision = ArmCollision(CollisionScene.from_scene(self.sim.scene, shapes), self.sim.arm_model)
        held = None
        if self.sim.arm.held is not None:
            in_hand = np.linalg.inv(self.sim.arm.effector_pose()) @ self.sim.poses()[self.sim.arm.held.name]
            held = Held(self.sim.arm.held.name, in_hand, opening=self.sim.fingers.opening)  # as they are now
        found = transit_segment(self._collision, self.sim.arm.q, q_target, self.sim.poses(), held, seed=0)
        if isinstance(found, TransitFailure):
            raise ArmStuck(f"the arm cannot get to where its planned path starts: {found.reason}")
        return found

    def motion_chain(self, segment: paths.Segment, seeds: list[np.ndarray | None]) -> list[np.ndarray]:
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
        for seed in self.sim.arm_model.spread_seeds():
            q = self.sim.arm_model.ik(pose, q0=seed)
            if q is not None and all(self.sim.arm.link_travel(q, other) > MAX_CHAIN_JUMP for other in found):
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
            return self._continue(poses, self.sim.arm.solve(poses[0], seeds))
        except ArmStuck as upwards:
            top = self.sim.arm.solve(poses[-1], [*seeds[1:], seeds[0]] if seeds else [])
            try:
                return self._continue(poses[::-1], top)[::-1]
            except ArmStuck:
                raise upwards from None

    def _continue(self, poses: list[np.ndarray], q0: np.ndarray) -> list[np.ndarray]:
        joints = [q0]
        for pose in poses[1:]:
            q = self.sim.arm.solve(pose, [joints[-1]])
            jump = self.sim.arm.link_travel(joints[-1], q)
            if jump > MAX_CHAIN_JUMP:
                xyz = ", ".join(f"{v:.3f}" for v in pose[:3, 3])
                raise ArmStuck(
                    f"the arm cannot come straight down to the contact: near ({xyz}) m a link "
                    f"would jump {jump * 100:.1f} cm (another joint configuration)"
                )
            joints.append(q)
        return joints


__all__ = ["ArmMoves"]
