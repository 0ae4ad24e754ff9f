"""Syntax errors: Lark's UnexpectedInput -> diagnostics (E101-E105), and recovery.

After a syntax error the parse resumes at the next declaration that starts a
line, so each broken declaration of a file gives one error. The functions take
the one Lark parser (vkgl/lang/syntax/parser.py) to re-parse and to name terminals.
"""

from __future__ import annotations

import re
from functools import lru_cache

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken
from lark.lexer import PatternStr

from vkgl.errors import did_you_mean
from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import DIMENSION, UNITS_BY_DIMENSION
from vkgl.lang.syntax.values import new_node, token_span

_TOKEN_WORDS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "UNIT": "a unit",
    "FACE": "a face (`+x`, `-x`, `+y`, `-y`, `+z` or `-z`)",
    "STRING": 'a quoted path such as `"file.vkg"`',
    "$END": "the end of the file",
}
_UNIT_WORDS = [f"`{u}`" for units in UNITS_BY_DIMENSION.values() for u in units]
_ALL_UNITS = ", ".join(_UNIT_WORDS[:-1]) + " or " + _UNIT_WORDS[-1]


# A declaration that starts a line: where the parser resumes after a syntax error.
DECLARATION_START = re.compile(r"^(?:use|body|robot|affordances|correspondences|scene|task)\b", re.MULTILINE)
MAX_SYNTAX_ERRORS = 20


def syntax_diagnostics(parser: Lark, first: UnexpectedInput, text: str, path: str) -> list[Diagnostic]:
    """The first syntax error, then the first error of each later declaration that does not parse either.

    After an error the parser resumes at the next declaration keyword in column 1
    (`body`, `scene`, ...), with all text before it blanked out (newlines kept, so
    positions stay true). One mistake gives one error, not a cascade, and every
    broken declaration of the file is reported in one run.
    """
    diagnostics = [_syntax_diagnostic(parser, first, text, path)]
    search_from = _error_offset(first)
    # Each resumption parses to the end of the file: bound the extra work on huge files.
    budget = 2 * len(text) + 20_000
    while search_from is not None and len(diagnostics) < MAX_SYNTAX_ERRORS:
        match = DECLARATION_START.search(text, search_from)
        budget -= len(text) - match.start() if match is not None else 0
        if match is None or budget < 0:
            break
        rest = re.sub(r"[^\n]", " ", text[: match.start()]) + text[match.start() :]
        try:
            parser.parse(rest)
            break
        except UnexpectedInput as exc:
            diagnostics.append(_syntax_diagnostic(parser, exc, rest, path))
            offset = _error_offset(exc)
            search_from = None if offset is None else max(offset, match.start() + 1)
    return diagnostics


def _error_offset(exc: UnexpectedInput) -> int | None:
    """Where in the text a syntax error is (None at the end of the file: nothing follows to resume at)."""
    if isinstance(exc, UnexpectedToken) and exc.token.type != "$END":
        return exc.token.start_pos
    if isinstance(exc, UnexpectedCharacters):
        return exc.pos_in_stream
    return None


def _syntax_diagnostic(parser: Lark, exc: UnexpectedInput, text: str, path: str) -> Diagnostic:
    if isinstance(exc, UnexpectedToken) and exc.token.type != "$END":
        return _unexpected_token(parser, exc, text, path)
    if isinstance(exc, UnexpectedCharacters):
        return _unexpected_character(parser, exc, text, path)
    expected = _expected(exc) if isinstance(exc, (UnexpectedEOF, UnexpectedToken)) else set()
    line, col = _end_position(text)
    span = new_node(ir.Span, file=path, line=line, col=col, end_line=line, end_col=col + 1)
    opened = _unclosed_brace(text)
    notes = (f"the `{{` at {path}:{opened[0]}:{opened[1]} is never closed: add `}}`",) if opened else ()
    return codes.UNEXPECTED_END.diagnostic(f"unexpected end of file; expected {_words(parser, expected)}", span, *notes)


