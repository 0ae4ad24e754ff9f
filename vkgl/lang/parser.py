"""The parser: VKG source text -> IR `Module`, with units checked and converted to SI.

Lark's LALR parser (grammar/vkg.lark) builds a tree; `_Builder` turns it into
IR nodes that keep their source spans. Problems that need no other module
(syntax, units, missing or repeated statements) are found here; everything that
needs names from other modules is the checker's job (vkgl/lang/checks.py).
"""

from __future__ import annotations

import gc
import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, TypeVar

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken
from lark.lexer import PatternStr

from vkgl.errors import CompileError
from vkgl.lang import ir
from vkgl.lang.diagnostics import Diagnostic
from vkgl.lang.units import ARTICLE_NAME, SI_UNIT, dimension_of, to_si, unit_list
from vkgl.resources import grammar_path

_N = TypeVar("_N", bound=ir.Node)


@dataclass(frozen=True)
class Comment:
    """A `#` comment as lexed: where it starts and its text (including the `#`)."""

    line: int
    col: int
    text: str


def parse_module(text: str, path: str) -> ir.Module:
    """Parse one module. Raises CompileError with every diagnostic found in the file."""
    return parse_module_with_comments(text, path)[0]


def parse_module_with_comments(text: str, path: str) -> tuple[ir.Module, list[Comment]]:
    """Parse one module and return the comments the lexer skipped (for `vkgc fmt`)."""
    module, comments, diagnostics = parse_collecting(text, path)
    errors = [d for d in diagnostics if d.is_error]
    if errors or module is None:
        raise CompileError(sorted(diagnostics, key=Diagnostic.sort_key))
    return module, comments


def parse_collecting(text: str, path: str) -> tuple[ir.Module | None, list[Comment], list[Diagnostic]]:
    """Parse one module without raising: the module (None after a syntax error), comments, diagnostics."""
    module, comments, diagnostics = _parse_cached(text, path)
    return module, list(comments), list(diagnostics)


@lru_cache(maxsize=512)
def _parse_cached(text: str, path: str) -> tuple[ir.Module | None, tuple[Comment, ...], tuple[Diagnostic, ...]]:
    # A compilation parses each imported module once; checking many files that share
    # imports (vkgc check examples/ stdlib/) parses each shared module once per process.
    module, comments, diagnostics = _parse_uncached(text, path)
    return module, tuple(comments), tuple(diagnostics)


def _parse_uncached(text: str, path: str) -> tuple[ir.Module | None, list[Comment], list[Diagnostic]]:
    comments: list[Token] = []
    builder = _builder()
    builder.start_file(path, text)
    _COMMENT_SINK[0] = comments
    # The parse allocates a few objects per character and frees none of them until
    # the end; pausing the cyclic garbage collector meanwhile halves the time.
    collecting = gc.isenabled()
    gc.disable()
    try:
        tree = _parser().parse(text)
        module = builder.build(tree)
    except UnexpectedInput as exc:
        return None, [], _syntax_diagnostics(exc, text, path)
    except RecursionError:
        span = _new(ir.Span, file=path, line=1, col=1, end_line=1, end_col=2)
        message = f"shapes nest too deeply to read; unions may nest at most {MAX_UNION_DEPTH} levels"
        return None, [], [Diagnostic("E104", message, span)]
    finally:
        _COMMENT_SINK[0] = []
        if collecting:
            gc.enable()
    lexed = [Comment(t.line or 0, t.column or 0, str(t)) for t in comments]
    module = module.model_copy(update={"doc": _doc_comment(text, lexed)})
    return module, lexed, builder.diagnostics


# ---------------------------------------------------------------- the Lark parser


# The lexer callback of the one cached parser appends to the list of the parse in progress.
_COMMENT_SINK: list[list[Token]] = [[]]


@lru_cache(maxsize=1)
def _builder() -> _Builder:
    return _Builder("<input>")


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return Lark(
        grammar_path().read_text(encoding="utf-8"),
        parser="lalr",
        lexer="contextual",
        propagate_positions=True,
        maybe_placeholders=False,
        lexer_callbacks={"COMMENT": lambda token: _COMMENT_SINK[0].append(token)},
    )


def _doc_comment(text: str, comments: list[Comment]) -> str | None:
    """The file's doc comment: its first block of full-line comments, when a blank line ends it.

    A comment block directly above a statement belongs to that statement instead.
    """
    lines: list[str] = []
    by_line = {c.line: c for c in comments}
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            if lines:
                return "\n".join(lines)
            continue
        comment = by_line.get(number)
        if comment is None or not stripped.startswith("#"):
            return None
        body = comment.text[1:]
        lines.append((body[1:] if body.startswith(" ") else body).rstrip())
    return "\n".join(lines) if lines else None


