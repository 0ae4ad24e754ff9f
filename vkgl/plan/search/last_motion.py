"""A last motion that failed alone fails the same after any prefix that leaves what it depends on where it rests.

A sequence is checked when its last mode moves a goal body. When that motion is the sequence's only one (a push
from where everything rests, maybe with a tool grasped first) and it fails because the hand would leave the arm's
reach, or because the bodies would pass through one another (the tool through a body lying in its way), every
longer sequence that ends with the same mode fails the same way whenever what comes before leaves the moved body,
the tool and the bodies the failure names at the poses they had:

- the hand's poses during the last mode depend only on the moved body's pose at its start, the motion's value and
  (with a tool) the grasp that holds the tool; with the problem's one goal on that body, the values that meet it
  are the same (a reach failure);
- the bodies' sweep during the last mode is the same for the same value, and the bodies it passed through stand
  where they stood (a collision of the bodies; the arm's own collisions are not remembered: the arm may come in
  another configuration after another prefix).

On the physical bench's far blocked tasks (a cube beyond the fingertip, a stick and a hook on the table) the
search for a plan that clears a blocker checked the same turn of the blocker with the stick, out of reach, and the
same push of it with the hook through the goal body, after each of a hundred prefixes that moved something else
(another body pushed aside, the goal body nudged): on gen1_001 of seed 1 the sub-search that finds the plan did
1,223 units of work (`SearchStats.work_done`) without this, 557 with reach failures remembered.

A tool that the last action puts on the body (its tip's push) jumps to that contact at the transition, wherever it
was: a prefix that pushed another body with the same tool in the hand leaves the last mode as it was without that
prefix (the tool's pose through it follows the body and the motion's value, the hand's the tool and the grasp, one
of the last mode's contacts). Such a tool does not count as moved before (`_jumped_tools`). On the far blocked tasks
gen1_013 and gen1_021 of seed 1, the stick's push of the goal body after the stick had pushed a body in the way was
checked in full (the optimiser, the values that move bodies aside: 74 and 128 ms on average) for the failure of the
same push alone: now 73 and 40 such sequences in their 20 CPU-s are rejected unchecked.

`LastMotion` remembers such failures for one search, keyed by the last mode's contacts in force and the poses of
the bodies they act on and of the tools that enact them (none moved by a motion value before the last mode:
exactly the poses with every value 0); a later sequence with the same key whose earlier motions moved none of the
bodies the failure names is rejected at once, with the same reason. Nothing is remembered when the problem has
more than one goal (another goal body's motion could be what failed), when the sequence carries a body, or when
its last action is not an "add".
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection

_Key = tuple[object, ...]

POSE_DECIMALS = 6
"""Decimals of a pose's entries in a key (m, and unit-vector entries): poses equal to a micrometre are the same."""


@dataclass
class LastMotion:
    """The failures of single last motions seen in one search, by `last_motion_key`."""

    seen: dict[_Key, Rejection] = field(default_factory=dict)

    def known(self, problem: Problem, seq: Sequence) -> Rejection | None:
        """The failure remembered for `seq`'s last mode, when the motions before it moved none of the bodies it
        names; else None."""
        if not self.seen:
            return None
        key = last_motion_key(problem, seq)
        found = None if key is None else self.seen.get(key)
        if found is None or found.bodies & (_moved_before_last(problem, seq) - _jumped_tools(problem, seq)):
            return None
        return found

    def forget_after(self, count: int) -> None:
        """Forget the failures remembered after the first `count` (those of a check the clock cut short: they
        may be the clock's, `search`'s pause)."""
        for key in list(self.seen)[count:]:
            del self.seen[key]

    def remember(self, problem: Problem, seq: Sequence, rejection: Rejection) -> None:
        """Remember `rejection` of `seq` when `seq`'s last mode is its only motion and the failure is the hand out
        of reach or bodies passing through one another (the bodies' check: the caller knows which check made it)."""
        if rejection.kind is not Kind.REACH and not (rejection.kind is Kind.COLLISION and rejection.bodies):
            return
        if not seq.variables:
            return
        last = len(seq.graphs) - 1
        if any(mode != last for mode, _ in (*seq.variables, *seq.offsets)):
            return
        key = last_motion_key(problem, seq)
        if key is not None:
            self.seen.setdefault(key, rejection)


def last_motion_key(problem: Problem, seq: Sequence) -> _Key | None:
    """What `seq`'s last mode depends on, or None when that is not known without its motion values: the contacts in
    force (effector, body, affordance), and the poses of the bodies they act on and of the tools that enact them,
    none of which a motion value before the last mode moved. None also when the problem has other goals than the
    one on the last motion's body, when the sequence carries a body or the last action is no "add"."""
    last = seq.last
    if last is None or last.op != "add" or seq.carries or len(problem.goals) != 1:
        return None
    if problem.goals[0].body != last.engagement.body:
        return None
    engaged = seq.graphs[-1].engaged
    names = {e.body for e in engaged} | {t for e in engaged if (t := problem.effector(e.effector).tool) is not None}
    if names & (_moved_before_last(problem, seq) - _jumped_tools(problem, seq)):
        return None
    poses = tuple((name, _rounded(seq.zero_poses[name])) for name in sorted(names))
    contacts = tuple(sorted((e.effector, e.body, e.affordance) for e in engaged))
    return contacts, poses


def _moved_before_last(problem: Problem, seq: Sequence) -> set[str]:
    """The bodies a motion value of a mode before the last moves: each such motion's body and the tools of the
    contacts on it in that mode (a tool acting on a moving body moves with it)."""
    last = len(seq.graphs) - 1
    moved = set()
    for mode, e in seq.variables:
        if mode == last:
            continue
        moved.add(e.body)
        for other in seq.graphs[mode].engaged:
            tool = problem.effector(other.effector).tool
            if tool is not None and other.body == e.body:
                moved.add(tool)
    return moved


def _jumped_tools(problem: Problem, seq: Sequence) -> set[str]:
    """The tool whose contact the last action adds, when that contact's body did not move before: the tool jumps
    to its contact there (`rollout._transition`), so its pose through the last mode is the same whatever moved it
    before (it was carried in the hand against another body, say); with the grasp that holds it among the last
    mode's contacts (the key's), the hand's poses are the same too."""
    last = seq.last
    if last is None or last.op != "add":
        return set()
    tool = problem.effector(last.engagement.effector).tool
    if tool is None or last.engagement.body in _moved_before_last(problem, seq):
        return set()
    return {tool}


def _rounded(pose: np.ndarray) -> tuple[float, ...]:
    return tuple(np.round(np.asarray(pose, dtype=float)[:3, :4], POSE_DECIMALS).ravel().tolist())


__all__ = ["LastMotion", "last_motion_key"]
