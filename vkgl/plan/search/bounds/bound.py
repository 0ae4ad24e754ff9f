"""A lower bound of the graphs a sequence still needs before its goal can hold: the guide of the best-first search.

`Bound(problem)(seq)` is a whole number (or `math.inf`: no extension of `seq`
can ever reach the goal) that never exceeds the number of actions any feasible
extension of `seq` within the search's space adds. Its parts, per goal body `b`:

1. **Moving modes in all** (`N_b`, fixed per problem). A body that is not a tool
   and has no `free` affordance moves only during modes in which an engagement
   of a prismatic or revolute affordance on it is in force (`rollout`: nothing
   else changes its pose; transitions only move tools and put released bodies
   down), by one motion value within `value_bounds` per mode. One mode
   translates its frame's origin by at most `step_b`: a slide by its range's
   upper end (`v` along a unit axis), a turn by `θ ≤ θmax` about an axis at
   distance `r` from the origin by `2 r sin(min(θmax, π) / 2)` (the chord);
   `step_b` is the largest over the affordances that can move `b` (of the type
   of its physical joint, if it has one); a turn whose contact may move along
   its family moves its pivot by `offset * drift` too, and `r` is the largest
   over the family's band (at one of its ends: the distance to the axis is
   convex in the offset). A goal at distance `d` with tolerance
   `t` needs the origin to move at least `d - t` (triangle inequality), hence
   at least `ceil((d - t) / step_b)` modes. Headings: only turns change one; a
   turn about an axis vertical in the world changes it by its angle, so a
   heading off by `ψ - t_ψ` (the circle's distance, less the tolerance) needs
   `ceil((ψ - t_ψ) / θmax)` turning modes; when some turn's axis is not
   vertical every turn counts as half a turn (one mode could give any heading). No
   turning affordance and a heading off by more than its tolerance: never
   (`inf`). Likewise a body whose every moving affordance slides it along
   one axis of its frame keeps its heading and its origin on the world line
   through its rest pose along that axis: a goal position farther from that
   line than its tolerance is never reached (`inf`). A prismatic joint's opening moves by at most the slide per mode
   (`|axis · joint_axis| <= 1`); a hinge's opening counts one mode. `N_b` is
   the largest of these (a mode may serve several at once). **Far and turned
   together**: a slide keeps the heading and moves the origin by at most `S`
   (the largest slide), a turn changes the heading by at most `T` and moves the
   origin by at most `C` (the largest chord), so `k` turns and `j` slides cover
   a distance `D = d - t` and a heading `Ψ = ψ - t_ψ` only if `k T >= Ψ` and
   `k C + j S >= D` (triangle inequality): `N_b` is at least the fewest `k + j`
   that do (`fewest_modes`). The separate counts above are never more: with
   `k T >= Ψ`, `k >= ceil(Ψ / T)`, and `(k + j) max(S, C) >= D`.
2. **Moving modes still to come**: `m_b = max(0, N_b - k_b)` where `k_b` counts
   the modes of `seq` that move `b` (its motion variables): each moved `b` by at
   most `step_b` too, so the rest must cover what they did not. Sharper, from
   the kinds of those modes: after `k_s` slides and `k_t` turns of `b`, what is
   left to cover is at least `D - k_s S - k_t C` and `Ψ - k_t T`, and the
   modes still to come at least `fewest_modes` of those (`PoseNeed.left`):
   two turns of a few centimetres each leave a far goal as far as ever.
3. **Contacts made and broken.** Every graph is one action. When no tool has two
   effector frames, the graph in which an engagement on `b` acts holds nothing
   but it and the grasp of the tool it acts through (one contact per effector;
   a tool frame acts only while its tool is held, and a tool in use stays in
   hand): its only successor removes it. Then each further moving mode of `b`
   needs its own ADD on `b`, and each ADD but the first a REMOVE of the one
   before: `2 m_b` actions on `b` when something engages `b` now, `2 m_b - 1`
   when nothing does. These actions target `b`, so those of different bodies
   are different actions and add up. With a tool of two frames (one may act
   while the other holds its contact) each further mode still needs a graph
   (`m_b`), and a body not moving now at least one ADD (and a REMOVE first when
   something holds it still): the bound is the larger of the largest `m_b` and
   the sum of those actions.
   A **region goal** (in a region, beyond a half-plane) needs its footprint's farthest point moved, not its
   origin: `vkgl.plan.search.bounds.region_need` gives part 1 for it (and proves it), parts 2 to 6 apply unchanged.
4. **The grasp a tool needs first.** A body still at rest whose every moving
   affordance puts the hand out of the arm's reach can only be moved through a
   tool: the search never adds the hand's own contact there (it cuts that
   subtree at once, `vkgl.plan.search.search`), and the body stays at rest until
   something moves it. When no tool is in the hand that is one more ADD (its
   target is a tool, not a goal body: it adds to the sum); with no tool at all,
   never.

5. **A body the hand can carry.** A goal body with a `free` affordance that is
   no tool (`vkgl.plan.graphs.carry.carriable`) may be grasped and set down
   anywhere in one contact (`ADD` its grasp, `REMOVE` it: the carry's values
   put it at any position and heading, `vkgl.plan.graphs.carry`), so parts 1
   to 3 bound nothing for it: one mode may move it any distance. What stays
   true: while nothing has moved it yet (it is not in `seq.dependent`, so it
   lies exactly where `seq.zero_poses` has it) and a goal of it does not hold
   there, some later action targets it (an ADD on it: a push, a grasp; or the
   REMOVE that sets it down, when the hand holds it now): one action, counted
   with the others (they target other bodies, or are a tool's grasp). A tool
   is never set down elsewhere (it lies where it was used), so a goal on a
   tool counts nothing.

6. **The hand cannot end it there.** When the robot's own effector cannot
   hold any moving contact of `b` with `b` anywhere its goal accepts (outside
   the arm's reach: `vkgl.plan.search.bounds.goal_reach`, whose docstring proves it),
   the last mode that moves `b` is enacted by a tool's frame, so a tool is in
   the hand then. While `m_b > 0` that mode is still to come: with no tool in
   the hand now, one more ADD (a tool's grasp, counted once with part 4's). And
   when the last mode of `seq` that moved `b` was the hand's own, `seq` cannot
   end there: another mode must move `b` (`m_b >= 1`). With no tool at all:
   never (`inf`), and the reason says why with the reach's numbers. The same
   holds through each tool grasp: the hand at `pose @ action(s) @ frame⁻¹ @
   grasp` (`rollout.hand_chain`). A grasp (tool, affordance) with which no
   frame of the tool can hold a contact of `b` anywhere the goal accepts is
   *wrong* for `b`: a last mode of `seq` on `b` through it needs another
   (`m_b >= 1`); while `m_b > 0` and the hand holds a tool by a wrong grasp,
   the extension lets go of it (a REMOVE) and grasps a tool another way (an
   ADD), two actions on tools (none on a goal body: they add up), instead of
   the one grasp; and when every grasp of every tool is wrong: never (`inf`).
   **Contact by contact** (`goal_reach.wrong_ends`): the same proof for one
   moving affordance `a` of `b` alone. When the robot's own effector cannot
   hold `a`'s contact with `b` anywhere its goal accepts, or no frame of a
   tool held by a grasp can, a last mode of `seq` on `b` by that effector
   (that tool held so) on `a` cannot be the last that moves `b`: `m_b >= 1`,
   though other contacts of the hand (or of that grasp) may end it there. On
   the physical bench's far pushes most contacts are such (gen21_009: 19 of
   the hand's 20; 105 of the 160 pairs of a tool's grasp and a contact). Not
   with a tool of two frames (the hand may follow the other frame's contact).

7. **One mode from rest.** A sequence that has moved `b` in one mode only, by
   affordance `a`, leaves it where that mode from rest put it (nothing else
   moves it, part 1). When no value and no contact offset of `a` puts `b`
   within its goal's tolerances from rest (`vkgl.plan.search.bounds.one_mode`,
   whose docstring proves it on its grid), `seq` cannot end there: `m_b >= 1`.
   When that holds for every `a`, `N_b >= 2` (part 1). The same with the hand:
   when that mode, enacted by the robot's own effector (or by a tool held by a
   given grasp, which jumps to its contact whatever it did before), ends `b`
   there only with a hand sample of the mode out of the arm's reach
   (`one_mode.missing_ends`), `seq` cannot end there either. Counted with
   part 2's `m_b` (the larger), so the other parts apply unchanged. What each
   goal body needs of parts 1, 4, 6 and 7 is found once per problem
   (`vkgl.plan.search.bounds.needs`).

Each part counts actions that every feasible extension must contain, and parts
that add up count disjoint actions, so the bound never exceeds the true
remaining depth: the best-first search that prunes at `depth + bound >
max_depth` loses no plan within `max_depth`, and, checking sequences in the
order of `depth + bound`, it returns a shortest plan (ties: first the sequences
that moved the bodies in a goal body's way, `vkgl.plan.search.ordering`, then
the breadth-first order of their actions; with no body in the way, the very
plan breadth-first search returns; tests/plan/search/test_bound.py checks the bound
against exhaustive breadth-first search).
"""