def doc_line_count(text: str) -> int:
    """How many lines at the top of `text` the doc comment spans (0 if none); for `vkgc fmt`."""
    last = 0
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            if last:
                return last
            continue
        if not stripped.startswith("#"):
            return 0
        last = number
    return last


# ---------------------------------------------------------------- syntax errors

_TOKEN_WORDS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "UNIT": "a unit",
    "FACE": "a face (`+x`, `-x`, `+y`, `-y`, `+z` or `-z`)",
    "STRING": 'a quoted path such as `"file.vkg"`',
    "$END": "the end of the file",
}
_ALL_UNITS = "`m`, `cm`, `mm`, `deg`, `rad`, `kg`, `g`, `N`, `s` or `ms`"


# A declaration that starts a line: where the parser resumes after a syntax error.
_DECLARATION_START = re.compile(r"^(?:use|body|robot|affordances|correspondences|scene|task)\b", re.MULTILINE)
MAX_SYNTAX_ERRORS = 20


def _syntax_diagnostics(first: UnexpectedInput, text: str, path: str) -> list[Diagnostic]:
    """The first syntax error, then the first error of each later declaration that does not parse either.

    After an error the parser resumes at the next declaration keyword in column 1
    (`body`, `scene`, ...), with all text before it blanked out (newlines kept, so
    positions stay true). One mistake gives one error, not a cascade, and every
    broken declaration of the file is reported in one run.
    """
    diagnostics = [_syntax_diagnostic(first, text, path)]
    search_from = _error_offset(first)
    # Each resumption parses to the end of the file: bound the extra work on huge files.
    budget = 2 * len(text) + 20_000
    while search_from is not None and len(diagnostics) < MAX_SYNTAX_ERRORS:
        match = _DECLARATION_START.search(text, search_from)
        budget -= len(text) - match.start() if match is not None else 0
        if match is None or budget < 0:
            break
        rest = re.sub(r"[^\n]", " ", text[: match.start()]) + text[match.start() :]
        try:
            _parser().parse(rest)
            break
        except UnexpectedInput as exc:
            diagnostics.append(_syntax_diagnostic(exc, rest, path))
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


def _syntax_diagnostic(exc: UnexpectedInput, text: str, path: str) -> Diagnostic:
    if isinstance(exc, UnexpectedToken) and exc.token.type != "$END":
        return _unexpected_token(exc, text, path)
    if isinstance(exc, UnexpectedCharacters):
        return _unexpected_character(exc, text, path)
    expected = _expected(exc) if isinstance(exc, (UnexpectedEOF, UnexpectedToken)) else set()
    line, col = _end_position(text)
    span = _new(ir.Span, file=path, line=line, col=col, end_line=line, end_col=col + 1)
    opened = _unclosed_brace(text)
    notes = (f"the `{{` at {path}:{opened[0]}:{opened[1]} is never closed: add `}}`",) if opened else ()
    return Diagnostic("E103", f"unexpected end of file; expected {_words(expected)}", span, notes=notes)


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


def _unexpected_token(exc: UnexpectedToken, text: str, path: str) -> Diagnostic:
    token = exc.token
    span = _token_span(token, path)
    before = _text_before(text, token)
    if token.type == "NAME" and _looks_like_unit(str(token), before):
        return Diagnostic("E105", f"unknown unit `{token}`; units are {_ALL_UNITS}", span)
    got = "`" + str(token).replace("\n", " ") + "`"
    keyword = _keyword_read_as_name(exc)
    notes: tuple[str, ...] = ()
    if keyword:
        notes = (f"`{keyword}` before it was read as a name; is something missing before `{keyword}`?",)
    elif token.column == 1 and _DECLARATION_START.match(str(token)) and (opened := _unclosed_brace(before)):
        notes = (f"the `{{` at {path}:{opened[0]}:{opened[1]} is never closed: add `}}` before this declaration",)
    return Diagnostic("E101", f"unexpected {got}; expected {_words(_expected(exc))}", span, notes=notes)


def _keyword_read_as_name(exc: UnexpectedToken) -> str | None:
    """The keyword just before the error if the parser took it as a name (`scene goal b ...`: `goal` named a scene)."""
    state = getattr(getattr(exc, "interactive_parser", None), "parser_state", None)
    stack = getattr(state, "value_stack", None) or []
    last = stack[-1] if stack else None
    if isinstance(last, Token) and last.type == "NAME" and str(last) in _keywords():
        return str(last)
    return None


