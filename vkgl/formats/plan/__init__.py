"""The `vkg-plan/8` document: the one definition of the plan format, its only reader and
writer (`document`: the types; `writing`; `reading`).

docs/formats.md is the contract. In memory a plan document is a tree of frozen
dataclasses (`PlanDocument` > `PlanRobot`, `PlanStats`, `PlanStepRecord`) with
poses as 4x4 numpy arrays; `to_json` gives the plain data that `vkgc solve
--json` writes, `from_json` checks every field of such data and builds the
document, raising `PlanFormatError` with the JSON path of the first bad field
(`steps[2].poses_start.block: expected a 4x4 matrix of finite numbers`).

    from vkgl.formats import plan as plan_format
    doc = plan_format.read("a_push.json")
    plan_format.write("copy.json", doc)

Numbers are written rounded to 1e-12 (poses without negative zeros), so that
runs whose products differ only in their last bits give the same file. The
documents compare by identity; compare `to_json(a) == to_json(b)` for content.
"""

from vkgl.errors import PlanFormatError
from vkgl.formats.plan.document import (
    MOTIONS,
    OLDER_READABLE,
    OPS,
    PHASES,
    PLAN_FORMAT,
    SAME_LAYOUT,
    STATUSES,
    ArmSegment,
    Edge,
    PlanDocument,
    PlanRobot,
    PlanStats,
    PlanStepRecord,
    Poses,
)
from vkgl.formats.plan.reading import from_json, read
from vkgl.formats.plan.writing import dumps, matrix_json, rounded, to_json, write

__all__ = [
    "MOTIONS",
    "OLDER_READABLE",
    "OPS",
    "PHASES",
    "PLAN_FORMAT",
    "SAME_LAYOUT",
    "STATUSES",
    "ArmSegment",
    "Edge",
    "PlanDocument",
    "PlanFormatError",
    "PlanRobot",
    "PlanStats",
    "PlanStepRecord",
    "Poses",
    "dumps",
    "from_json",
    "matrix_json",
    "read",
    "rounded",
    "to_json",
    "write",
]
