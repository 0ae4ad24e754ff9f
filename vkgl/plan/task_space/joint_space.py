"""Is a feasible task-space solution feasible in joint space? (Paper §2.3, step 2.)

Inverse kinematics of the arm (NLopt over the URDF's joints, DART forward
kinematics, `Arm.ik`) at the start and end of every mode and at
`JOINT_SAMPLES` points along each motion (`vkgl.plan.task_space.feasible`),
each run warm-started from the previous solution so that the arm moves
continuously.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.feasible import Counters, TaskSolution


@dataclass
class JointSolution:
    """Joint configurations of the arm at the start and end of every mode (None while nothing pins the hand)."""

    q_start: list[np.ndarray]
    q_end: list[np.ndarray]
    ik_calls: int


def joint_space(
    problem: Problem,
    solution: TaskSolution,
    deadline: float,
    counters: Counters | None = None,
    *,
    pin_yaw: bool = False,
) -> JointSolution | Rejection:
    """IK for every hand pose of the rollout, in order, each warm-started from the one before.

    A fingertip's yaw about its push direction is free (the round fingertip pushes the same at any yaw);
    with `pin_yaw` it is the action frame's, as the arm's paths pin it (`vkgl.plan.arm.paths`): the
    hand then lies along the face it pushes, not across it (the search asks for that when the hand at
    a free yaw hits something, such as the cabinet around a drawer's handle).
    """
    arm = problem.arm
    q = arm.home.copy()
    q_start: list[np.ndarray] = []
    q_end: list[np.ndarray] = []
    calls = 0
    for k, trace in enumerate(solution.traces):
        path = []
        for pose in trace.hand:
            if time.perf_counter() > deadline:
                return Rejection(Kind.TIMEOUT, "ran out of time in inverse kinematics")
            calls += 1
            if counters is not None:
                counters.ik_calls += 1
            found = arm.ik(pose, q0=q, yaw_free=trace.yaw_free and not pin_yaw)
            if found is None:
                where = f"({pose[0, 3]:.3f}, {pose[1, 3]:.3f}, {pose[2, 3]:.3f}) m"
                return Rejection(Kind.IK, f"no joint configuration puts the hand at {where} in mode {k}")
            q = found
            path.append(q)
        q_start.append(path[0] if path else q)
        q_end.append(q)
    return JointSolution(q_start, q_end, calls)


__all__ = ["JointSolution", "joint_space"]
