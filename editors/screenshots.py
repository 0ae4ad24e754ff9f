"""Render the pictures of docs/editors.md: highlighted `.vkg`, and a diagnostic as an editor shows it.

    python editors/screenshots.py        # writes docs/img/editor_highlight.png, docs/img/editor_diagnostic.png

The colours are those `VkgLexer` gives each token under a Pygments style; the
diagnostic is the one `vkgc lsp` publishes for the file (the same analysis,
`vkgl.editor.analysis.analyze`), drawn as a squiggle with its hover box.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import matplotlib
from PIL import Image, ImageDraw, ImageFont
from pygments.styles import get_style_by_name

from vkgl.editor.analysis import analyze
from vkgl.editor.lexer import VkgLexer

REPO = Path(__file__).resolve().parent.parent
FONTS = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
SIZE, LINE, PAD, GUTTER, TITLE = 15, 21, 12, 48, 30
STYLE = get_style_by_name("monokai")


def _font(bold: bool = False, italic: bool = False) -> ImageFont.FreeTypeFont:
    name = (
        "DejaVuSansMono"
        + ("-Bold" if bold else "")
        + ("Oblique" if italic and bold else "-Oblique" if italic else "")
    )
    return ImageFont.truetype(str(FONTS / f"{name}.ttf"), SIZE)


def render(
    text: str,
    title: str,
    out: Path,
    squiggles: Sequence[tuple[int, int, int]] = (),
    hover: Sequence[str] = (),
    hover_at: tuple[int, int] = (0, 0),
    status: str = "",
) -> None:
    """Draw `text` highlighted, with red squiggles (line, start, end; 0-based) and a hover box of `hover` lines."""
    lines = text.rstrip("\n").split("\n")
    plain = _font()
    char = plain.getlength("M")
    width = int(GUTTER + PAD + char * (max(len(line) for line in lines) + 4))
    if hover:
        width = max(
            width, int(GUTTER + PAD + char * (hover_at[1] + max(map(len, hover)) + 4))
        )
    height = (
        TITLE
        + PAD * 2
        + LINE * (len(lines) + (len(hover) + 2 if hover else 0))
        + (LINE + 8 if status else 0)
    )
    image = Image.new("RGB", (width, height), STYLE.background_color)
    draw = ImageDraw.Draw(image)
    draw.rectangle([0, 0, width, TITLE], fill="#1e1f1c")
    draw.text((PAD, 7), title, font=plain, fill="#cfcfc2")

    def xy(line: int, col: int) -> tuple[float, float]:
        return GUTTER + PAD + col * char, TITLE + PAD + line * LINE

    for number in range(len(lines)):
        draw.text(
            (PAD, xy(number, 0)[1]), f"{number + 1:>3}", font=plain, fill="#75715e"
        )
    line, col = 0, 0
    for kind, value in VkgLexer().get_tokens(text):
        style = STYLE.style_for_token(kind)
        font = _font(style["bold"], style["italic"])
        colour = "#" + (style["color"] or "f8f8f2")
        for i, part in enumerate(value.split("\n")):
            if i:
                line, col = line + 1, 0
            if part and line < len(lines):
                draw.text(xy(line, col), part, font=font, fill=colour)
            col += len(part)
    for row, start, end in squiggles:
        x0, y = xy(row, start)
        x1, _ = xy(row, end)
        y += LINE - 3
        points = [
            (x0 + k * 3, y + (2 if k % 2 else -1))
            for k in range(int((x1 - x0) / 3) + 1)
        ]
        draw.line(points, fill="#f92672", width=2)
    if hover:
        x, y = xy(hover_at[0] + 1, hover_at[1])
        box = [
            x,
            y + 4,
            x + char * (max(map(len, hover)) + 2),
            y + 4 + LINE * len(hover) + PAD,
        ]
        draw.rectangle(box, fill="#3e3d32", outline="#75715e")
        for i, text_line in enumerate(hover):
            draw.text(
                (x + char, y + 4 + PAD / 2 + i * LINE),
                text_line,
                font=_font(bold=i == 0),
                fill="#f8f8f2" if i == 0 else "#cfcfc2",
            )
    if status:
        draw.rectangle([0, height - LINE - 8, width, height], fill="#75715e")
        draw.text((PAD, height - LINE - 4), status, font=plain, fill="#f8f8f2")
    out.parent.mkdir(parents=True, exist_ok=True)
    image.save(out)


def main() -> int:
    """Write both pictures into docs/img/."""
    hook = REPO / "stdlib" / "bodies" / "hook.vkg"
    render(
        hook.read_text(encoding="utf-8"),
        "stdlib/bodies/hook.vkg",
        REPO / "docs" / "img" / "editor_highlight.png",
    )
    task = REPO / "examples" / "tasks" / "a_push.vkg"
    text = task.read_text(encoding="utf-8").replace(
        "within 1 cm, 3deg", "within 1 deg, 3deg"
    )
    analysis = analyze(task, {task.resolve(): text})
    diag = analysis.diagnostics[0]
    assert diag.span is not None
    row, start, end = diag.span.line - 1, diag.span.col - 1, diag.span.end_col - 1
    message = [
        f"{diag.message}  vkgc({diag.code})",
        *(f"note: {n}" for n in diag.notes),
    ]
    status = f"Problems: {len(analysis.diagnostics)} error  --  tasks/a_push.vkg:{diag.span.line}:{diag.span.col}"
    render(
        text,
        "examples/tasks/a_push.vkg (unsaved)",
        REPO / "docs" / "img" / "editor_diagnostic.png",
        squiggles=[(row, start, end)],
        hover=message,
        hover_at=(row, start),
        status=status,
    )
    print("docs/img/editor_highlight.png, docs/img/editor_diagnostic.png: written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
