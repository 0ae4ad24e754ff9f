"""An independent check of a plan's contact chains (`vkg-plan/8` `steps[k].contact`): the contact is rigid.

A chain lists the arm's joints at evenly spaced fractions s_i = i / (n - 1) of
a contact's motion, `q_start` first and `q_end` last. While the arm pushes
(or pulls, or turns) a body, the hand does not slide over it: the hand's pose
in the moving body's frame stays what it was at the start. Here the hand comes
from forward kinematics of each entry (DART loading the plan's URDF, with the
base and effector offset the plan states) and the body's pose at s_i from the
step's affordance, moved by s_i times the step's value (scipy for the
rotations); nothing of the planner is used. Consecutive entries must not jump
either (an IK branch switch in the middle of a contact).

    problems = check_contact_chains(program, plan.to_json())   # [] when every chain holds
    drifts = chain_drifts(program, plan.to_json())             # what the plan achieves, per chain
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.lang.ir.program import Program

CHAIN_POSITION_TOL = 0.002
"""m: the hand stays this close to where it held the body at the start of the contact, in the body's frame (the
replay's `HAND_TOL` at q_start and q_end). The planner's chains keep it within 0.14 mm: the nine example tasks,
the generated tasks of tests/bench, the crates of tests/scenarios/goals/test_tall_bodies.py and the long stick."""
CHAIN_ANGLE_TOL = float(np.radians(1.0))
"""rad: and turned this little against it (the replay's `AXIS_TOL`; the planner's chains: under 0.9 mrad)."""
CHAIN_JOINT_STEP = 0.2
"""rad: no joint moves more than this from one chain entry to the next. Entries are about 1 cm of hand travel
apart and the planner's chains move a joint by at most 0.087 rad between them (task e's 45 cm stick push; most
stay under 0.05 rad); a switch of IK branch moves joints by a large fraction of a radian."""
ENDS_TOL = 1e-9  # rad: the chain starts on q_start and ends on q_end


class DartFK:
    """Forward kinematics of the plan's robot: DART loads the URDF; base and offset as the plan states."""

    def __init__(self, robot: dict[str, Any]) -> None:
        import dartpy as dart

        loader = dart.utils.DartLoader()
        options = dart.utils.DartLoaderOptions()
        options.mDefaultRootJointType = dart.utils.DartLoaderRootJointType.FIXED
        loader.setOptions(options)
        self.skeleton = loader.parseSkeleton(robot["urdf"])
        self.link = self.skeleton.getBodyNode(robot["effector_link"])
        self.joints = [self.skeleton.getJoint(name) for name in robot["joints"]]
        self.base = np.array(robot["base"])
        self.offset = np.array(robot["effector_offset"])
        self.lower = np.array([j.getPositionLowerLimit(0) for j in self.joints])
        self.upper = np.array([j.getPositionUpperLimit(0) for j in self.joints])

    def __call__(self, q: list[float]) -> np.ndarray:
        for joint, value in zip(self.joints, q):
            joint.setPosition(0, value)
        return self.base @ self.link.getWorldTransform().matrix() @ self.offset


def motion(constraint: Any, value: float) -> np.ndarray:
    """The affordance's motion by `value`, in the body's frame, composed independently of the planner."""
    m = np.eye(4)
    axis = np.asarray(constraint.axis.values, dtype=float)
    axis /= np.linalg.norm(axis)
    if isinstance(constraint, PrismaticC):
        m[:3, 3] = value * axis
    elif isinstance(constraint, RevoluteC):
        rotation = Rotation.from_rotvec(value * axis).as_matrix()
        center = np.asarray(constraint.center.values, dtype=float)
        m[:3, :3] = rotation
        m[:3, 3] = center - rotation @ center
    return m


@dataclass(frozen=True)
class ChainDrift:
    """How far one step's chain strays from a rigid contact: the worst entry, and the largest joint step."""

    step: int  # 1-based, as the problems name it
    entries: int
    position: float  # m, the hand's largest distance from its start pose in the body's frame
    angle: float  # rad, its largest turn against it
    joint_step: float  # rad, the largest change of one joint between consecutive entries


