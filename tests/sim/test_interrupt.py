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
    process = subprocess.Popen(
        argv, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    time.sleep(delay)
    os.killpg(process.pid, signal.SIGINT)
    sent = time.monotonic()
    try:
        _, err = process.communicate(timeout=2.0)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        pytest.fail(f"interrupt {k} at {delay:.2f} s: still running 2 s after Ctrl-C")
    assert time.monotonic() - sent < 2.0
    assert process.returncode == 130, err
    assert "Traceback" not in err
    assert err.strip().endswith("vkgc: interrupted")
    deadline = time.monotonic() + 1.0
    while _group_alive(process.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _group_alive(process.pid), "a worker process outlived the interrupt"
    assert not partial.exists()
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == []


@pytest.mark.parametrize("k", range(4))
def test_sigterm_to_the_main_process_ends_everything(k: int, tmp_path: Path) -> None:
    """SIGTERM (`timeout`, a scheduler) often reaches the main process only: its workers must end with it."""
    out = tmp_path / "affordances"
    argv = [*VKGC, "learn", str(STDLIB / "bodies" / "block.vkg"), "-o", str(out)]
    process = subprocess.Popen(
        argv, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    time.sleep(1.0 + 0.4 * k)  # while the workers simulate
    process.send_signal(signal.SIGTERM)
    try:
        _, err = process.communicate(timeout=2.0)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        pytest.fail(f"SIGTERM {k}: still running 2 s after it")
    assert process.returncode == 143, err
    assert "Traceback" not in err
    assert err.strip().endswith("vkgc: terminated")
    deadline = time.monotonic() + 1.0
    while _group_alive(process.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _group_alive(process.pid), "a worker process outlived SIGTERM"
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == []
