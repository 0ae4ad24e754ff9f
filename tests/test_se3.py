"""`vkgl.se3`: the screw motion between two poses, at one fraction and at many."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from vkgl.se3 import screw_motion

_angles = st.floats(-3.0, 3.0)
_offsets = st.floats(-0.5, 0.5)


def _pose(rotvec: tuple[float, float, float], at: tuple[float, float, float]) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    pose[:3, 3] = at
    return pose


@settings(max_examples=60, deadline=None)
@given(
    st.tuples(_angles, _angles, _angles),
    st.tuples(_offsets, _offsets, _offsets),
    st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(0.1, 1.0)),
    st.tuples(_offsets, _offsets, _offsets),
)
def test_the_motion_at_many_fractions_is_the_motion_at_each(start_rot, start_at, end_axis, end_at) -> None:
    start = _pose(start_rot, start_at)
    end = _pose(tuple(np.asarray(end_axis) / np.linalg.norm(end_axis) * 1.2), end_at)
    motion = screw_motion(start, end)
    fractions = np.linspace(0.0, 1.0, 9)
    along = motion.along(fractions)
    for k, s in enumerate(fractions):
        np.testing.assert_allclose(along[k], motion.at(s), atol=1e-12)
    np.testing.assert_allclose(along[-1] @ start, end, atol=1e-9)  # all of it takes the start to the end
    np.testing.assert_allclose(along[0], np.eye(4), atol=1e-12)
