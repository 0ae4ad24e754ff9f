"""Collision geometry in feasibility: a candidate sequence is a plan only if no body passes through another.

Checked for every sequence that task space accepted (`bodies`), and again
for the arm once joint space found its configurations (`arm`):

- every moved body swept along its motion against every body the mode keeps
  still (`vkgl.plan.geometry.sweep`: no 5 mm overlap slips between samples), a tool
  pushing or pulling a body moving with it, its whole shape checked;
- no body a keep-out region of the task applies to entering it along its motion
  (`vkgl.plan.geometry.keep_out`);
- every mode's start and end poses free of overlap (a tool and the body it
  acts on may touch, by no more than the tool's thickness: `_tool_through`;
  a released tool must land clear of the others), and a tool's parts beside
  its contact (a hook's shaft) `BESIDE_CLEARANCE` clear of the body it acts on
  (`vkgl.plan.geometry.tool_parts`), and the tool `BYSTANDER_CLEARANCE` clear of
  every other body there and along the mode's motion (a tool touching a bystander drags it);
- the arm's links at the configurations inverse kinematics returned, and a
  held tool in its hand, against the bodies and the table (the body the hand
  touches excepted).

The collision world (`vkgl.motion.collision`, DART's FCL) is built once per
problem, on first use.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from vkgl.motion.arm_collision import ArmCollision, Held
from vkgl.motion.collision import TOUCH_TOL, CollisionScene, Contact, pair
from vkgl.plan.geometry.grip_load import grip_rejection
from vkgl.plan.geometry.grip_load import held as held_tool
from vkgl.plan.geometry.keep_out import keep_out_rejection
from vkgl.plan.geometry.sweep import sweep_mode
from vkgl.plan.geometry.tool_parts import BESIDE_CLEARANCE, BesideParts
from vkgl.plan.graphs.graph import Engagement, KGraph
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem, collision_scene
from vkgl.plan.problem.rejection import Kind, Rejection

TRANSIT_CLEARANCE = 0.01
"""m: a transit of the bare arm keeps it at least this far from every body (the physics' contacts have margins,
and the bodies are not exactly where the plan has them)."""

HELD_TRANSIT_CLEARANCE = 0.003
"""m: with a tool in the hand the bodies are grown by this for transits, but for the tool itself and the body the
transit leads to (the tool works close to it: the hook's stand-off 1 cm from the Block it is to pull in task c;
that body is grown by `TARGET_CLEARANCE`),
so that, less the 1 mm tolerance of a touch, the tool and the links keep 2 mm from every other body; no more: a
tool's stand-off may be tight beside another body (the hook from the side of a Drawer's bar, 3 mm below a ledge:
tests/scenarios/tools/test_side_approach.py). Such transits are checked every `HELD_TOLERANCE` of travel
(`vkgl.motion.transit_segment`), so the line between two samples 2 mm clear stays clear, and execution fails a
transit on any touch. With the exact geometry (and its tolerance) gen3_027's hook ended its transit 1 mm into the
corner of a Block beside its next contact. The arm's paths try a held tool's transit with the body it goes to grown
too (`transit_space(held)`), and this tighter space only when that way is blocked: a hook swinging over a 25 cm crate
it was to pull passed 2 mm over its top and touched it in DART."""

TARGET_CLEARANCE = 0.002
"""m: in that tighter space the body the transit leads to is grown by this (less the 1 mm tolerance of a touch:
the tool keeps 1 mm from it), and so is it where the approach's stand-off is checked: with its exact shape a
touch within the tolerance passed, and a hook whose stand-off lay 0.06 mm inside a turned crate it was to pull
ended its transit touching it in DART."""


BYSTANDER_CLEARANCE = HELD_TRANSIT_CLEARANCE
"""m: a tool at a contact keeps this far (less the 1 mm tolerance of a touch) from every body but the one it acts on,
at the start and the end of the contact's mode and all along its motion (`GeometryCheck._bystander_sweep`).
Touching is not enough room there: the tool and what it acts on move together, the tool driven by the arm, and a
tool resting on a bystander drags it. gen9_015 of the physical bench: the Hook, pulling a 12 cm cube at its
mid-height, lay with its underside on the top of a 5 cm slab beside the cube (0 mm apart, a touch); in DART the
slab was dragged 3.5 cm and the Hook turned 6 deg in the hand. The same room as a held tool's transit keeps from
the bodies it does not go to (`HELD_TRANSIT_CLEARANCE`)."""

BYSTANDER_STEP = 0.003
"""m: the largest displacement of any point of a tool between two samples of its sweep against the bystanders
(`vkgl.plan.geometry.sweep`). A touch between two samples lies within half of it of the nearer one, where the
tool is then at most that far from the bystander: inside it grown by `BYSTANDER_CLEARANCE` by at least
`BYSTANDER_CLEARANCE - BYSTANDER_STEP / 2` (1.5 mm), more than a touch's tolerance, so no touch slips through.
The exact sweep's 6 mm step lets a 5 mm overlap slip."""

