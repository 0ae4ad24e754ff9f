"""Diagnostics: errors and warnings with a stable code and a source span.

Rendering follows docs/language.md ("The language in one example", its last block):

    path:line:col: error[E201]: message
        <source line>
        ^^^^^
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass, field
from typing import Literal

from vkgl.lang.ir.nodes import Span

Severity = Literal["error", "warning"]


@dataclass(frozen=True)
class Diagnostic:
    """One error or warning.

    `span` may be None only for problems with no place in a source: then `file` names the file the
    problem is about (a missing file given on the command line), shown as `path: error[CODE]: ...`.
    Made through the code registry: `vkgl.lang.diagnostics.codes.UNKNOWN_NAME.diagnostic(message, span, *notes)`.
    """

    code: str
    message: str
    span: Span | None
    severity: Severity = "error"
    notes: tuple[str, ...] = field(default=())
    file: str | None = None

    @property
    def is_error(self) -> bool:
        """True for errors, False for warnings."""
        return self.severity == "error"

    def location(self) -> str:
        """`path:line:col`; `path` for a problem of a whole file; `<input>` when neither is known."""
        if self.span is not None:
            return str(self.span)
        return self.file if self.file is not None else "<input>"

    def headline(self) -> str:
        """The first line: `path:line:col: error[CODE]: message`."""
        return escape_controls(f"{self.location()}: {self.severity}[{self.code}]: {self.message}")

    def sort_key(self) -> tuple[str, int, int, str]:
        """Order by file, then position, then code."""
        if self.span is None:
            return (self.file or "", 0, 0, self.code)
        return (self.span.file, self.span.line, self.span.col, self.code)


# Longer source lines are shown as a window around the span, so one huge generated
# line does not flood the terminal.
MAX_SHOWN = 120


def render(diag: Diagnostic, source: str | None) -> str:
    """The full rendering: headline, the source line, carets under the span, then notes."""
    lines = [diag.headline()]
    if diag.span is not None and source is not None:
        src_lines = source_lines(source)
        if 1 <= diag.span.line <= len(src_lines):
            text = src_lines[diag.span.line - 1].expandtabs(1)
            start = max(diag.span.col - 1, 0)
            if diag.span.end_line == diag.span.line:
                end = max(diag.span.end_col - 1, start + 1)
            else:
                end = max(len(text), start + 1)
            text, start, end = _window(text, start, end)
            text, start, end = _escaped_line(text, start, end)
            lines.append("    " + text)
            lines.append("    " + " " * start + "^" * (end - start))
    lines.extend(f"    note: {escape_controls(n)}" for n in diag.notes)
    return "\n".join(lines)


def source_lines(source: str) -> list[str]:
    """The lines of a source as the parser counts them: split at `\\n` only (a `\\r` before it dropped).

    Python's `str.splitlines()` also breaks at `\\v`, `\\f`, `\\x1c`-`\\x1e`, `\\x85`, `\\u2028` and
    `\\u2029`, which Lark does not; using it would show the wrong line.
    """
    return [line[:-1] if line.endswith("\r") else line for line in source.split("\n")]


def _needs_escape(char: str) -> bool:
    """Control characters (a tab too: source lines have theirs expanded first), line and paragraph
    separators and bidirectional overrides."""
    return unicodedata.category(char) in ("Cc", "Zl", "Zp") or char in _BIDI


_BIDI = frozenset("\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


def _escape_char(char: str) -> str:
    code = ord(char)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def escape_controls(text: str) -> str:
    """`text` with control characters written as escapes (`\\x1b`): no terminal escape sequence gets through."""
    if text.isprintable():
        return text
    return "".join(_escape_char(c) if _needs_escape(c) else c for c in text)


def _escaped_line(text: str, start: int, end: int) -> tuple[str, int, int]:
    """A shown source line with its control characters escaped, and the caret columns moved to match."""
    if text.isprintable():
        return text, start, end
    out: list[str] = []
    width = 0
    new_start, new_end = start, end
    for i, char in enumerate(text):
        if i == start:
            new_start = width
        if i == end:
            new_end = width
        piece = _escape_char(char) if _needs_escape(char) else char
        out.append(piece)
        width += len(piece)
    if start >= len(text):
        new_start = width + (start - len(text))
    if end >= len(text):
        new_end = max(width + (end - len(text)), new_start + 1)
    return "".join(out), new_start, max(new_end, new_start + 1)


def _window(text: str, start: int, end: int) -> tuple[str, int, int]:
    """At most MAX_SHOWN characters of `text` around [start, end), with `...` where cut."""
    if len(text) <= MAX_SHOWN:
        return text, start, end
    left = max(0, min(start - 20, len(text) - MAX_SHOWN))
    right = left + MAX_SHOWN
    prefix = "..." if left > 0 else ""
    suffix = "..." if right < len(text) else ""
    shown = prefix + text[left:right] + suffix
    new_start = start - left + len(prefix)
    new_end = min(end, right) - left + len(prefix)
    return shown, new_start, max(new_end, new_start + 1)
