"""Comparing JSON documents of computed numbers: floats within a tolerance, everything else exactly.

Golden files of computed results (plans, reports) cannot be compared byte for byte: the same code gives
results that differ in the last bits on another CPU. numpy picks SIMD kernels (AVX2, AVX-512) and OpenBLAS
picks matrix kernels by the CPU it runs on, and each sums and rounds in its own order.

`REL` and `ABS` say how far apart two floats may be: `|a - b| <= max(REL * max(|a|, |b|), ABS)`.

- `REL = 1e-7`: for values computed in closed form (products of transforms, sums), another summation
  order or a vectorised sine moves a result by a few units in the last place per operation, 1e-13 after
  hundreds of them; 1e-7 leaves a million times that, and is still far below anything physical (0.1 um
  on a metre). The example plans' task-space numbers agree to the bit between two CPUs.
- `ABS = 1e-8`, the floor for values near zero, where a relative bound means nothing: a pose's
  off-diagonal rotation entries are sums whose terms cancel and keep the absolute error of their terms.
  The values are SI (metres, radians, seconds), so 1e-8 is 10 nm or 10 nanoradians.

Values that come out of an iterative solver stopped at a tolerance (IK, optimisers) differ between CPUs
by up to that tolerance, not by rounding: give them a comparison of their own with `by_path` (the plan's
joint values do: tests/support/checkers/plan_close.py).

Everything that is not a float is compared exactly: strings, integers (counts are not floats), booleans,
null, the keys of objects in their order (the order is part of the file), the length of lists. An integer
never equals a float: `1` where `1.0` was written is a change of type.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from typing import Any

Comparer = Callable[[Any, Any, str], list[str]]
"""A comparison of its own for one field: (actual, expected, path) -> the differences, one line each."""

REL = 1e-7
ABS = 1e-8


def floats_close(a: float, b: float, *, rel: float = REL, abs_: float = ABS) -> bool:
    """Whether two floats agree within `rel` (relative) or `abs_` (absolute floor); NaN equals NaN."""
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= max(rel * max(abs(a), abs(b)), abs_)


def json_differences(
    actual: Any,
    expected: Any,
    *,
    rel: float = REL,
    abs_: float = ABS,
    by_path: Mapping[str, Comparer] | None = None,
    limit: int = 20,
) -> list[str]:
    """Where two parsed JSON values differ, one line per difference (`path: what`), at most `limit` lines.

    Paths are written as in the plan format's errors: `steps[1].q_end[2]`. `by_path` gives some fields
    a comparison of their own, in place of the numbers' tolerance: its keys are paths with the list
    indices left out (`steps[].q_end` stands for every step's `q_end`).
    """
    found: list[str] = []
    _Walk(rel, abs_, dict(by_path or {}), found, limit).compare(actual, expected, "")
    return found[:limit]


def assert_json_close(
    actual: Any,
    expected: Any,
    *,
    rel: float = REL,
    abs_: float = ABS,
    by_path: Mapping[str, Comparer] | None = None,
    what: str = "the JSON",
) -> None:
    """Fail, listing the differences (up to 20), unless `actual` and `expected` agree as `json_differences` says."""
    differences = json_differences(actual, expected, rel=rel, abs_=abs_, by_path=by_path)
    if differences:
        head = f"{what} differs (floats within {rel:g} relative or {abs_:g} absolute)"
        raise AssertionError(head + ":\n  " + "\n  ".join(differences))


def _where(path: str) -> str:
    return path or "(the document)"


class _Walk:
    """One comparison's settings and the differences found so far."""

    def __init__(self, rel: float, abs_: float, by_path: dict[str, Comparer], found: list[str], limit: int) -> None:
        self.rel, self.abs_, self.by_path, self.found, self.limit = rel, abs_, by_path, found, limit

    def compare(self, actual: Any, expected: Any, path: str) -> None:
        if len(self.found) >= self.limit:
            return
        if type(actual) is not type(expected):
            self.found.append(f"{_where(path)}: {_show(actual)} where {_show(expected)} was expected (another type)")
        elif isinstance(expected, dict):
            self.compare_objects(actual, expected, path)
        elif isinstance(expected, list):
            if len(actual) != len(expected):
                self.found.append(f"{_where(path)}: {len(actual)} items where {len(expected)} were expected")
                return
            for k, (a, e) in enumerate(zip(actual, expected, strict=True)):
                self.compare(a, e, f"{path}[{k}]")
        elif isinstance(expected, float):
            if not floats_close(actual, expected, rel=self.rel, abs_=self.abs_):
                off = abs(actual - expected)
                self.found.append(f"{_where(path)}: {actual!r} where {expected!r} was expected (off by {off:.3g})")
        elif actual != expected:
            self.found.append(f"{_where(path)}: {_show(actual)} where {_show(expected)} was expected")

    def compare_objects(self, actual: dict[str, Any], expected: dict[str, Any], path: str) -> None:
        if list(actual) != list(expected):
            missing = [k for k in expected if k not in actual]
            extra = [k for k in actual if k not in expected]
            detail = f"missing {missing}, unexpected {extra}" if missing or extra else "the same keys in another order"
            self.found.append(f"{_where(path)}: keys {list(actual)} where {list(expected)} were expected ({detail})")
        for key in expected:
            if key not in actual:
                continue
            where = f"{path}.{key}" if path else key
            own = self.by_path.get(re.sub(r"\[\d+\]", "[]", where))
            if own is not None:
                self.found.extend(own(actual[key], expected[key], where))
            else:
                self.compare(actual[key], expected[key], where)


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
