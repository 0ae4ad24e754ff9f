"""A bounded cache of parses by (text, path): the parser's, and the parses read back from the cache folder.

Light on purpose (no Lark): `vkgl.lang.module_cache` keeps what it reads back here, and a warm `vkgc check`
must not import the parser.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Generic, TypeVar

ParsedT = TypeVar("ParsedT")


class ParseCache(Generic[ParsedT]):
    """Parses by (text, path), least recently used dropped first, bounded by the characters of the texts kept
    (this parser's, and `vkgl.lang.module_cache`'s parses read back from the cache folder)."""

    def __init__(self, budget: int) -> None:
        self.budget = budget
        self.chars = 0
        self._entries: OrderedDict[tuple[str, str], ParsedT] = OrderedDict()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._entries)

    def get(self, key: tuple[str, str]) -> ParsedT | None:
        """The parse of `key`, now the most recently used; None if it is not kept."""
        with self._lock:
            found = self._entries.get(key)
            if found is not None:
                self._entries.move_to_end(key)
            return found

    def put(self, key: tuple[str, str], parsed: ParsedT) -> None:
        """Keep `parsed` (unless its text is too large to), dropping the least recently used beyond the budget."""
        size = len(key[0]) + len(key[1])
        if size > self.budget // 4:
            return
        with self._lock:
            if key in self._entries:
                return
            self._entries[key] = parsed
            self.chars += size
            while self.chars > self.budget:
                (text, path), _ = self._entries.popitem(last=False)
                self.chars -= len(text) + len(path)

    def clear(self) -> None:
        """Drop every parse."""
        with self._lock:
            self._entries.clear()
            self.chars = 0


__all__ = ["ParseCache"]
