"""The arm: a robot's URDF loaded by DART and placed at a base pose, with its kinematics and reach.

`Arm.load(robot, effector, base)` turns a `robot` declaration (docs/language.md, "Robots")
and the pose of its base in a scene into a model of the chain from the URDF's
root to the effector's link:

- `fk(q)`: the world pose of the effector frame, `base * link(q) * offset *
  Rx(180 deg)` (docs/language.md, "The effector frame convention": the hand's approach
  axis points down at the table, so the effector frame's z axis points up);
- `ik(target)`: joint angles within the URDF's limits that put the effector
  frame at `target`, found by NLopt (gradient-based, analytic gradients from
  DART's Jacobian) from deterministic seeds; `yaw_free=True` leaves the
  rotation about the target's z axis free (a round fingertip pushes the same
  at any yaw);
- `reach(height)`: the radial interval around the base's z axis in which the
  effector can be held hand-down at that height, computed from the URDF
  (constrained NLopt optimisation of the extreme radii, checked by IK all
  around the base).

The work is done in the URDF root's frame by `Chain` (kinematics.py),
`InverseKinematics` (ik.py) and reach.py; this class applies the base pose in
numpy, so that one parsed URDF serves every base. Everything is deterministic:
the restarts of the IK come from a fixed seed.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from vkgl.errors import InputError
from vkgl.robot import reach as reach_module
from vkgl.robot.frames import rx_pi
from vkgl.robot.ik import InverseKinematics
from vkgl.robot.kinematics import Chain
from vkgl.robot.ready_pose import ready_pose
from vkgl.robot.urdf import link_names, load_skeleton

if TYPE_CHECKING:
    from vkgl.lang.ir.nodes import Robot, Scene, SceneRobot
    from vkgl.lang.ir.program import Program

IK_REMEMBERED = 50_000
"""IK answers an arm keeps (about 20 MB at most: each a 4x4 target, a seed and 7 joints)."""

# per URDF, link and offset: the base does not matter, and the optimisation takes a while
_READY_POSES: dict[tuple[Any, ...], np.ndarray] = {}


class Arm:
    """A robot arm: the DART chain from the URDF's root to one effector, placed at a base pose.

    Attributes: `name` (the robot type), `urdf` (absolute path), `effector` (its
    name), `effector_link`, `link_offset` (4x4: the effector frame in the link's
    frame, `offset * Rx(180 deg)`), `base` (4x4 world pose of the URDF root),
    `skeleton` (this arm's own DART skeleton, root at the origin: the base is
    applied in numpy), `joint_names` (the chain's joints, root first), `lower`,
    `upper` (their URDF position limits, rad), `home` (a ready pose, hand down).
    """

    def __init__(
        self,
        skeleton: Any,
        *,
        name: str,
        urdf: str,
        effector: str,
        effector_link: str,
        link_offset: np.ndarray,
        base: np.ndarray,
    ) -> None:
        """Wrap `skeleton` (owned by this arm); use `Arm.load` to build one from a robot declaration."""
        self.skeleton = skeleton
        self.name = name
        self.urdf = urdf
        self.effector = effector
        self.effector_link = effector_link
        self.link_offset = np.asarray(link_offset, dtype=float)
        self.base = np.asarray(base, dtype=float)
        self._base_inverse = np.linalg.inv(self.base)
        self._chain = Chain(skeleton, effector_link, self.link_offset, robot=name)
        self.joint_names = self._chain.joint_names
        self.lower = self._chain.lower
        self.upper = self._chain.upper
        self._model_key = (urdf, effector_link, self.link_offset.tobytes())
        if self._model_key not in _READY_POSES:
            _READY_POSES[self._model_key] = ready_pose(self._chain, name)
        self.home = _READY_POSES[self._model_key].copy()
        self._ik = InverseKinematics(self._chain, self.home)
        self._solved: dict[tuple[Any, ...], np.ndarray | None] = {}  # `ik` and `ik_near` answers by their inputs
        self._wrist_lever: float | None = None

    @classmethod
    def load(cls, robot: Robot, effector: str, base: np.ndarray) -> Arm:
        """The arm of `robot` (IR) acting through its effector `effector`, its URDF root at `base` (4x4, world).

        The URDF is `robot.urdf_resolved` if the checker set it, else `robot.urdf`;
        DART parses each path once. Raises InputError (saying where) for an
        unknown effector, an unreadable URDF or an effector link the URDF lacks.
        """
        spec = robot.effector(effector)
        if spec is None:
            known = ", ".join(e.name for e in robot.effectors) or "none"
            raise InputError(f"{_where(robot)}robot {robot.name} has no effector `{effector}` (it has: {known})")
        path = robot.urdf_resolved or robot.urdf
        try:
            skeleton = load_skeleton(path)
        except InputError as error:
            raise InputError(f"{_where(robot)}robot {robot.name}: {error}") from None
        if skeleton.getBodyNode(spec.link) is None:
            raise InputError(
                f"{_where(spec)}effector {effector} of robot {robot.name}: the URDF has no link `{spec.link}` "
                f"(its links: {', '.join(link_names(skeleton))})"
            )
        base = np.asarray(base, dtype=float)
        if base.shape != (4, 4):
            raise InputError(f"the base pose of robot {robot.name} must be a 4x4 matrix, got shape {base.shape}")
        return cls(
            skeleton,
            name=robot.name,
            urdf=str(Path(path).resolve()),
            effector=effector,
            effector_link=spec.link,
            link_offset=spec.offset.matrix() @ rx_pi(),
            base=base,
        )

    # ------------------------------------------------------------ kinematics

    def fk(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """The world pose (4x4) of the effector frame at joint angles `q` (order of `joint_names`)."""
        return self.base @ self._chain.link_pose(np.asarray(q, dtype=float)) @ self.link_offset

    def jacobian(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """The 6 x n geometric Jacobian of the effector frame in world axes: rows 0-2 linear, 3-5 angular velocity."""
        _, jac = self._chain.pose_and_jacobian(np.asarray(q, dtype=float))
        rotation = self.base[:3, :3]
        return np.vstack([rotation @ jac[3:], rotation @ jac[:3]])

    # ------------------------------------------------------------ inverse kinematics

    def ik(
        self,
        target: np.ndarray,
        q0: Sequence[float] | np.ndarray | None = None,
        *,
        yaw_free: bool = False,
        tol: float = 1e-4,
    ) -> np.ndarray | None:
        """Joint angles within the URDF limits that put the effector frame at `target` (4x4, world), or None.

        Minimises |position error|^2 + (0.1 m * orientation error)^2 with NLopt
        (LD_SLSQP, analytic gradient) from `q0` first (if given; when that run
        succeeds the answer stays near `q0`), then `home` turned toward the
        target, `home`, and fixed random seeds, until a run reaches `tol` (in
        metres of that weighted error); the first run that is a solution wins. The
        answer is a solution when the effector is within 1 mm and 0.5 deg of the
        target (or `tol` and `tol / 0.1 m` rad if looser). With `yaw_free` only
        the effector's z axis must match the target's (rotation about it is free).
        Targets farther than the chain's total length are rejected at once.
        """
        target = np.asarray(target, dtype=float)
        start = None if q0 is None else np.asarray(q0, dtype=float)
        key = ("ik", target.tobytes(), None if start is None else start.tobytes(), yaw_free, tol)
        if key not in self._solved:
            self._remember(key, self._ik.solve(self._base_inverse @ target, start, yaw_free=yaw_free, tol=tol))
        return self._recalled(key)

    def ik_near(
        self, target: np.ndarray, q0: Sequence[float] | np.ndarray, *, yaw_free: bool = False, tol: float = 1e-4
    ) -> np.ndarray | None:
        """`ik` for a target a small step from `q0`'s effector pose (a straight path's next pose).

        Damped Gauss-Newton steps from `q0` first (`InverseKinematics.track`: a
        few forward kinematics instead of an NLopt run); when they stall, `ik`
        from `q0`. The same tolerance and solution rule as `ik`.
        """
        target = np.asarray(target, dtype=float)
        start = np.asarray(q0, dtype=float)
        key = ("near", target.tobytes(), start.tobytes(), yaw_free, tol)
        if key not in self._solved:
            local = self._base_inverse @ target
            found = self._ik.track(local, start, yaw_free=yaw_free, tol=tol)
            self._remember(
                key, found if found is not None else self._ik.solve(local, start, yaw_free=yaw_free, tol=tol)
            )
        return self._recalled(key)

    def _remember(self, key: tuple[Any, ...], q: np.ndarray | None) -> None:
        """Keep an IK answer for `key` (its inputs, byte for byte): the planner asks the same again and again
        (the same contact of many candidate sequences, the same straight move from it), and IK is deterministic,
        so the answer is the one a new run would give (`IK_REMEMBERED` at most; then it starts afresh)."""
        if len(self._solved) >= IK_REMEMBERED:
            self._solved.clear()
        self._solved[key] = None if q is None else q.copy()

    def _recalled(self, key: tuple[Any, ...]) -> np.ndarray | None:
        """The remembered answer for `key`, as an array of the caller's own."""
        q = self._solved[key]
        return None if q is None else q.copy()

    def spread_seeds(self) -> list[np.ndarray]:
        """`home` and the fixed random seeds within the joint limits (the same on every run): starting
        points for IK that should find the arm's other configurations for one pose."""
        return [self.home.copy(), *(seed.copy() for seed in self._ik.random_seeds)]

    # ------------------------------------------------------------ reach

    def reach(self, height: float) -> tuple[float, float]:
        """(r_min, r_max): the distances from the base's z axis at which the effector can be hand-down at `height`.

        "Hand-down" means the effector frame's z axis points up (yaw free: the
        rotation about it, like the fingertip's, does not matter); `height` is
        world z. Computed from the URDF, not assumed:
        1. the smallest and the largest radius of a hand-down effector at that
           height, by constrained NLopt optimisations over the joint angles
           (within their limits), each moved 1 mm inward;
        2. at every azimuth of `REACH_AZIMUTHS_DEG` (every 45 deg, including
           straight behind, where the first joint's +-166 deg limits force the
           arm to reach over with its other joints) IK must reach both ends;
           where it does not, the interval is cut to the one found by bisection
           with IK along that azimuth (`radial_interval`).
        So the interval holds all around the base (for the Panda it is the same
        at every azimuth). Points inside it are assumed reachable (tests sample
        them); self-collision is not considered. (0.0, 0.0) means nowhere at
        that height. Assumes an upright base; cached per URDF, effector and
        height above the base (to the mm) for the process.
        """
        return reach_module.reach_at(self._ik, self._model_key, float(self.base[2, 3]), float(height))

    @property
    def wrist_lever(self) -> float:
        """m: how far above the effector, along its z axis, the wrist lies (the origin of the link the chain's last
        joint moves, at `home`; 0 when the wrist is not above it). A hand tilted by t about a horizontal axis moves
        its wrist L sin t sideways: the reach of a tilted hand is about the hand-down reach of the point below its
        wrist (`vkgl.plan.task_space.reach.workspace.hand_down_point`)."""
        if self._wrist_lever is None:
            self._wrist_lever = max(0.0, float(self._chain.wrist_in_effector(self.home)[2]))
        return self._wrist_lever

    def reachable(self, point: Sequence[float] | np.ndarray) -> bool:
        """Whether the effector can be hand-down at `point` (world, 3-d): its radius lies in `reach(point z)`."""
        point = np.asarray(point, dtype=float)
        r_min, r_max = self.reach(float(point[2]))
        radius = float(np.hypot(point[0] - self.base[0, 3], point[1] - self.base[1, 3]))
        return r_max > 0.0 and r_min <= radius <= r_max

    def radial_interval(self, height: float, azimuth: float) -> tuple[float, float] | None:
        """The reachable radii (min, max) hand-down at root-frame `height` along `azimuth` (rad), or None.

        Bisection to `REACH_PRECISION` between a reachable radius and the chain's
        length (outward) and the axis (inward); each IK starts from the solution
        at the nearest reachable radius so far.
        """
        return reach_module.radial_interval(self._ik, height, azimuth)


