"""Small planning problems around one stdlib Block (a ranged slide, a ranged turn, a goal near it), shared by the
search's tests: the bound's (tests/plan/search/bounds), the order of checks' and the kept-still bodies'
(tests/plan/search/clutter)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem

PROGRAM = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.affordances.stick
use stdlib.tools

affordances Block {{
    affordance push_px {{
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to {slide} cm
    }}
    affordance turn_left {{
        action fixed at (-5, 6.56, 0) cm yaw 0deg
        motion revolute about (-0.54, -11.1, 0) cm axis (0, 0, -1) range 0 to {turn} deg{family}
    }}
{grasp}}}

scene s {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at ({x}, 0) m yaw 0deg
{stick}}}

task t {{ scene s  goal block at ({gx}, {gy}) m{yaw} within 1 cm, 3 deg }}
"""

DEPTH = 6
"""Graphs in the longest sequence enumerated (G0 included)."""


GRASP = """    affordance grasp_top {
        action fixed at (0, 0, 0) cm yaw 90deg
        motion free
    }
"""
"""A grasp of the block from above (its 10 cm across the fingers: the planner does not check widths)."""


FAMILY = "\n        family along (0, 1, 0) from 0 to 4 cm drift (0.3, 0.77, 0) sigma 1 cm"
"""A band of contacts along the face for the turn, its pivot moving with the contact (as the stdlib Block's)."""


def block_problem(tmp_path: Path, **fields: object) -> Problem:
    fields.setdefault("grasp", "")
    fields.setdefault("family", "")
    path = tmp_path / "bound.vkg"
    path.write_text(PROGRAM.format(**fields), encoding="utf-8")
    program = compile_file(str(path))
    return build_problem(program, program.task(), max_depth=DEPTH)


STICK = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"


def drawn_block_problem(
    tmp_path: Path, *, x: float, gx: float, gy: float, yaw: int | None, stick: str = "", family: bool = False
) -> Problem:
    """`block_problem` for a property test's draw: the goal's position rounded to the millimetre, a heading in
    degrees or none, the 30 cm slide and 25 deg turn, with `STICK` or no tool, the turn's family or none."""
    return block_problem(
        tmp_path,
        x=x,
        gx=round(gx, 3),
        gy=round(gy, 3),
        yaw="" if yaw is None else f" yaw {yaw}deg",
        slide=30,
        turn=25,
        stick=stick,
        family=FAMILY if family else "",
    )


def labels(problem: Problem, seq: Sequence) -> tuple[str, ...]:
    return tuple(a.label(problem) for a in seq.actions)


def block_to(
    tmp_path: Path,
    gx: float,
    stick: bool,
    grasp: bool,
    depth: int,
    other: str = "",
    yaw: str = " yaw -20deg",
    slide: int = 10,
    gy: float = 0.04,
) -> Problem:
    """The block at x 0.6 m to (gx, gy) m (turned by `yaw`), `other` (scene lines) besides (at `gy` 0 and no `yaw`,
    one push of the block reaches the goal; at 0.04 m no one contact from rest does: the bound's part 7)."""
    problem = block_problem(
        tmp_path,
        x=0.6,
        gx=gx,
        gy=gy,
        yaw=yaw,
        slide=slide,
        turn=25,
        stick=(STICK if stick else "") + other,
        grasp=GRASP if grasp else "",
    )
    return replace(problem, max_depth=depth)


IN_THE_WAY = "    other : Block on table at (0.77, 0.02) m yaw 90deg\n"
"""A second Block across the block's way to a goal at x 0.8 m or beyond."""

ASIDE = "    other : Block on table at (0.77, -0.35) m yaw 90deg\n"
"""The same Block well to the side of that way."""


def labelled_sequence(problem: Problem, *labels: str) -> Sequence:
    """The sequence of the actions with these labels (`Action.label`: "add Block.push_px on block with
    arm.fingertip"), each among the successors of the graph before it."""
    seq = start_sequence(problem)
    for label in labels:
        action = next(a for a in successors(problem, seq.graphs[-1], seq.last) if a.label(problem) == label)
        seq, _ = extend(problem, seq, action)
    return seq


def block_across_the_way(max_depth: int) -> str:
    """The source of task `through`: a Block to be pushed 30 cm on, a second Block lying across its way (the search
    finds the plan that pushes block2 aside first at 4 graphs), searched to `max_depth` graphs, a 60 s timeout."""
    return f"""
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene cluttered {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, 0) m yaw 90deg
}}

task through {{
    scene cluttered
    goal block at (0.75, 0) m within 1 cm
    search {{ max_depth {max_depth}  timeout 60 s }}
}}
"""
