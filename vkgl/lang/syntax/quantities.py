"""Numbers, quantities, vectors and poses as canonical VKG text (the printer's values).

Numbers are printed with the shortest decimal that the parser converts back to
the very same SI float in the unit the user wrote (`format_scaled`), using the
unit table of vkgl/lang/ir/units.py.
"""

from __future__ import annotations

import math
from fractions import Fraction

from vkgl.lang.ir.nodes import Family, Joint, MotionRange, Pose, Quantity, Vector
from vkgl.lang.ir.units import DIMENSION, SCALE, SI_UNIT, to_si


def format_number(value: float) -> str:
    """A dimensionless float as the shortest decimal that reads back as the same float.

    Integers have no `.0` (`3`, not `3.0`); very large or small magnitudes use
    scientific notation without a `+` (`1e-05` is written `1e-5`).
    """
    _require_finite(value)
    if value == 0:
        return "0"
    # repr is the shortest text that round-trips through a correctly rounded read.
    return _decimal_text(Fraction(repr(value)))


def format_scaled(value: float, unit: str) -> str | None:
    """The shortest decimal `t` with `to_si(t, unit) == value`, or None if there is none.

    The search runs over the decimals nearest `value / scale` with 1, 2, ...
    significant digits, keeps those inside the exact interval of reals that
    round to `value`, and confirms the winner with the parser's own conversion.
    """
    _require_finite(value)
    if value == 0:
        return "0"
    scale = _exact_scale(unit)
    if scale == 1:
        text = format_number(value)
        return text if to_si(text, unit) == value else None
    sign = "-" if value < 0 else ""
    magnitude = abs(value)
    low, high = _rounding_interval(magnitude)
    low, high, target = low / scale, high / scale, Fraction(magnitude) / scale
    top = _exponent10(target)
    for digits in range(1, 41):
        exponent = top - digits + 1
        below = _floor_scaled(target, exponent)
        candidates = [m for m in (below, below + 1) if m > 0 and low <= _times_ten(m, exponent) <= high]
        candidates.sort(key=lambda m: abs(_times_ten(m, exponent) - target))
        for mantissa in candidates:
            text = sign + _digits_text(mantissa, exponent)
            if to_si(text, unit) == value:
                return text
    return None


def _rounding_interval(x: float) -> tuple[Fraction, Fraction]:
    """The reals that round to the positive float `x` lie in [low, high] (ends by round-half-even)."""
    down = Fraction(math.nextafter(x, 0.0))
    up = math.nextafter(x, math.inf)
    up_exact = Fraction(up) if math.isfinite(up) else Fraction(x) + Fraction(math.ulp(x))
    exact = Fraction(x)
    return (exact + down) / 2, (exact + up_exact) / 2


def _times_ten(mantissa: int, exponent: int) -> Fraction:
    return Fraction(mantissa * 10**exponent) if exponent >= 0 else Fraction(mantissa, 10**-exponent)


def _floor_scaled(x: Fraction, exponent: int) -> int:
    """floor(x / 10**exponent)."""
    if exponent >= 0:
        return x.numerator // (x.denominator * 10**exponent)
    return x.numerator * 10**-exponent // x.denominator


def _require_finite(value: float) -> None:
    if not math.isfinite(value):
        raise ValueError(f"cannot print the non-finite number {value!r} in VKG source")


def _exact_scale(unit: str) -> Fraction:
    if unit not in SCALE:
        raise ValueError(f"unknown unit `{unit}`")
    return Fraction(SCALE[unit])


def _exponent10(x: Fraction) -> int:
    """floor(log10(x)) for x > 0, exactly."""
    e = len(str(x.numerator)) - len(str(x.denominator))
    while _times_ten(1, e) > x:
        e -= 1
    while _times_ten(1, e + 1) <= x:
        e += 1
    return e


