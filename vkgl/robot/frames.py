"""The effector frame convention (docs/language.md): one definition of Rx(180 deg).

A hand's approach axis (its link's z) points down at the table, while an
effector frame's z axis points up, so that "hand-down" poses are plain yaw
rotations. The effector frame is therefore `offset * Rx(180 deg)` in its link's
frame.
"""

from __future__ import annotations

import numpy as np


def rx_pi() -> np.ndarray:
    """Rotation by 180 deg about x (4x4, a fresh array): turns a link's approach axis (z down) into z up.

    Written out exactly (no 1e-16 residues from cos/sin of pi) so that poses
    composed with it stay bit-for-bit reproducible.
    """
    return np.diag([1.0, -1.0, -1.0, 1.0])


__all__ = ["rx_pi"]
