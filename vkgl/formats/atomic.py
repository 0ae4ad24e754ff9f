"""Writing output files atomically, so that a failed or interrupted write never leaves half a file.

Every writer of `vkgl.formats` and the CLI write through here: the bytes go to
a temporary file in the destination's folder (same file system), which is
flushed to disk and then renamed over the destination in one step.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

_IN_FLIGHT: set[str] = set()  # temporary files being written now (removed by `discard_temporaries`)


def write_bytes(path: str | Path, data: bytes) -> None:
    """Replace `path` by `data` in one step; on any error the old file (if any) is left as it was."""
    destination = Path(path)
    handle, temporary = tempfile.mkstemp(prefix=f".{destination.name}.", suffix=".tmp", dir=destination.parent)
    _IN_FLIGHT.add(temporary)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, _mode_for(destination))  # mkstemp makes 0600; give what a plain write would
        os.replace(temporary, destination)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    finally:
        _IN_FLIGHT.discard(temporary)


def _mode_for(destination: Path) -> int:
    """The old file's permissions when replacing one, else 0666 less the umask (as `open(..., "w")` gives)."""
    try:
        return destination.stat().st_mode & 0o777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def discard_temporaries() -> None:
    """Remove the temporary files of writes under way (a process about to end at once calls this)."""
    for temporary in list(_IN_FLIGHT):
        with contextlib.suppress(OSError):
            os.unlink(temporary)


def write_text(path: str | Path, text: str) -> None:
    """`write_bytes` of UTF-8 text."""
    write_bytes(path, text.encode("utf-8"))
