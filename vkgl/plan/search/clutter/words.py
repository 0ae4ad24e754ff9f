"""The clear-first walk's words (`vkgl.plan.search.clutter.clear_first`): where a blocker was cleared to, a clearing
search's closest miss, and how a combined plan was found and whether it is shortest."""

from __future__ import annotations

from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.search.clutter.tool_path import PathSide
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import closest_miss
from vkgl.plan.task_space.clearing import Side


def side_words(blocker: str, side: Side) -> str:
    """Where `blocker` was cleared to, in words: a side of the way, or out of a tool's path (`PathSide`)."""
    return f"{blocker} {side.words}" if isinstance(side, PathSide) else f"{blocker} {side.words} of the way"


def closest(found: SearchResult) -> str:
    """The closest miss of a search for a plan that clears a blocker, in words (" (closest: ...)"), or "": what
    a user needs to see why the blocker could not be moved there (the hand a few millimetres beyond the arm's
    reach, the blocker through the goal body)."""
    _, why = closest_miss(found.stats)
    return f" (closest: {why})" if why else ""


def plan_words(moved: str, prefix: Sequence, depth: int, proven: int) -> str:
    """How the plan was found, and whether it is proven shortest."""
    shortest = (
        f"a shortest plan (no plan of at most {proven} graphs exists)"
        if depth <= proven + 1
        else f"not proven shortest (no plan of at most {proven} graphs exists; this one has {depth})"
    )
    return (
        f"cleared the way first: {moved} (a plan of {prefix.depth} graphs), then the goal from there, {depth} "
        f"graphs in all: {shortest}"
    )


__all__ = ["closest", "plan_words", "side_words"]
