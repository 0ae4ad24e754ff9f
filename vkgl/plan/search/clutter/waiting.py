"""A plan that clears the way, waiting with the search for the goals after it (`Waiting`), and what the clear-first
walk returns (`Cleared`): `vkgl.plan.search.clutter.clear_first`'s searches for the goals after its clearing plans
get a first try each, and those that spend it wait for the second round, the likeliest first (`Waiting.rank`),
where each goes on from where its first try stopped (`search(paused=)`)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Protocol

from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.clutter.words import closest as _closest
from vkgl.plan.search.clutter.words import plan_words as _words
from vkgl.plan.search.clutter.words import side_words as _side_words
from vkgl.plan.search.search import Paused, SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import Side


@dataclass(frozen=True)
class Cleared:
    """What `clear_first` did: the combined plan's search result (None: no plan found) and, in words, how it was
    found and whether it is shortest, or what was tried."""

    result: SearchResult | None
    words: str


class Walker(Protocol):
    """What a waiting search needs of the walk (`clear_first._Walk`): its searches, counters and words."""

    stats: SearchStats
    log: list[str]

    def search(
        self,
        problem: Problem,
        root: Sequence,
        budget: float,
        still: frozenset[str] = frozenset(),
        paused: Paused | None = None,
    ) -> SearchResult: ...

    def ran_out(self) -> str: ...


@dataclass
class Waiting:
    """A plan that clears the way (`prefix`, the blockers and their sides `cleared`) and the problem of the goals
    after it (`deeper`: its values pinned, or free again once proven to have no plan); `order`: when found."""

    deeper: Problem
    prefix: Sequence
    cleared: list[tuple[str, Side]]
    order: int
    paused: Paused = field(default_factory=Paused)  # its search, where the first try's budget stopped it

    def rank(self) -> tuple[bool, int, int]:
        """The order the waiting searches go in: a prefix that leaves every goal body where it lies first (one
        that pushed the goal body back to make room leaves it farther from its goal, with more to undo), then
        the shorter prefix, then the one found first."""
        moved = any(goal.body in self.prefix.dependent for goal in self.deeper.goals)
        return moved, self.prefix.depth, self.order

    def moved(self) -> str:
        """The blockers and the sides they were cleared to, in words."""
        return ", then ".join(_side_words(name, side) for name, side in self.cleared)

    def search(self, walk: Walker, budget: float) -> SearchResult:
        """The goals searched from the prefix with `budget` units: with its values pinned, and free again (moved
        farther aside where need be) when no plan keeps them."""
        result = walk.search(self.deeper, self.prefix, budget, paused=self.paused)
        if result.status == "infeasible" and self.deeper.pinned:
            self.deeper = replace(self.deeper, pinned=())
            result = walk.search(self.deeper, self.prefix, budget, paused=self.paused)
        return result

    def solved(self, walk: Walker, result: SearchResult, proven: int) -> Cleared:
        """The combined plan, with its words."""
        assert result.sequence is not None
        words = _words(self.moved(), self.prefix, result.sequence.depth, proven)
        return Cleared(replace(result, stats=walk.stats), words)

    def log(self, walk: Walker, result: SearchResult) -> None:
        """How the search for the goals after the prefix ended, in `walk.log`."""
        ended = (
            f"no plan of at most {self.deeper.max_depth} graphs" if result.status == "infeasible" else walk.ran_out()
        )
        walk.log.append(f"{self.moved()} ({self.prefix.depth} graphs), then {ended}{_closest(result)}")


__all__ = ["Cleared", "Waiting", "Walker"]