def _expected(exc: UnexpectedToken | UnexpectedEOF) -> set[str]:
    """The terminals the parser really accepts where it stopped.

    LALR's default reductions run before the error is noticed, so `exc.expected`
    may be the follow set of a value in every context (`,`, `and`, `at`, ...);
    the interactive parser replays the lookahead and knows the actual choices.
    """
    interactive = getattr(exc, "interactive_parser", None)
    if interactive is not None:
        try:
            return set(interactive.accepts())
        except Exception:  # the replay is a refinement only; fall back to Lark's set
            pass
    return set(exc.expected)


def _unexpected_token(parser: Lark, exc: UnexpectedToken, text: str, path: str) -> Diagnostic:
    token = exc.token
    span = token_span(token, path)
    before = _text_before(text, token)
    compound = _compound_unit(path, text, token.start_pos or 0) if token.type == "NAME" else None
    if compound is not None:
        return compound
    if token.type == "NAME" and _looks_like_unit(str(token), before):
        unit_notes = _unit_hint(str(token))
        return codes.UNKNOWN_UNIT.diagnostic(f"unknown unit `{token}`; units are {_ALL_UNITS}", span, *unit_notes)
    got = "`" + str(token).replace("\n", " ") + "`"
    keyword = _keyword_read_as_name(parser, exc)
    notes: tuple[str, ...] = ()
    if keyword:
        notes = (f"`{keyword}` before it was read as a name; is something missing before `{keyword}`?",)
    elif token.column == 1 and DECLARATION_START.match(str(token)) and (opened := _unclosed_brace(before)):
        notes = (f"the `{{` at {path}:{opened[0]}:{opened[1]} is never closed: add `}}` before this declaration",)
    elif token.type == "NAME" and (close := did_you_mean(str(token), _expected_keywords(parser, _expected(exc)))):
        notes = (close,)  # `mas 0.8 kg`: a misspelled keyword
    elif missing := _missing_at(exc):
        notes = (missing,)
    elif heading := _heading_word(exc):
        notes = (heading,)
    return codes.UNEXPECTED_TOKEN.diagnostic(
        f"unexpected {got}; expected {_words(parser, _expected(exc))}", span, *notes
    )


MISSING_AT_NOTES = {
    "UNION": "every part of a `union` is placed in the union's frame: write `at (x, y, z) UNIT` after the shape "
    "before this (`box (10, 20, 4) cm at (-10, 15, 0) cm`)",
    "TABLE_SIZE": "a table is placed by the centre of its top: `table size (1.6, 1.2) m at (0.5, 0, 0) m`",
    "ON_TABLE": "a body on the table is placed at its (x, y) position: `block : Block on table at (0.45, 0) m`",
    "ROBOT": "a robot is placed at its base's pose: `robot arm : Panda at (0, 0, 0) m`",
}
"""The note for an `at POSE` left out, by what the parser was reading: the bare "expected `at`" points at what
follows (often the next line's statement or a `}`), not at the statement that lacks its pose."""


def _missing_at(exc: UnexpectedToken) -> str | None:
    """The note for a statement that lacks its `at POSE`, when the parser waits for `at` alone; else None.

    A `union` token stays on the parser's stack while its braces are open, and inside them only a part's shape is
    followed by `at` alone; outside a union, the statement is the one whose tokens end the stack.
    """
    if _expected(exc) != {"AT"}:
        return None
    state = getattr(getattr(exc, "interactive_parser", None), "parser_state", None)
    types = [getattr(v, "type", None) for v in getattr(state, "value_stack", None) or []]
    if "UNION" in types:
        return MISSING_AT_NOTES["UNION"]
    if "SIZE" in types[-3:] and "TABLE" in types[-3:]:
        return MISSING_AT_NOTES["TABLE_SIZE"]
    if types[-2:] == ["ON", "TABLE"]:
        return MISSING_AT_NOTES["ON_TABLE"]
    if "ROBOT" in types[-4:]:
        return MISSING_AT_NOTES["ROBOT"]
    return None


HEADING_WORDS = frozenset({"rotated", "rotation", "rotate", "heading", "angle", "orientation", "theta", "turned"})
"""Words a newcomer writes for a body's heading (`at (0.4, 0) m rotated 30deg`): the parser reads the word as the
name of the next scene body and stops at the angle after it, asking for that body's `:`."""


