"""What grasp trials hand to inference: the candidates tried and, per trial, how far the body slipped.

`vkgc learn` tries a body's grasp candidates in DART (`vkgl.sim.grasp`) and
keeps those that held (`vkgl.infer.grasps.kept`); these records are what passes
between the two (in memory: no file format), and what `vkgl.infer.grasps.kept`
states in the learned module's `evidence ... slip`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class GraspCandidate:
    """A grasp to try: `pose` (4x4, the effector frame in the body frame), `width` (m across the pads), the
    `opening` the hand starts with (m), its `approach` (`top` or `side`) and a `name` that says where it is
    (`grasp_top_y`: from above, closing along the body's y; `grasp_side_px_z`: from the +x side, closing
    along z; `_p2`: on the body's part 2)."""

    name: str
    pose: np.ndarray
    width: float
    opening: float
    approach: str


@dataclass(frozen=True)
class GraspTrial:
    """One trial of candidate `candidate` (an index): `blocked` when the open hand had no room there (it
    overlapped the body or the table: not run), else `slip` (m, the most the body moved relative to the hand
    after the fingers closed) and `moved` (m, how far the body went along the lift or pull)."""

    candidate: int
    blocked: bool = False
    slip: float = float("nan")
    moved: float = 0.0


@dataclass
class GraspTrials:
    """The grasp trials of one body: the `force` (N) and `lift` (m) they used, the `candidates`, the `trials`."""

    body: str
    force: float
    lift: float
    candidates: list[GraspCandidate] = field(default_factory=list)
    trials: list[GraspTrial] = field(default_factory=list)

    def of(self, index: int) -> list[GraspTrial]:
        """The trials of candidate `index`, in the order they ran."""
        return [t for t in self.trials if t.candidate == index]


__all__ = ["GraspCandidate", "GraspTrial", "GraspTrials"]