def _decimal_text(x: Fraction) -> str:
    """A terminating decimal `x` as text (see `_digits_text`)."""
    if x == 0:
        return "0"
    sign = "-" if x < 0 else ""
    x = abs(x)
    twos, fives = _power_of(x.denominator, 2), _power_of(x.denominator, 5)
    if x.denominator != 2**twos * 5**fives:
        raise ValueError(f"{x} is not a terminating decimal")
    shift = max(twos, fives)
    return sign + _digits_text(x.numerator * 10**shift // x.denominator, -shift)


def _digits_text(mantissa: int, exponent: int) -> str:
    """mantissa * 10**exponent (mantissa > 0) as text: positional for 1e-4 <= x < 1e16, else `1.5e-7`."""
    while mantissa % 10 == 0:
        mantissa, exponent = mantissa // 10, exponent + 1
    digits = str(mantissa)
    lead = len(digits) - 1 + exponent
    if lead < -4 or lead >= 16:
        fraction = "." + digits[1:] if len(digits) > 1 else ""
        return f"{digits[0]}{fraction}e{lead}"
    if exponent >= 0:
        return digits + "0" * exponent
    point = len(digits) + exponent
    if point > 0:
        return f"{digits[:point]}.{digits[point:]}"
    return f"0.{'0' * -point}{digits}"


def _power_of(n: int, p: int) -> int:
    k = 0
    while n % p == 0:
        n, k = n // p, k + 1
    return k


def _si_unit(unit: str) -> str:
    """The SI unit of `unit`'s dimension (the unit whose scale is 1)."""
    return SI_UNIT[DIMENSION[unit]]


def _number_in(value: float, unit: str) -> tuple[str, str]:
    """(text, unit) for a value in the display unit `unit`; falls back to the SI unit
    only if no decimal converts back exactly (cannot happen with an exact conversion)."""
    text = format_scaled(value, unit)
    if text is not None:
        return text, unit
    si = _si_unit(unit)
    return format_number(value), si


def _with_unit(text: str, unit: str) -> str:
    # A scalar angle in degrees reads like `90deg` (as docs/language.md writes yaws);
    # everything else is spaced: `10 cm`, `(0, 0, 90) deg`.
    if not unit:
        return text
    return f"{text}{unit}" if unit == "deg" and not text.startswith("(") else f"{text} {unit}"


def quantity_text(q: Quantity) -> str:
    """`10 cm`, `90deg`, `0.5 kg`: the value in its display unit."""
    text, unit = _number_in(q.value, q.unit)
    return _with_unit(text, unit)


def vector_text(v: Vector) -> str:
    """`(10, 20, 5) cm` or `(1, 0, 0)`; all components in the vector's display unit."""
    texts = [format_scaled(x, v.unit) for x in v.values]
    unit = v.unit
    if any(t is None for t in texts):
        unit = _si_unit(v.unit)
        texts = [format_number(x) for x in v.values]
    return _with_unit("(" + ", ".join(texts) + ")", unit)  # type: ignore[arg-type]


def pair_text(lower: Quantity, upper: Quantity) -> str:
    """Joint limits `(0, 30) cm`; both in one unit when they share it."""
    if lower.unit == upper.unit:
        return vector_text(Vector(values=(lower.value, upper.value), unit=lower.unit))
    return f"({quantity_text(lower)}, {quantity_text(upper)})"


def pose_text(p: Pose) -> str:
    """`(x, y, z) UNIT [yaw Q | rpy (r, p, y) UNIT]`."""
    text = vector_text(p.position)
    if p.yaw is not None:
        text += " yaw " + quantity_text(p.yaw)
    elif p.rpy is not None:
        text += " rpy " + vector_text(p.rpy)
    return text


def string_text(s: str) -> str:
    """A double-quoted string literal."""
    if any(ch in s for ch in '"\\\n\r'):
        raise ValueError(f"cannot write the string {s!r} as a VKG literal (quote, backslash or newline)")
    return f'"{s}"'


def range_text(r: MotionRange | None) -> str:
    """` range 0 to 24 cm` (one unit written once when both bounds have it), ` ... open` when open, "" for none."""
    if r is None:
        return ""
    lower = format_scaled(r.lower.value, r.lower.unit) if r.lower.unit == r.upper.unit else None
    text = f" range {lower if lower is not None else quantity_text(r.lower)} to {quantity_text(r.upper)}"
    return text + " open" if r.open else text


def family_text(f: Family) -> str:
    """`family along V from LO to HI UNIT [drift V] [arc lever Q bias Q ahead Q [beyond Q]] [sigma Q]` (one unit
    written once when both bounds have it)."""
    lower = format_scaled(f.lower.value, f.lower.unit) if f.lower.unit == f.upper.unit else None
    text = f"family along {vector_text(f.along)} from {lower if lower is not None else quantity_text(f.lower)}"
    text += f" to {quantity_text(f.upper)}"
    if f.drift is not None:
        text += " drift " + vector_text(f.drift)
    if f.arc is not None:
        a = f.arc
        text += f" arc lever {quantity_text(a.lever)} bias {quantity_text(a.bias)} ahead {quantity_text(a.ahead)}"
        if a.beyond is not None:
            text += f" beyond {quantity_text(a.beyond)}"
    return text if f.sigma is None else text + " sigma " + quantity_text(f.sigma)


def joint_text(j: Joint) -> str:
    """`prismatic axis V [through P] limits (lo, hi) UNIT [damping Q] [friction Q]` (after `joint`)."""
    text = f"{j.type} axis {vector_text(j.axis)}"
    if j.through is not None:
        text += " through " + vector_text(j.through)
    text += " limits " + pair_text(j.lower, j.upper)
    if j.damping is not None:
        text += " damping " + quantity_text(j.damping)
    if j.friction is not None:
        text += " friction " + quantity_text(j.friction)
    return text
