"""The one writer of output files: whole or not at all, and never over what is not a regular file.

Every output of vkgl (plans, reports, datasets, generated modules, pictures,
animations, `vkgc fmt`'s rewrites, the reach cache) is written through here.
What happens depends on what the destination is (`decide`):

- a new path, or a regular file: the bytes go to a temporary file in the same
  folder (same file system), are flushed to disk, and the temporary file is
  renamed over the destination in one step, so a failed or interrupted write
  leaves the old file as it was and never half a file;
- a symbolic link: the file it points to is written as above (the link stays a
  link: `vkgc fmt link.vkg` formats the link's target);
- `/dev/stdout`, `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N`: the bytes go to
  that open stream, after what the process already printed to it;
- a character device (`/dev/null`, a terminal) or a named pipe (FIFO): opened
  and written in place, never created, truncated or renamed over. A FIFO that
  no process reads is refused at once rather than waited on;
- a directory, a block device or a socket: refused (`InputError`, exit 1).

A temporary file is registered before it exists, so Ctrl-C at any moment
(`discard_temporaries`, which the CLI's interrupt handler calls, or the
KeyboardInterrupt unwinding through `write_bytes`) leaves none behind.
"""

from __future__ import annotations

import contextlib
import enum
import errno
import os
import re
import stat
import sys
from collections.abc import Iterator
from pathlib import Path

from vkgl.errors import InputError

_IN_FLIGHT: set[str] = set()  # temporary files of writes under way (removed by `discard_temporaries`)
_STREAM = re.compile(r"/(?:dev/fd|proc/self/fd)/(\d+)")
_NAMED_STREAMS = {"/dev/stdout": 1, "/dev/stderr": 2}
_NAME_ROOM = 180  # characters of the destination's name kept in its temporary file's name (NAME_MAX is 255)


class Way(enum.Enum):
    """How an output is written (`decide`)."""

    REPLACE = "written to a temporary file, then renamed over the file"
    IN_PLACE = "opened and written in place (a character device or a FIFO)"
    STREAM = "written to the process's own open stream"


def decide(path: str | Path, shown: str | None = None) -> tuple[Way, Path]:
    """How `path` is written, and the path actually written (a link's final target); InputError if it cannot be.

    Looks with `stat` only: nothing is opened, created or changed. Messages
    name the output as `shown` (default: the path).
    """
    shown = shown or str(path)
    if _stream_fd(Path(path)) is not None:
        return Way.STREAM, Path(path)
    target = _final_target(Path(path))
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        return Way.REPLACE, target  # a new file (its folder is checked when it is made)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(f"{shown}: is a symbolic link loop; name a file") from None
        raise
    if stat.S_ISREG(mode):
        return Way.REPLACE, target
    if stat.S_ISDIR(mode):
        raise InputError(f"{shown}: is a directory; name a file in it")
    if stat.S_ISCHR(mode) or stat.S_ISFIFO(mode):
        return Way.IN_PLACE, target
    raise InputError(f"{shown}: is {_kind(mode)}; an output is a regular file, a named pipe or a character device")


def check_destination(path: str | Path, shown: str | None = None) -> Way:
    """Raise InputError unless `path` can be written (called before any work); return how it will be."""
    shown = shown or str(path)
    way, target = decide(path, shown)
    if way is Way.REPLACE:
        folder = target.parent
        if not folder.is_dir():
            raise InputError(f"{shown}: there is no directory `{folder}`; create it first")
        if not os.access(folder, os.W_OK):
            raise InputError(f"{shown}: the directory `{folder}` is not writable")
    return way


def write_bytes(path: str | Path, data: bytes) -> None:
    """Write `data` to the output `path` as `decide` says; on any error a replaced file is left as it was."""
    way, target = decide(path)
    stream_fd = _stream_fd(Path(path))
    if stream_fd is not None:
        _write_stream(stream_fd, data)
    elif way is Way.IN_PLACE:
        _write_in_place(target, data, shown=str(path))
    else:
        with _temporary_beside(target) as temporary:
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o600)
            with os.fdopen(fd, "wb") as stream:
                stream.write(data)
                stream.flush()
                os.fsync(stream.fileno())
            _commit(temporary, target)


def write_text(path: str | Path, text: str) -> None:
    """`write_bytes` of UTF-8 text."""
    write_bytes(path, text.encode("utf-8"))


