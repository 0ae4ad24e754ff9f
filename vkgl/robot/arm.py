"""The arm: a robot's URDF loaded by DART, forward and inverse kinematics, reach.

`Arm.load(robot, effector, base)` turns a `robot` declaration (LANGUAGE.md §4)
and the pose of its base in a scene into a kinematic model of the chain from
the URDF's root to the effector's link:

- `fk(q)`: the world pose of the effector frame, `base * link(q) * offset *
  Rx(180 deg)` (LANGUAGE.md's effector frame convention: the hand's approach
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

DART does the forward kinematics; the base pose is applied in numpy so that one
parsed URDF serves every base. Everything is deterministic: the restarts of
the IK come from a fixed seed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.errors import InputError

if TYPE_CHECKING:
    from vkgl.lang.ir import Robot, Scene, SceneRobot
    from vkgl.lang.program import Program

LENGTH_SCALE = 0.1
"""m: one radian of orientation error weighs like this much position error in the IK cost."""

POSITION_TOL = 1e-3
"""m: an IK result is a solution when its effector is this close to the target ..."""

ANGLE_TOL = math.radians(0.5)
"""rad: ... and its orientation this close (about any axis, or of the z axis when yaw is free)."""

RANDOM_SEEDS = 16
"""Random restarts of the IK after the informed seeds (drawn once per arm from a fixed seed)."""

MAX_EVALUATIONS = 250
"""Objective evaluations per local IK run."""

REACH_PRECISION = 1e-3
"""m: `reach` keeps this far inside the extreme radii, and its bisections stop at this width."""

REACH_SEEDS = 4
"""Random seeds (after `home`) of each optimisation of an extreme radius in `reach`."""

REACH_AZIMUTHS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0, -135.0, -90.0, -45.0)
"""Directions (deg about the base's z axis, from its x axis) at which `reach` checks its interval by IK."""

_RX_PI = np.diag([1.0, -1.0, -1.0, 1.0])  # rotation by 180 deg about x


# ---------------------------------------------------------------- URDF loading


@cache
def _parsed_skeleton(path: str) -> Any:
    """The URDF at `path` parsed by DART with its root welded to the world (one parse per path)."""
    import dartpy as dart

    loader = dart.utils.DartLoader()
    options = dart.utils.DartLoaderOptions()
    # The arm stands on the table: its root link is welded, not floating.
    options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
    loader.setOptions(options)
    return loader.parseSkeleton(path)


def load_skeleton(path: str | Path) -> Any:
    """A fresh DART skeleton of the URDF at `path` (a clone of the cached parse).

    Raises InputError when the file is missing or DART cannot read it.
    """
    path = str(Path(path).resolve())
    if not Path(path).is_file():
        raise InputError(f"URDF file not found: {path}")
    skeleton = _parsed_skeleton(path)
    if skeleton is None:
        raise InputError(f"DART cannot load the URDF {path}: check that it is valid URDF")
    return skeleton.clone()


def _where(node: Any) -> str:
    """`path:line:col: ` of an IR node, or nothing when it has no span."""
    span = getattr(node, "span", None)
    return f"{span}: " if span is not None else ""


def _chain_joints(skeleton: Any, link: Any) -> list[Any]:
    """The joints with degrees of freedom from the root to `link`, root first."""
    joints = []
    node = link
    while node is not None:
        joint = node.getParentJoint()
        if joint.getNumDofs() > 0:
            joints.append(joint)
        node = node.getParentBodyNode()
    return joints[::-1]


# ---------------------------------------------------------------- the arm


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
        self._link = skeleton.getBodyNode(effector_link)
        joints = _chain_joints(skeleton, self._link)
        if not joints:
            raise InputError(f"{name}: no joint of the URDF moves the effector link {effector_link}")
        if any(j.getNumDofs() != 1 for j in joints):
            raise InputError(
                f"{name}: the joints from the URDF's root to {effector_link} must each have one degree of freedom"
            )
        self.joint_names: list[str] = [j.getName() for j in joints]
        self._dofs = np.array([j.getIndexInSkeleton(0) for j in joints])
        self._dof_list = [int(d) for d in self._dofs]
        self._all_dofs = self._dof_list == list(range(skeleton.getNumDofs()))
        self.lower = np.array([j.getPositionLowerLimit(0) for j in joints])
        self.upper = np.array([j.getPositionUpperLimit(0) for j in joints])
        self._jacobian_columns = self._columns_of_chain()
        self._point = self.link_offset[:3, 3].copy()
        self._anchor, self._radius = self._reach_bound()
        self._random_seeds = np.random.default_rng(0).uniform(self.lower, self.upper, (RANDOM_SEEDS, len(joints)))
        self._model_key = (urdf, effector_link, self.link_offset.tobytes())
        if self._model_key not in _READY_POSES:
            _READY_POSES[self._model_key] = self._ready_pose()
        self.home = _READY_POSES[self._model_key].copy()
        home_point = self._local_pose_and_jacobian(self.home)[0][:3, 3]
        self._home_azimuth = math.atan2(home_point[1], home_point[0])

    # ------------------------------------------------------------ construction

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
            links = ", ".join(skeleton.getBodyNode(i).getName() for i in range(skeleton.getNumBodyNodes()))
            raise InputError(
                f"{_where(spec)}effector {effector} of robot {robot.name}: the URDF has no link `{spec.link}` "
                f"(its links: {links})"
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
            link_offset=spec.offset.matrix() @ _RX_PI,
            base=base,
        )

    def _columns_of_chain(self) -> np.ndarray | None:
        """Which columns of the link's DART Jacobian belong to `joint_names`, in their order (None: all, in order)."""
        dependent = [self._link.getDependentGenCoordIndex(i) for i in range(self._link.getNumDependentGenCoords())]
        columns = [dependent.index(int(d)) for d in self._dofs]
        return None if columns == list(range(len(dependent))) else np.array(columns)

    def _reach_bound(self) -> tuple[np.ndarray, float]:
        """A point that no joint moves (on the first joint's axis) and how far from it the effector can ever be.

        The bound is the sum of the lengths of the chain's fixed offsets after
        that point: rotations never lengthen them (triangle inequality). It lets
        `ik` reject far targets at once.
        """
        q = np.zeros(len(self.joint_names))
        first = self.skeleton.getJoint(self.joint_names[0])
        child = first.getChildBodyNode()
        anchors = []
        for angle in (0.0, 1.0):
            q[0] = angle
            self._set(q)
            anchors.append(child.getWorldTransform().translation())
        if np.linalg.norm(anchors[0] - anchors[1]) < 1e-9:
            start, anchor = child.getName(), anchors[0]
        else:
            start, anchor = None, np.zeros(3)
        length = float(np.linalg.norm(self._point))
        node = self._link
        while node is not None and node.getName() != start:
            joint = node.getParentJoint()
            length += float(np.linalg.norm(joint.getTransformFromParentBodyNode().translation()))
            length += float(np.linalg.norm(joint.getTransformFromChildBodyNode().translation()))
            node = node.getParentBodyNode()
        return anchor, length

    def _ready_pose(self) -> np.ndarray:
        """A ready pose: hand down in front of the base, effector x along the base's x, joints central.

        The configuration closest to the middle of the joint ranges (in
        range-normalised units) whose effector frame has exactly that
        orientation and lies in the base's xz plane (height and distance free);
        NLopt SLSQP with those as constraints, from the middle of the ranges.
        """
        import nlopt

        middle = (self.lower + self.upper) / 2
        span = self.upper - self.lower

        def distance(q: np.ndarray, grad: np.ndarray) -> float:
            centre = (q - middle) / span
            if grad.size:
                grad[:] = 2.0 * centre / span
            return float(centre @ centre)

        def orientation(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            residual, direction = _orientation_error(pose[:3, :3], np.eye(3), yaw_free=False)
            if grad.size:
                grad[:] = jac[:3].T @ direction
            return residual - 1e-10

        def sideways(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            if grad.size:
                grad[:] = jac[4]
            return float(pose[1, 3])

        optimiser = nlopt.opt(nlopt.LD_SLSQP, len(middle))
        optimiser.set_lower_bounds(self.lower)
        optimiser.set_upper_bounds(self.upper)
        optimiser.set_min_objective(distance)
        optimiser.add_inequality_constraint(orientation, 0.0)
        optimiser.add_equality_constraint(sideways, 1e-9)
        optimiser.set_xtol_abs(1e-10)
        optimiser.set_maxeval(2000)
        try:
            q = optimiser.optimize(middle)
        except (nlopt.RoundoffLimited, nlopt.runtime_error, ValueError, RuntimeError):
            q = middle
        pose = self._local_pose_and_jacobian(q)[0]
        if _angle_error(pose, np.eye(4), yaw_free=False) > ANGLE_TOL:
            raise InputError(f"{self.name}: the arm cannot point its effector straight down (no ready pose)")
        return q

    # ------------------------------------------------------------ kinematics

    def _set(self, q: np.ndarray) -> None:
        if self._all_dofs:
            self.skeleton.setPositions(q)
        else:
            self.skeleton.setPositions(self._dof_list, q)

    def _local_pose_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The effector frame in the URDF root frame and its 6 x n Jacobian (angular rows first, root frame)."""
        self._set(q)
        pose = self._link.getWorldTransform().matrix() @ self.link_offset
        jac = self._link.getWorldJacobian(self._point)
        if self._jacobian_columns is not None:
            jac = jac[:, self._jacobian_columns]
        return pose, jac

    def fk(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """The world pose (4x4) of the effector frame at joint angles `q` (order of `joint_names`)."""
        self._set(np.asarray(q, dtype=float))
        return self.base @ self._link.getWorldTransform().matrix() @ self.link_offset

    def jacobian(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """The 6 x n geometric Jacobian of the effector frame in world axes: rows 0-2 linear, 3-5 angular velocity."""
        _, jac = self._local_pose_and_jacobian(np.asarray(q, dtype=float))
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
        local = self._base_inverse @ np.asarray(target, dtype=float)
        if not np.isfinite(local).all() or np.linalg.norm(local[:3, 3] - self._anchor) > self._radius + POSITION_TOL:
            return None
        seeds: list[np.ndarray] = [] if q0 is None else [np.asarray(q0, dtype=float)]
        seeds += [self._aimed_home(local[:3, 3], None if yaw_free else local[:3, :3]), self.home, *self._random_seeds]
        return self._solve(local, seeds, yaw_free=yaw_free, tol=tol)

    def spread_seeds(self) -> list[np.ndarray]:
        """`home` and the fixed random seeds within the joint limits (the same on every run): starting
        points for IK that should find the arm's other configurations for one pose."""
        return [self.home.copy(), *(seed.copy() for seed in self._random_seeds)]

    def _aimed_home(self, point: np.ndarray, rotation: np.ndarray | None = None) -> np.ndarray:
        """`home` with the first joint turned so that the arm faces `point` (root frame), and with
        the last joint turned toward `rotation` (if given) about its own axis."""
        seed = self.home.copy()
        turn = math.atan2(point[1], point[0]) - self._home_azimuth
        seed[0] = _wrapped(seed[0] + turn, self.lower[0], self.upper[0])
        if rotation is not None:
            pose, jac = self._local_pose_and_jacobian(seed)
            # the rotation still missing, projected on the last joint's axis, is what that joint can add
            missing = Rotation.from_matrix(rotation @ pose[:3, :3].T).as_rotvec()
            seed[-1] = _wrapped(seed[-1] + float(missing @ jac[:3, -1]), self.lower[-1], self.upper[-1])
        return seed

    def _solve(
        self, local: np.ndarray, seeds: Sequence[np.ndarray], *, yaw_free: bool, tol: float
    ) -> np.ndarray | None:
        """The first seed's local optimum that is a solution for the root-frame target `local`, or None."""
        cost = self._ik_cost(local, yaw_free)
        position_tol = max(POSITION_TOL, tol)
        angle_tol = max(ANGLE_TOL, tol / LENGTH_SCALE)
        for seed in seeds:
            q, _ = _minimise(cost, seed, self.lower, self.upper, stop=tol * tol, evaluations=MAX_EVALUATIONS)
            pose = self._local_pose_and_jacobian(q)[0]
            if _position_error(pose, local) <= position_tol and _angle_error(pose, local, yaw_free) <= angle_tol:
                return q
        return None

    def _ik_cost(self, local: np.ndarray, yaw_free: bool) -> Callable[[np.ndarray, np.ndarray], float]:
        """The NLopt objective (value and gradient) of the weighted pose error to `local`."""
        point = local[:3, 3]
        rotation = local[:3, :3]
        weight = LENGTH_SCALE**2

        def cost(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            offset = pose[:3, 3] - point
            residual, direction = _orientation_error(pose[:3, :3], rotation, yaw_free)
            if grad.size:
                grad[:] = 2.0 * (jac[3:].T @ offset) + weight * (jac[:3].T @ direction)
            return float(offset @ offset) + weight * residual

        return cost

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
        key = (*self._model_key, round(height - self.base[2, 3], 3))
        if key not in _REACH_CACHE:
            _REACH_CACHE[key] = self._compute_reach(key[-1])
        return _REACH_CACHE[key]

    def reachable(self, point: Sequence[float] | np.ndarray) -> bool:
        """Whether the effector can be hand-down at `point` (world, 3-d): its radius lies in `reach(point z)`."""
        point = np.asarray(point, dtype=float)
        r_min, r_max = self.reach(float(point[2]))
        radius = float(np.hypot(point[0] - self.base[0, 3], point[1] - self.base[1, 3]))
        return r_max > 0.0 and r_min <= radius <= r_max

    def _compute_reach(self, height: float) -> tuple[float, float]:
        """The reach at root-frame `height`: extreme radii by optimisation, then checked by IK at every azimuth."""
        inner, outer = self._extreme_radius(height, largest=False), self._extreme_radius(height, largest=True)
        if inner is None or outer is None:
            return (0.0, 0.0)
        interval: tuple[float, float] | None = (inner[0] + REACH_PRECISION, outer[0] - REACH_PRECISION)
        for azimuth in (math.radians(a) for a in REACH_AZIMUTHS_DEG):
            if interval is None or interval[0] >= interval[1]:
                return (0.0, 0.0)
            interval = self._confirmed_interval(height, azimuth, interval, (inner[1], outer[1]))
        return (0.0, 0.0) if interval is None else interval

    def _extreme_radius(self, height: float, *, largest: bool) -> tuple[float, np.ndarray] | None:
        """The largest (smallest) distance from the root's z axis of a hand-down effector at `height`, with its joints.

        NLopt SLSQP maximises (minimises) x^2 + y^2 of the effector subject to
        its height and its z axis pointing up, from `home` and a few fixed random
        seeds; the best feasible optimum wins.
        """
        import nlopt

        sign = -1.0 if largest else 1.0

        def radius_squared(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            x, y = pose[0, 3], pose[1, 3]
            if grad.size:
                grad[:] = sign * 2.0 * (x * jac[3] + y * jac[4])
            return sign * (x * x + y * y)

        def at_height(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            if grad.size:
                grad[:] = jac[5]
            return float(pose[2, 3] - height)

        def upright(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self._local_pose_and_jacobian(q)
            residual, direction = _orientation_error(pose[:3, :3], np.eye(3), yaw_free=True)
            if grad.size:
                grad[:] = jac[:3].T @ direction
            return residual - 1e-10

        best: tuple[float, np.ndarray] | None = None
        for seed in (self.home, *self._random_seeds[:REACH_SEEDS]):
            optimiser = nlopt.opt(nlopt.LD_SLSQP, len(seed))
            optimiser.set_lower_bounds(self.lower)
            optimiser.set_upper_bounds(self.upper)
            optimiser.set_min_objective(radius_squared)
            optimiser.add_equality_constraint(at_height, 1e-7)
            optimiser.add_inequality_constraint(upright, 0.0)
            optimiser.set_xtol_abs(1e-9)
            optimiser.set_maxeval(MAX_EVALUATIONS)
            try:
                q = optimiser.optimize(seed)
            except (nlopt.RoundoffLimited, nlopt.runtime_error, ValueError, RuntimeError):
                continue
            pose = self._local_pose_and_jacobian(q)[0]
            if abs(pose[2, 3] - height) > POSITION_TOL / 10 or _angle_error(pose, np.eye(4), True) > ANGLE_TOL / 10:
                continue
            radius = math.hypot(pose[0, 3], pose[1, 3])
            if best is None or (radius > best[0] if largest else radius < best[0]):
                best = (radius, q)
        return best

    def _confirmed_interval(
        self, height: float, azimuth: float, interval: tuple[float, float], extremes: tuple[np.ndarray, np.ndarray]
    ) -> tuple[float, float] | None:
        """`interval` if IK reaches both its ends along `azimuth`, else its intersection with the bisected one there.

        The IK of each end starts from the extreme configuration turned by the
        first joint to face `azimuth`, when the joint's limits allow.
        """
        solve = self._hand_down_solver(height, azimuth)
        inner, outer = (self._turned_toward(q, azimuth) for q in extremes)
        if solve(interval[1], outer, True) is not None and solve(interval[0], inner, True) is not None:
            return interval
        here = self.radial_interval(height, azimuth)
        if here is None or max(interval[0], here[0]) >= min(interval[1], here[1]):
            return None
        return (max(interval[0], here[0]), min(interval[1], here[1]))

    def _turned_toward(self, q: np.ndarray, azimuth: float) -> list[np.ndarray]:
        """`q` with the first joint turned so that the effector faces `azimuth`, as seeds (none beyond limits)."""
        point = self._local_pose_and_jacobian(q)[0][:3, 3]
        turned = q.copy()
        turned[0] += (azimuth - math.atan2(point[1], point[0]) + math.pi) % (2 * math.pi) - math.pi
        return [turned] if self.lower[0] <= turned[0] <= self.upper[0] else []

    def radial_interval(self, height: float, azimuth: float) -> tuple[float, float] | None:
        """The reachable radii (min, max) hand-down at root-frame `height` along `azimuth` (rad), or None.

        Bisection to `REACH_PRECISION` between a reachable radius and the chain's
        length (outward) and the axis (inward); each IK starts from the solution
        at the nearest reachable radius so far.
        """
        horizontal = self._radius**2 - (height - self._anchor[2]) ** 2
        if horizontal <= 0:
            return None
        limit = math.sqrt(horizontal) + math.hypot(self._anchor[0], self._anchor[1])
        solve = self._hand_down_solver(height, azimuth)
        for radius in limit * np.array([0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8]):
            q = solve(radius, [], True)
            if q is not None:
                break
        else:
            return None
        r_max = _bisect_edge(solve, radius, q, limit)
        r_min = _bisect_edge(solve, radius, q, 0.0)
        return (r_min, r_max)

    def _hand_down_solver(self, height: float, azimuth: float) -> HandDownSolver:
        """IK for `(radius, warm, thorough) -> hand-down pose at (radius, azimuth, height)` (root frame).

        The `warm` seeds (e.g. the solution at a neighbouring radius) are tried
        first, then `home` turned toward the target, then, if `thorough`, the
        other seeds of `ik`.
        """
        rotation = Rotation.from_euler("z", azimuth).as_matrix()

        def solve(radius: float, warm: list[np.ndarray], thorough: bool = False) -> np.ndarray | None:
            local = np.eye(4)
            local[:3, :3] = rotation
            local[:3, 3] = rotation @ np.array([radius, 0.0, 0.0]) + np.array([0.0, 0.0, height])
            seeds = [*warm, self._aimed_home(local[:3, 3])]
            if thorough:
                seeds += [self.home, *self._random_seeds]
            return self._solve(local, seeds, yaw_free=True, tol=1e-4)

        return solve


def _wrapped(angle: float, lower: float, upper: float) -> float:
    """`angle` moved by whole turns into [lower, upper] if it can be, else clipped to it."""
    centre = (lower + upper) / 2
    angle = centre + (angle - centre + math.pi) % (2 * math.pi) - math.pi
    return min(max(angle, lower), upper)


HandDownSolver = Callable[[float, list[np.ndarray], bool], "np.ndarray | None"]
_REACH_CACHE: dict[tuple[Any, ...], tuple[float, float]] = {}
_READY_POSES: dict[tuple[Any, ...], np.ndarray] = {}  # per URDF, link and offset: the base does not matter


def _bisect_edge(solve: HandDownSolver, inside: float, q: np.ndarray, outside: float) -> float:
    """The reachable radius closest to `outside`, by bisection from the reachable `inside` (solution `q`)."""
    if solve(outside, [q], False) is not None:
        return outside
    while abs(outside - inside) > REACH_PRECISION:
        middle = (inside + outside) / 2
        found = solve(middle, [q], False)
        if found is None:
            outside = middle
        else:
            inside, q = middle, found
    return float(inside)


# ---------------------------------------------------------------- errors and the optimiser


def _orientation_error(rotation: np.ndarray, target: np.ndarray, yaw_free: bool) -> tuple[float, np.ndarray]:
    """A smooth orientation residual (about angle^2 when small) and its gradient direction.

    The gradient of the residual with respect to joint k is `w_k . direction`
    (w_k: the joint's angular Jacobian column). Full orientation: 3 - trace(Rt^T R);
    yaw free: 2 (1 - z . z_t).
    """
    if yaw_free:
        (_, _, ax), (_, _, ay), (_, _, az) = rotation
        (_, _, bx), (_, _, by), (_, _, bz) = target
        # z x z_target written out: np.cross costs more than the rest of the IK objective
        cross = np.array([ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx])
        return 2.0 * (1.0 - (ax * bx + ay * by + az * bz)), -2.0 * cross
    a = rotation @ target.T
    direction = -np.array([a[1, 2] - a[2, 1], a[2, 0] - a[0, 2], a[0, 1] - a[1, 0]])
    return 3.0 - float(np.trace(a)), direction


def _position_error(pose: np.ndarray, target: np.ndarray) -> float:
    return float(np.linalg.norm(pose[:3, 3] - target[:3, 3]))


def _angle_error(pose: np.ndarray, target: np.ndarray, yaw_free: bool) -> float:
    if yaw_free:
        return math.acos(min(1.0, max(-1.0, float(pose[:3, 2] @ target[:3, 2]))))
    cosine = (float(np.trace(pose[:3, :3] @ target[:3, :3].T)) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, cosine)))


def _minimise(
    cost: Callable[[np.ndarray, np.ndarray], float],
    seed: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    *,
    stop: float,
    evaluations: int,
) -> tuple[np.ndarray, float]:
    """One bounded local NLopt run (SLSQP) from `seed`: the best point it evaluated and its cost."""
    import nlopt

    best: list[Any] = [math.inf, None]

    def tracked(q: np.ndarray, grad: np.ndarray) -> float:
        value = cost(q, grad)
        if value < best[0]:
            best[0], best[1] = value, q.copy()
        return value

    optimiser = nlopt.opt(nlopt.LD_SLSQP, len(seed))
    optimiser.set_lower_bounds(lower)
    optimiser.set_upper_bounds(upper)
    optimiser.set_min_objective(tracked)
    optimiser.set_stopval(stop)
    optimiser.set_maxeval(evaluations)
    optimiser.set_ftol_abs(1e-16)
    optimiser.set_xtol_abs(1e-10)
    try:
        optimiser.optimize(np.clip(seed, lower, upper))
    except (nlopt.RoundoffLimited, nlopt.runtime_error, ValueError, RuntimeError):
        pass  # the best point evaluated so far still counts
    if best[1] is None:
        return np.clip(seed, lower, upper), math.inf
    return best[1], best[0]


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
    if not scene.robots:
        raise InputError(f"{_where(scene)}scene {scene.name} has no robot")
    if robot_name is None:
        return scene.robots[0]
    for placed in scene.robots:
        if placed.name == robot_name:
            return placed
    names = ", ".join(r.name for r in scene.robots)
    raise InputError(f"{_where(scene)}scene {scene.name} has no robot `{robot_name}` (it has: {names})")


__all__ = ["ANGLE_TOL", "POSITION_TOL", "Arm", "arm_for_scene", "load_skeleton"]