assert BYSTANDER_CLEARANCE - BYSTANDER_STEP / 2 > TOUCH_TOL, "a touch must not slip between a tool's samples"


class GeometryCheck:
    """The collision checks of one planning problem (built lazily: most sequences never get this far)."""

    def __init__(self, problem: Problem) -> None:
        """Checks for `problem`'s bodies, table and arm."""
        self.problem = problem
        self.names = frozenset(problem.bodies)  # the problem's bodies: those a rejection may name (`Rejection.bodies`)
        self._scene: CollisionScene | None = None
        self._arm: ArmCollision | None = None
        self._transit: ArmCollision | None = None
        self._held_transit: dict[tuple[str, str | None], ArmCollision] = {}
        self._thicknesses: dict[str, float] = {}
        self._palm: ArmCollision | None = None
        self.beside = BesideParts(problem)
        self._bystanders: dict[str, CollisionScene] = {}
        self.queries = 0

    @property
    def scene(self) -> CollisionScene:
        """The bodies and the table as FCL objects."""
        if self._scene is None:
            self._scene = collision_scene(self.problem)
        return self._scene

    @property
    def transit_collision(self) -> ArmCollision:
        """The arm against the bodies grown by `TRANSIT_CLEARANCE`: free space for transits, with room to spare."""
        if self._transit is None:
            grown = collision_scene(self.problem, margin=TRANSIT_CLEARANCE)
            self._transit = ArmCollision(grown, self.problem.arm)
        return self._transit

    def transit_space(self, held: Held | None, toward: str | None = None) -> ArmCollision:
        """What the configurations of a transit to a contact with `toward` must be free in: `transit_collision`
        for the bare arm; with a held tool, the bodies grown by `HELD_TRANSIT_CLEARANCE`, but the tool (exact)
        and `toward` (grown by `TARGET_CLEARANCE`)."""
        if held is None:
            return self.transit_collision
        key = (held.body, toward)
        if key not in self._held_transit:
            close = {toward: TARGET_CLEARANCE} if toward is not None else None
            grown = collision_scene(self.problem, margin=HELD_TRANSIT_CLEARANCE, exact={held.body}, margins=close)
            self._held_transit[key] = ArmCollision(grown, self.problem.arm)
        return self._held_transit[key]

    @property
    def palm_collision(self) -> ArmCollision:
        """The arm's links but the gripper's fingers against the scene: a grasp's hand checked against the body
        its fingers close on (they may touch it; the palm and the rest may not)."""
        if self._palm is None:
            self._palm = ArmCollision(self.scene, self.problem.arm, skip_links=self.arm_collision.finger_links)
        return self._palm

    @property
    def arm_collision(self) -> ArmCollision:
        """The arm's link geometry against the scene."""
        if self._arm is None:
            self._arm = ArmCollision(self.scene, self.problem.arm)
        return self._arm

    def bodies(self, graphs: Iterable[KGraph], traces: list[ModeTrace]) -> Rejection | None:
        """Why the bodies of a rollout would pass through one another, or None when they do not."""
        for k, (graph, trace) in enumerate(zip(graphs, traces, strict=True)):
            allowed = self._tool_pairs(graph)
            self.queries += 1
            found = sweep_mode(self.scene, self.problem, trace, allowed)
            if found:
                return _rejection(
                    found, f"in mode {k}, {_moving(self.problem, graph, trace)}", self.names, placed=False
                )
            kept_out = keep_out_rejection(self.problem, trace, f"in mode {k}, {_moving(self.problem, graph, trace)}")
            if kept_out is not None:
                return kept_out
            for when, poses in (("start", trace.start), ("end", trace.end)):
                self.queries += 1
                found = self.scene.overlap(poses, ignore=allowed)
                if found:
                    return _rejection(found, f"at the {when} of mode {k}", self.names)
            through = self._tool_through(graph, trace.start)
            if through is not None:
                where = f"at the start of mode {k} (a tool touches what it acts on at its tip only)"
                return _rejection([through], where, self.names)
            beside = self._beside(graph, trace.start, k)
            if beside is not None:
                return beside
            for when, poses in (("start", trace.start), ("end", trace.end)):
                close = self._bystander(graph, poses)
                if close is not None:
                    return _bystander_rejection(close, f"at the {when} of mode {k}", self.names)
            passing = self._bystander_sweep(graph, trace)
            if passing is not None:
                where = f"in mode {k}, {_moving(self.problem, graph, trace)}"
                return _bystander_rejection(passing, where, self.names, placed=False)
        return None

    def _bystander_sweep(self, graph: KGraph, trace: ModeTrace) -> Contact | None:
        """The first overlap, along the mode's motion, of a tool that moves with the body it acts on with a body
        it does not act on, grown by `BYSTANDER_CLEARANCE` (sampled every `BYSTANDER_STEP`), or None. The exact
        sweep lets a tool slide over a bystander touching it (within the 1 mm of a touch): gen3_017 of the
        physical bench, the Stick turning a 6 cm slab at its mid-height, its underside 3 cm up, passed with
        0 mm to spare over the 2 cm high Hook lying beside, and in DART dragged it 9.8 cm."""
        for tool in self._tools(graph):
            self.queries += 1
            # the table is not grown (`collision_scene`): the exact sweep checked the tool against it
            scene = self._bystander_scene(tool)
            found = sweep_mode(scene, self.problem, trace, step=BYSTANDER_STEP, only={tool}, table=False)
            if found:
                return max(found, key=lambda c: c.depth)
        return None

    def _bystander_scene(self, tool: str) -> CollisionScene:
        """The bodies grown by `BYSTANDER_CLEARANCE`, but `tool` (exact), made when first asked."""
        if tool not in self._bystanders:
            self._bystanders[tool] = collision_scene(self.problem, margin=BYSTANDER_CLEARANCE, exact={tool})
        return self._bystanders[tool]

    def _tools(self, graph: KGraph) -> list[str]:
        """The tools that act on a body in `graph`, each once."""
        tools = (self.problem.effector(e.effector).tool for e in graph.engaged)
        return list(dict.fromkeys(tool for tool in tools if tool is not None))

    def _bystander(self, graph: KGraph, poses: dict[str, np.ndarray]) -> Contact | None:
        """The deepest overlap of a tool at its contact with a body it does not act on, grown by
        `BYSTANDER_CLEARANCE`, or None (the table is not grown: a tool pushes a low body just above it)."""
        for e in graph.engaged:
            tool = self.problem.effector(e.effector).tool
            if tool is None:
                continue
            acted_on = {x.body for x in graph.engaged if self.problem.effector(x.effector).tool == tool}
            others = [name for name in poses if name != tool and name not in acted_on]
            if not others:
                continue
            scene = self._bystander_scene(tool)
            scene.place({name: poses[name] for name in others})
            self.queries += 1
            found = scene.against(tool, poses[tool], others)
            deepest = max(found, key=lambda c: c.depth, default=None)
            if deepest is not None:
                return deepest
        return None

    def _tool_through(self, graph: KGraph, poses: dict[str, np.ndarray]) -> Contact | None:
        """The overlap of a tool with the body it acts on deeper than the tool's thickness, or None.

        At a contact the tool's frame lies on the body's face, so the tool overlaps it by at most its own
        thickness (its part's half width where the frame sits at the part's centre: the Stick's and Hook's
        tips, 1 cm; the Hook behind the Drawer's round bar, 1.4 cm); deeper, another part of the tool (a
        hook's shaft) passes through the body, which the arm's approach would find only after joint space.
        Checked at the mode's start: the tool and the body move together through the mode."""
        acting = [(tool, e.body) for e in graph.engaged if (tool := self.problem.effector(e.effector).tool)]
        if not acting:
            return None
        self.scene.place(poses)
        for tool, body in acting:
            self.queries += 1
            found = self.scene.collide(self.scene.group([tool]), self.scene.group([body]))
            deepest = max(found, key=lambda c: c.depth, default=None)
            if deepest is not None and deepest.depth > self._thickness(tool):
                return deepest
        return None

    def _beside(self, graph: KGraph, poses: dict[str, np.ndarray], k: int) -> Rejection | None:
        """Why a tool's part beside its contact (a hook's shaft) stands too close to the body the tool acts on at
        the start of mode `k` (`vkgl.plan.geometry.tool_parts`), or None."""
        for e in graph.engaged:
            effector = self.problem.effector(e.effector)
            if effector.tool is None:
                continue
            self.queries += 1
            found = self.beside.overlap(effector, e.body, poses)
            if found is not None:
                gap = BESIDE_CLEARANCE + TOUCH_TOL - found.depth  # the part's distance from the body (m)
                at = found.point
                where = f"{abs(gap) * 100:.2f} cm inside" if gap < 0 else f"only {gap * 100:.2f} cm from"
                return Rejection(
                    Kind.COLLISION,
                    f"{effector.tool}, acting on {e.body} with {effector.name}, would stand {where} {e.body} beside "
                    f"its contact at ({at[0]:.2f}, {at[1]:.2f}, {at[2]:.2f}) m at the start of mode {k} (a part "
                    f"beside the contact keeps {BESIDE_CLEARANCE * 100:.1f} cm clear): {e.body} is in the way",
                    float(found.depth),
                    (effector.tool, e.body),
                    frozenset({e.body}),
                )
        return None

    def _thickness(self, tool: str) -> float:
        """The least width of any part of `tool` (m): how deep its tip may sit in what it acts on."""
        if tool not in self._thicknesses:
            self._thicknesses[tool] = min(2.0 * float(half.min()) for _, half in self.scene.part_boxes_local(tool))
        return self._thicknesses[tool]

    def arm(self, graphs: Iterable[KGraph], traces: list[ModeTrace], q_start: list, q_end: list) -> Rejection | None:
        """Why the arm (or a tool in its hand) would hit a body or the table at its configurations, or None."""
        robot = self.problem.robot_effector.name
        before: set[str] = set()
        for k, (graph, trace) in enumerate(zip(graphs, traces, strict=True)):
            touched = {e.body for e in graph.engaged if e.effector == robot}
            if not trace.hand or graph.using(robot) is None:
                # the hand rests where the previous mode left it, still at the contact it has just removed
                # (the retreat out of it is checked with the arm's paths), or around the tool it has just set
                # down where it was picked up (`vkgl.plan.search.put_back`: the mode's one hand pose)
                touched |= before
            before = touched
            held = self._held(graph, touched)
            if held is not None and q_start[k] is not None:
                slipping = grip_rejection(self.problem, graph, trace, np.asarray(q_start[k], dtype=float), held[0])
                if slipping is not None:
                    return slipping
            for q, poses, when in ((q_start[k], trace.start, "start"), (q_end[k], trace.end, "end")):
                if q is None:
                    continue
                q = np.asarray(q, dtype=float)
                hold = None
                if held is not None:
                    tool, grasp, acts_on = held
                    in_hand = np.linalg.inv(self.problem.arm.fk(q)) @ poses[tool]
                    hold = held_tool(self.problem, tool, grasp, in_hand, frozenset(acts_on))
                self.queries += 1
                found = self.arm_collision.overlap(q, poses, ignore=touched, held=hold)
                if found:
                    return _rejection(found, f"with the arm at the {when} of mode {k}", self.names, arm=True)
        return None

    def _tool_pairs(self, graph: KGraph) -> set[frozenset[str]]:
        """Pairs that may touch in a mode: a tool and the body it acts on."""
        out = set()
        for e in graph.engaged:
            tool = self.problem.effector(e.effector).tool
            if tool is not None:
                out.add(pair(tool, e.body))
        return out

    def _held(self, graph: KGraph, touched: set[str]) -> tuple[str, str, set[str]] | None:
        """The tool the hand holds in a mode (the touched body whose affordance lets it move freely), the
        affordance it is held by, and the bodies it acts on."""
        for e in graph.engaged:
            if e.body in touched and self.problem.affordance(e.body, e.affordance).motion.type == "free":
                acts_on = {f.body for f in graph.engaged if self.problem.effector(f.effector).tool == e.body}
                return e.body, e.affordance, acts_on
        return None


