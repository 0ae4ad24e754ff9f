"""`VkgLexer`: Pygments highlighting for `.vkg` files.

Registered under the `pygments.lexers` entry point as `vkg`, so once the
package is installed `pygmentize -l vkg file.vkg` works, and Markdown renderers
that use Pygments highlight ```vkg fences. The keyword lists come from the Lark
grammar (`vkgl.editor.vocabulary`), so a keyword added there is highlighted here.

Token classes: declaration keywords (`body`, `scene`, ...) and the name they
declare; type keywords (`box`, `prismatic`, ...); other keywords; units right
after a number or a vector (`10 cm`, `(1, 2) m`); faces (`+x`); strings;
numbers; `#` comments. A character the language does not allow is an `Error`
token, which is how tests check that real files lex cleanly.
"""

from __future__ import annotations

import re
from typing import ClassVar

from pygments.lexer import RegexLexer, bygroups, default
from pygments.token import (
    Comment,
    Keyword,
    Name,
    Number,
    Operator,
    Punctuation,
    String,
    Whitespace,
)

from vkgl.editor.vocabulary import (
    DECLARATIONS,
    FACE_PATTERN,
    NAME_PATTERN,
    NUMBER_PATTERN,
    TYPES,
    plain_keywords,
    units,
)

_END = r"(?![A-Za-z0-9_])"
_NAMED = tuple(d for d in DECLARATIONS if d != "use")


def _one_of(options: tuple[str, ...]) -> str:
    """A regex group matching any of `options` as a whole word (longest first)."""
    ordered = sorted(options, key=lambda w: (-len(w), w))
    return "(" + "|".join(re.escape(w) for w in ordered) + ")" + _END


class VkgLexer(RegexLexer):
    """Lexer for VKG, the language of virtual kinematic graphs (`vkgc`)."""

    name = "VKG"
    aliases: ClassVar[list[str]] = ["vkg"]
    filenames: ClassVar[list[str]] = ["*.vkg"]
    mimetypes: ClassVar[list[str]] = ["text/x-vkg"]
    url = "https://github.com/vkgl/vkgl"

    tokens: ClassVar[dict[str, list]] = {  # type: ignore[type-arg]
        "root": [
            (r"\s+", Whitespace),
            (r"#[^\n]*", Comment.Single),
            (r'"[^"\n]*"', String.Double),
            (
                r"(use)(\s+)(" + NAME_PATTERN + r"(?:\." + NAME_PATTERN + r")*)",
                bygroups(Keyword.Namespace, Whitespace, Name.Namespace),
            ),
            (r"(use)" + _END, Keyword.Namespace),
            (
                _one_of(_NAMED) + r"(\s+)(" + NAME_PATTERN + r")(?![A-Za-z0-9_]|\s*:)",
                bygroups(Keyword.Declaration, Whitespace, Name.Class),
            ),
            (_one_of(_NAMED), Keyword.Declaration),
            (
                r"(frame|effector)(\s+)(" + NAME_PATTERN + r")",
                bygroups(Keyword, Whitespace, Name.Variable),
            ),
            (
                r"(" + NAME_PATTERN + r")(\s*)(:)(\s*)(" + NAME_PATTERN + r")",
                bygroups(Name.Variable, Whitespace, Punctuation, Whitespace, Name.Class),
            ),
            (_one_of(TYPES), Keyword.Type),
            (_one_of(plain_keywords()), Keyword),
            (FACE_PATTERN, Name.Constant),
            (NUMBER_PATTERN, Number, "unit"),
            (NAME_PATTERN, Name),
            (r"\)", Punctuation, "unit"),
            (r"[{}(,.:]", Punctuation),
            (r"[=~]", Operator),
        ],
        # A unit directly after a number or a closing parenthesis, on the same line.
        "unit": [
            (
                r"([ \t]*)" + _one_of(units()),
                bygroups(Whitespace, Name.Builtin),
                "#pop",
            ),
            default("#pop"),
        ],
    }
