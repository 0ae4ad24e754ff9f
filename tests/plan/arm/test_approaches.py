"""The ways into a contact: the three rules first, then a bounded, ordered search; how each is left again."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from vkgl.motion.moves import STANDOFF, way_out
from vkgl.plan.arm.approaches import (
    CONE_ANGLES,
    LONG_STANDOFF,
    MAX_SEARCHED,
    SHORT_STANDOFF,
    Way,
    rules,
    searched,
    summary,
)

PUSH = np.array([-1.0, 0.0, 0.0])  # a pull toward the arm's base, as behind a drawer's handle bar


def angle(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1.0, 1.0))))


def test_the_three_rules_come_first_and_unchanged():
    along, above, slanted = rules(PUSH)
    assert np.allclose(along.direction, PUSH) and along.standoff == STANDOFF
    assert np.allclose(above.direction, [0, 0, -1])
    assert angle(slanted.direction, PUSH) == pytest.approx(30.0)
    assert slanted.direction[2] < 0  # from above and behind


def test_the_search_is_bounded_ordered_and_new():
    ways = searched(PUSH)
    assert len(ways) == MAX_SEARCHED
    assert all(np.linalg.norm(w.direction) == pytest.approx(1.0) for w in ways)
    cone = [w for w in ways if "cone" in w.family]
    assert len(cone) == 16
    # closest to the push first: every way of the 20 deg ring before the 40 deg ring, then the sides (90 deg)
    offs = [angle(w.direction, PUSH) for w in cone]
    assert offs == sorted(offs)
    assert {round(o) for o in offs} == {round(np.degrees(a)) for a in CONE_ANGLES}
    assert cone[0].direction[2] < 0 and cone[7].direction[2] > 0  # from above first, from below last
    side = [w for w in ways if "side along the bar" in w.family]
    assert len(side) == 6
    assert all(angle(w.direction, PUSH) == pytest.approx(90.0) for w in side)
    assert sum(abs(w.direction[2]) < 1e-9 for w in side) == 2  # level, either end; then higher and lower
    assert {w.standoff for w in ways} == {STANDOFF, SHORT_STANDOFF, LONG_STANDOFF}
    # none repeats a rule (same direction and stand-off)
    for rule in rules(PUSH):
        assert not any(np.allclose(w.direction, rule.direction) and w.standoff == rule.standoff for w in ways)
    again = searched(PUSH)  # deterministic
    assert [w.name for w in again] == [w.name for w in ways]
    assert all(np.array_equal(a.direction, b.direction) for a, b in zip(ways, again))


@given(st.floats(-np.pi, np.pi), st.floats(-1.2, 1.2))
def test_the_search_works_for_any_push(yaw, pitch):
    push = np.array([np.cos(pitch) * np.cos(yaw), np.cos(pitch) * np.sin(yaw), np.sin(pitch)])
    ways = searched(push)
    assert len(ways) == MAX_SEARCHED
    assert all(np.isfinite(w.direction).all() and np.linalg.norm(w.direction) == pytest.approx(1.0) for w in ways)
    # the bar's axis is horizontal and across the push
    side = next(w.direction for w in ways if w.name.startswith("from the side along the bar, from one end"))
    assert abs(side[2]) < 1e-9 and abs(side @ push) < 1e-9


def test_the_summary_counts_what_was_tried():
    tried = rules(PUSH) + searched(PUSH)
    words = summary(tried)
    assert words.startswith("tried 31 approaches: along the push, from above, 30 deg below the push, ")
    assert "16 in a 40 deg cone about the push" in words
    assert "6 from the side along the bar (level, higher and lower)" in words
    assert "4 with a shorter stand-off (1.5 cm)" in words and "2 with a longer stand-off (6 cm)" in words
    assert summary([Way("along the push", "along the push", PUSH)]) == "tried 1 approach: along the push"


def test_each_way_is_left_by_the_rule_execution_follows():
    """Straight up after coming down, back against the push after coming in near it, else back out the way it
    came: never back against the push after coming in from the side (the hand would sweep along the bar)."""
    along, above, slanted = rules(PUSH)
    assert way_out(along.direction, PUSH) == "back"
    assert way_out(above.direction, PUSH) == "up"
    assert way_out(slanted.direction, PUSH) == "back"
    for way in searched(PUSH):
        rule = way_out(way.direction, PUSH)
        if way.direction[2] < -np.linalg.norm(way.direction[:2]):
            assert rule == "up", way.name
        elif angle(way.direction, PUSH) < 30.0:
            assert rule == "back", way.name
        else:
            assert rule == "reverse", way.name
