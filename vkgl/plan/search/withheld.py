"""The contacts a search withholds: bodies kept still until a rejected sequence names one (`search(still=...)`).

`vkgl.plan.search.clutter.still` keeps still the bodies that lie in no goal body's way: the search makes no
contact on them (`withholds`) until a check's rejection names one (`Rejection.bodies`, gathered in
`SearchStats.met`). From then on the body's contacts are successors like any other, and those withheld from the
sequences already expanded are made at once (`Withheld.bring_back`), each with the successor index it would have
had among all the successors (`search._expand(only=...)`), so with the key it would have had.

Why the plan stays a shortest one. Call open the sequences that make no contact on a body still withheld. At
any time every open sequence not yet made has an open ancestor in the queue, not yet expanded: so it is in the
search that withholds nothing, and so it stays here, since a sequence expanded while a body was withheld gets its
children on that body queued as soon as the body is met. Every ancestor of an open plan of `d` graphs has a key
(its depth plus the admissible bound) of at most `d`, so it leaves the queue before any sequence of a larger key:
a plan found is a shortest among the open sequences of that time (the argument of `vkgl.plan.search.search._Entry`).
A child queued late whose key is below the level the search had reached is taken next, the level going back for
it. The checks made before a meeting keep their outcome (the body met stood where it stands, counted in every
collision check): none is made again.
"""

from __future__ import annotations

from vkgl.plan.graphs.graph import Action
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.search.stats import SearchStats


def withholds(action: Action, bodies: frozenset[str]) -> bool:
    """Whether `action` makes a contact on one of `bodies`."""
    return action.op == "add" and action.engagement.body in bodies


class Withheld:
    """The bodies whose contacts a search withholds (`bodies`: fewer as they are met), and the sequences it
    expanded while some were (with the successor indices that made them)."""

    def __init__(self, still: frozenset[str]) -> None:
        self.bodies = still
        self._expanded: list[tuple[Sequence, tuple[int, ...]]] = []

    def expanded(self, seq: Sequence, path: tuple[int, ...]) -> None:
        """Note `seq` (reached by the successor indices `path`), just expanded without the bodies' contacts."""
        if self.bodies:
            self._expanded.append((seq, path))

    def bring_back(self, stats: SearchStats) -> list[tuple[Sequence, tuple[int, ...], frozenset[str]]]:
        """The bodies `stats` met since the last call are withheld no more: every sequence expanded while they
        were, with its path and those bodies (whose contacts the caller makes as its children now)."""
        met = self.bodies & stats.met
        if not met:
            return []
        self.bodies -= met
        again = [(seq, path, met) for seq, path in self._expanded]
        if not self.bodies:
            self._expanded.clear()
        return again


__all__ = ["Withheld", "withholds"]
