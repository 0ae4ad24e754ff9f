"""Whether the hand's grip holds a tool through the pushes it makes with it: the planner's side of the grip model
(`vkgl.robot.grip`) the executor watches.

A push with a held tool loads the grip with the force the pushed body resists
with, at the tool's contact: that force, and its moment about the effector,
must stay within what the pads' Coulomb friction carries (`Grip.usage`), or the
tool turns or slides in the hand and the body is not pushed where the plan
says. Measured on generated tasks (a 1.62 kg crate turned with the stdlib
Stick held at its middle by a 20 N grasp): the executor saw 7.2 N and
0.15 N m at the grip, 103 % of what it carries, and the Stick slipped 7.6 mm;
the estimate here (the crate's weight times its friction, 7.9 N, at the Stick's
tip) is on the safe side of it. The estimate is quasi-static: a slide resists
with the body's whole friction on the table, a turn about a pivot with less,
so turns are judged as slides (on the safe side too). A body on a joint
resists with its joint's Coulomb friction and damping at the executor's push
speed (and its weight along a slide that is not level), at the contact's
distance from a hinge (`resistance`): a hook pulling the stdlib drawer (1.5 N,
4 N s/m) uses a few per cent of the grip, a stiff slide of 100 N is never
pushed with a held tool. A tool never holds a body by a grasp
(`graphs.graph.tool_enacts`), so every load a held tool meets is a push's.
A body the hand carries that is no tool loads the grip with its own weight at its centre of mass
(`carry_rejection`).
"""

from __future__ import annotations

import numpy as np

from vkgl.errors import InputError
from vkgl.lang.ir.geometry import body_mesh
from vkgl.lang.ir.grasps import HAND_OPENING
from vkgl.lang.ir.values import Vector
from vkgl.motion.arm_collision import Held
from vkgl.plan.geometry.grip_words import Slip, Strain, slip_advice, slip_why
from vkgl.plan.graphs.graph import Engagement, KGraph
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.hulls import kept_centre, kept_width
from vkgl.plan.problem.over import tool_parts
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.robot.grip import DEFAULT_FRICTION, GRAVITY, TOUCH_GAP, grip_for, push_load, resisting_force, tool_width
from vkgl.robot.gripper import gripper

PUSH_FACTOR = 2.0
"""How much harder than the estimate a push may load the grip: the estimate leaves out what the tool's contact
carries along the tool (friction at the contact pushes the tip up or down: a moment about the pads' normal) and
the push's dynamics, so the push's part of the load is doubled (the tool's weight is known and is not).
Measured in DART on generated tasks (`vkgc solve --execute`, the executor's peak load against the estimate with
the push's part as it is): a 20 N grasp turning a 1.62 kg crate, estimated 0.58, broke at 1.03 (1.8 times);
pushes with the stick or hook held at the handle by 70 N, estimated 0.32-0.38, peaked at 0.30-0.55."""

PEAK_RATIO = 1.68
"""The largest ratio of the executor's peak load on the grip to the estimate measured in DART (`GRIP_MARGIN`)."""

GRIP_MARGIN = 1.1 * PEAK_RATIO
"""The estimate (the larger of the tool's weight alone and the push counted `PUSH_FACTOR` times) times this must
stay within the grip. Measured with `bench/physical/bench_grip_margin.py` (18 pushes and pulls with the Stick and
the Hook
held by `wield` at 70 N or by a 20 N top grasp, bodies resisting with 1.3 to 5.7 N, moved 12 to 28 cm, carried
out in DART): the executor's peak load over the step came to 1.00 to 1.68 times the estimate (median 1.20; the
largest, the Hook wielded pulling a 0.5 kg cube at mu 0.8, `PEAK_RATIO`); the margin is that plus 10 % (1.85):
a plan uses at most 54 % of the grip by the estimate.
The weight alone counts because DART's contact with a pushed body comes and goes (the executor's median load
step sees none): a Stick held by its 20 N grasp at the handle carries its own weight at 106 % of the grip, and
every such push broke the grip, whatever the push's own moment took off the weight's (gen9_026)."""


JOINT_PUSH_SPEED = 0.05
"""m/s a contact moves at in execution (the executor's `effector_path.PUSH_SPEED`; a test holds them equal): a
damped joint resists in proportion to it."""

