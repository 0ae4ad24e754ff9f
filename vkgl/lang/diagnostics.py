"""Diagnostics: errors and warnings with a stable code and a source span.

Rendering follows LANGUAGE.md §9:

    path:line:col: error[E201]: message
        <source line>
        ^^^^^
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from vkgl.lang.ir import Span

Severity = Literal["error", "warning"]


@dataclass(frozen=True)
class Diagnostic:
    """One error or warning.

    `span` may be None only for problems with no place (e.g. a missing file given on the command line).
    Made through the code registry: `vkgl.lang.codes.UNKNOWN_NAME.diagnostic(message, span, *notes)`.
    """

    code: str
    message: str
    span: Span | None
    severity: Severity = "error"
    notes: tuple[str, ...] = field(default=())

    @property
    def is_error(self) -> bool:
        """True for errors, False for warnings."""
        return self.severity == "error"

    def location(self) -> str:
        """`path:line:col`, or `<input>` when there is no span."""
        return str(self.span) if self.span is not None else "<input>"

    def headline(self) -> str:
        """The first line: `path:line:col: error[CODE]: message`."""
        return f"{self.location()}: {self.severity}[{self.code}]: {self.message}"

    def sort_key(self) -> tuple[str, int, int, str]:
        """Order by file, then position, then code."""
        if self.span is None:
            return ("", 0, 0, self.code)
        return (self.span.file, self.span.line, self.span.col, self.code)


# Longer source lines are shown as a window around the span, so one huge generated
# line does not flood the terminal.
MAX_SHOWN = 120


def render(diag: Diagnostic, source: str | None) -> str:
    """The full rendering: headline, the source line, carets under the span, then notes."""
    lines = [diag.headline()]
    if diag.span is not None and source is not None:
        src_lines = source.splitlines()
        if 1 <= diag.span.line <= len(src_lines):
            text = src_lines[diag.span.line - 1].expandtabs(1)
            start = max(diag.span.col - 1, 0)
            if diag.span.end_line == diag.span.line:
                end = max(diag.span.end_col - 1, start + 1)
            else:
                end = max(len(text), start + 1)
            text, start, end = _window(text, start, end)
            lines.append("    " + text)
            lines.append("    " + " " * start + "^" * (end - start))
    lines.extend(f"    note: {n}" for n in diag.notes)
    return "\n".join(lines)


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
