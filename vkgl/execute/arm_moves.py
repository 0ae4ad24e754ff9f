"""How the arm moves in the scene's world: along effector paths, through free space, and down to a contact.

`ArmMoves` turns effector paths (`vkgl.execute.effector_path`) into joint
motions of the arm in a `SceneWorld`: following a segment, travelling above
the table to a point behind a contact (the way down solved backwards from the
contact as a chain of IK solutions, so that the arm arrives in the
configuration the planner checked), and solving a whole contact motion
beforehand so that no configuration switch happens in contact.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vkgl.execute import effector_path as paths
from vkgl.execute.scene_world import CLEARANCE, SceneWorld
from vkgl.execute.world_arm import ArmStuck

MAX_CHAIN_JUMP = 0.05  # m a link may move between IK solutions 2 cm apart on the way down
CHAIN_SPACING = 0.01  # m of hand travel between two IK solutions of a contact motion solved beforehand
MOTION_LEVER = 0.2  # m: a turn of the hand counts as this lever arm times its angle, for that spacing
WAYPOINT_TOL = 0.002  # m the effector may leave its straight way down between two joint waypoints
WAYPOINT_TOL_ANGLE = np.radians(1.0)  # rad it may turn away from it
MAX_SPLITS = 5  # halvings of one joint move at most
RAISED_TOPS = (0.0, 0.1, 0.2)  # m above the safe height where the way down may start


class ArmMoves:
    """The arm's moves in one `SceneWorld` (the world advances while the arm moves)."""

    def __init__(self, sim: SceneWorld) -> None:
        self.sim = sim

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

    def travel(
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
        safe_z = self.sim.safe_height()
        seeds = [*seeds, self.sim.arm.q, getattr(self.sim.arm_model, "home", None)]
        self.sim.guarded = True
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
                if self._joint_line_clears(self.sim.arm.q, joints[-1], safe_z - CLEARANCE / 2):
                    distance = float(np.linalg.norm(over[:3, 3] - self.sim.arm.effector_pose()[:3, 3]))
                    self.sim.label = f"{label} transit"
                    self.sim.arm.move_joints(
                        joints[-1], lambda n, s: self.sim.advance(n), min_duration=distance / paths.TRANSIT_SPEED
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
            self.sim.guarded = False
        if contact is not None:
            self._through([contact], [joints[0]], paths.APPROACH_SPEED, f"{label} approach")

    def _cross_via_home(self, q_top: np.ndarray, z_min: float, label: str) -> bool:
        """Cross through the arm's home configuration (hand high above its base) to `q_top`, when both
        joint-space lines keep the effector above `z_min`. Returns whether it did."""
        home = getattr(self.sim.arm_model, "home", None)
        if home is None or not (
            self._joint_line_clears(self.sim.arm.q, home, z_min) and self._joint_line_clears(home, q_top, z_min)
        ):
            return False
        self.sim.label = f"{label} transit"
        for q in (home, q_top):
            self.sim.arm.move_joints(np.asarray(q, dtype=float), lambda n, s: self.sim.advance(n))
        return True

    def _lift(self, safe_z: float, label: str) -> None:
        """Straight up from where the effector is to `safe_z` (nothing if it is higher already)."""
        start = self.sim.arm.effector_pose()
        up = paths.at_height(start, max(safe_z, start[2, 3]))
        if up[2, 3] - start[2, 3] > 1e-6:
            self.run([paths.line("transit", start, up)], label)

    def _swing(self, over: np.ndarray, q_over: np.ndarray, label: str) -> None:
        """Across to `over` about the robot's base, then into the configuration `q_over` in place."""
        self.run([paths.swing("transit", self.sim.arm.effector_pose(), over, self.sim.base_xy)], label)
        # The swing's IK may end in another configuration than the way down starts from.
        self._through([over], [q_over], paths.TRANSIT_SPEED, f"{label} transit")

    def _through(self, poses: list[np.ndarray], joints: list[np.ndarray], speed: float, label: str) -> None:
        """Visit `joints` in turn (IK solutions of `poses`) at `speed` of the effector."""
        self.sim.label = label
        for q in joints:
            for q_next in self._straight_waypoints(self.sim.arm.q, q):
                distance = float(
                    np.linalg.norm(self.sim.arm_model.fk(q_next)[:3, 3] - self.sim.arm.effector_pose()[:3, 3])
                )
                self.sim.arm.move_joints(q_next, lambda n, s: self.sim.advance(n), min_duration=distance / speed)

    def _straight_waypoints(self, q_a: np.ndarray, q_b: np.ndarray, depth: int = 0) -> list[np.ndarray]:
        """Joint waypoints from q_a to q_b (q_b last) between which the effector stays on the straight line.

        Near the shoulder singularity two IK solutions 2 cm apart may differ by
        a large, mutually compensating turn of joints 1 and 3; halfway along the
        joint line the effector is then off its path and tilted (a held stick
        dips by centimetres). Such a move is split at the IK solution of the
        midpoint pose until the halfway effector error is small.
        """
        pose_a, pose_b = self.sim.arm_model.fk(q_a), self.sim.arm_model.fk(q_b)
        wanted = paths.line("probe", pose_a, pose_b).pose(0.5)
        q_mid = (q_a + q_b) / 2
        halfway = self.sim.arm_model.fk(q_mid)
        off = float(np.linalg.norm(halfway[:3, 3] - wanted[:3, 3]))
        if depth >= MAX_SPLITS or (off < WAYPOINT_TOL and paths.rotation_angle(halfway, wanted) < WAYPOINT_TOL_ANGLE):
            return [q_b]
        solved = self.sim.arm_model.ik(wanted, q0=q_mid)
        if solved is None:
            return [q_b]
        q_mid = np.asarray(solved, dtype=float)
        return self._straight_waypoints(q_a, q_mid, depth + 1) + self._straight_waypoints(q_mid, q_b, depth + 1)

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

    def _joint_line_clears(self, q_a: np.ndarray, q_b: np.ndarray, z_min: float) -> bool:
        """True when the effector stays above `z_min` all along the joint-space line from q_a to q_b."""
        return all(self.sim.arm_model.fk(q_a + (q_b - q_a) * s)[2, 3] >= z_min for s in np.linspace(0.0, 1.0, 12))

    # ------------------------------------------------------------ geometry helpers


def _steps_up(pose: np.ndarray, z: float, step: float = 0.02) -> list[np.ndarray]:
    """Poses straight above `pose` every `step` metres up to height `z` (z included)."""
    heights = np.arange(pose[2, 3] + step, z, step).tolist() + [z] if z > pose[2, 3] + 1e-9 else []
    return [paths.at_height(pose, h) for h in heights]


__all__ = ["ArmMoves"]