@lru_cache(maxsize=1)
def _keywords() -> frozenset[str]:
    """The grammar's keywords (`body`, `goal`, ...): the string terminals made of letters."""
    words = set()
    for terminal in _parser().terminals:
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


def _unexpected_character(exc: UnexpectedCharacters, text: str, path: str) -> Diagnostic:
    line, col = exc.line, exc.column
    span = _new(ir.Span, file=path, line=line, col=col, end_line=line, end_col=col + 1)
    char = exc.char
    if char == '"':
        return Diagnostic("E102", 'unterminated string: close it with `"` on the same line', span)
    if char == ";":
        return Diagnostic("E102", "unexpected `;`: VKG statements need no separator; remove it", span)
    shown = repr(char)[1:-1] if not char.isprintable() else char
    allowed = {name for name in exc.allowed or set()}
    return Diagnostic("E102", f"unexpected character `{shown}`; expected {_words(allowed)}", span)


def _words(expected: set[str] | frozenset[str]) -> str:
    """Terminal names as a user reads them: keywords and symbols quoted, classes in words."""
    parser = _parser()
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


def _token_span(token: Token, path: str) -> ir.Span:
    line, col = token.line or 1, token.column or 1
    end_line = token.end_line or line
    end_col = token.end_column or col + max(len(str(token)), 1)
    return _new(ir.Span, file=path, line=line, col=col, end_line=end_line, end_col=end_col)


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


# ---------------------------------------------------------------- raw values (before unit checks)


def _new(cls: type[_N], **fields: Any) -> _N:
    """An IR node built from values the builder already typed: pydantic's validation skipped.

    Validation is a third of the front end's time on large files, and the
    builder only ever passes values of the declared types (the hypothesis
    round trip in tests/lang compares against validated nodes).
    """
    return cls.model_construct(**fields)


@dataclass
class _RawQ:
    """A number as written: its text, its unit ("" if none), where, and the source text."""

    text: str
    unit: str
    span: ir.Span
    written: str


@dataclass
class _RawVec:
    components: list[_RawQ]
    unit: str | None
    span: ir.Span
    written: str


@dataclass
class _RawPose:
    vector: _RawVec
    yaw: _RawQ | None
    rpy: _RawVec | None
    span: ir.Span


@dataclass
class _Item:
    """A statement inside a block, before it is assigned to its field."""

    key: str
    value: Any
    span: ir.Span


# ---------------------------------------------------------------- tree -> IR

# The value of something already reported (bad unit, missing statement): NaN fails every
# comparison, so the checker's range checks (mass > 0, lo <= hi, ...) stay quiet about it
# instead of piling a second, confusing error on the first.
_INVALID = float("nan")
# The count that stands in for a count already reported as not a whole number.
_VALID_COUNT = 1

# Deeper unions are almost certainly generated by mistake, and every later stage walks them recursively.
MAX_UNION_DEPTH = 32


def _union_depth(shape: Any) -> int:
    if isinstance(shape, ir.UnionShape):
        return 1 + max((_union_depth(p.shape) for p in shape.parts), default=0)
    return 0


