"""The arm's ready pose (`Arm.home`): hand down in front of the base, joints as central as they can be."""

from __future__ import annotations

import numpy as np

from vkgl.errors import InputError
from vkgl.robot.kinematics import Chain
from vkgl.robot.optimise import slsqp
from vkgl.robot.pose_error import ANGLE_TOL, angle_error, orientation_residual


def ready_pose(chain: Chain, robot: str) -> np.ndarray:
    """A ready pose of `chain`: hand down in front of the root, effector x along the root's x, joints central.

    The configuration closest to the middle of the joint ranges (in
    range-normalised units) whose effector frame has exactly that orientation
    and lies in the root's xz plane (height and distance free); NLopt SLSQP
    with those as constraints, from the middle of the ranges. Raises
    InputError (naming `robot`) when the arm cannot hold its hand so.
    """
    middle = (chain.lower + chain.upper) / 2
    span = chain.upper - chain.lower
    kinematics = chain.at_last_q()  # the two constraints are asked at the same points
    up = np.eye(3)

    def distance(q: np.ndarray, grad: np.ndarray) -> float:
        centre = (q - middle) / span
        if grad.size:
            grad[:] = 2.0 * centre / span
        return float(centre @ centre)

    def orientation(q: np.ndarray, grad: np.ndarray) -> float:
        pose, jac = kinematics(q)
        residual, direction = orientation_residual(pose[:3, :3], up, yaw_free=False)
        if grad.size:
            grad[:] = jac[:3].T @ direction
        # the residual is never negative: <= 0 means within 1e-10 of upright (about 1e-5 rad)
        return residual - 1e-10

    def sideways(q: np.ndarray, grad: np.ndarray) -> float:
        pose, jac = kinematics(q)
        if grad.size:
            grad[:] = jac[4]
        return float(pose[1, 3])

    found = slsqp(
        distance,
        middle,
        chain.lower,
        chain.upper,
        max_evaluations=2000,
        xtol=1e-10,
        equalities=[(sideways, 1e-9)],
        inequalities=[(orientation, 0.0)],
    )
    q = middle if found is None else found
    pose = chain.pose_and_jacobian(q)[0]
    if angle_error(pose, np.eye(4), yaw_free=False) > ANGLE_TOL:
        raise InputError(f"{robot}: the arm cannot point its effector straight down (no ready pose)")
    return q


__all__ = ["ready_pose"]
