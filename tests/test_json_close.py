"""tests/support/checkers/json_close.py: floats within a tolerance, everything else exactly, each difference by
its path."""

from __future__ import annotations

import math
from typing import Any

from checkers.json_close import ABS, REL, assert_json_close, floats_close, json_differences
from hypothesis import given
from hypothesis import strategies as st

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
leaves = st.one_of(finite, st.integers(-5, 5), st.text(max_size=4), st.booleans(), st.none())
documents = st.recursive(
    leaves,
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=3), inner, max_size=4)),
    max_leaves=30,
)


def _scaled(value: Any, factor: float) -> Any:
    if isinstance(value, dict):
        return {k: _scaled(v, factor) for k, v in value.items()}
    if isinstance(value, list):
        return [_scaled(v, factor) for v in value]
    return value * factor if isinstance(value, float) else value


@given(documents)
def test_a_document_matches_itself_and_itself_perturbed_by_1e_9(document: Any) -> None:
    assert json_differences(document, document) == []
    assert json_differences(_scaled(document, 1.0 + 1e-9), document) == []


@given(st.floats(min_value=0.1, max_value=1e6))  # above ABS / (10 REL): the relative bound decides
def test_a_float_off_by_more_than_the_tolerance_is_named_by_its_path(value: float) -> None:
    expected = {"steps": [{"value": value}]}
    actual = {"steps": [{"value": value * (1 + 10 * REL)}]}
    (line,) = json_differences(actual, expected)
    assert line.startswith("steps[0].value: ")


def test_near_zero_the_absolute_floor_decides() -> None:
    assert floats_close(0.0, ABS / 2) and not floats_close(0.0, ABS * 2)
    assert floats_close(math.nan, math.nan) and not floats_close(math.nan, 0.0)
    assert floats_close(math.inf, math.inf) and not floats_close(math.inf, 1e308)


def test_everything_but_floats_is_compared_exactly() -> None:
    assert json_differences({"a": 1, "b": 2}, {"b": 2, "a": 1}) == [
        "(the document): keys ['a', 'b'] where ['b', 'a'] were expected (the same keys in another order)"
    ]
    assert json_differences({"n": 1}, {"n": 1.0}) == ["n: 1 where 1.0 was expected (another type)"]
    assert json_differences(["x", [1.0]], ["y", [1.0, 2.0]]) == [
        "[0]: 'x' where 'y' was expected",
        "[1]: 1 items where 2 were expected",
    ]
    assert json_differences({"a": 1}, {"b": 1}) == [
        "(the document): keys ['a'] where ['b'] were expected (missing ['b'], unexpected ['a'])"
    ]


def test_a_field_may_have_a_comparison_of_its_own() -> None:
    def never(actual: Any, expected: Any, path: str) -> list[str]:
        return [f"{path}: compared its own way"]

    found = json_differences(
        {"s": [{"q": [0.0]}, {"q": [9.0]}]}, {"s": [{"q": [0.0]}, {"q": [0.0]}]}, by_path={"s[].q": never}
    )
    assert found == ["s[0].q: compared its own way", "s[1].q: compared its own way"]


def test_the_assertion_lists_the_differences() -> None:
    try:
        assert_json_close({"x": 1.0}, {"x": 2.0}, what="the report")
    except AssertionError as error:
        assert "the report differs" in str(error) and "x: 1.0 where 2.0 was expected" in str(error)
    else:
        raise AssertionError("no difference reported")