class _Builder:
    """Builds IR nodes bottom-up; collects (does not raise) diagnostics about units and statements.

    Each grammar rule has a method of the same name taking (meta, children).
    """

    def __init__(self, path: str) -> None:
        self.start_file(path)

    def build(self, tree: Tree) -> Any:
        """The value of `tree`: its children built first, then its rule's method."""
        # A plain walk: Lark's Transformer with v_args(meta=True) costs 3x more per node.
        children = [self.build(c) if isinstance(c, Tree) else c for c in tree.children]
        return getattr(self, str(tree.data))(tree.meta, children)

    def start_file(self, path: str, text: str = "") -> None:
        """Reset for a new file (one builder serves every parse)."""
        self.path = path
        self.text = text
        self.diagnostics: list[Diagnostic] = []

    # ------------------------------------------------------------ helpers

    def span(self, meta: Any) -> ir.Span:
        if getattr(meta, "empty", True):
            return _new(ir.Span, file=self.path, line=1, col=1, end_line=1, end_col=1)
        return _new(
            ir.Span, file=self.path, line=meta.line, col=meta.column, end_line=meta.end_line, end_col=meta.end_column
        )

    def written(self, meta: Any) -> str:
        """The source text of a rule, whitespace runs shown as one space."""
        if getattr(meta, "empty", True):
            return ""
        return " ".join(self.text[meta.start_pos : meta.end_pos].split())

    def tspan(self, token: Token) -> ir.Span:
        return _token_span(token, self.path)

    def error(self, code: str, message: str, span: ir.Span | None, *notes: str) -> None:
        self.diagnostics.append(Diagnostic(code, message, span, notes=tuple(notes)))

    def to_quantity(self, raw: _RawQ, dimension: str) -> ir.Quantity:
        """A quantity of `dimension`, or an error (and 0) when its unit is missing or wrong."""
        if not self.check_unit(raw, dimension):
            return _new(ir.Quantity, value=_INVALID, unit=SI_UNIT[dimension], span=raw.span)
        return _new(ir.Quantity, value=self.si(raw, raw.unit), unit=raw.unit, span=raw.span)

    def check_unit(self, raw: _RawQ, dimension: str, span: ir.Span | None = None) -> bool:
        """True if `raw` has `dimension`; otherwise an error that says what was expected and got."""
        got = dimension_of(raw.unit)
        if got == dimension:
            return True
        where = span or raw.span
        message = f"expected {ARTICLE_NAME[dimension]}, got {ARTICLE_NAME[got]} `{raw.written}`"
        if got == "number":
            self.error("E202", message, where, f"add a unit: {unit_list(dimension)}")
        elif dimension == "number":
            self.error("E203", message, where, "remove the unit: this value has no dimension")
        else:
            self.error("E201", message, where, f"use {unit_list(dimension)}")
        return False

    def si(self, raw: _RawQ, unit: str) -> float:
        """The SI value of `raw` in `unit`; an error (and NaN) when it is too large for a float."""
        try:
            value = to_si(raw.text, unit)
        except OverflowError:
            value = math.inf
        if math.isfinite(value):
            return value
        self.error(
            "E208", f"`{raw.text}` is too large a number", raw.span, "numbers must stay below about 1e308 in SI units"
        )
        return _INVALID

    def number(self, raw: _RawQ) -> float:
        return self.si(raw, "") if self.check_unit(raw, "number") else _INVALID

    def integer(self, raw: _RawQ, what: str) -> int:
        if not self.check_unit(raw, "number"):
            return _VALID_COUNT
        if not re.fullmatch(r"[+-]?\d+", raw.text):
            self.error("E206", f"{what} must be a whole number, got `{raw.text}`", raw.span)
            return _VALID_COUNT
        return int(raw.text)

    def to_vector(self, raw: _RawVec, dimension: str, sizes: tuple[int, ...], what: str) -> ir.Vector:
        """A vector of `dimension` with one of `sizes` components (SI values, display unit kept)."""
        n = len(raw.components)
        if n not in sizes:
            want = " or ".join(str(s) for s in sizes)
            self.error("E204", f"{what} needs {want} components, got {n}", raw.span)
        zeros = _new(ir.Vector, values=tuple(_INVALID for _ in raw.components), unit=SI_UNIT[dimension], span=raw.span)
        if raw.unit is not None:
            return self._vector_with_unit(raw, dimension, zeros)
        ok = True
        for c in raw.components:
            ok = self.check_unit(c, dimension) and ok
        if not ok:
            return zeros
        units = {c.unit for c in raw.components}
        unit = units.pop() if len(units) == 1 else SI_UNIT[dimension]
        values = [self.si(c, c.unit) for c in raw.components]
        return _new(ir.Vector, values=tuple(values), unit=unit, span=raw.span)

    def _vector_with_unit(self, raw: _RawVec, dimension: str, zeros: ir.Vector) -> ir.Vector:
        """`(a, b, c) UNIT`: components must be plain numbers."""
        ok = True
        for c in raw.components:
            if not c.unit:
                continue
            ok = False
            if dimension_of(c.unit) == dimension:
                self.error(
                    "E205",
                    "the unit is given twice: after the vector and on this component",
                    c.span,
                    "write the unit once after the vector, or on every component",
                )
            else:
                self.check_unit(c, dimension)
        whole = _RawQ("", raw.unit or "", raw.span, raw.written)
        if not self.check_unit(whole, dimension, raw.span) or not ok:
            return zeros
        values = [self.si(c, raw.unit or "") for c in raw.components]
        return _new(ir.Vector, values=tuple(values), unit=raw.unit, span=raw.span)

    def to_pose(self, raw: _RawPose, sizes: tuple[int, ...] = (3,), rpy_allowed: bool = True) -> ir.Pose:
        position = self.to_vector(raw.vector, "length", sizes, "a position")
        yaw = self.to_quantity(raw.yaw, "angle") if raw.yaw is not None else None
        rpy = None
        if raw.rpy is not None:
            if not rpy_allowed:
                self.error("E207", "a body on the table can only turn about z: give `yaw`, not `rpy`", raw.rpy.span)
            rpy = self.to_vector(raw.rpy, "angle", (3,), "`rpy`")
        return _new(ir.Pose, position=position, yaw=yaw, rpy=rpy, span=raw.span)

    def single(self, items: list[_Item], owner: str, required: dict[str, str], where: ir.Span) -> dict[str, Any]:
        """Fields of a block whose statements may appear once each; reports repeats and missing ones."""
        seen: dict[str, _Item] = {}
        for item in items:
            if item.key in seen:
                first = seen[item.key].span
                self.error("E406", f"`{item.key}` given twice in {owner}", item.span, f"first given at {first}")
                continue
            seen[item.key] = item
        for key, example in required.items():
            if key not in seen:
                self.error("E407", f"{owner} has no `{key}`: add e.g. `{example}`", where)
        return {k: v.value for k, v in seen.items()}

    # ------------------------------------------------------------ values

    def quantity(self, meta: Any, children: list[Token]) -> _RawQ:
        number = children[0]
        unit = str(children[1]) if len(children) > 1 else ""
        return _RawQ(str(number), unit, self.span(meta), self.written(meta))

    def component(self, meta: Any, children: list[Token]) -> _RawQ:
        return self.quantity(meta, children)

    def vector(self, meta: Any, children: list[Any]) -> _RawVec:
        unit = str(children[-1]) if isinstance(children[-1], Token) else None
        comps = [c for c in children if isinstance(c, _RawQ)]
        return _RawVec(comps, unit, self.span(meta), self.written(meta))

    def yaw(self, meta: Any, children: list[Any]) -> tuple[str, _RawQ]:
        return ("yaw", children[0])

    def rpy(self, meta: Any, children: list[Any]) -> tuple[str, _RawVec]:
        return ("rpy", children[0])

    def pose(self, meta: Any, children: list[Any]) -> _RawPose:
        extra = dict(children[1:])
        return _RawPose(children[0], extra.get("yaw"), extra.get("rpy"), self.span(meta))

    # ------------------------------------------------------------ module

    def start(self, meta: Any, children: list[Any]) -> ir.Module:
        uses = [c for c in children if isinstance(c, ir.Use)]
        decls = [c for c in children if not isinstance(c, ir.Use)]
        return _new(ir.Module, path=self.path, uses=uses, decls=decls, span=self.span(meta))

    def use(self, meta: Any, children: list[Any]) -> ir.Use:
        target = children[0]
        if isinstance(target, Token):
            return _new(ir.Use, target=str(target)[1:-1], by_path=True, span=self.span(meta))
        return _new(ir.Use, target=target, by_path=False, span=self.span(meta))

    def dotted(self, meta: Any, children: list[Token]) -> str:
        return ".".join(str(c) for c in children)

    # ------------------------------------------------------------ bodies

    def body(self, meta: Any, children: list[Any]) -> ir.Body:
        name, items = children[0], children[1:]
        owner = f"body `{name}`"
        singles = [i for i in items if i.key not in ("frame", "explore")]
        fields = self.single(
            singles, owner, {"shape": "shape box (10, 10, 10) cm", "mass": "mass 0.5 kg"}, self.tspan(name)
        )
        spans = {i.key: i.span for i in singles}
        return _new(
            ir.Body,
            name=str(name),
            shape=fields.get("shape", _new(ir.BoxShape, size=_new(ir.Vector, values=(_INVALID,) * 3, unit="m"))),
            mass=fields.get("mass", _new(ir.Quantity, value=_INVALID, unit="kg")),
            friction=fields.get("friction"),
            friction_span=spans.get("friction"),
            frames=[i.value for i in items if i.key == "frame"],
            joint=fields.get("joint"),
            explores=[i.value for i in items if i.key == "explore"],
            span=self.span(meta),
            name_span=self.tspan(name),
        )

    def shape_stmt(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("shape", children[0], self.span(meta))

    def box(self, meta: Any, children: list[Any]) -> ir.BoxShape:
        return _new(ir.BoxShape, size=self.to_vector(children[0], "length", (3,), "a box size"), span=self.span(meta))

    def cylinder(self, meta: Any, children: list[Any]) -> ir.CylinderShape:
        return _new(
            ir.CylinderShape,
            radius=self.to_quantity(children[0], "length"),
            height=self.to_quantity(children[1], "length"),
            span=self.span(meta),
        )

    def mesh(self, meta: Any, children: list[Any]) -> ir.MeshShape:
        scale = self.number(children[1]) if len(children) > 1 else 1.0
        return _new(ir.MeshShape, path=str(children[0])[1:-1], scale=scale, span=self.span(meta))

    def union(self, meta: Any, children: list[Any]) -> ir.UnionShape:
        if not children:
            self.error("E407", "a union needs at least one `SHAPE at POSE` part", self.span(meta))
        depth = 1 + max((_union_depth(part.shape) for part in children), default=0)
        if depth == MAX_UNION_DEPTH + 1:  # reported once, at the innermost union too deep
            self.error("E104", f"unions nest more than {MAX_UNION_DEPTH} levels deep; flatten them", self.span(meta))
        return _new(ir.UnionShape, parts=children, span=self.span(meta))

    def union_part(self, meta: Any, children: list[Any]) -> ir.ShapePart:
        return _new(ir.ShapePart, shape=children[0], pose=self.to_pose(children[1]), span=self.span(meta))

    def mass_stmt(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("mass", self.to_quantity(children[0], "mass"), self.span(meta))

    def friction_stmt(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("friction", self.number(children[0]), self.span(meta))

    def frame_stmt(self, meta: Any, children: list[Any]) -> _Item:
        name = children[0]
        frame = _new(
            ir.Frame, name=str(name), pose=self.to_pose(children[1]), span=self.span(meta), name_span=self.tspan(name)
        )
        return _Item("frame", frame, self.span(meta))

    def joint_type(self, meta: Any, children: list[Token]) -> str:
        return str(children[0])

    def joint_stmt(self, meta: Any, children: list[Any]) -> _Item:
        kind = children[0]
        axis = self.to_vector(children[1], "number", (3,), "a joint axis")
        through = self.to_vector(children[2], "length", (3,), "`through`") if len(children) == 4 else None
        limits_raw: _RawVec = children[-1]
        dimension = "length" if kind == "prismatic" else "angle"
        limits = self.to_vector(limits_raw, dimension, (2,), "`limits`")
        values = list(limits.values) + [_INVALID] * (2 - len(limits.values))
        joint = _new(
            ir.Joint,
            type=kind,
            axis=axis,
            through=through,
            lower=_new(ir.Quantity, value=values[0], unit=limits.unit, span=limits_raw.span),
            upper=_new(ir.Quantity, value=values[1], unit=limits.unit, span=limits_raw.span),
            span=self.span(meta),
        )
        return _Item("joint", joint, self.span(meta))

    def explore_stmt(self, meta: Any, children: list[Any]) -> _Item:
        name, items = children[0], children[1:]
        fields = self.single(items, f"explore `{name}`", {}, self.tspan(name))
        explore = _new(
            ir.Explore,
            name=str(name),
            contacts=fields.get("contacts"),
            grasp=fields.get("grasp"),
            force=fields.get("force"),
            duration=fields.get("duration"),
            span=self.span(meta),
        )
        return _Item("explore", explore, self.span(meta))

    def contacts(self, meta: Any, children: list[Any]) -> _Item:
        faces = [str(c) for c in children[:-1]]
        spec = _new(ir.ContactSpec, faces=faces, steps=self.integer(children[-1], "`steps`"), span=self.span(meta))
        return _Item("contacts", spec, self.span(meta))

    def force_normal(self, meta: Any, children: list[Any]) -> _Item:
        spec = _new(ir.ForceSpec, mode="normal", magnitude=self.to_quantity(children[0], "force"), span=self.span(meta))
        return _Item("force", spec, self.span(meta))

    def force_directions(self, meta: Any, children: list[Any]) -> _Item:
        counts = [self.integer(_RawQ(str(t), "", self.tspan(t), str(t)), "a grid size") for t in children[:3]]
        spec = _new(
            ir.ForceSpec,
            mode="directions",
            grid=(counts[0], counts[1], counts[2]),
            magnitude=self.to_quantity(children[3], "force"),
            span=self.span(meta),
        )
        return _Item("force", spec, self.span(meta))

    def grasp(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("grasp", _new(ir.Ref, name=str(children[0]), span=self.tspan(children[0])), self.span(meta))

    def duration(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("duration", self.to_quantity(children[0], "time"), self.span(meta))

    # ------------------------------------------------------------ robots

    def robot(self, meta: Any, children: list[Any]) -> ir.Robot:
        name, items = children[0], children[1:]
        urdfs = [i for i in items if i.key == "urdf"]
        fields = self.single(urdfs, f"robot `{name}`", {"urdf": 'urdf "arm.urdf"'}, self.tspan(name))
        return _new(
            ir.Robot,
            name=str(name),
            urdf=fields.get("urdf", ""),
            urdf_span=urdfs[0].span if urdfs else None,
            effectors=[i.value for i in items if i.key == "effector"],
            span=self.span(meta),
            name_span=self.tspan(name),
        )

    def urdf(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("urdf", str(children[0])[1:-1], self.span(meta))

    def effector(self, meta: Any, children: list[Any]) -> _Item:
        name, link, offset = children
        effector = _new(ir.Effector, name=str(name), link=str(link), offset=self.to_pose(offset), span=self.span(meta))
        return _Item("effector", effector, self.span(meta))

    # ------------------------------------------------------------ affordances

    def affordances(self, meta: Any, children: list[Any]) -> ir.AffordanceSet:
        body = children[0]
        return _new(
            ir.AffordanceSet,
            body=_new(ir.Ref, name=str(body), span=self.tspan(body)),
            affordances=children[1:],
            span=self.span(meta),
        )

    def affordance(self, meta: Any, children: list[Any]) -> ir.Affordance:
        name, items = children[0], children[1:]
        fields = self.single(
            items, f"affordance `{name}`", {"action": "action fixed", "motion": "motion free"}, self.tspan(name)
        )
        return _new(
            ir.Affordance,
            name=str(name),
            action=fields.get(
                "action",
                _new(
                    ir.FreeC,
                ),
            ),
            motion=fields.get(
                "motion",
                _new(
                    ir.FreeC,
                ),
            ),
            evidence=fields.get("evidence"),
            span=self.span(meta),
        )

    def action(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("action", children[0], self.span(meta))

    def motion(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("motion", children[0], self.span(meta))

    def fixed(self, meta: Any, children: list[Any]) -> ir.FixedC:
        pose = self.to_pose(children[0]) if children else None
        return _new(ir.FixedC, pose=pose, span=self.span(meta))

    def prismatic(self, meta: Any, children: list[Any]) -> ir.PrismaticC:
        axis = self.to_vector(children[0], "number", (3,), "a direction")
        origin = self.to_vector(children[1], "length", (3,), "`from`") if len(children) > 1 else None
        return _new(ir.PrismaticC, axis=axis, origin=origin, span=self.span(meta))

    def revolute(self, meta: Any, children: list[Any]) -> ir.RevoluteC:
        center = self.to_vector(children[0], "length", (3,), "`about`")
        axis = self.to_vector(children[1], "number", (3,), "an axis")
        return _new(ir.RevoluteC, center=center, axis=axis, span=self.span(meta))

    def free(self, meta: Any, children: list[Any]) -> ir.FreeC:
        return _new(ir.FreeC, span=self.span(meta))

    def evidence(self, meta: Any, children: list[Any]) -> _Item:
        trials, loglik, posterior = children
        evidence = _new(
            ir.Evidence,
            trials=self.integer(trials, "`trials`"),
            loglik=self.number(loglik),
            posterior=self.number(posterior),
            span=self.span(meta),
        )
        return _Item("evidence", evidence, self.span(meta))

    # ------------------------------------------------------------ correspondences

    def correspondences(self, meta: Any, children: list[Any]) -> ir.Correspondences:
        return _new(ir.Correspondences, items=children, span=self.span(meta))

    def correspondence(self, meta: Any, children: list[Token]) -> ir.Correspondence:
        body, frame, effector = children
        frame_span = _new(
            ir.Span,
            file=self.path,
            line=body.line or 1,
            col=body.column or 1,
            end_line=frame.end_line or 1,
            end_col=frame.end_column or 1,
        )
        return _new(
            ir.Correspondence,
            frame=_new(ir.FrameRef, body=str(body), frame=str(frame), span=frame_span),
            effector=_new(ir.Ref, name=str(effector), span=self.tspan(effector)),
            span=self.span(meta),
        )

    # ------------------------------------------------------------ scenes

    def scene(self, meta: Any, children: list[Any]) -> ir.Scene:
        name, items = children[0], children[1:]
        tables = [i for i in items if isinstance(i, ir.Table)]
        if len(tables) > 1:
            self.error(
                "E406", f"`table` given twice in scene `{name}`", tables[1].span, f"first given at {tables[0].span}"
            )
        return _new(
            ir.Scene,
            name=str(name),
            table=tables[0] if tables else None,
            robots=[i for i in items if isinstance(i, ir.SceneRobot)],
            bodies=[i for i in items if isinstance(i, ir.SceneBody)],
            span=self.span(meta),
            name_span=self.tspan(name),
        )

    def table(self, meta: Any, children: list[Any]) -> ir.Table:
        size = self.to_vector(children[0], "length", (2,), "a table size")
        position = self.to_vector(children[1], "length", (3,), "the table position")
        return _new(ir.Table, size=size, position=position, span=self.span(meta))

    def scene_robot(self, meta: Any, children: list[Any]) -> ir.SceneRobot:
        name, kind, pose = children
        return _new(
            ir.SceneRobot,
            name=str(name),
            type=_new(ir.Ref, name=str(kind), span=self.tspan(kind)),
            pose=self.to_pose(pose),
            span=self.span(meta),
        )

    def scene_on_table(self, meta: Any, children: list[Any]) -> ir.SceneBody:
        name, kind, raw = children
        pose = self.to_pose(raw, sizes=(2,), rpy_allowed=False)
        return _new(
            ir.SceneBody,
            name=str(name),
            type=_new(ir.Ref, name=str(kind), span=self.tspan(kind)),
            placement=_new(ir.Placement, on_table=True, pose=pose, span=raw.span),
            span=self.span(meta),
        )

    def scene_at(self, meta: Any, children: list[Any]) -> ir.SceneBody:
        name, kind, raw = children
        return _new(
            ir.SceneBody,
            name=str(name),
            type=_new(ir.Ref, name=str(kind), span=self.tspan(kind)),
            placement=_new(ir.Placement, on_table=False, pose=self.to_pose(raw), span=raw.span),
            span=self.span(meta),
        )

    # ------------------------------------------------------------ tasks

    def task(self, meta: Any, children: list[Any]) -> ir.Task:
        name, items = children[0], children[1:]
        owner = f"task `{name}`"
        fields = self.single(
            [i for i in items if i.key != "goal"], owner, {"scene": "scene tabletop"}, self.tspan(name)
        )
        goals = [g for i in items if i.key == "goal" for g in i.value]
        if not goals:
            self.error(
                "E410", f"{owner} has no goal: add e.g. `goal block at (0.6, 0) m within 1 cm`", self.tspan(name)
            )
        return _new(
            ir.Task,
            name=str(name),
            scene=fields.get("scene", _new(ir.Ref, name="")),
            goals=goals,
            search=fields.get("search"),
            span=self.span(meta),
            name_span=self.tspan(name),
        )

    def task_scene(self, meta: Any, children: list[Token]) -> _Item:
        return _Item("scene", _new(ir.Ref, name=str(children[0]), span=self.tspan(children[0])), self.span(meta))

    def task_goal(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("goal", children, self.span(meta))

    def goal_at(self, meta: Any, children: list[Any]) -> ir.Goal:
        body, vector = children[0], children[1]
        rest = children[2:]
        yaw = self.to_quantity(rest.pop(0), "angle") if rest and isinstance(rest[0], _RawQ) else None
        tolerances: list[_RawQ] = rest[0] if rest else []
        tol_position = self.to_quantity(tolerances[0], "length") if tolerances else None
        tol_yaw = self.to_quantity(tolerances[1], "angle") if len(tolerances) > 1 else None
        return _new(
            ir.Goal,
            body=_new(ir.Ref, name=str(body), span=self.tspan(body)),
            position=self.to_vector(vector, "length", (2, 3), "a goal position"),
            yaw=yaw,
            tol_position=tol_position,
            tol_yaw=tol_yaw,
            span=self.span(meta),
        )

    def goal_yaw(self, meta: Any, children: list[Any]) -> ir.Goal:
        body, yaw = children[0], children[1]
        tolerances: list[_RawQ] = children[2] if len(children) > 2 else []
        if len(tolerances) > 1:
            self.error("E204", "a heading goal takes one tolerance, an angle: `within 3 deg`", tolerances[1].span)
        return _new(
            ir.Goal,
            body=_new(ir.Ref, name=str(body), span=self.tspan(body)),
            yaw=self.to_quantity(yaw, "angle"),
            tol_yaw=self.to_quantity(tolerances[0], "angle") if tolerances else None,
            span=self.span(meta),
        )

    def within(self, meta: Any, children: list[_RawQ]) -> list[_RawQ]:
        return children

    def task_search(self, meta: Any, children: list[Any]) -> _Item:
        fields = self.single(children, "`search`", {}, self.span(meta))
        spec = _new(
            ir.SearchSpec, max_depth=fields.get("max_depth"), timeout=fields.get("timeout"), span=self.span(meta)
        )
        return _Item("search", spec, self.span(meta))

    def max_depth(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("max_depth", self.integer(children[0], "`max_depth`"), self.span(meta))

    def timeout(self, meta: Any, children: list[Any]) -> _Item:
        return _Item("timeout", self.to_quantity(children[0], "time"), self.span(meta))
