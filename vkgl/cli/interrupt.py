"""Ctrl-C or SIGTERM in `vkgc`: stop at once, cleanly.

The console script installs `on_interrupt` as the SIGINT and SIGTERM handler
(SIGTERM is what `timeout`, a job scheduler or a container's stop sends,
often to the main process only). It ends
the worker processes (exploration runs trials in a process pool), removes the
temporary files of writes under way (outputs are written atomically, so no
output is ever half written), says so on stderr and exits 130 (Ctrl-C) or
143 (SIGTERM, 128 + 15, as a shell reports) — without
unwinding through the interpreter's exit handlers, which would wait for the
threads of the pool just torn down, and without letting the interrupt land
inside a C extension's import (which would turn it into an ImportError).
"""

from __future__ import annotations

import os
import signal
import sys
import time
from types import FrameType

from vkgl.cli.exit_codes import EXIT_INTERRUPTED, EXIT_TERMINATED

_GRACE = 0.5  # s the workers are given to end after SIGTERM before they are killed


def install() -> None:
    """Make Ctrl-C and SIGTERM end `vkgc` at once (call once, in the main thread of the console script)."""
    signal.signal(signal.SIGINT, on_interrupt)
    signal.signal(signal.SIGTERM, on_interrupt)


def on_interrupt(signum: int, frame: FrameType | None) -> None:
    """End the workers, drop half-written files, exit 130 (SIGINT) or 143 (SIGTERM)."""
    from vkgl.atomic import discard_temporaries

    # No worker without multiprocessing imported; importing it at the top would cost every `vkgc` start 4 ms.
    # Ctrl-C may come while it is being imported: a module half initialised has no `active_children` yet, and
    # no worker either.
    active_children = getattr(sys.modules.get("multiprocessing"), "active_children", None)
    children = active_children() if callable(active_children) else []
    for child in children:
        child.terminate()
    # one grace for all of them, not one each: two workers busy in a long DART step took 2 s in turn
    deadline = time.monotonic() + _GRACE
    for child in children:
        child.join(max(0.0, deadline - time.monotonic()))
    stuck = [child for child in children if child.is_alive()]
    for child in stuck:
        child.kill()
    for child in stuck:
        child.join(_GRACE)  # reaped: a killed child left unreaped lingers as a zombie in its process group
    discard_temporaries()
    try:
        sys.stdout.flush()
        if sys.stderr.isatty():  # a live bar (exploring, executing) hides the cursor: clear its line, show it
            sys.stderr.write("\r\x1b[2K\x1b[?25h")
        sys.stderr.write("vkgc: terminated\n" if signum == signal.SIGTERM else "vkgc: interrupted\n")
        sys.stderr.flush()
    finally:
        os._exit(EXIT_TERMINATED if signum == signal.SIGTERM else EXIT_INTERRUPTED)
