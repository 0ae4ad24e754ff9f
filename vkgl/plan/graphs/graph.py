"""Kinematic graphs over the scene's bodies, the robot and the world, and how the search changes them.

A graph is the set of affordances in force (`Engagement`: an effector enacting
an affordance of a target body). Its edges follow (paper §2.3):

- every body has an edge to `world`: the motion type of the affordance that
  engages it, or, when none does, `fixed` at rest (or the type of its
  physical joint, which holds it at rest until something moves it);
- the robot has a `free` edge to `world`;
- each engagement adds an edge effector -> target with the action's type
  (`fixed`; a grasp holds its body rigidly: `fixed` too): from the robot for
  its own effector, from the tool for a tool frame.

`G0` has no engagement. `successors(G)` lists the ADDs and REMOVEs that the
search may try from `G`, in a fixed order (ADDs by effector, body and
affordance in declaration order, then REMOVEs), skipping transitions that can
never be part of a first-found plan (see `successors`).
"""

from __future__ import annotations

from dataclasses import dataclass

from vkgl.lang.ir.families import tool_only
from vkgl.lang.ir.nodes import Affordance, Constraint
from vkgl.plan.graphs.carry import carriable
from vkgl.plan.problem.problem import Problem

WORLD = "world"


@dataclass(frozen=True)
class Engagement:
    """An affordance in force: `effector` (e.g. `arm.fingertip`, `stick.tip`) enacts `body`'s `affordance`."""

    effector: str
    body: str
    affordance: str


@dataclass(frozen=True)
class Action:
    """A transition of the search: ADD or REMOVE one engagement."""

    op: str  # "add" | "remove"
    engagement: Engagement

    def label(self, problem: Problem) -> str:
        """`add Block.push_center_px on block with arm.fingertip`."""
        e = self.engagement
        return f"{self.op} {problem.bodies[e.body].type.name}.{e.affordance} on {e.body} with {e.effector}"


@dataclass(frozen=True)
class KGraph:
    """A kinematic graph: the engagements in force, in the order they were added."""

    engaged: tuple[Engagement, ...] = ()

    def engaging(self, body: str) -> Engagement | None:
        """The engagement whose target is `body`, if any."""
        return next((e for e in self.engaged if e.body == body), None)

    def using(self, effector: str) -> Engagement | None:
        """The engagement that `effector` enacts, if any."""
        return next((e for e in self.engaged if e.effector == effector), None)

    def apply(self, action: Action) -> KGraph:
        """The graph after `action`."""
        if action.op == "add":
            return KGraph(self.engaged + (action.engagement,))
        return KGraph(tuple(e for e in self.engaged if e != action.engagement))


def g0() -> KGraph:
    """The start graph: the robot free, every body at rest."""
    return KGraph()


def motion_type(problem: Problem, engagement: Engagement) -> str:
    """The motion type (`fixed`, `prismatic`, `revolute`, `free`) an engagement gives its target."""
    return problem.affordance(engagement.body, engagement.affordance).motion.type


def is_grasp(problem: Problem, body: str, affordance: str) -> bool:
    """Whether an affordance is enacted by the hand's fingers closing on the body: an `action grasp`, or any
    action whose motion is `free` (a tool's `wield`, written `action fixed at ...` before grasps had their own
    action). A grasp pins the hand's whole pose (its fingers close along one axis); a push leaves its yaw free.
    A grasp whose motion is a joint's (a drawer's knob, a door's bar) moves the hand along the joint."""
    aff = problem.affordance(body, affordance)
    return aff.action.type == "grasp" or aff.motion.type == "free"


def tool_enacts(affordance: Affordance) -> bool:
    """Whether a tool frame may enact `affordance`: any but an `action grasp`. A correspondence
    (`Hook.tip ~ fingertip`) lets the tool's frame stand where the fingertip would push; a grasp is the hand's two
    fingers closing on the body, which no tool frame does. Enacted by a tip, a grasp's rigid hold is a promise
    nothing keeps: the Hook's tip at the Drawer's side grasp (its x across the bar, the drawer pulled along its
    own) was planned past a ledge and, in DART, jammed on the handle and slipped 8 mm in the hand (55 N, 19 N m:
    39 times the grip)."""
    return affordance.action.type != "grasp"