HINGE_LEVER = 0.01
"""m: the least lever a hinge's resistance is divided by (a contact on the hinge's line cannot turn it at all)."""


def grip_rejection(problem: Problem, graph: KGraph, trace: ModeTrace, q: np.ndarray, tool: str) -> Rejection | None:
    """Why the grip on `tool` (held by the hand at joints `q` at the start of the mode) would give way under a
    push the mode makes with it, or, a body that is no tool, under its own weight as the hand carries it
    (`carry_rejection`), or None. The rejection says which load decides (the push, or the tool's weight
    alone), against which limit, by how much, and (`Rejection.advice`) what the task's author can change."""
    robot = problem.robot_effector.name
    holding = next((e for e in graph.engaged if e.body == tool and e.effector == robot), None)
    if holding is None:
        return None
    too_wide = width_rejection(problem, tool, holding.affordance)
    if too_wide is not None:
        return too_wide
    pushes = [e for e in graph.engaged if problem.effector(e.effector).tool == tool and trace.values.get(e, 0.0) > 0.0]
    if not pushes and not _is_tool(problem, tool):
        return carry_rejection(problem, tool, holding.affordance, trace.start[tool], trace.end[tool], problem.arm.fk(q))
    for e in pushes:
        spec = problem.effector(e.effector)
        move = (holding.affordance, e, trace.start[tool], trace.end[tool], q)
        pushed, weight = _strain(problem, *move, PUSH_FACTOR), _strain(problem, *move, 0.0)
        if pushed is None or weight is None:
            continue
        worst = pushed if pushed.usage >= weight.usage else weight
        if worst.usage * GRIP_MARGIN > 1.0:
            at = (trace.start[tool] @ spec.frame)[:3, 3]
            slip = _slip(problem, holding.affordance, e, worst, weight.usage, at)
            return Rejection(
                Kind.GRIP,
                slip_why(slip, f"(DART's loads came to up to {PEAK_RATIO:.2f} times the estimate)"),
                worst.usage * GRIP_MARGIN - 1.0,
                advice=slip_advice(slip),
            )
    return None


def carry_rejection(
    problem: Problem, body: str, grasp: str, start: np.ndarray, end: np.ndarray, hand: np.ndarray
) -> Rejection | None:
    """Why the grip on `body` (held by its affordance `grasp`, the hand's effector at world pose `hand` while the
    body is at `start`) would give way under the body's own weight as the hand carries it to `end`, or None.

    The body's weight acts at its centre of mass, not at its frame's origin: an L-shaped body grasped on its long
    leg, 5 cm from its centre of mass, was planned into the hand and carried (0.6 kg, 2 x 20 N at mu 0.5: its
    weight twists the grip by 0.32 N m where the pads hold 0.13 N m); in DART the grip broke as the hand lifted
    it. The hand's tilt changes with the carry, so the load is judged where it starts and where it ends."""
    in_hand = np.linalg.inv(hand) @ start
    grip = grip_for(problem.affordance(body, grasp).action, problem.bodies[body].type.friction)
    mass = float(problem.bodies[body].type.mass.value)
    centre = _centre_of_mass(problem, body)
    worst: tuple[float, np.ndarray, np.ndarray, np.ndarray] | None = None
    for pose in (start, end):
        effector = pose @ np.linalg.inv(in_hand)
        at = (pose @ np.append(centre, 1.0))[:3]
        load, torque = push_load(effector, at, np.array([1.0, 0.0, 0.0]), 0.0, at, mass)
        usage = grip.usage(load, torque)
        if worst is None or usage > worst[0]:
            worst = (usage, load, torque, at - effector[:3, 3])
    assert worst is not None
    usage, load, torque, lever = worst
    if usage * GRIP_MARGIN <= 1.0:
        return None
    kind = problem.bodies[body].type.name
    twisted = abs(float(torque[1])) / grip.max_torque >= float(np.hypot(load[0], load[2])) / grip.max_force
    if twisted:
        what = f"twists the grip by {abs(float(torque[1])):.2f} N m about the fingers' axis, where the pads hold "
        what += f"{grip.max_torque:.2f} N m"
    else:
        what = f"loads the grip with {float(np.hypot(load[0], load[2])):.1f} N in the pads' plane, where they hold "
        what += f"{grip.max_force:.1f} N"
    return Rejection(
        Kind.GRIP,
        f"{body} would slip in the hand as it is carried: its own weight ({mass:.2f} kg, its centre of mass "
        f"{float(np.linalg.norm(lever)) * 100:.1f} cm from the fingers) {what} ({kind} held by `{grasp}`: "
        f"{grip.text()}): {usage:.0%} of the grip, {usage * GRIP_MARGIN:.1f} times the {1.0 / GRIP_MARGIN:.0%} a "
        "plan may use",
        usage * GRIP_MARGIN - 1.0,
        advice=f"for the grip to hold {body}: a grasp nearer its centre of mass, a lighter {kind} (`mass` {mass:g} "
        "kg), a grasp that presses harder (`force`), or more friction",
    )


