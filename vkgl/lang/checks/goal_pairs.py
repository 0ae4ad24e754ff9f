"""Goals of one task that cannot all hold (E427).

`goal b at (0.6, 0) m within 1 mm` and `goal b at (0.7, 0) m` name two places 10 cm apart for one body: no
plan meets both, and without this check the search spends its whole timeout to say that the optimiser found
no motion values. Two goals on one body contradict each other when their positions lie farther apart than
their two position tolerances, their headings farther than their two heading tolerances, or their joint
openings farther than their two tolerances. Relative goals are compared as the pose goals they stand for
(run after `place_relative_goals`); a region goal has no single position and is not compared.
"""

from __future__ import annotations

import math
from itertools import combinations

from vkgl.lang.checks.context import CheckContext
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program

SLACK = 1e-9
"""m or rad: rounding, far below any tolerance."""


def check_goal_pairs(program: Program, ctx: CheckContext) -> None:
    """E427 for each pair of goals of a task that name one body and cannot both hold."""
    for task in program.tasks.values():
        for first, second in combinations(task.goals, 2):
            if first.body.name != second.body.name:
                continue
            why = _contradiction(first, second)
            if why:
                ctx.error(
                    codes.CONTRADICTORY_GOALS,
                    f"the goals of `{second.body.name}` cannot both hold: {why}",
                    second.span,
                    f"the other goal is at {first.span}" if first.span is not None else "",
                    "keep one of them, or widen their tolerances",
                )


def _contradiction(a: ir.Goal, b: ir.Goal) -> str:
    """Why goals `a` and `b` of one body cannot both hold, in words; '' when they can."""
    if a.position is not None and b.position is not None and a.region is None and b.region is None:
        axes = min(len(a.position.values), len(b.position.values))
        gap = math.dist(a.position.values[:axes], b.position.values[:axes])
        allowed = a.tolerance()[0] + b.tolerance()[0]
        if math.isfinite(gap) and gap > allowed + SLACK:
            return f"their positions are {gap * 100:.1f} cm apart, their tolerances allow {allowed * 100:.1f} cm"
    if a.yaw is not None and b.yaw is not None:
        turn = abs(math.remainder(float(a.yaw.value) - float(b.yaw.value), 2 * math.pi))
        allowed = a.tolerance()[1] + b.tolerance()[1]
        if math.isfinite(turn) and turn > allowed + SLACK:
            return (
                f"their headings are {math.degrees(turn):.1f} deg apart, their tolerances allow "
                f"{math.degrees(allowed):.1f} deg"
            )
    if a.opening is not None and b.opening is not None:
        gap = abs(float(a.opening.value) - float(b.opening.value))
        allowed = a.opening_tolerance() + b.opening_tolerance()
        if math.isfinite(gap) and gap > allowed + SLACK:
            angle = a.opening.unit in ("deg", "rad")
            shown = (lambda v: f"{math.degrees(v):.1f} deg") if angle else (lambda v: f"{v * 100:.1f} cm")
            return f"their openings are {shown(gap)} apart, their tolerances allow {shown(allowed)}"
    return ""
