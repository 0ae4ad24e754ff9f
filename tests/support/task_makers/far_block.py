"""A Block 62 cm out at a 20 deg heading whose goal leaves the heading free, with slides and turns of bounded
ranges: the problem the hand-reach proofs' tests enumerate every short sequence of
(tests/plan/task_space/test_hand_reach.py, test_hand_heading.py)."""

from __future__ import annotations

from pathlib import Path

from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem

PROGRAM = """
use stdlib.robots.panda
use stdlib.bodies.block

affordances Block {
    affordance push_px {
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 12 cm
    }
    affordance push_nx {
        action fixed at (5, 0, 0) cm yaw 180deg
        motion prismatic along (-1, 0, 0) from (0, 0, 0) cm range 0 to 6 cm
    }
    affordance turn_left {
        action fixed at (-5, 6.56, 0) cm yaw 0deg
        motion revolute about (-0.54, -11.1, 0) cm axis (0, 0, -1) range 0 to 40 deg
        family along (0, 1, 0) from 0 to 2.66 cm drift (0.288, 2.214, 0) sigma 1.37 cm
    }
    affordance turn_right {
        action fixed at (5, -6.56, 0) cm yaw 180deg
        motion revolute about (3, 9, 0) cm axis (0, 0, 1) range 0 to 25 deg
        family along (0, 1, 0) from -2.66 to 0 cm drift (-0.586, 1.894, 0) sigma 1.87 cm
    }
}

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.62, 0.05) m yaw 20deg
}

task t { scene s  goal block at (0.6, 0.1) m within 1 cm }
"""

DEPTH = 4
"""Graphs in the longest sequence enumerated (G0 included): two contacts, so up to two turns."""


def far_block_problem(folder: Path) -> Problem:
    """The problem, its module written into `folder`."""
    path = folder / "far_block.vkg"
    path.write_text(PROGRAM, encoding="utf-8")
    program = compile_file(str(path))
    return build_problem(program, program.task(), max_depth=DEPTH)


def block_moving_sequences(problem: Problem) -> list[Sequence]:
    """Every sequence of at most `DEPTH` graphs whose last mode moves the block."""
    found, layer = [], [start_sequence(problem)]
    while layer:
        deeper = []
        for seq in layer:
            if seq.depth >= DEPTH:
                continue
            for action in successors(problem, seq.graphs[-1], seq.last):
                child, _ = extend(problem, seq, action)
                deeper.append(child)
                if any(m == child.depth - 1 for m, _ in child.variables):
                    found.append(child)
        layer = deeper
    return found
