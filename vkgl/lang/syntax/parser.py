"""The parser: VKG source text -> IR `Module`, with units checked and converted to SI.

Lark's LALR parser (grammar/vkg.lark, made once per process) makes a tree;
`Builder` (vkgl/lang/syntax/builder.py) turns it into IR nodes that keep their source
spans; syntax errors become diagnostics in vkgl/lang/syntax/syntax_errors.py. Problems
that need no other module (syntax, units, missing or repeated statements) are
found here; everything that needs names from other modules is the checker's job
(vkgl/lang/checks/checker.py).
"""

from __future__ import annotations

import gc
import re
import threading
from dataclasses import dataclass
from functools import lru_cache

from lark import Lark, Token
from lark.exceptions import UnexpectedInput

from vkgl.errors import CompileError
from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.syntax.builders.builder import MAX_UNION_DEPTH, Builder
from vkgl.lang.syntax.parse_cache import ParseCache
from vkgl.lang.syntax.syntax_errors import syntax_diagnostics
from vkgl.lang.syntax.tables import load_or_build
from vkgl.lang.syntax.values import new_node
from vkgl.resources import grammar_path


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


PARSE_CACHE_CHARS = 512 * 1024
"""The parse cache holds the parses of at most this many characters of source (least recently used go first).

A parse takes about 170 bytes of memory per character of source, so the cache
stays under about 90 MB however many distinct texts are parsed (an editor
sends a new text on every keystroke); a text larger than a quarter of the
budget is never kept. The stdlib and the examples are about 20 K characters.
"""

_Parsed = tuple[ir.Module | None, tuple[Comment, ...], tuple[Diagnostic, ...]]


_cache: ParseCache[_Parsed] = ParseCache(PARSE_CACHE_CHARS)


def parse_cache() -> ParseCache:
    """The process's parse cache (benchmarks clear it; tests look at its size)."""
    return _cache


def _parse_cached(text: str, path: str) -> _Parsed:
    # A compilation parses each imported module once; checking many files that share
    # imports (vkgc check examples/ stdlib/) parses each shared module once per process.
    found = _cache.get((text, path))
    if found is not None:
        return found
    module, comments, diagnostics = _parse_uncached(text, path)
    parsed = (module, tuple(comments), tuple(diagnostics))
    _cache.put((text, path), parsed)
    return parsed


MAX_TOKENS = 200_000
"""The most tokens a source file may hold (E510). Compiling costs about 1 KB of memory per token at its peak;
a 10,000-body scene is about 140,000 tokens (bench/lang/bench_limits.py measures both sides of the limit)."""

# What counts as a token: a name, a number (with its exponent), a string, any other mark; a comment is skipped.
_TOKEN = re.compile(r'#[^\n]*|"[^"\n]*"?|\w+(?:\.\w+)*(?:[eE][-+]?\d+)?|\S')


def too_many_tokens(text: str, path: str) -> Diagnostic | None:
    """E510 at the first token past MAX_TOKENS, or None (the count stops there: its cost is bounded too)."""
    if len(text) <= MAX_TOKENS:  # every token takes at least one character
        return None
    count = 0
    for match in _TOKEN.finditer(text):
        if match.group().startswith("#"):
            continue
        count += 1
        if count > MAX_TOKENS:
            start = match.start()
            line = text.count("\n", 0, start) + 1
            col = start - text.rfind("\n", 0, start)
            span = new_node(ir.Span, file=path, line=line, col=col, end_line=line, end_col=col + len(match.group()))
            limit = f"{MAX_TOKENS:,} tokens, the limit for a source file"
            message = f"`{path}` has more than {limit}; token {MAX_TOKENS + 1:,} is here"
            note = "split it into modules joined by `use` (a file this large would take gigabytes to compile)"
            return codes.TOO_MANY_TOKENS.diagnostic(message, span, note)
    return None


def _parse_uncached(text: str, path: str) -> tuple[ir.Module | None, list[Comment], list[Diagnostic]]:
    refused = too_many_tokens(text, path)
    if refused is not None:
        return None, [], [refused]
    builder = Builder(path, text)
    # The parse allocates a few objects per character and frees none of them until
    # the end; pausing the cyclic garbage collector meanwhile halves the time.
    collecting = gc.isenabled()
    gc.disable()
    try:
        with _comments.collect() as comments:
            tree = lark_parser().parse(text)
        module = builder.build(tree)
    except UnexpectedInput as exc:
        return None, [], syntax_diagnostics(lark_parser(), exc, text, path)
    except RecursionError:
        span = new_node(ir.Span, file=path, line=1, col=1, end_line=1, end_col=2)
        message = f"shapes nest too deeply to read; unions may nest at most {MAX_UNION_DEPTH} levels"
        return None, [], [codes.NESTING_TOO_DEEP.diagnostic(message, span)]
    finally:
        if collecting:
            gc.enable()
    lexed = [Comment(t.line or 0, t.column or 0, str(t)) for t in comments]
    module = module.model_copy(update={"doc": _doc_comment(text, lexed)})
    return module, lexed, builder.diagnostics


# ---------------------------------------------------------------- the Lark parser


class _CommentCollector:
    """The lexer callback of the one Lark parser: appends each comment to the list of the parse in progress.

    Lark fixes lexer callbacks when it builds the parser, so the list of the
    current parse lives here, one per thread.
    """

    def __init__(self) -> None:
        self._local = threading.local()

    def __call__(self, token: Token) -> None:
        sink = getattr(self._local, "sink", None)
        if sink is not None:
            sink.append(token)

    def __reduce__(self) -> str:
        # Saved with the grammar's tables (tables.py) by name, so that a loaded parser calls this very collector.
        return "_comments"

    def collect(self) -> _Collecting:
        """A context in which the comments lexed go to a fresh list (the context's value)."""
        return _Collecting(self._local)


class _Collecting:
    def __init__(self, local: threading.local) -> None:
        self._local = local
        self.tokens: list[Token] = []

    def __enter__(self) -> list[Token]:
        self._local.sink = self.tokens
        return self.tokens

    def __exit__(self, *exc: object) -> None:
        self._local.sink = None


_comments = _CommentCollector()


_OPTIONS: dict[str, object] = {
    "parser": "lalr",
    "lexer": "contextual",
    "propagate_positions": True,
    "maybe_placeholders": False,
}


@lru_cache(maxsize=1)
def lark_parser() -> Lark:
    """The LALR parser of grammar/vkg.lark, made once per process (its tables kept between processes: tables.py)."""
    grammar = grammar_path().read_text(encoding="utf-8")
    return load_or_build(grammar, _OPTIONS, lambda: Lark(grammar, lexer_callbacks={"COMMENT": _comments}, **_OPTIONS))


def _doc_comment(text: str, comments: list[Comment]) -> str | None:
    """The file's doc comment: its first block of full-line comments, when a blank line ends it.

    A comment block directly above a statement belongs to that statement instead.
    """
    lines: list[str] = []
    by_line = {c.line: c for c in comments}
    for number, line in enumerate(text.split("\n"), start=1):
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
    for number, line in enumerate(text.split("\n"), start=1):
        stripped = line.strip()
        if not stripped:
            if last:
                return last
            continue
        if not stripped.startswith("#"):
            return 0
        last = number
    return last
