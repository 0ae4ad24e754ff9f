"""Inverse kinematics in the chain's root frame: NLopt from deterministic seeds.

Each run minimises |position error|^2 + (LENGTH_SCALE * orientation error)^2
with SLSQP and analytic gradients; the seeds come in a fixed order (the
caller's, then `home` aimed at the target, `home`, random ones drawn once from
a fixed seed), and the first run that ends within tolerance wins. So the
same target gives the same joints on every run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from functools import cached_property
from typing import Any

import numpy as np

from vkgl.robot.kinematics import Chain
from vkgl.robot.optimise import Objective, slsqp
from vkgl.robot.pose_error import ANGLE_TOL, POSITION_TOL, angle_error, orientation_residual, position_error
from vkgl.rotations import matrix_rotvec, yaw_matrix

LENGTH_SCALE = 0.1
"""m: one radian of orientation error weighs like this much position error in the IK cost."""

RANDOM_SEEDS = 16
"""Random restarts of the IK after the informed seeds (drawn once per arm from a fixed seed)."""

MAX_EVALUATIONS = 250
"""Objective evaluations per local IK run."""

TRACK_STEPS = 8
"""Gauss-Newton steps of `InverseKinematics.track` before it gives up (a 1 cm step needs two or three)."""

TRACK_DAMPING = 1e-3
"""Damping of `track`'s least-squares steps (keeps them bounded near singular configurations)."""

HandDownSolver = Callable[[float, list[np.ndarray], bool], "np.ndarray | None"]
"""`solve(radius, warm_seeds, thorough)`: IK of a hand-down pose at one height and azimuth (see `hand_down_solver`)."""


