"""A note for a position off the table that a smaller length unit would put on it.

`goal puck at (600, 100) m` is 600 m away, but `(600, 100) mm` lies on the table: the writer meant
millimetres. E421 and E423 then say so, instead of leaving the reader to spot a unit among the numbers.
"""

from __future__ import annotations

import math

from vkgl.lang.checks.geometry.placed import Table
from vkgl.lang.checks.geometry.placed import m as _m
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import SCALE

FAR_FACTOR = 3.0
"""A position is a unit slip only this many table diagonals or more from the table's centre: a goal just past
the edge is a goal just past the edge, not a unit written wrong."""
SMALLER = {"m": ("cm", "mm"), "cm": ("mm",)}
"""Length units, and the smaller ones a writer may have meant instead, nearest first."""


def unit_slip_note(position: ir.Vector, table: Table) -> str:
    """`did you mean `mm`? ...` when `position`, written in one unit, lies on the table in a smaller one; else ''."""
    if len(position.values) < 2 or not _far(position.values[0], position.values[1], table):
        return ""
    for unit in SMALLER.get(position.unit, ()):
        scale = float(SCALE[unit] / SCALE[position.unit])
        x, y = (v * scale for v in position.values[:2])
        if table.low[0] <= x <= table.high[0] and table.low[1] <= y <= table.high[1]:
            a, b = (float(v / SCALE[position.unit]) for v in position.values[:2])
            return f"did you mean `{unit}`? `({a:g}, {b:g}) {unit}` is ({_m(x)}, {_m(y)}) m, on the table"
    return ""


def _far(x: float, y: float, table: Table) -> bool:
    centre = ((table.low[0] + table.high[0]) / 2, (table.low[1] + table.high[1]) / 2)
    diagonal = math.hypot(table.high[0] - table.low[0], table.high[1] - table.low[1])
    return math.hypot(x - centre[0], y - centre[1]) > FAR_FACTOR * diagonal
