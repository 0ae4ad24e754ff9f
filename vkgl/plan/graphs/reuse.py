"""Rollouts of one sequence that reuse the modes whose values did not change.

The task-space optimiser rolls its sequence out at every point it tries, and
at every step of its finite differences, which move one value at a time: the
modes before that value's mode are then the same as at the point the step is
taken from, and the modes before the sequence's first motion are the same at
every point. Mode k of a rollout depends only on the values that act in modes
0 .. k (its motions, the offsets of the contacts added up to it, its carries:
`rollout.mode_values`) and is computed from the poses after mode k - 1 with
the same operations whether those were just computed or remembered, so a
reused rollout equals the full one bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vkgl.plan.graphs.carry import CARRY_VALUES
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, mode_values, rest_poses, roll_mode
from vkgl.plan.problem.problem import Problem

MODES_KEPT = 256
"""Rolled-out modes a `Rollouts` keeps (then forgets them all): tens of the optimiser's evaluations, each a
point and its finite-difference steps (a step reuses its point's modes; older points are seldom asked again)."""


class Rollouts:
    """`rollout(problem, seq, values, samples)` for one sequence, with the prefixes already rolled out reused.

    The modes rolled out are kept as a tree: a mode's node is found under its parent's by the bytes of the
    values that act in it, so a prefix is found by one lookup per mode. The traces given are shared with later
    rollouts of the same object: read them, never write to them.
    """

    def __init__(self, problem: Problem, seq: Sequence, samples: int) -> None:
        self.problem, self.seq, self.samples = problem, seq, samples
        self._root: dict[bytes, _Node] = {}
        self._kept = 0
        self._ranges: dict[int, list[list[slice]]] = {}  # per length of the values: per mode, the values it reads
        self.modes_rolled = 0  # modes computed (the rest were reused): for the benchmarks and tests

    def rollout(self, values: np.ndarray) -> list[ModeTrace]:
        """Every mode of the sequence at `values`: equal to `rollout(problem, seq, values, samples)`."""
        flat = np.asarray(values, dtype=float)
        ranges = self._ranges.get(len(flat))
        if ranges is None:
            ranges = self._ranges[len(flat)] = mode_ranges(self.seq, len(flat))
        if self._kept + len(ranges) > MODES_KEPT:
            self._root, self._kept = {}, 0
        node, traces, live = self._root, [], _NO_OFFSETS
        for read in ranges:
            child = node.get(_key(flat, read))
            if child is None:
                break
            traces.append(child.trace)
            live, node = child.live, child.children
        else:
            return traces
        reused = len(traces)
        poses = dict(traces[-1].end) if traces else rest_poses(self.problem)
        live = dict(live)
        given = mode_values(self.seq, flat)
        for k in range(reused, len(ranges)):
            trace = roll_mode(self.problem, self.seq, k, poses, live, given, self.samples)
            traces.append(trace)
            child = node[_key(flat, ranges[k])] = _Node(trace, dict(live), {})
            node = child.children
        self.modes_rolled += len(ranges) - reused
        self._kept += len(ranges) - reused
        return traces


@dataclass
class _Node:
    """A mode rolled out: its trace, the family offsets in force after it, and the next modes by their values."""

    trace: ModeTrace
    live: dict[Engagement, float]
    children: dict[bytes, _Node]


_NO_OFFSETS: dict[Engagement, float] = {}


def _key(values: np.ndarray, read: list[slice]) -> bytes:
    """The bytes of the values a mode reads (empty for a mode that reads none)."""
    if not read:
        return b""
    if len(read) == 1:
        return values[read[0]].tobytes()
    return b"".join(values[r].tobytes() for r in read)


def mode_ranges(seq: Sequence, size: int) -> list[list[slice]]:
    """Per mode of `seq`, the slices of the values (a vector of `size`: the motions, the offsets if given, the
    carries) that act in it: its motions, the offsets of the contacts added at the transition into it, the carry
    values of the grasps carried during it (`rollout.mode_values` reads them the same way), as runs of
    neighbours (`rollout.extend` keeps each kind in mode order: one run per kind)."""
    given_offsets = size - len(seq.variables) - CARRY_VALUES * len(seq.carries)
    if given_offsets not in (0, len(seq.offsets)):
        raise ValueError(f"{size} values for a sequence of {seq.size} (or {seq.size - len(seq.offsets)}, no offsets)")
    acting = [mode for mode, _ in seq.variables]
    acting += [mode for mode, _ in seq.offsets[:given_offsets]]
    for mode, _ in seq.carries:
        acting += [mode] * CARRY_VALUES
    out: list[list[slice]] = [[] for _ in seq.graphs]
    start = 0
    for i in range(1, len(acting) + 1):  # runs of equal modes
        if i == len(acting) or acting[i] != acting[start]:
            out[acting[start]].append(slice(start, i))
            start = i
    return out