def _heading_word(exc: UnexpectedToken) -> str | None:
    """The note for a heading written with a word the language does not have (one of `HEADING_WORDS`: the name
    unexpected where `yaw` could stand, or the name just read), else None."""
    state = getattr(getattr(exc, "interactive_parser", None), "parser_state", None)
    stack = getattr(state, "value_stack", None) or []
    word = exc.token if exc.token.type == "NAME" and "YAW" in _expected(exc) else (stack[-1] if stack else None)
    if getattr(word, "type", None) != "NAME" or str(word).lower() not in HEADING_WORDS:
        return None
    return f"a heading is written `yaw ANGLE` after the position, not `{word} ...`: `at (0.4, 0) m yaw 30deg`"


def _expected_keywords(parser: Lark, expected: set[str]) -> list[str]:
    """The keywords among the expected terminals (`mass`, `friction`, ...)."""
    words = []
    for name in expected:
        try:
            pattern = parser.get_terminal(name).pattern
        except KeyError:
            continue
        if isinstance(pattern, PatternStr) and pattern.value.isalpha():
            words.append(pattern.value)
    return words


def _unit_hint(word: str) -> tuple[str, ...]:
    """ "did you mean `cm`?" for `CM`, `degrees`, `mmm`: a unit in another case, or one typo away."""
    units = [u for u in DIMENSION if u]
    same = [u for u in units if u.lower() == word.lower()]
    hint = f"did you mean `{same[0]}`?" if same else did_you_mean(word, units)
    return (hint,) if hint else ()


def _keyword_read_as_name(parser: Lark, exc: UnexpectedToken) -> str | None:
    """The keyword just before the error if the parser took it as a name (`scene goal b ...`: `goal` named a scene)."""
    state = getattr(getattr(exc, "interactive_parser", None), "parser_state", None)
    stack = getattr(state, "value_stack", None) or []
    last = stack[-1] if stack else None
    if isinstance(last, Token) and last.type == "NAME" and str(last) in _keywords(parser):
        return str(last)
    return None


@lru_cache(maxsize=1)
def _keywords(parser: Lark) -> frozenset[str]:
    """The grammar's keywords (`body`, `goal`, ...): the string terminals made of letters."""
    words = set()
    for terminal in parser.terminals:
        if isinstance(terminal.pattern, PatternStr) and terminal.pattern.value.isidentifier():
            words.add(terminal.pattern.value)
    return frozenset(words)


# Unit-like words a user may write after a number; any short word directly after a number counts too.
_FOREIGN_UNITS = {
    "lb",
    "lbs",
    "oz",
    "in",
    "inch",
    "ft",
    "km",
    "um",
    "mg",
    "kN",
    "mN",
    "min",
    "h",
    "hr",
    "sec",
    "degree",
    "degrees",
    "radian",
    "radians",
    "meter",
    "meters",
    "metre",
    "metres",
    "newton",
    "newtons",
    "gram",
    "grams",
    "mins",
    "minute",
    "minutes",
    "hour",
    "hours",
    "inches",
    "feet",
    "pound",
    "pounds",
    "lbf",
    "kgf",
}


_ENDS_WITH_NUMBER = re.compile(r"(?:^|[^\w.])[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*$")


def _looks_like_unit(word: str, before: str) -> bool:
    """True for a name right after a number that is meant as a unit (`500 lb`, `3sec`), not a keyword."""
    if not _ENDS_WITH_NUMBER.search(before):
        return False
    return word in _FOREIGN_UNITS or not before[-1:].isspace() or len(word) <= 3


# A unit made of words joined by `*` and `/` (spaces allowed, so that `N * s / m` is recognised too).
# Matches start at word starts only, and are looked for near the error, so that a long line costs little.
_COMPOUND = re.compile(r"(?<![A-Za-z])[A-Za-z]+(?:[ \t]*[*/][ \t]*[A-Za-z]*)+")
_COMPOUND_REACH = 40