def clear_caches() -> None:
    """Forget the ready poses and reach intervals computed so far (for benchmarks and determinism tests)."""
    _READY_POSES.clear()
    reach_module.clear_reach_cache()


# ---------------------------------------------------------------- scenes


def arm_for_scene(
    program: Program,
    scene: Scene | str,
    robot_name: str | None = None,
    effector: str | None = None,
) -> Arm:
    """The arm of a scene's robot (`robot_name`, default the scene's first), at its scene pose.

    `scene` is a Scene IR or the name of a scene of `program`; `effector`
    defaults to the robot type's first effector. Raises InputError when the
    scene, robot, robot type or effector does not exist.
    """
    if isinstance(scene, str):
        if scene not in program.scenes:
            raise InputError(f"no scene `{scene}` in the program (scenes: {', '.join(program.scenes) or 'none'})")
        scene = program.scenes[scene]
    placed = _scene_robot(scene, robot_name)
    robot = program.robots.get(placed.type.name)
    if robot is None:
        raise InputError(f"{_where(placed)}robot {placed.name} has the unknown type `{placed.type.name}`")
    if effector is None:
        if not robot.effectors:
            raise InputError(f"{_where(robot)}robot {robot.name} declares no effector")
        effector = robot.effectors[0].name
    return Arm.load(robot, effector, placed.pose.matrix())


def _scene_robot(scene: Scene, robot_name: str | None) -> SceneRobot:
    """The robot `robot_name` placed in `scene` (default its first), or InputError."""
    if not scene.robots:
        raise InputError(f"{_where(scene)}scene {scene.name} has no robot")
    if robot_name is None:
        return scene.robots[0]
    for placed in scene.robots:
        if placed.name == robot_name:
            return placed
    names = ", ".join(r.name for r in scene.robots)
    raise InputError(f"{_where(scene)}scene {scene.name} has no robot `{robot_name}` (it has: {names})")


def _where(node: Any) -> str:
    """`path:line:col: ` of an IR node, or nothing when it has no span."""
    span = getattr(node, "span", None)
    return f"{span}: " if span is not None else ""


__all__ = ["Arm", "arm_for_scene", "clear_caches"]
