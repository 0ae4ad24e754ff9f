"""The "no plan" reason (`vkgl.plan.search.stats.infeasible_reason`): a rejection that decides and says what to
change is said first; otherwise the counts lead, and what to change follows its closest miss."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.stats import SearchStats, decisive, infeasible_reason, timeout_reason

_PROBLEM: Any = SimpleNamespace(max_depth=4)
_GRIP = Rejection(Kind.GRIP, "bar would slip in the hand: ... 947% of the grip", 16.5, advice="for the grip: lighter")
_REACH = Rejection(Kind.REACH, "the hand would be 1.100 m from the arm's base", 0.3)


def _stats(*rejections: tuple[Rejection, int]) -> SearchStats:
    stats = SearchStats()
    for rejection, times in rejections:
        for _ in range(times):
            stats.reject(rejection, "add SteelBar.wield on bar with arm.fingertip")
    return stats


def test_the_grip_that_decides_is_said_first_with_what_to_change() -> None:
    stats = _stats((_REACH, 5), (_GRIP, 1))
    assert decisive(stats) == Kind.GRIP
    lines = infeasible_reason(_PROBLEM, stats, bound=None).splitlines()  # type: ignore[arg-type]
    assert lines[0] == f"no sequence of at most 4 graphs reaches the goal: {_GRIP.why}"
    assert lines[1] == "  for the grip: lighter"
    assert lines[2].startswith(f"  rejected: 1 {Kind.GRIP.words}, 5 needed")
    assert "    why: as said first" in lines and sum("947%" in line for line in lines) == 1


def test_a_grip_that_does_not_lead_keeps_the_counts_first_and_its_advice_after_its_why() -> None:
    collision = Rejection(Kind.COLLISION, "the arm would hit block", 0.01)
    stats = _stats((collision, 3), (_GRIP, 1))  # the same stage, collisions more often: they lead
    assert decisive(stats) is None
    lines = infeasible_reason(_PROBLEM, stats, bound=None).splitlines()  # type: ignore[arg-type]
    assert lines[0].startswith("no sequence of at most 4 graphs reaches the goal: 3 would make a body pass")
    at = lines.index("    why: bar would slip in the hand: ... 947% of the grip")
    assert lines[at + 1] == "    for the grip: lighter"


def test_a_timeout_whose_closest_miss_is_the_grip_says_what_to_change() -> None:
    stats = _stats((_REACH, 2), (_GRIP, 1))
    reason = timeout_reason(SimpleNamespace(max_depth=4, timeout=20.0), stats)  # type: ignore[arg-type]
    assert (
        "why the closest miss failed: bar would slip in the hand: ... 947% of the grip\nfor the grip: lighter\n"
        in reason
    )


def test_a_rejections_label_is_made_only_when_it_becomes_the_example() -> None:
    """The search names a pruned child by its whole sequence, made lazily: thousands are pruned, few kept."""
    made: list[str] = []

    def label(words: str) -> Any:
        return lambda: made.append(words) or words

    stats = SearchStats()
    stats.reject(_REACH, label("add Stick.wield on stick with arm.fingertip -> add Block.push on block with stick.tip"))
    stats.reject(_REACH, label("farther"))  # not closer: never made
    closer = Rejection(Kind.REACH, "the hand would be 0.9 m from the arm's base", 0.1)
    stats.reject(closer, label("closer"))
    assert made == ["add Stick.wield on stick with arm.fingertip -> add Block.push on block with stick.tip", "closer"]
    assert stats.examples[Kind.REACH][1] == "closer"
