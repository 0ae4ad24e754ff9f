"""The words of VKG, read from the Lark grammar so that highlighters cannot drift from it.

`keywords()` is every string terminal of `grammar/vkg.lark` made of letters
(`body`, `goal`, `x`, ...); `units()` the alternatives of its `UNIT` terminal.
The groups below only sort keywords into highlighting categories; a test checks
that each group holds grammar keywords only, and the lexer and the TextMate
grammar put every keyword that no group claims in the plain keyword class.
"""

from __future__ import annotations

import re
from functools import lru_cache

from lark import Lark
from lark.lexer import PatternRE, PatternStr

from vkgl.resources import grammar_path

# Keywords that open a declaration or a named block; the name after them is a definition.
DECLARATIONS: tuple[str, ...] = (
    "use",
    "body",
    "robot",
    "affordances",
    "affordance",
    "correspondences",
    "scene",
    "task",
    "explore",
)
# Keywords that name a kind of thing: shapes, joint and constraint types.
TYPES: tuple[str, ...] = (
    "box",
    "cylinder",
    "mesh",
    "union",
    "prismatic",
    "revolute",
    "fixed",
    "free",
    "grasp",
)

NAME_PATTERN = r"[A-Za-z_][A-Za-z0-9_]*"
NUMBER_PATTERN = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
FACE_PATTERN = r"[+-][xyz](?![A-Za-z0-9_])"


@lru_cache(maxsize=1)
def _grammar() -> Lark:
    return Lark(grammar_path().read_text(encoding="utf-8"), parser="lalr", lexer="contextual")


@lru_cache(maxsize=1)
def keywords() -> tuple[str, ...]:
    """Every keyword of the grammar (string terminals that are identifiers), sorted."""
    words = {
        t.pattern.value
        for t in _grammar().terminals
        if isinstance(t.pattern, PatternStr) and t.pattern.value.isidentifier()
    }
    return tuple(sorted(words))


@lru_cache(maxsize=1)
def units() -> tuple[str, ...]:
    """The unit words of the grammar's `UNIT` terminal, longest first (so `ms` is tried before `m`)."""
    for terminal in _grammar().terminals:
        if terminal.name == "UNIT" and isinstance(terminal.pattern, PatternRE):
            # Alternatives are words or compounds such as `N\*s\/m` (escaped in the regex).
            group = re.search(r"\(((?:[A-Za-z|]|\\[*/])+)\)", terminal.pattern.value)
            if group:
                words = [w.replace("\\", "") for w in group.group(1).split("|")]
                return tuple(sorted(words, key=lambda u: (-len(u), u)))
    raise LookupError(f"{grammar_path()}: no UNIT terminal of the form /(u1|u2|...)/")


def plain_keywords() -> tuple[str, ...]:
    """The keywords that are neither declarations nor types."""
    special = set(DECLARATIONS) | set(TYPES)
    return tuple(w for w in keywords() if w not in special)