def _is_tool(problem: Problem, body: str) -> bool:
    """Whether `body` is a tool of the problem (an effector's frame is on it): a tool's weight is judged with
    each push it makes (`_strain`)."""
    return any(spec.tool == body for spec in problem.effectors)


_CENTRES: dict[bytes, np.ndarray] = {}
"""The centres of mass found in this process, by the shape's parts' vertices."""


def _centre_of_mass(problem: Problem, body: str) -> np.ndarray:
    """`body`'s centre of mass in its frame (m): its mesh's, at a uniform density (as the world's mass
    properties, `vkgl.sim.world.mass_properties`), kept in the cache folder (`hulls.kept_centre`)."""
    body_type = problem.bodies[body].type
    points = np.concatenate([np.asarray(part, dtype=float).ravel() for part in tool_parts(body_type.shape)])
    key = points.tobytes()
    if key not in _CENTRES:
        _CENTRES[key] = kept_centre(points, lambda: np.asarray(body_mesh(body_type).center_mass, dtype=float))
    return _CENTRES[key]


def hand_opening(urdf: str) -> float:
    """m: the widest the arm's fingers open, from its URDF's finger joints (`Gripper.max_opening`), else the
    language's `HAND_OPENING` (an arm without the Panda's finger joints: E461 judged its grasps by that)."""
    try:
        return gripper(urdf).max_opening
    except InputError:
        return HAND_OPENING


def width_rejection(problem: Problem, tool: str, grasp: str) -> Rejection | None:
    """Why the fingers cannot close on `tool` where its affordance `grasp` holds it (it is wider there than the
    hand opens), or None. A grasp states its width (E461 keeps it within the hand); a tool held by a `fixed`
    action (`wield`) is measured on its mesh, and nothing else stopped a 12 cm bar being planned in the hand."""
    width = 2.0 * (_opening(problem, tool, grasp, np.linalg.inv(problem.action(tool, grasp))) - TOUCH_GAP)
    opening = hand_opening(problem.arm.urdf)
    if width <= opening + 1e-6:
        return None
    kind = problem.bodies[tool].type.name
    hand = f"{opening * 100:.0f} cm"
    return Rejection(
        Kind.GRIP,
        f"{tool} is {width * 100:.1f} cm across where `{grasp}` holds it ({kind}, along the effector frame's y, "
        f"where the fingers close), and the hand's fingers open {hand} at most: they cannot close on it",
        width - opening,
        advice=f"for the hand to hold {tool}: hold it where it is at most {hand} across (`{grasp}`'s action pose, "
        f"or a grasp of a narrower part), or a narrower {kind}",
    )


def push_usage(
    problem: Problem,
    grasp: str,
    engagement: Engagement,
    tool_start: np.ndarray,
    tool_end: np.ndarray,
    q: np.ndarray,
    factor: float = PUSH_FACTOR,
) -> tuple[float, float] | None:
    """(the fraction of its grip a push uses, the force the pushed body resists with (N)) for a push of
    `engagement` by a tool held by its affordance `grasp`, the tool moving from `tool_start` to `tool_end` (world
    poses), the arm at joints `q` at the push's start; the resisting force counted `factor` times. None when the
    tool's contact does not move."""
    strain = _strain(problem, grasp, engagement, tool_start, tool_end, q, factor)
    if strain is None:
        return None
    at = (tool_start @ problem.effector(engagement.effector).frame)[:3, 3]
    return strain.usage, resistance(problem, engagement.body, at)


