"""Titles that fit: line breaks put into a picture's text so that no line is wider than the room it has.

Matplotlib draws a title on one line however long it is: a plan's step named
`add CrateM.turn_px_right@+2.63cm/over+20deg+1.00cm on target with hook.tip`
ran over its neighbours' titles and past the figure's edge, where it was cut.
`fit_lines` breaks a text between words, never between a number and its unit
(and inside a word longer than a line, after a `.`, `_`, `@`, `/` or `+`, or
anywhere as a last resort), by the
width matplotlib's own font metrics give it, so a title stays within its
column. Only matplotlib's text layout is used: nothing is drawn.
"""

from __future__ import annotations

import re

__all__ = ["fit_lines", "text_width"]

_BREAKS = re.compile(r"(?<=[._@/+])")  # a long word is broken after these
_UNIT = re.compile(r"(?:cm|mm|m|deg|rad|s|N|kg|%)(?![A-Za-z0-9_])")


def text_width(text: str, fontsize: float) -> float:
    """Points the one-line `text` spans at `fontsize` in matplotlib's default font."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    width, _, _ = text_to_path.get_text_width_height_descent(text, FontProperties(size=fontsize), ismath=False)
    return float(width)


def fit_lines(text: str, width: float, fontsize: float) -> str:
    """`text` with line breaks so that no line spans more than `width` points at `fontsize`; the breaks it
    already has are kept."""
    return "\n".join(_fit_line(line, width, fontsize) for line in text.split("\n"))


def _fit_line(line: str, width: float, fontsize: float) -> str:
    if text_width(line, fontsize) <= width:
        return line
    lines: list[str] = []
    current = ""
    for word in _words(line):
        joined = f"{current} {word}" if current else word
        if text_width(joined, fontsize) <= width:
            current = joined
            continue
        if current:
            lines.append(current)
        current = ""
        for piece in _pieces(word, width, fontsize):
            if current and text_width(current + piece, fontsize) <= width:
                current += piece
            else:
                if current:
                    lines.append(current)
                current = piece
    if current:
        lines.append(current)
    return "\n".join(lines)


def _words(line: str) -> list[str]:
    """The line's words, a unit kept with the number before it (`10.2 cm`, `47 cm)`): never broken apart."""
    words: list[str] = []
    for word in line.split(" "):
        if words and _UNIT.match(word) and words[-1][-1:].isdigit():
            words[-1] = f"{words[-1]} {word}"
        else:
            words.append(word)
    return words


def _pieces(word: str, width: float, fontsize: float) -> list[str]:
    """`word` cut after its break characters, and a piece still wider than `width` cut where it must be."""
    pieces: list[str] = []
    for part in _BREAKS.split(word):
        while part and text_width(part, fontsize) > width:
            cut = max(1, next((k for k in range(len(part), 0, -1) if text_width(part[:k], fontsize) <= width), 1))
            pieces.append(part[:cut])
            part = part[cut:]
        if part:
            pieces.append(part)
    return pieces