def _compound_unit(path: str, text: str, offset: int) -> Diagnostic | None:
    """E105 for a compound unit after a number that is not one of VKG's (`N*m*s`, `N * s / m`), else None.

    The lexer reads only the compound units it knows, as one token; anything else stops at its first
    word or at a `*` or `/`, which would read as a stray character without this.
    """
    line_start = text.rfind("\n", 0, offset) + 1
    line_end = text.find("\n", offset)
    low = max(line_start, offset - _COMPOUND_REACH)
    window = text[low : min(line_end if line_end >= 0 else len(text), offset + _COMPOUND_REACH)]
    for match in _COMPOUND.finditer(window):
        start = low + match.start()
        before = text[max(line_start, start - _COMPOUND_REACH) : start]
        if not start <= offset < low + match.end() or not _ENDS_WITH_NUMBER.search(before):
            continue
        written = match.group().rstrip()
        number = text.count("\n", 0, line_start) + 1
        col = start - line_start + 1
        span = new_node(ir.Span, file=path, line=number, col=col, end_line=number, end_col=col + len(written))
        packed = re.sub(r"\s+", "", written)
        note = f"write compound units without spaces: `{packed}`" if packed in DIMENSION else ""
        return codes.UNKNOWN_UNIT.diagnostic(f"unknown unit `{written}`; units are {_ALL_UNITS}", span, note)
    return None


def _unclosed_brace(text: str) -> tuple[int, int] | None:
    """Line and column of the innermost `{` that is never closed (comments and strings skipped)."""
    stack: list[tuple[int, int]] = []
    for number, line in enumerate(text.split("\n"), start=1):
        for match in re.finditer(r'"[^"\n]*"?|#.*|[{}]', line):
            if match.group() == "{":
                stack.append((number, match.start() + 1))
            elif match.group() == "}" and stack:
                stack.pop()
    return stack[-1] if stack else None


def _unexpected_character(parser: Lark, exc: UnexpectedCharacters, text: str, path: str) -> Diagnostic:
    line, col = exc.line, exc.column
    span = new_node(ir.Span, file=path, line=line, col=col, end_line=line, end_col=col + 1)
    char = exc.char
    if char == '"':
        return codes.UNEXPECTED_CHARACTER.diagnostic('unterminated string: close it with `"` on the same line', span)
    if char == ";":
        return codes.UNEXPECTED_CHARACTER.diagnostic(
            "unexpected `;`: VKG statements need no separator; remove it", span
        )
    compound = _compound_unit(path, text, exc.pos_in_stream or 0) if char in "*/" else None
    if compound is not None:
        return compound
    shown = repr(char)[1:-1] if not char.isprintable() else char
    if char.isdigit() and not char.isascii():
        return codes.UNEXPECTED_CHARACTER.diagnostic(
            f"unexpected character `{shown}`: numbers are written with the ASCII digits 0-9", span
        )
    allowed = {name for name in exc.allowed or set()}
    return codes.UNEXPECTED_CHARACTER.diagnostic(
        f"unexpected character `{shown}`; expected {_words(parser, allowed)}", span
    )


def _words(parser: Lark, expected: set[str] | frozenset[str]) -> str:
    """Terminal names as a user reads them: keywords and symbols quoted, classes in words."""
    words: set[str] = set()
    for name in expected:
        if name in _TOKEN_WORDS:
            words.add(_TOKEN_WORDS[name])
            continue
        try:
            pattern = parser.get_terminal(name).pattern
        except KeyError:
            continue
        if isinstance(pattern, PatternStr):
            words.add(f"`{pattern.value}`")
    ordered = sorted(words, key=lambda w: (not w.startswith("`"), w))
    if not ordered:
        return "something else"
    if len(ordered) > 10:  # the top level has 9 choices (8 keywords and the end): show them all
        ordered = ordered[:10] + ["..."]
        return ", ".join(ordered)
    return ordered[0] if len(ordered) == 1 else ", ".join(ordered[:-1]) + " or " + ordered[-1]


def _text_before(text: str, token: Token) -> str:
    start = token.start_pos if token.start_pos is not None else 0
    return text[:start]


def _end_position(text: str) -> tuple[int, int]:
    """Just after the last character that is not blank or a comment, so the rendering can show that line."""
    lines = text.split("\n")
    for number in range(len(lines), 0, -1):
        code = re.sub(r"#.*", "", lines[number - 1]) if '"' not in lines[number - 1] else lines[number - 1]
        if code.strip():
            return number, len(code.rstrip()) + 1
    return 1, 1
