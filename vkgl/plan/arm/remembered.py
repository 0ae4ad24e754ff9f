"""What the arm's straight moves computed for one contact, remembered for the next candidate that asks the same.

The search hands the arm's paths many candidate sequences that share steps: the same first contact at the bodies'
rest poses, the same push with the same value where the goal pins it. A contact's chains of arm configurations
(`ArmPathPlanner._contact_chain`: IK at the contact, chained IK along its motion, the links' collision checks)
and its straight approach (`StraightMoves.into_contact`) depend only on the step (its body, affordance,
effector, the bodies' poses at its start and end, the arm's joints there), on the tool in the hand and on the
step's label (in a rejection's words); the collision world is the problem's and does not change. Both are
deterministic, so a step asked again, byte for byte, gets the answers a new computation would give, without it.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterator, Mapping
from typing import Generic, TypeVar

import numpy as np

from vkgl.formats.plan import PlanStepRecord
from vkgl.motion.arm_collision import Held

REMEMBERED = 1024
"""Steps whose answers a planner keeps (then it starts afresh): a few MB of chains at most."""

T = TypeVar("T")


def step_key(step: PlanStepRecord, held: Held | None, label: str) -> Hashable:
    """Everything a contact's chains and approach depend on, byte for byte."""
    return (
        step.op,
        step.body,
        step.affordance,
        step.effector,
        step.motion,
        _poses(step.poses_start),
        _poses(step.poses_end),
        np.asarray(step.q_start, dtype=float).tobytes(),
        np.asarray(step.q_end, dtype=float).tobytes(),
        None if held is None else (held.body, np.asarray(held.in_hand, dtype=float).tobytes(), held.acts_on),
        label,
    )


def _poses(poses: Mapping[str, np.ndarray]) -> tuple[tuple[str, bytes], ...]:
    return tuple(sorted((name, np.asarray(pose, dtype=float).tobytes()) for name, pose in poses.items()))


class Replay(Generic[T]):
    """A generator's items, made once, in order, only as far as some caller has asked; every iteration gives
    them from the first (arrays as copies of their own: a caller may keep one in its plan)."""

    def __init__(self, source: Iterator[T]) -> None:
        self._source = source
        self._made: list[T] = []
        self._done = False

    def __iter__(self) -> Iterator[T]:
        k = 0
        while True:
            if k == len(self._made):
                if self._done:
                    return
                try:
                    self._made.append(next(self._source))
                except StopIteration:
                    self._done = True
                    return
            item = self._made[k]
            k += 1
            yield item.copy() if isinstance(item, np.ndarray) else item  # type: ignore[misc]


class Remembered(Generic[T]):
    """Answers by key, at most `REMEMBERED` (then forgotten all at once)."""

    def __init__(self) -> None:
        self._kept: dict[Hashable, T] = {}

    def get(self, key: Hashable) -> T | None:
        """The answer kept for `key`, if any."""
        return self._kept.get(key)

    def keep(self, key: Hashable, answer: T) -> T:
        """Keep `answer` for `key`; return it."""
        if len(self._kept) >= REMEMBERED:
            self._kept.clear()
        self._kept[key] = answer
        return answer
