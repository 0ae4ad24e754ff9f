"""How a trial's motion ended: still moving when the trial ended, or stopped before it.

A body pushed until the end of its trial either stopped on the way (a joint's
limit, a wall, a stall against friction: the motion has a bound there) or was
still moving when the push ended (a block sliding on the table: its explored
range is where exploration stopped, not where the motion does). The data tell
them apart: the body's speed along its motion over the last `END_WINDOW` of
the trial, against the fastest it went over any such window of the trial
(`end_ratio`). A body at its stop has an end speed of about 0; one still being
pushed has about its steady speed (docs/inference.md, "Open slides", has the
measurements behind `MOVING_RATIO`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

END_WINDOW = 0.5
"""s: the last part of a trial whose mean speed is the end speed (25 samples at 50 Hz)."""

MOVING_RATIO = 0.5
"""A motion whose end speed is at least this share of its peak speed was still moving when the trial ended."""


@dataclass(frozen=True)
class Ending:
    """The end speed and the peak speed of a motion's state (m/s or rad/s, means over `END_WINDOW`)."""

    end_speed: float
    peak_speed: float

    @property
    def ratio(self) -> float:
        """End speed over peak speed (0 for a motion that never moved)."""
        return self.end_speed / self.peak_speed if self.peak_speed > 0 else 0.0

    @property
    def moving(self) -> bool:
        """Whether the body was still moving when the trial ended (`ratio >= MOVING_RATIO`)."""
        return self.ratio >= MOVING_RATIO


def motion_ending(t: np.ndarray, states: np.ndarray) -> Ending | None:
    """The ending of a motion with `states` at times `t` (s), or None when the trial is too short to tell.

    Speeds are mean speeds over windows of `END_WINDOW` ending at each sample
    (the state `END_WINDOW` earlier interpolated between samples), so a single
    noisy sample does not decide; a trial shorter than two windows cannot
    show a steady speed and a stop, and gets None (read as a bound).
    """
    keep = np.isfinite(t) & np.isfinite(states)
    t, s = np.asarray(t, dtype=float)[keep], np.asarray(states, dtype=float)[keep]
    if len(t) < 3 or t[-1] - t[0] < 2.0 * END_WINDOW:
        return None
    later = t >= t[0] + END_WINDOW
    speeds = (s[later] - np.interp(t[later] - END_WINDOW, t, s)) / END_WINDOW
    return Ending(end_speed=max(0.0, float(speeds[-1])), peak_speed=max(0.0, float(speeds.max())))