from __future__ import annotations

import math

from vkgl.plan.graphs.carry import carriable
from vkgl.plan.graphs.graph import Engagement, KGraph, is_held, motion_type
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.bounds.needs import MOVING, BodyNeed, body_needs
from vkgl.plan.task_space.feasible import goal_holds


class Bound:
    """The lower bound of one problem (see the module's docstring); call it on a sequence."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        tools = [e.tool for e in problem.effectors if e.tool is not None]
        self.tools = frozenset(tools)
        self.two_frames = any(tools.count(t) > 1 for t in self.tools)
        self.needs = [need for need in body_needs(problem, self.tools) if need.modes > 0]
        self.grasps = frozenset(
            (tool, a.name) for tool in self.tools for a in problem.bodies[tool].affordances if a.motion.type == "free"
        )
        self.carried_goals = [g for g in problem.goals if _carriable_goal(problem, g.body, self.tools)]

    def __call__(self, seq: Sequence) -> float:
        """The fewest actions any feasible extension of `seq` adds (`inf`: none can reach the goal)."""
        carries = self._carries(seq)
        if not self.needs:
            return carries
        graph = seq.graphs[-1]
        remaining, actions, tool, regrasp = 0.0, 0.0, False, False
        held = self._held_grasp(graph)
        for need in self.needs:
            still = self._still(need, seq)
            if still <= 0:
                continue
            if math.isinf(still):
                return math.inf
            engaged = graph.engaging(need.body)
            moving = engaged is not None and motion_type(self.problem, engaged) in MOVING
            remaining = max(remaining, still)
            if self.two_frames:
                actions += 0 if moving else (2 if engaged is not None else 1)
            else:
                actions += 2 * still - (0 if engaged is not None else 1)
            tool = tool or (need.needs_tool and not moving and need.body not in seq.dependent) or need.ends_by_tool
            if need.ends_by_tool and self.tools and self.grasps <= need.wrong_grasps:
                return math.inf  # part 6: neither the hand nor any tool, held any way, can end it there
            regrasp = regrasp or (need.ends_by_tool and held in need.wrong_grasps)
        if regrasp:
            actions += 2  # part 6: let go of the tool held so, grasp one that can end the body there
        elif tool and held is None:
            if not self.tools:
                return math.inf
            actions += 1
        return max(remaining, actions + carries)

    def _held_grasp(self, graph: KGraph) -> tuple[str, str] | None:
        """(tool, grasp affordance) of the tool in the hand, or None."""
        for tool in self.tools:
            if is_held(self.problem, graph, tool):
                e = graph.engaging(tool)
                assert e is not None
                return tool, e.affordance
        return None

    def _still(self, need: BodyNeed, seq: Sequence) -> float:
        """Part 2: the moving modes of `need.body` still to come, given those `seq` made (slides and turns)."""
        turns = slides = 0
        last, when = None, 0
        for mode, e in seq.variables:
            if e.body == need.body:
                last, when = e, mode
                if motion_type(self.problem, e) == "revolute":
                    turns += 1
                else:
                    slides += 1
        still = need.modes - turns - slides
        if need.pose is not None:
            still = max(still, need.pose.left(slides, turns))
        if turns + slides == 1 and last is not None and self._missed(need, last, seq.graphs[when]):
            still = max(still, 1)  # part 7: moved once, from rest, by a contact that cannot end it there
        if last is not None and self._cannot_end(need, last, seq.graphs[when]):
            still = max(still, 1)  # part 6: what moved it last cannot where its goal is: it moves again
        return still

    def _missed(self, need: BodyNeed, engagement: Engagement, graph: KGraph) -> bool:
        """Part 7: whether one mode of `engagement` (in force in `graph`) from rest cannot end `need.body` at its goal
        (its contact, or that effector, a tool held by its grasp then, with the hand in reach)."""
        if engagement.affordance in need.misses:
            return True
        tool = self.problem.effector(engagement.effector).tool
        if tool is None:
            return (None, None, engagement.affordance) in need.missed_ends
        held = graph.engaging(tool)
        return held is not None and (tool, held.affordance, engagement.affordance) in need.missed_ends

    def _cannot_end(self, need: BodyNeed, engagement: Engagement, graph: KGraph) -> bool:
        """Part 6: whether `engagement` (in force in `graph`) cannot hold `need.body` where its goal is: the hand's
        own when no contact of it can, a tool's frame with the tool held by a grasp in `need.wrong_grasps`, or
        that effector (and grasp) on that affordance in `need.wrong_ends`."""
        tool = self.problem.effector(engagement.effector).tool
        if tool is None:
            return need.ends_by_tool or need.cannot_end((None, None, engagement.affordance))
        held = graph.engaging(tool)
        if held is None:
            return False
        by = (tool, held.affordance)
        return (need.ends_by_tool and by in need.wrong_grasps) or need.cannot_end((*by, engagement.affordance))

    def _carries(self, seq: Sequence) -> int:
        """Part 5: one action for each body the hand can carry that nothing has moved yet and whose goal does
        not hold where it lies."""
        waiting = {
            g.body
            for g in self.carried_goals
            if g.body not in seq.dependent and not goal_holds(self.problem, seq.zero_poses, [g])
        }
        return len(waiting)

    def explain(self) -> str:
        """Why the goal needs the graphs the bound gives at the start (empty when it gives none)."""
        words = [need.why for need in self.needs if need.why]
        for need in self.needs:
            if not need.ends_by_tool:
                continue
            if not self.tools:
                words.append(f"{need.beyond_why}: only a tool could move it there, and none can act")
            elif self.grasps <= need.wrong_grasps:
                words.append(f"{need.beyond_why}, and so would it holding any tool any way")
            else:
                words.append(f"{need.beyond_why}: only a tool can move it last")
        return "; ".join(words)


def _carriable_goal(problem: Problem, body: str, tools: frozenset[str]) -> bool:
    """Whether a goal body can be carried (part 5): a grasp (`free` affordance) on a body that is no tool."""
    plan_body = problem.bodies[body]
    return (
        body not in tools and carriable(problem, body) and any(a.motion.type == "free" for a in plan_body.affordances)
    )
