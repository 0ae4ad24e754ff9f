"""Which grasps a body keeps: the candidates that held in every one of their trials, as affordances.

A candidate is kept when it ran all the policy's trials (the open hand had
room) and in each the body slipped in the hand by at most the policy's `slip`
(`vkgl.lang.ir.grasps.GraspSettings`). Its affordance says

    action grasp at POSE width W force F    # the candidate's effector frame, the width across the pads
    motion free                             # a free body rides in the hand, or the body's joint:
                                            # `prismatic along ... range 0 to L`, `revolute about ...`
    evidence trials N loglik 0 posterior 1 slip S

`posterior` is the fraction of the trials that held (1: all did, as a kept
grasp's must), `loglik` 0 (no model is fitted: the trial is the test), `slip`
the largest slip of its trials, to 0.1 mm. The joint's motion is the sense the
trial pulled (its coordinate growing from the lower limit) over the joint's
whole range: the hand follows the joint.
"""

from __future__ import annotations

import warnings

import numpy as np

from vkgl.formats.grasp_trials import GraspCandidate, GraspTrials
from vkgl.infer.affordances import _si, direction_ir, point_ir, pose_ir, range_ir
from vkgl.lang.ir.grasps import GraspSettings
from vkgl.lang.ir.nodes import Affordance, Body, Constraint, Evidence, FreeC, GraspC, PrismaticC, RevoluteC


def kept_grasps(body: Body, trials: GraspTrials) -> list[Affordance]:
    """The affordances of the grasps of `body` that held in all their trials, in the candidates' order."""
    settings = GraspSettings.of(body.grasps)
    kept = []
    for index, candidate in enumerate(trials.candidates):
        runs = trials.of(index)
        if len(runs) < settings.trials or any(r.blocked or not r.slip <= settings.slip for r in runs):
            continue
        slip = max(r.slip for r in runs)
        evidence = Evidence(
            trials=len(runs), loglik=0.0, posterior=1.0, slip=_si(1000.0 * slip, 1, "mm"), slip_unit="mm"
        )
        action = grasp_ir(candidate, trials.force)
        kept.append(Affordance(name=candidate.name, action=action, motion=held_motion(body), evidence=evidence))
    return kept


def grasp_ir(candidate: GraspCandidate, force: float) -> GraspC:
    """`grasp at POSE width W force F`: the pose to 0.01 cm and 0.1 deg, the width to 0.01 cm, the force to 0.1 N."""
    with warnings.catch_warnings():  # a hand level from the side is an rpy at pitch +-90 deg: any split is exact
        warnings.simplefilter("ignore", UserWarning)
        pose = pose_ir(candidate.pose)
    return GraspC(
        pose=pose,
        width=_si(100.0 * candidate.width, 2, "cm"),
        width_unit="cm",
        force=_si(force, 1, "N"),
        force_unit="N",
    )


def held_motion(body: Body) -> Constraint:
    """How a held body moves: `free`, or along its joint, opening over the joint's whole range."""
    joint = body.joint
    if joint is None:
        return FreeC()
    axis = joint.axis.array() / np.linalg.norm(joint.axis.array())
    through = joint.through.array() if joint.through is not None else np.zeros(3)
    span = (0.0, float(joint.upper.value - joint.lower.value))
    if joint.type == "prismatic":
        return PrismaticC(axis=direction_ir(axis), origin=point_ir(through), range=range_ir(span, "cm"))
    return RevoluteC(center=point_ir(through), axis=direction_ir(axis), range=range_ir(span, "deg"))


__all__ = ["grasp_ir", "held_motion", "kept_grasps"]
