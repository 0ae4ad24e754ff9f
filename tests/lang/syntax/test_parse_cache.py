"""The parse cache is bounded by the characters of source it holds, not by a count of texts (issue 25).

An editor sends a new text on every keystroke; a cache of 512 whole texts kept
about 8 MB per keystroke of a 48 KB document.
"""

from __future__ import annotations

import pytest

from vkgl.lang.syntax import parser
from vkgl.lang.syntax.parser import PARSE_CACHE_CHARS, ParseCache

CRATE = "body Crate{i} {{\n    shape box (30, 30, 20) cm\n    mass 2 kg\n}}\n"


def test_many_keystrokes_keep_the_cache_within_its_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    cache = ParseCache(budget=20_000)  # the real one is PARSE_CACHE_CHARS; smaller here to stay fast
    monkeypatch.setattr(parser, "_cache", cache)
    document = "".join(CRATE.format(i=i) for i in range(60))  # about 3.6 K characters
    for keystroke in range(15):
        module, _, diagnostics = parser.parse_collecting(document + "#" * keystroke, "typing.vkg")
        assert module is not None and not diagnostics
        assert cache.chars <= cache.budget
    assert len(cache) == cache.budget // (len(document) + 20)
    assert PARSE_CACHE_CHARS <= 1024 * 1024  # about 170 bytes of parse per character: under 180 MB


def test_the_cache_keeps_recent_texts_and_drops_the_least_recently_used() -> None:
    cache = ParseCache(budget=1000)
    parsed = (None, (), ())
    for name in "abcd":
        cache.put((name * 239, "p"), parsed)  # 240 characters each, with the path
    assert cache.get(("a" * 239, "p")) is parsed  # a is now the most recent
    cache.put(("e" * 239, "p"), parsed)  # over budget: b, the least recently used, goes
    assert cache.get(("b" * 239, "p")) is None and cache.get(("a" * 239, "p")) is parsed
    assert cache.chars == 960
    cache.put(("f" * 250, "p"), parsed)  # larger than a quarter of the budget: never kept
    assert cache.get(("f" * 250, "p")) is None


def test_a_shared_module_is_parsed_once() -> None:
    text = CRATE.format(i="Shared")
    first = parser.parse_collecting(text, "shared.vkg")[0]
    assert parser.parse_collecting(text, "shared.vkg")[0] is first
