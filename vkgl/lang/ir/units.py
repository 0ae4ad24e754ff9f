"""Units and dimensions: the one table the parser, checker and printer share.

Every physical value in the IR is SI. Conversion goes through exact fractions
so that the printer can find, for any SI float, the shortest decimal that the
parser converts back to the very same float.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from fractions import Fraction
from typing import Any

DIMENSION: dict[str, str] = {
    "m": "length",
    "cm": "length",
    "mm": "length",
    "rad": "angle",
    "deg": "angle",
    "kg": "mass",
    "g": "mass",
    "N": "force",
    "s": "time",
    "ms": "time",
    # Compound units of the physical joints' dynamics, written without spaces (one token each).
    "N*s/m": "linear damping",
    "N*m*s/rad": "angular damping",
    "N*m": "torque",
    "": "number",
}
SI_UNIT: dict[str, str] = {
    "length": "m",
    "angle": "rad",
    "mass": "kg",
    "force": "N",
    "time": "s",
    "linear damping": "N*s/m",
    "angular damping": "N*m*s/rad",
    "torque": "N*m",
    "number": "",
}
SCALE: dict[str, Fraction] = {
    "m": Fraction(1),
    "cm": Fraction(1, 100),
    "mm": Fraction(1, 1000),
    "rad": Fraction(1),
    "deg": Fraction(math.pi) / 180,
    "kg": Fraction(1),
    "g": Fraction(1, 1000),
    "N": Fraction(1),
    "s": Fraction(1),
    "ms": Fraction(1, 1000),
    "N*s/m": Fraction(1),
    "N*m*s/rad": Fraction(1),
    "N*m": Fraction(1),
    "": Fraction(1),
}
# How a dimension is named in messages ("expected a length").
ARTICLE_NAME: dict[str, str] = {
    "length": "a length",
    "angle": "an angle",
    "mass": "a mass",
    "force": "a force",
    "time": "a time",
    "linear damping": "a linear damping coefficient",
    "angular damping": "an angular damping coefficient",
    "torque": "a torque",
    "number": "a plain number",
}
UNITS_BY_DIMENSION: dict[str, tuple[str, ...]] = {
    "length": ("m", "cm", "mm"),
    "angle": ("deg", "rad"),
    "mass": ("kg", "g"),
    "force": ("N",),
    "time": ("s", "ms"),
    "linear damping": ("N*s/m",),
    "angular damping": ("N*m*s/rad",),
    "torque": ("N*m",),
}


MAX_EXACT_CHARS = 60
"""Longer numbers are converted through a float, not exactly (no printed number is that long)."""
MAX_EXACT_EXPONENT = 400
"""Numbers with a larger decimal exponent are 0 or infinite in every unit: converted through a float."""
_EXPONENT = re.compile(r"[eE]([+-]?[0-9]+)$")


def to_si(text: str, unit: str) -> float:
    """The SI value of the number `text` written in `unit`, correctly rounded."""
    scale = SCALE[unit]
    if scale == 1:
        return float(text)  # no digit limit, and fast for any exponent
    exponent = _EXPONENT.search(text)
    if len(text) > MAX_EXACT_CHARS or (exponent is not None and abs(int(exponent.group(1))) > MAX_EXACT_EXPONENT):
        # Exact conversion would build integers of the exponent's size (`1e-99999999`) or of
        # more than 4300 digits (which Python refuses); such values are out of any range anyway.
        return float(text) * float(scale)
    return float(Fraction(text) * scale)


def dimension_of(unit: str) -> str:
    """The dimension of a unit ("" is a plain number)."""
    return DIMENSION[unit]


def unit_list(dimension: str) -> str:
    """The units of a dimension, for messages: "m, cm or mm"."""
    units = [f"`{u}`" for u in UNITS_BY_DIMENSION.get(dimension, ())]
    if len(units) <= 1:
        return "".join(units)
    return ", ".join(units[:-1]) + " or " + units[-1]


def measured_repr(field: str) -> Callable[[Any], str]:
    """The `__repr__` of a node holding SI `field` and the `unit` it was written in: `Quantity(0.01 m, written 1
    cm)`, not pydantic's `Quantity(value=0.01, unit='cm')`, which reads as 0.01 cm."""

    def show(node: Any) -> str:
        value = getattr(node, field)
        values = tuple(value) if isinstance(value, tuple) else (value,)
        return f"{type(node).__name__}({si_and_written(values, node.unit)})"

    return show


def si_and_written(values: tuple[float, ...], unit: str) -> str:
    """`0.01 m, written 1 cm`: SI values with their unit, then as the source wrote them (IR nodes' repr)."""

    def show(numbers: tuple[float, ...]) -> str:
        text = ", ".join(f"{v:.10g}" for v in numbers)
        return text if len(numbers) == 1 else f"({text})"

    dimension = DIMENSION.get(unit)
    si = SI_UNIT.get(dimension, "") if dimension is not None else unit
    shown = f"{show(values)} {si}".rstrip()
    if dimension is None or unit == si:
        return shown
    scale = float(SCALE[unit])
    return f"{shown}, written {show(tuple(v / scale for v in values))} {unit}"
