"""Reading source files safely: only regular files, at most MAX_SOURCE_BYTES, UTF-8.

Every `.vkg` file the front end reads (given on the command line, or named by a
`use`) goes through `read_source`. It stats the path before opening it, so a
FIFO, a device, a directory or a symbolic-link loop is reported (E506) instead
of hanging or exhausting memory; a file larger than the limit is refused
(E507); bytes that are not UTF-8 are reported at the line and column where the
first bad byte is (E508), without showing the file's text. A file reached
through a symbolic link is read only when the file it finally names is a
`.vkg` file (E509): `pw.vkg` linking to `/etc/passwd` is never read, so its
lines are never quoted in a diagnostic.
"""

from __future__ import annotations

import errno
import os
import stat
from dataclasses import replace
from pathlib import Path

from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir

MAX_SOURCE_BYTES = 10 * 1024 * 1024
"""10 MiB: the largest source file read (the stdlib's largest module is a few KiB)."""


def read_source(path: Path, shown: str, span: ir.Span | None = None) -> str | Diagnostic:
    """The text of the source file `path` (shown as `shown`), or a diagnostic saying why it cannot be used.

    `span` is where the file was named (a `use`); None for a file given on the
    command line, whose diagnostics then name the file without a position.
    """
    problem = foreign_link(path, shown, span) or file_problem(path, shown, span)
    if problem is not None:
        return problem
    try:
        with open(path, "rb") as stream:
            data = stream.read(MAX_SOURCE_BYTES + 1)
    except OSError as exc:
        return _unreadable(shown, exc.strerror or str(exc), span)
    if len(data) > MAX_SOURCE_BYTES:  # a file that grew, or one of /proc whose size stat does not know
        return _too_large(shown, span)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        return not_utf8(shown, data, exc, span)


def foreign_link(path: Path, shown: str, span: ir.Span | None = None) -> Diagnostic | None:
    """E509 when `path` goes through a symbolic link to a file that is not a `.vkg` file (nothing is opened)."""
    real = Path(os.path.realpath(path))
    if real.suffix == ".vkg" or real == Path(os.path.abspath(path)):
        return None
    message = f"`{shown}` is a link to `{_relative(real)}`, which is not a .vkg file; it is not read"
    note = "a source reached through a symbolic link must be a .vkg file; name the .vkg file itself"
    return _at(codes.USE_NOT_VKG.diagnostic(message, span, note), shown)


def _relative(real: Path) -> str:
    """`real` relative to the working directory when inside it, else absolute."""
    try:
        relative = os.path.relpath(real)
    except ValueError:  # another drive on Windows
        return str(real)
    return str(real) if relative.startswith("..") else relative


def file_problem(path: Path, shown: str, span: ir.Span | None = None, *, limit: bool = True) -> Diagnostic | None:
    """Why `path` cannot be read as a source file, found by `stat` alone (nothing is opened); None if it can.

    `limit=False` skips the size limit (for inputs that are not `.vkg` sources, e.g. trials datasets).
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        dangling = os.path.islink(path)
        return _unreadable(shown, "no such file (a symbolic link points there)" if dangling else "no such file", span)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return _not_regular(shown, "a symbolic link loop", span)
        return _unreadable(shown, exc.strerror or str(exc), span)
    if stat.S_ISDIR(info.st_mode):
        note = f"name the .vkg files in it, e.g. `{Path(shown) / '*.vkg'}`"
        return _not_regular(shown, "a directory", span, note)
    if not stat.S_ISREG(info.st_mode):
        return _not_regular(shown, _kind(info.st_mode), span)
    if limit and info.st_size > MAX_SOURCE_BYTES:
        return _too_large(shown, span)
    if not os.access(path, os.R_OK):
        return _unreadable(shown, "permission denied", span)
    return None


def not_a_regular_file(path: str | Path) -> str | None:
    """Why `path` is not a regular file, by `stat` alone (nothing is opened); None when it is one.

    For messages: "no such file", "it is a named pipe (FIFO), not a regular file", ...
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return "no such file"
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return "it is a symbolic link loop, not a regular file"
        return exc.strerror or str(exc)
    if stat.S_ISDIR(info.st_mode):
        return "it is a directory, not a regular file"
    if not stat.S_ISREG(info.st_mode):
        return f"it is {_kind(info.st_mode)}, not a regular file"
    return None


def oversized_text(text: str, shown: str, span: ir.Span | None = None) -> Diagnostic | None:
    """E507 when `text` (an editor buffer standing for `shown`) is larger than a source file may be; else None."""
    if len(text) <= MAX_SOURCE_BYTES // 4 or len(text.encode("utf-8", "surrogatepass")) <= MAX_SOURCE_BYTES:
        return None
    return _too_large(shown, span)


def _kind(mode: int) -> str:
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a special file"


def _unreadable(shown: str, reason: str, span: ir.Span | None) -> Diagnostic:
    return _at(codes.SOURCE_UNREADABLE.diagnostic(f"cannot read `{shown}`: {reason}", span), shown)


def _not_regular(shown: str, what: str, span: ir.Span | None, note: str = "") -> Diagnostic:
    message = f"`{shown}` is not a regular file: it is {what}"
    notes = (note or "sources are regular .vkg files; name the file itself",)
    return _at(codes.NOT_REGULAR_FILE.diagnostic(message, span, *notes), shown)


def _too_large(shown: str, span: ir.Span | None) -> Diagnostic:
    message = f"`{shown}` is larger than {MAX_SOURCE_BYTES // (1024 * 1024)} MiB, the limit for a source file"
    return _at(codes.SOURCE_TOO_LARGE.diagnostic(message, span, "split it into modules joined by `use`"), shown)


def not_utf8(shown: str, data: bytes, exc: UnicodeDecodeError, span: ir.Span | None = None) -> Diagnostic:
    """E508 for `data` read from `shown`: where (line:col of the first bad byte) and what, never the text."""
    start = exc.start
    line = data.count(b"\n", 0, start) + 1
    line_start = data.rfind(b"\n", 0, start) + 1
    col = len(data[line_start:start].decode("utf-8", errors="replace")) + 1
    message = f"`{shown}` is not UTF-8 text: byte 0x{data[start]:02x} at line {line}, column {col} ({exc.reason})"
    note = "a .vkg file is UTF-8 text; save it as UTF-8"
    if span is None:
        # model_construct: typed values, and validation would build the validator of Span
        span = ir.Span.model_construct(file=shown, line=line, col=col, end_line=line, end_col=col + 1)
    return codes.NOT_UTF8.diagnostic(message, span, note)


def _at(diag: Diagnostic, shown: str) -> Diagnostic:
    """The diagnostic naming the file it is about when it has no position."""
    return diag if diag.span is not None else replace(diag, file=shown)
