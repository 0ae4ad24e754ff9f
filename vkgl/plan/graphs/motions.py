"""The motion of a body under a prismatic or revolute constraint, as matrices in its own frame.

A body at `P` moved by value `v` ends at `P @ motion_matrix(c, v)` (motions are object-centric: the constraint's
axis and centre are in the body's frame). The matrices of a path are computed in one call and remembered, since
the optimiser's finite differences move one value at a time and the other modes' motions repeat.
"""

from __future__ import annotations

import numpy as np

from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import pivot_shift
from vkgl.plan.problem.problem import Problem
from vkgl.rotations import rotvec_matrices


def motion_matrix(constraint: object, value: float) -> np.ndarray:
    """The motion of a body by `value` (m or rad) under a prismatic or revolute constraint, in its own frame."""
    return motion_matrices(constraint, np.array([value]))[0]


_MOTIONS: dict[tuple[int, bytes], tuple[object, np.ndarray]] = {}
_MOTIONS_KEPT = 4096
"""Motion matrices remembered (the optimiser's finite differences move one value at a time: the other modes'
motions repeat, and a SciPy rotation costs tens of microseconds)."""
_MOTION_PATH = 16
"""Paths up to this many values are remembered (a rollout's have 5 or 6): at most about 8 MB."""


def motion_matrices(constraint: object, values: np.ndarray) -> np.ndarray:
    """`motion_matrix` for each of `values` at once (n x 4 x 4, read-only): one scipy call for a whole path."""
    if len(values) > _MOTION_PATH:  # long scans (closed_form's 181 angles) are not kept
        m = _motion_matrices(constraint, values)
        m.flags.writeable = False
        return m
    key = (id(constraint), np.asarray(values, dtype=float).tobytes())
    cached = _MOTIONS.get(key)
    if cached is not None and cached[0] is constraint:  # the constraint is kept, so that its id stays its own
        return cached[1]
    if len(_MOTIONS) >= _MOTIONS_KEPT:
        _MOTIONS.clear()
    m = _motion_matrices(constraint, values)
    m.flags.writeable = False
    _MOTIONS[key] = (constraint, m)
    return m


def member_motions(problem: Problem, engagement: Engagement, offset: float, values: np.ndarray) -> np.ndarray:
    """`motion_matrices` of an engagement's motion at `offset` along its family (a turn's pivot moved)."""
    motion = problem.affordance(engagement.body, engagement.affordance).motion
    shift = pivot_shift(problem, engagement.body, engagement.affordance, offset)
    if shift is None:
        return motion_matrices(motion, values)
    if len(values) > _MOTION_PATH:
        return _motion_matrices(motion, values, shift)
    key = (id(motion), np.asarray(values, dtype=float).tobytes() + np.asarray(shift, dtype=float).tobytes())
    cached = _MOTIONS.get(key)  # the finite differences move one value at a time: the other modes' paths repeat
    if cached is not None and cached[0] is motion:
        return cached[1]
    if len(_MOTIONS) >= _MOTIONS_KEPT:
        _MOTIONS.clear()
    m = _motion_matrices(motion, values, shift)
    m.flags.writeable = False
    _MOTIONS[key] = (motion, m)
    return m


def _motion_matrices(constraint: object, values: np.ndarray, shift: np.ndarray | None = None) -> np.ndarray:
    axis, center = unit_axis_and_center(constraint)
    if center is not None and shift is not None:
        center = center + shift
    m = np.zeros((len(values), 4, 4))
    m[:, 3, 3] = 1.0
    if center is None:  # prismatic (or anything that does not move: axis zero)
        m[:, 0, 0] = m[:, 1, 1] = m[:, 2, 2] = 1.0
        m[:, :3, 3] = _outer(values, axis)
        return m
    rotations = rotvec_matrices(_outer(values, axis))
    m[:, :3, :3] = rotations
    m[:, :3, 3] = center - rotations @ center
    return m


def _outer(values: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """`np.outer(values, axis)`, the same products, without its dispatch (a rollout asks for it at every mode)."""
    column = np.asarray(values)
    return column[:, None] * axis if column.ndim == 1 and axis.ndim == 1 else np.outer(values, axis)


_AXES: dict[int, tuple[object, np.ndarray, np.ndarray | None]] = {}


def rest_axis(rest: np.ndarray, constraint: object) -> np.ndarray:
    """The world x, y of `constraint`'s axis (`unit_axis_and_center`) where its body rests at `rest` (4x4): the
    direction on the table a slide moves the body, not normalised (a vertical axis gives about zero)."""
    return (rest[:3, :3] @ unit_axis_and_center(constraint)[0])[:2]


def unit_axis_and_center(constraint: object) -> tuple[np.ndarray, np.ndarray | None]:
    """(unit axis, centre) of a revolute constraint, (unit axis, None) of a prismatic one, zero axis otherwise."""
    cached = _AXES.get(id(constraint))
    if cached is not None and cached[0] is constraint:
        return cached[1], cached[2]
    if isinstance(constraint, (PrismaticC, RevoluteC)):
        axis = constraint.axis.array()
        axis = axis / np.linalg.norm(axis)
    else:
        axis = np.zeros(3)
    center = constraint.center.array() if isinstance(constraint, RevoluteC) else None
    _AXES[id(constraint)] = (constraint, axis, center)  # the constraint is kept so that its id stays unique
    return axis, center
