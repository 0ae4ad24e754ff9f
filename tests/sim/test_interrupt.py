"""Ctrl-C or SIGTERM in `vkgc explore` and `vkgc learn`: exit 130 (143) within 2 s, no process left, no partial file.

Twenty interrupts at random (seeded) moments of the exploration, sent as a
terminal does: SIGINT to the whole process group.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from conftest import STDLIB

VKGC = [sys.executable, "-m", "vkgl.cli"]
MOMENTS = random.Random(20261123)


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    return True


def _ended_at_once(argv: list[str], delay: float, send: Callable[[int], None], what: str) -> tuple[int, str]:
    """Start `vkgc` (`argv`) in its own process group, `send` it a signal after `delay` s; its exit code and
    stderr once it and every worker have ended (it fails the test if they take more than 2 s, or 1 s more)."""
    process = subprocess.Popen(
        argv, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    time.sleep(delay)
    send(process.pid)
    sent = time.monotonic()
    try:
        _, err = process.communicate(timeout=2.0)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        pytest.fail(f"{what} at {delay:.2f} s: still running 2 s after it")
    assert time.monotonic() - sent < 2.0
    assert "Traceback" not in err
    deadline = time.monotonic() + 1.0
    while _group_alive(process.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _group_alive(process.pid), f"a worker process outlived {what}"
    return process.returncode, err


@pytest.mark.parametrize("k", range(20))
def test_ctrl_c_ends_everything_at_once(k: int, tmp_path: Path) -> None:
    delay = MOMENTS.uniform(0.6, 2.5)  # after start-up, while the workers simulate
    if k % 2:
        out = tmp_path / "affordances"
        argv = [*VKGC, "learn", str(STDLIB / "bodies" / "block.vkg"), "-o", str(out)]
        partial = out / "block.vkg"
    else:
        partial = tmp_path / "trials.npz"
        argv = [*VKGC, "explore", str(STDLIB / "bodies" / "block.vkg"), "-o", str(partial)]
    code, err = _ended_at_once(argv, delay, lambda pid: os.killpg(pid, signal.SIGINT), f"Ctrl-C {k}")
    assert code == 130, err
    assert err.strip().endswith("vkgc: interrupted")
    assert not partial.exists()
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == []


@pytest.mark.parametrize("k", range(4))
def test_sigterm_to_the_main_process_ends_everything(k: int, tmp_path: Path) -> None:
    """SIGTERM (`timeout`, a scheduler) often reaches the main process only: its workers must end with it."""
    argv = [*VKGC, "learn", str(STDLIB / "bodies" / "block.vkg"), "-o", str(tmp_path / "affordances")]
    code, err = _ended_at_once(argv, 1.0 + 0.4 * k, lambda pid: os.kill(pid, signal.SIGTERM), f"SIGTERM {k}")
    assert code == 143, err
    assert err.strip().endswith("vkgc: terminated")
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == []
