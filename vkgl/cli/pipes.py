"""A reader that goes away (`vkgc solve t.vkg | head -1`): `vkgc` goes quiet, finishes its work, exits 141.

Python ignores SIGPIPE, so a write to a pipe whose reader has exited raises
BrokenPipeError, which used to end the command with "Broken pipe" and exit 1,
before the files it was asked for (`--json plan.json`, `--plot p.png`) were
written. The console script instead puts `sys.stdout` and `sys.stderr` on
writers that, the first time their pipe is found closed, point the descriptor
at `/dev/null` (so every later write, by Python or by a child process, goes
nowhere without an error) and carry on. The command ends as it would have,
writing every file it was asked for, and `vkgc` then exits with
`EXIT_PIPE_CLOSED` (141, 128 + SIGPIPE, what a shell reports for a Unix tool
ended by a closed pipe) in place of 0; any other exit code (no plan, an
error) is kept, since it says more.
"""

from __future__ import annotations

import io
import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from typing_extensions import Buffer

__all__ = ["closed_by_reader", "install"]

_ENDS: list[_PipeEnd] = []


class _PipeEnd(io.RawIOBase):
    """A descriptor written with `os.write`; once its reader is gone, `/dev/null` takes its place. Closing it
    (RawIOBase's close: marks it closed) leaves the descriptor open: it is the process's, not this writer's."""

    def __init__(self, fd: int) -> None:
        super().__init__()
        self._fd = fd
        self.reader_gone = False

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self._fd

    def isatty(self) -> bool:
        return os.isatty(self._fd)

    def write(self, data: Buffer, /) -> int:
        if self.reader_gone:
            return memoryview(data).nbytes
        try:
            return os.write(self._fd, data)
        except BrokenPipeError:
            self._silence()
            return memoryview(data).nbytes

    def _silence(self) -> None:
        self.reader_gone = True
        devnull = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(devnull, self._fd)
        finally:
            os.close(devnull)


def install() -> None:
    """Put `sys.stdout` and `sys.stderr` on writers that go quiet when their reader goes (console script only)."""
    for name in ("stdout", "stderr"):
        old = getattr(sys, name)
        try:
            fd = old.fileno()
        except (AttributeError, OSError, ValueError):  # not a real descriptor (embedded, captured): leave it
            continue
        old.flush()
        end = _PipeEnd(fd)
        new = io.TextIOWrapper(
            io.BufferedWriter(end),
            encoding=old.encoding,
            errors=old.errors,
            line_buffering=old.line_buffering,
            write_through=getattr(old, "write_through", False),
        )
        _ENDS.append(end)
        setattr(sys, name, new)


def closed_by_reader() -> bool:
    """Whether a reader of `vkgc`'s standard output or error went away before the command ended (flushes both)."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a stream not ours, closed or broken: nothing more to say on it
            pass
    return any(end.reader_gone for end in _ENDS)