def _strain(
    problem: Problem,
    grasp: str,
    engagement: Engagement,
    tool_start: np.ndarray,
    tool_end: np.ndarray,
    q: np.ndarray,
    factor: float,
) -> Strain | None:
    """`push_usage`'s load, in parts (`grip_words.Strain`); with `factor` 0 the tool's weight alone."""
    spec = problem.effector(engagement.effector)
    tool = spec.tool
    assert tool is not None
    body = problem.bodies[engagement.body]
    start = (tool_start @ spec.frame)[:3, 3]
    direction = (tool_end @ spec.frame)[:3, 3] - start
    if float(np.linalg.norm(direction)) < 1e-6:
        return None
    grip = grip_for(problem.affordance(tool, grasp).action, problem.bodies[tool].type.friction)
    force = factor * resistance(problem, body.name, start)
    tool_mass = float(problem.bodies[tool].type.mass.value)
    effector = problem.arm.fk(q)
    centre = tool_start[:3, 3]
    load, torque = push_load(effector, start, direction, force, centre, tool_mass)
    weight_alone = grip.usage(*push_load(effector, start, direction, 0.0, centre, tool_mass))
    push_alone = grip.usage(*push_load(effector, start, direction, force, centre, 0.0))
    by_weight = weight_alone >= push_alone
    return Strain(
        usage=grip.usage(load, torque),
        in_plane=float(np.hypot(load[0], load[2])),
        twist=abs(float(torque[1])),
        pushed=factor > 0.0,
        by_weight=by_weight,
        lever=float(np.linalg.norm((centre if by_weight else start) - effector[:3, 3])),
    )


def resistance(problem: Problem, body: str, at: np.ndarray) -> float:
    """N `body` resists a push at world point `at` with: on the table its weight times its friction
    (`resisting_force`); on a slide its joint's Coulomb friction, its damping at `JOINT_PUSH_SPEED` and its weight
    along the slide; on a hinge the same torques (and its weight's about a hinge that is not upright) over the
    contact's distance from the hinge's line, at least `HINGE_LEVER`."""
    placed = problem.bodies[body]
    mass = float(placed.type.mass.value)
    terms = _joint_terms(problem, body)
    if terms is None:
        return resisting_force(mass, placed.type.friction)
    friction, damping, zero, axis, through = terms
    if placed.joint == "prismatic":
        return friction + damping * JOINT_PUSH_SPEED + mass * GRAVITY * abs(float(axis[2]))
    lever = max(_hinge_lever(zero, axis, through, at), HINGE_LEVER)
    weight = mass * GRAVITY * float(np.linalg.norm(axis[:2])) * _hinge_lever(zero, axis, through, zero[:3, 3])
    return (friction + damping * JOINT_PUSH_SPEED / lever + weight) / lever


def _joint_terms(problem: Problem, body: str) -> tuple[float, float, np.ndarray, np.ndarray, Vector | None] | None:
    """A body on a joint's Coulomb friction, damping, joint-zero pose, world axis and hinge point (body frame);
    None for a body on the table."""
    placed = problem.bodies[body]
    joint = placed.type.joint
    if placed.joint is None or joint is None or placed.joint_axis is None:
        return None
    friction = 0.0 if joint.friction is None else float(joint.friction.value)
    damping = 0.0 if joint.damping is None else float(joint.damping.value)
    zero = placed.rest if placed.joint_zero is None else placed.joint_zero
    return friction, damping, zero, zero[:3, :3] @ placed.joint_axis, joint.through


def _hinge_lever(zero: np.ndarray, axis: np.ndarray, through: Vector | None, point: np.ndarray) -> float:
    """m from world `point` to the hinge's line (`axis`, world, through body point `through` at pose `zero`)."""
    on_line = zero[:3, :3] @ (np.zeros(3) if through is None else through.array()) + zero[:3, 3]
    off = np.asarray(point, dtype=float) - on_line
    return float(np.linalg.norm(off - float(off @ axis) * axis))