class InverseKinematics:
    """IK of one chain, with its seeds: `home` and random ones within the limits.

    Attributes: `chain`, `home`, `random_seeds` (RANDOM_SEEDS x n, the same on
    every run), `anchor` and `radius` (no target farther than `radius` from
    `anchor` is reachable: see `Chain.reach_bound`).
    """

    def __init__(self, chain: Chain, home: np.ndarray) -> None:
        """IK of `chain`, with `home` (a ready pose, hand down) as its informed seed."""
        self.chain = chain
        self.home = home
        self.anchor, self.radius = chain.reach_bound()
        home_point = chain.pose_and_jacobian(home)[0][:3, 3]
        self._home_azimuth = math.atan2(home_point[1], home_point[0])

    @cached_property
    def random_seeds(self) -> np.ndarray:
        """RANDOM_SEEDS x n joint vectors drawn uniformly within the limits, the same on every run; drawn when
        first wanted (most IK succeeds from `home`, and numpy's random module costs a solve's start)."""
        return np.random.default_rng(0).uniform(
            self.chain.lower, self.chain.upper, (RANDOM_SEEDS, len(self.chain.joint_names))
        )

    def solve(
        self, local: np.ndarray, q0: np.ndarray | None = None, *, yaw_free: bool = False, tol: float = 1e-4
    ) -> np.ndarray | None:
        """Joint angles that put the effector frame at `local` (4x4, root frame), or None (see `Arm.ik`)."""
        if not np.isfinite(local).all() or np.linalg.norm(local[:3, 3] - self.anchor) > self.radius + POSITION_TOL:
            return None
        return self.solve_from(local, self._seeds(local, q0, yaw_free), yaw_free=yaw_free, tol=tol)

    def _seeds(self, local: np.ndarray, q0: np.ndarray | None, yaw_free: bool) -> Iterator[np.ndarray]:
        """`q0` (if given), `home` aimed at `local`, `home`, the random seeds: made only when tried (the first
        one usually solves)."""
        if q0 is not None:
            yield q0
        yield self.aimed_home(local[:3, 3], None if yaw_free else local[:3, :3])
        yield self.home
        yield from self.random_seeds

    def solve_from(
        self, local: np.ndarray, seeds: Iterable[np.ndarray], *, yaw_free: bool, tol: float
    ) -> np.ndarray | None:
        """The first seed's local optimum that is a solution for the root-frame target `local`, or None."""
        cost = self._cost(local, yaw_free)
        position_tol = max(POSITION_TOL, tol)
        angle_tol = max(ANGLE_TOL, tol / LENGTH_SCALE)
        for seed in seeds:
            q = self._best_point(cost, seed, stop=tol * tol)
            pose = self.chain.pose_and_jacobian(q)[0]
            if position_error(pose, local) <= position_tol and angle_error(pose, local, yaw_free) <= angle_tol:
                return q
        return None

    def track(self, local: np.ndarray, q0: np.ndarray, *, yaw_free: bool, tol: float) -> np.ndarray | None:
        """A solution for `local` near `q0` by damped Gauss-Newton steps on the pose residual, or None.

        For targets a small step from `q0`'s pose (a straight Cartesian path in
        1 cm steps): two or three steps of one forward kinematics each, where an
        NLopt run from `q0` costs about 30 evaluations. It stops where `solve`'s
        runs stop (the weighted pose error within `tol`), within the joint
        limits. None when the steps stall (a far target, a joint limit, a
        singular configuration): then use `solve`.
        """
        lower, upper = self.chain.lower, self.chain.upper
        point, rotation = local[:3, 3], local[:3, :3]
        q = np.clip(np.asarray(q0, dtype=float), lower, upper)
        for _ in range(TRACK_STEPS + 1):
            pose, jac = self.chain.pose_and_jacobian(q)
            residual, jacobian = _pose_residual(pose, jac, point, rotation, yaw_free)
            if float(residual @ residual) <= tol * tol:
                return q
            normal = jacobian @ jacobian.T + TRACK_DAMPING**2 * np.eye(len(residual))
            q = np.clip(q - jacobian.T @ np.linalg.solve(normal, residual), lower, upper)
        return None

    def aimed_home(self, point: np.ndarray, rotation: np.ndarray | None = None) -> np.ndarray:
        """`home` with the first joint turned so that the arm faces `point` (root frame), and with
        the last joint turned toward `rotation` (if given) about its own axis."""
        lower, upper = self.chain.lower, self.chain.upper
        seed = self.home.copy()
        turn = math.atan2(point[1], point[0]) - self._home_azimuth
        seed[0] = _wrapped(seed[0] + turn, lower[0], upper[0])
        if rotation is not None:
            pose, jac = self.chain.pose_and_jacobian(seed)
            # the rotation still missing, projected on the last joint's axis, is what that joint can add
            missing = matrix_rotvec(rotation @ pose[:3, :3].T)
            seed[-1] = _wrapped(seed[-1] + float(missing @ jac[:3, -1]), lower[-1], upper[-1])
        return seed

    def hand_down_solver(self, height: float, azimuth: float) -> HandDownSolver:
        """IK for `(radius, warm, thorough) -> hand-down pose at (radius, azimuth, height)` (root frame).

        The `warm` seeds (e.g. the solution at a neighbouring radius) are tried
        first, then `home` turned toward the target, then, if `thorough`, the
        other seeds of `solve`.
        """
        rotation = np.array(yaw_matrix(azimuth))

        def solve(radius: float, warm: list[np.ndarray], thorough: bool = False) -> np.ndarray | None:
            local = np.eye(4)
            local[:3, :3] = rotation
            local[:3, 3] = rotation @ np.array([radius, 0.0, 0.0]) + np.array([0.0, 0.0, height])
            return self.solve_from(local, self._hand_down_seeds(local, warm, thorough), yaw_free=True, tol=1e-4)

        return solve

    def _hand_down_seeds(self, local: np.ndarray, warm: list[np.ndarray], thorough: bool) -> Iterator[np.ndarray]:
        """The seeds of `hand_down_solver`'s IK, made only when tried."""
        yield from warm
        yield self.aimed_home(local[:3, 3])
        if thorough:
            yield self.home
            yield from self.random_seeds

    def _cost(self, local: np.ndarray, yaw_free: bool) -> Objective:
        """The NLopt objective (value and gradient) of the weighted pose error to `local`."""
        point = local[:3, 3]
        rotation = local[:3, :3]
        weight = LENGTH_SCALE**2

        def cost(q: np.ndarray, grad: np.ndarray) -> float:
            pose, jac = self.chain.pose_and_jacobian(q)
            offset = pose[:3, 3] - point
            residual, direction = orientation_residual(pose[:3, :3], rotation, yaw_free)
            if grad.size:
                grad[:] = 2.0 * (jac[3:].T @ offset) + weight * (jac[:3].T @ direction)
            return float(offset @ offset) + weight * residual

        return cost

    def _best_point(self, cost: Objective, seed: np.ndarray, *, stop: float) -> np.ndarray:
        """The best point one local run from `seed` evaluated (the seed, clipped to the limits, if none).

        The best evaluated point, not NLopt's answer: when SLSQP stops with an
        error (round-off near the optimum, typically) the best point still counts.
        """
        lower, upper = self.chain.lower, self.chain.upper
        best: list[Any] = [math.inf, None]

        def tracked(q: np.ndarray, grad: np.ndarray) -> float:
            value = cost(q, grad)
            if value < best[0]:
                best[0], best[1] = value, q.copy()
            return value

        start = np.clip(seed, lower, upper)
        slsqp(tracked, start, lower, upper, max_evaluations=MAX_EVALUATIONS, xtol=1e-10, ftol=1e-16, stop=stop)
        return start if best[1] is None else best[1]


def _pose_residual(
    pose: np.ndarray, jac: np.ndarray, point: np.ndarray, rotation: np.ndarray, yaw_free: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The weighted pose error (position; LENGTH_SCALE x orientation) and its Jacobian in the joints.

    `jac` is the chain's (rows 0-2 angular, 3-5 linear). Full orientation: the
    small rotation w with R = exp(w) R_target (its rate is the angular
    velocity); yaw free: z - z_target (its rate is omega x z).
    """
    angular, linear = jac[:3], jac[3:]
    if yaw_free:
        z = pose[:3, 2]
        cross = np.array([[0.0, -z[2], z[1]], [z[2], 0.0, -z[0]], [-z[1], z[0], 0.0]])
        rot_error, rot_jac = z - rotation[:, 2], -cross @ angular
    else:
        rot_error, rot_jac = orientation_residual(pose[:3, :3], rotation, False)[1] / 2.0, angular
    residual = np.concatenate([pose[:3, 3] - point, LENGTH_SCALE * rot_error])
    return residual, np.vstack([linear, LENGTH_SCALE * rot_jac])


def _wrapped(angle: float, lower: float, upper: float) -> float:
    """`angle` moved by whole turns into [lower, upper] if it can be, else clipped to it."""
    centre = (lower + upper) / 2
    angle = centre + (angle - centre + math.pi) % (2 * math.pi) - math.pi
    return min(max(angle, lower), upper)


__all__ = ["LENGTH_SCALE", "MAX_EVALUATIONS", "RANDOM_SEEDS", "HandDownSolver", "InverseKinematics"]
