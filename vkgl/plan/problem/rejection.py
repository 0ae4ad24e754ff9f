"""Why a graph sequence is not a plan: a `Rejection` of one `Kind`, with a sentence and how far it missed.

The kinds are ordered by how far a rejected sequence got (`Kind.stage`): a hand pose out of reach (0) came less
close to a plan than a task-space failure (1), which came less close than a collision or an IK failure (2), than
an arm path that could not be found (3), or than a feasible plan that repeats what a re-solve must avoid (4). The
search's "no plan" reason leads with the furthest stage's kinds: the decisive cause. A contact that moves
nothing (-1) is no miss at all (the sequence without it was checked first): listed last, never the closest.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class Kind(StrEnum):
    """A category of rejection. A `StrEnum`: its value is the word in plans' details and `vkgc solve -v`."""

    REACH = "reach"
    YAW = "yaw"
    POSITION = "position"
    GOAL = "goal"
    IDLE = "idle"
    TABLE = "table"
    COLLISION = "collision"
    IK = "ik"
    GRIP = "grip"
    TIMEOUT = "timeout"
    APPROACH = "approach"
    TRANSIT = "transit"
    EXCLUDED = "excluded"

    @property
    def words(self) -> str:
        """How the search's summary names the sequences rejected for this kind ("12 <words> (closest: ...)")."""
        return _WORDS[self]

    @property
    def stage(self) -> int:
        """How far a sequence rejected for this kind got towards a plan (higher: closer)."""
        return _STAGE[self]


_WORDS = {
    Kind.REACH: "needed the hand out of the arm's reach",
    Kind.YAW: "cannot give the goal heading",
    Kind.POSITION: "cannot bring a body to its goal position",
    Kind.GOAL: "found no motion values reaching the goal",
    Kind.IDLE: "had a contact that moves nothing (the same without it is shorter)",
    Kind.TABLE: "would push a body off the table or past its joint's limits",
    Kind.IK: "failed inverse kinematics",
    Kind.GRIP: "would push harder with a held tool than its grip carries (or hold one wider than the hand opens)",
    Kind.COLLISION: "would make a body pass through another (or the arm hit one)",
    Kind.APPROACH: "had a contact the arm cannot approach or leave in a straight line",
    Kind.TRANSIT: "found no collision-free way for the arm between contacts",
    Kind.TIMEOUT: "ran out of time",
    Kind.EXCLUDED: "repeated a plan already tried or a step that failed in execution",
}

_STAGE = {
    Kind.IDLE: -1,  # not a miss: the same sequence without the idle contact was checked first
    Kind.REACH: 0,
    Kind.YAW: 1,
    Kind.POSITION: 1,
    Kind.GOAL: 1,
    Kind.TABLE: 1,
    Kind.COLLISION: 2,
    Kind.IK: 2,
    Kind.GRIP: 2,
    Kind.TIMEOUT: 2,
    Kind.APPROACH: 3,
    Kind.TRANSIT: 3,
    Kind.EXCLUDED: 4,
}


@dataclass
class Rejection:
    """Why a sequence is not feasible: a kind (for the summary), a sentence, and how far from feasible (m), to
    report the closest miss.

    `bodies` are the scene's bodies the rejection finds in the way, by name, where the check that made it knows
    them (the words name them too, for people): both bodies of two that would pass through each other or
    overlap where they are placed, the body a tool would stand in or too close to, the body the arm (or the
    tool in its hand) would hit at its contacts, along a contact's motion, on its straight approach or at a
    transit's end. Never an arm's link, the table, or a keep-out region. The search reads them, not the words:
    a body kept still is met when a rejection names it here (`vkgl.plan.search.clutter.still`), and a body
    the arm's checks name here may be pushed aside first (`vkgl.plan.search.arm_aside`).

    `advice`, where the check knows it, says what the task's author can change; when its kind decides a "no
    plan" (`vkgl.plan.search.stats.infeasible_reason`), the reason says the closest miss's why and advice first.
    """

    kind: Kind
    why: str
    excess: float = 0.0
    between: tuple[str, ...] = ()  # the two parts that overlap where they are placed (not swept into each other)
    bodies: frozenset[str] = frozenset()  # the scene's bodies found in the way (see above)
    advice: str = ""  # what the task's author can change to get past it (the grip: a lighter tool, ...)


__all__ = ["Kind", "Rejection"]
