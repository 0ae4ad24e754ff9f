"""Cache files are read only when they are regular files within their size limit, and never block
(`vkgl.resources.read_cache_file`, which the parse and hull caches use)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from vkgl.resources import read_cache_file


def test_a_regular_file_within_the_limit_is_read_whole(tmp_path: Path) -> None:
    path = tmp_path / "entry"
    path.write_bytes(b"x" * 1000)
    assert read_cache_file(path, 1000) == b"x" * 1000
    assert read_cache_file(path, 999) is None  # one byte too many


def test_what_is_not_a_regular_file_is_never_read(tmp_path: Path) -> None:
    assert read_cache_file(tmp_path / "missing", 100) is None
    assert read_cache_file(tmp_path, 100) is None  # a folder
    assert read_cache_file(Path("/dev/zero"), 100) is None  # endless


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_in_place_of_a_cache_file_does_not_block(tmp_path: Path) -> None:
    fifo = tmp_path / "entry"
    os.mkfifo(fifo)
    assert read_cache_file(fifo, 100) is None  # no writer: opening must not wait for one