def _moving(problem: Problem, graph: KGraph, trace: ModeTrace) -> str:
    moved = [e for e in graph.engaged if trace.values.get(e, 0.0) > 0.0]
    if not moved:
        return "while nothing is pushed"
    return "while " + ", ".join(_engagement_words(problem, e, trace.values[e]) for e in moved)


def _engagement_words(problem: Problem, e: Engagement, value: float) -> str:
    motion = problem.affordance(e.body, e.affordance).motion.type
    amount = f"{value * 100:.1f} cm" if motion == "prismatic" else f"{np.degrees(value):.1f} deg"
    return f"{e.effector} moves {e.body} by {amount} ({problem.bodies[e.body].type.name}.{e.affordance})"


def _bystander_rejection(close: Contact, where: str, names: frozenset[str], *, placed: bool = True) -> Rejection:
    """A tool at its contact (or along its motion: not `placed`, `GeometryCheck._bystander_sweep`) too close to a
    body it does not act on (`GeometryCheck._bystander`); `names`: the problem's bodies."""
    gap = BYSTANDER_CLEARANCE - close.depth  # m: the tool's distance from the body (negative: inside it)
    at = close.point
    how = f"{-gap * 1000:.1f} mm inside" if gap < 0 else f"only {gap * 1000:.1f} mm from"
    verb, when = ("stand", "at its contact") if placed else ("pass", "along its motion")
    return Rejection(
        Kind.COLLISION,
        f"{close.body_a} would {verb} {how} {close.body_b} at ({at[0]:.2f}, {at[1]:.2f}, {at[2]:.2f}) m {where} "
        f"(a tool {when} keeps {(BYSTANDER_CLEARANCE - TOUCH_TOL) * 1000:.0f} mm from every body but the one "
        f"it acts on: it would drag what it touches): {close.body_b} is in the way",
        float(close.depth),
        (close.body_a, close.body_b) if placed else (),
        frozenset({close.body_b}) & names,
    )


def _rejection(
    found: list[Contact], where: str, names: frozenset[str], *, arm: bool = False, placed: bool = True
) -> Rejection:
    """A collision rejection naming the deepest overlap; `names`: the problem's bodies (`Rejection.bodies` keeps
    those of the overlap's two parts: not the table); `arm`: the arm's check (a part no body is the arm's
    link); `placed`: an overlap where the parts are placed (a mode's start or end), whose pair it records, not one
    swept through during a motion."""
    deepest = max(found, key=lambda c: c.depth)
    a, b = deepest.body_a, deepest.body_b
    what = f"the arm's {a}" if arm and a not in names else a
    at = deepest.point
    return Rejection(
        Kind.COLLISION,
        f"{what} would pass through {b} by {deepest.depth * 100:.1f} cm at ({at[0]:.2f}, {at[1]:.2f}, "
        f"{at[2]:.2f}) m {where}: {b} is in the way",
        float(deepest.depth),
        (a, b) if placed else (),
        frozenset({b} if arm else {a, b}) & names,
    )
