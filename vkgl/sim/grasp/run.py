"""All the grasp trials of a body: its candidates (`vkgl.sim.grasp.candidates`), each tried `trials` times
(`vkgl.sim.grasp.trial`), the hand a little off its aim after the first trial.

Candidates on a part that holds a frame of the body (a handle, a knob) come
XX
the same body and seed give the same trials. A candidate whose first trial
finds no room for the hand is not tried again, nor is one once a trial of it
slipped past the policy's `slip` (it will not be kept: the rest would cost
time and tell nothing).
"""

from __future__ import annotations

import numpy as np

from vkgl.formats.grasp_trials import GraspTrials
from vkgl.lang.ir.grasps import GraspSettings
from vkgl.lang.ir.nodes import Body
from vkgl.resources import stdlib_dir
from vkgl.robot.gripper import gripper
from vkgl.sim.grasp.candidates import grasp_candidates
from vkgl.sim.grasp.trial import run_grasp_trial

MAX_GRASPS = 4
"""Candidates are tried in order until this many have held in all their trials (the rest are not tried:
a few grasps give the planner its choices; each trial costs half a second)."""
AIM_ERROR = 0.002
"""m: after the first trial, the hand lands up to this far off its aim, along the effector frame's x and z
(across the pads and along the fingers; along y, the closing fingers centre themselves)."""


def panda_urdf() -> str:
    """The URDF whose gripper the grasps are learned for: the stdlib Panda's."""
    return str(stdlib_dir() / "robots" / "panda.urdf")


def try_grasps(body: Body, seed: int = 0, urdf: str | None = None) -> GraspTrials:
    """Every grasp trial of `body` under its `explore grasps` policy (defaults without one)."""
    settings = GraspSettings.of(body.grasps)
    hand = gripper(urdf or panda_urdf())
    found = GraspTrials(body=body.name, force=settings.force, lift=settings.lift)
    if not settings.approaches:
        return found
    found.candidates = grasp_candidates(body, hand, settings)
    held = 0
    for index, candidate in enumerate(found.candidates):
        if held >= MAX_GRASPS:
            break
        for k in range(settings.trials):
            offset = _offset(seed, index, k)
            trial = run_grasp_trial(body, hand, candidate, index, settings.force, settings.lift, offset, settings.slip)
            found.trials.append(trial)
            if trial.blocked or not trial.slip <= settings.slip:
                break
        else:
            held += 1
    return found


def _offset(seed: int, index: int, k: int) -> np.ndarray:
    """Where the hand lands relative to its aim in trial `k` of candidate `index` (effector frame, m)."""
    if k == 0:
        return np.zeros(3)
    rng = np.random.default_rng([seed, index, k])
    x, z = rng.uniform(-AIM_ERROR, AIM_ERROR, size=2)
    return np.array([x, 0.0, z])


__all__ = ["AIM_ERROR", "MAX_GRASPS", "panda_urdf", "try_grasps"]