def is_held(problem: Problem, graph: KGraph, tool: str) -> bool:
    """Whether `tool` is in the robot's hand: engaged by the robot's effector with a free motion."""
    e = graph.engaging(tool)
    return e is not None and e.effector == problem.robot_effector.name and motion_type(problem, e) == "free"


def edges(problem: Problem, graph: KGraph) -> list[tuple[str, str, str]]:
    """The graph's edges `(parent, child, type)`: bodies to world, the robot to world, then the engagements."""
    out = []
    for name, body in problem.bodies.items():
        e = graph.engaging(name)
        rest = body.joint or "fixed"
        out.append((name, WORLD, motion_type(problem, e) if e is not None else rest))
    out.append((problem.robot_name, WORLD, "free"))
    for e in graph.engaged:
        owner = problem.effector(e.effector).tool or problem.robot_name
        action = problem.affordance(e.body, e.affordance).action.type
        out.append((owner, e.body, "fixed" if action == "grasp" else action))  # a grasp holds the body rigidly
    return out


def successors(problem: Problem, graph: KGraph, last: Action | None) -> list[Action]:
    """The transitions the search tries from `graph` (reached by `last`), in a fixed order.

    ADD (effector, body, affordance) when:
    - the effector enacts nothing else (one contact per effector) and the body
      is engaged by nothing else (at most one motion edge per body);
    - a tool effector only while the tool is held, only for motions other than
      `free` and actions other than `grasp` (grasping needs the hand: `tool_enacts`)
      and never on the tool itself;
    - a body with a physical joint only by an affordance of the joint's type;
    - not the very engagement `last` removed (ADD x, REMOVE x, ADD x moves
      nothing that ADD x alone cannot: the two motions compose), unless x's
      motion has a `range`: then one mode may not move it that far, and a
      longer motion is several contacts in a row.
    REMOVE an engagement when no tool frame of the target acts (a tool in use
    stays in the hand), and not a grasp of a tool just added (picking a tool
    up and putting it back down changes nothing); a grasp of any other free
    body may be let go of at once: pick and place, the body carried in between
    and set down where task space decides (`vkgl.plan.graphs.carry`).
    """
    out = []
    for effector in problem.effectors:
        if graph.using(effector.name) is not None:
            continue
        if effector.tool is not None and not is_held(problem, graph, effector.tool):
            continue
        for name, body in problem.bodies.items():
            if graph.engaging(name) is not None or name == effector.tool:
                continue
            for aff in body.affordances:
                action = Action("add", Engagement(effector.name, name, aff.name))
                if tool_only(aff.name) and (aff.name, effector.name) not in body.tool_members:
                    continue  # a tool rolled over the body, or its flat face off the centre: that tool's alone
                if effector.tool is not None and not tool_enacts(aff):
                    continue
                if _may_add(problem, effector.tool, body.joint, aff.motion, action, last):
                    out.append(action)
    for e in graph.engaged:
        if _tool_busy(problem, graph, e.body):
            continue
        just_grasped = last is not None and last.op == "add" and last.engagement == e
        if just_grasped and motion_type(problem, e) == "free" and not carriable(problem, e.body):
            continue
        out.append(Action("remove", e))
    return out


def _may_add(
    problem: Problem, tool: str | None, joint: str | None, motion: Constraint, action: Action, last: Action | None
) -> bool:
    if tool is not None and motion.type == "free":
        return False
    if joint is not None and motion.type != joint:
        return False
    if getattr(motion, "range", None) is not None:
        return True  # bounded: again after a break is how a motion goes past its range
    return not (last is not None and last.op == "remove" and last.engagement == action.engagement)


def _tool_busy(problem: Problem, graph: KGraph, body: str) -> bool:
    """Whether a frame of `body` (as a tool) enacts an engagement now."""
    return any(problem.effector(e.effector).tool == body for e in graph.engaged)