def chain_drifts(program: Program, plan_json: dict[str, Any], fk: DartFK | None = None) -> list[ChainDrift]:
    """The drift of every step's contact chain of 2 or more entries (steps without one left out)."""
    plan = json.loads(json.dumps(plan_json))  # only what survives JSON
    fk = fk or DartFK(plan["robot"])
    return [_drift(program, k, step, fk) for k, step in enumerate(plan["steps"], start=1) if len(step["contact"]) >= 2]


def _drift(program: Program, k: int, step: dict[str, Any], fk: DartFK) -> ChainDrift:
    """Step `k`'s chain against its body's motion: the body at s_i is its start pose moved by the affordance's
    motion by s_i times the step's value; the hand at s_i is FK of the chain's entry i."""
    chain = np.array(step["contact"], dtype=float)
    type_name, _, aff_name = step["affordance"].partition(".")
    aff = find_member(program.affordances[type_name], aff_name)  # a family's member too (`turn@+3.12cm`)
    assert aff is not None, f"step {k}: no affordance {step['affordance']}"
    start = np.array(step["poses_start"][step["body"]], dtype=float)
    fractions = np.linspace(0.0, 1.0, len(chain))
    relative = [
        np.linalg.inv(start @ motion(aff.motion, s * step["value"])) @ fk(list(q)) for s, q in zip(fractions, chain)
    ]
    position = max(float(np.linalg.norm(r[:3, 3] - relative[0][:3, 3])) for r in relative)
    angle = max(float(Rotation.from_matrix(relative[0][:3, :3].T @ r[:3, :3]).magnitude()) for r in relative)
    return ChainDrift(k, len(chain), position, angle, float(np.abs(np.diff(chain, axis=0)).max()))


def check_contact_chains(
    program: Program,
    plan_json: dict[str, Any],
    fk: DartFK | None = None,
    *,
    position_tol: float = CHAIN_POSITION_TOL,
    angle_tol: float = CHAIN_ANGLE_TOL,
    joint_step: float = CHAIN_JOINT_STEP,
) -> list[str]:
    """Every way the plan's contact chains break a rigid contact (see the module docstring); empty when none.

    A step that moves a body by contact (an ADD with a prismatic or revolute motion and a value above 0) has a
    chain; no other step has one.
    """
    plan = json.loads(json.dumps(plan_json))
    fk = fk or DartFK(plan["robot"])
    problems: list[str] = []
    for k, step in enumerate(plan["steps"], start=1):
        chain = np.array(step["contact"], dtype=float)
        moves = step["op"] == "add" and step["motion"] in ("prismatic", "revolute") and step["value"] > 0
        if len(chain) == 0:
            if moves:
                problems.append(f"step {k}: a contact motion without a contact chain")
            continue
        if not moves or len(chain) < 2:
            problems.append(f"step {k}: a contact chain of {len(chain)} entries on a step that moves nothing")
            continue
        if np.abs(chain[0] - np.array(step["q_start"])).max() > ENDS_TOL:
            problems.append(f"step {k}: the contact chain does not start on q_start")
        if np.abs(chain[-1] - np.array(step["q_end"])).max() > ENDS_TOL:
            problems.append(f"step {k}: the contact chain does not end on q_end")
        if np.any(chain < fk.lower - 1e-9) or np.any(chain > fk.upper + 1e-9):
            problems.append(f"step {k}: contact chain joints outside the URDF limits")
        drift = _drift(program, k, step, fk)
        if drift.position > position_tol:
            problems.append(
                f"step {k}: the hand slides {drift.position * 1000:.1f} mm over {step['body']} along the chain"
            )
        if drift.angle > angle_tol:
            problems.append(
                f"step {k}: the hand turns {np.degrees(drift.angle):.1f} deg against {step['body']} along the chain"
            )
        if drift.joint_step > joint_step:
            problems.append(f"step {k}: a joint jumps {drift.joint_step:.2f} rad between chain entries")
    return problems