@contextlib.contextmanager
def writing(path: str | Path) -> Iterator[Path]:
    """A temporary file name for a writer that needs one (ffmpeg); what it holds at the end is written to `path`.

    The output is written as `write_bytes` would (renamed over a regular file,
    copied into a device, FIFO or stream); on an error in the block nothing is
    written and the temporary file is removed.
    """
    way, target = decide(path)
    suffix = Path(path).suffix
    if way is Way.REPLACE:
        with _temporary_beside(target, suffix) as temporary:
            yield temporary
            with open(temporary, "rb+") as stream:
                os.fsync(stream.fileno())
            _commit(temporary, target)
        return
    import tempfile  # here: `vkgc check` writes nothing once its caches are kept, and starts without it

    with _temporary_beside(Path(tempfile.gettempdir()) / Path(path).name, suffix) as temporary:
        yield temporary
        data = temporary.read_bytes()
        os.unlink(temporary)
    write_bytes(path, data)


def discard_temporaries() -> None:
    """Remove the temporary files of writes under way (a process about to end at once calls this)."""
    for temporary in list(_IN_FLIGHT):
        with contextlib.suppress(OSError):
            os.unlink(temporary)


@contextlib.contextmanager
def _temporary_beside(target: Path, suffix: str = "") -> Iterator[Path]:
    """A fresh temporary name in `target`'s folder, registered before anything creates it, removed on error.

    `suffix` ends the name (ffmpeg chooses the container by it).
    """
    import secrets  # here, as tempfile above

    name = f".{target.name[:_NAME_ROOM]}.{os.getpid()}.{secrets.token_hex(4)}.tmp{suffix[:16]}"
    temporary = target.parent / name
    _IN_FLIGHT.add(str(temporary))
    try:
        yield temporary
    except BaseException:  # KeyboardInterrupt too: never leave a temporary file behind
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    finally:
        _IN_FLIGHT.discard(str(temporary))


def _commit(temporary: Path, target: Path) -> None:
    os.chmod(temporary, _mode_for(target))  # the temporary file is 0600; give what a plain write would
    os.replace(temporary, target)


def _mode_for(destination: Path) -> int:
    """The old file's permissions when replacing one, else 0666 less the umask (as `open(..., "w")` gives)."""
    try:
        return destination.stat().st_mode & 0o777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _final_target(path: Path) -> Path:
    """The file a path names once its symbolic links are followed (itself when it is not a link)."""
    if not os.path.islink(path):
        return path
    return Path(os.path.realpath(path))


def stream_descriptor(path: str | Path) -> int | None:
    """The descriptor of this process's own stream `path` names (`/dev/stdout` 1, `/dev/fd/N` N), else None."""
    return _stream_fd(Path(path))


def _stream_fd(path: Path) -> int | None:
    """The descriptor of `/dev/stdout`, `/dev/fd/N` or `/proc/self/fd/N`: this process's own streams."""
    text = os.path.normpath(str(path)) if str(path).startswith("/") else ""
    if text in _NAMED_STREAMS:
        return _NAMED_STREAMS[text]
    match = _STREAM.fullmatch(text)
    return int(match.group(1)) if match else None


def _write_stream(fd: int, data: bytes) -> None:
    """After what Python already printed there: through `sys.stdout`/`sys.stderr` for 1 and 2, else the descriptor."""
    stream = {1: sys.stdout, 2: sys.stderr}.get(fd)
    if stream is not None:
        stream.flush()
        buffer = getattr(stream, "buffer", None)
        if buffer is not None:
            buffer.write(data)
            buffer.flush()
        else:
            stream.write(data.decode("utf-8", errors="replace"))
            stream.flush()
        return
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def _write_in_place(target: Path, data: bytes, *, shown: str) -> None:
    """Open a character device or a FIFO for writing (never creating nor truncating anything) and write `data`."""
    flags = os.O_WRONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(target, flags)  # non-blocking: a FIFO without a reader fails at once (ENXIO) instead of hanging
    except OSError as exc:
        if exc.errno == errno.ENXIO:
            raise InputError(
                f"{shown}: is a named pipe (FIFO) that no process reads; start its reader first "
                f"(e.g. `cat {shown} &`), or write to a file"
            ) from None
        raise
    try:
        mode = os.fstat(fd).st_mode
        if not (stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)):  # replaced since `decide` looked: write nothing
            raise InputError(f"{shown}: changed while it was being written; try again")
        os.set_blocking(fd, True)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
    finally:
        os.close(fd)


def _kind(mode: int) -> str:
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a special file"


__all__ = [
    "Way",
    "check_destination",
    "decide",
    "discard_temporaries",
    "stream_descriptor",
    "write_bytes",
    "write_text",
    "writing",
]