def _joint_words(problem: Problem, body: str, at: np.ndarray) -> str:
    """How a body on a joint resists, for `grip_words` ("" on the table)."""
    terms = _joint_terms(problem, body)
    if terms is None:
        return ""
    friction, damping, zero, axis, through = terms
    speed = f"{JOINT_PUSH_SPEED * 100:g} cm/s"
    if problem.bodies[body].joint == "prismatic":
        return f"its slide's friction {friction:g} N and damping {damping:g} N s/m at {speed}"
    lever = _hinge_lever(zero, axis, through, at)
    return (
        f"its hinge's friction {friction:g} N m and damping {damping:g} N m s/rad at {speed}, "
        f"{lever * 100:.1f} cm from the hinge"
    )


def _slip(
    problem: Problem, grasp: str, engagement: Engagement, strain: Strain, weight_usage: float, at: np.ndarray
) -> Slip:
    """The facts `grip_words` tells of a grip that would give way under `strain` (`at`: where the tool's
    contact starts)."""
    tool = problem.effector(engagement.effector).tool
    assert tool is not None
    tool_type = problem.bodies[tool].type
    body_type = problem.bodies[engagement.body].type
    action = problem.affordance(tool, grasp).action
    return Slip(
        tool=tool,
        tool_type=tool_type.name,
        tool_mass=float(tool_type.mass.value),
        tool_friction=DEFAULT_FRICTION if tool_type.friction is None else tool_type.friction,
        friction_stated=tool_type.friction is not None,
        grasp=grasp,
        stated_force=getattr(action, "force", None) is not None,
        grip=grip_for(action, tool_type.friction),
        effector=engagement.effector,
        body=engagement.body,
        body_mass=float(body_type.mass.value),
        body_friction=DEFAULT_FRICTION if body_type.friction is None else body_type.friction,
        resists=resistance(problem, engagement.body, at),
        joint=_joint_words(problem, engagement.body, at),
        factor=PUSH_FACTOR,
        strain=strain,
        weight_usage=weight_usage,
        allowed=1.0 / GRIP_MARGIN,
    )


def held(problem: Problem, tool: str, grasp: str, in_hand: np.ndarray, acts_on: frozenset[str] = frozenset()) -> Held:
    """`tool` in the hand, held by its affordance `grasp` at `in_hand` (its pose in the effector frame), for the
    arm's collision checks: with the fingers open around it as the executor closes them
    (`vkgl.robot.grip.holding_opening`). gen2_038 of the physical bench: the Hook held by its cross-piece, rolled
    over a slab to pull it; checked with the fingers closed the hand was clear of the slab, but the fingers
    closed on the 2 cm cross-piece stand 1 cm further out, and the inner one sat 6.5 mm inside the slab's top
    edge: in DART it caught the slab before the hook did and turned it 5 deg off the goal."""
    return Held(tool, in_hand, acts_on, _opening(problem, tool, grasp, in_hand))


_OPENINGS: dict[bytes, float] = {}
"""The openings found in this process, by what determines them (`held` is asked at every check with a tool)."""


def _opening(problem: Problem, tool: str, grasp: str, in_hand: np.ndarray) -> float:
    """`vkgl.robot.grip.holding_opening` of `tool` held by `grasp` at `in_hand`: the grasp's stated width, else the
    width measured on the tool's mesh, kept in the cache folder (`hulls.kept_width`), so that a solve reads it
    back without importing trimesh."""
    action = problem.affordance(tool, grasp).action
    stated = getattr(action, "width", None)
    if stated is not None:
        return float(stated) / 2 + TOUCH_GAP
    body = problem.bodies[tool].type
    grasp_frame = np.linalg.inv(in_hand)  # the effector frame in the tool's frame
    parts = np.concatenate([np.asarray(part, dtype=float).ravel() for part in tool_parts(body.shape)])
    what = np.concatenate([parts, grasp_frame.ravel()])
    key = what.tobytes()
    if key not in _OPENINGS:
        width = kept_width(what, lambda: tool_width(action, body_mesh(body), grasp_frame))
        _OPENINGS[key] = width / 2 + TOUCH_GAP
    return _OPENINGS[key]


__all__ = [
    "GRIP_MARGIN",
    "HINGE_LEVER",
    "JOINT_PUSH_SPEED",
    "PEAK_RATIO",
    "PUSH_FACTOR",
    "carry_rejection",
    "grip_rejection",
    "held",
    "push_usage",
    "resistance",
    "width_rejection",
]
