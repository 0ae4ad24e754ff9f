"""`vkg-reach-cache/1` (vkgl.formats.reach_cache): the arm's reach kept between processes, exactly as computed."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import REPO

from vkgl.formats import reach_cache
from vkgl.robot import reach as reach_module

KEY = "ab" * 32


@pytest.fixture
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv(reach_cache.ENV_DIR, str(tmp_path))
    return tmp_path


def test_an_interval_is_read_back_exactly(folder: Path) -> None:
    reach_cache.store(KEY, 0.025, (0.1 / 3, 0.8 + 1e-13))
    reach_cache.store(KEY, 0.3, (0.0, 0.0))
    assert reach_cache.load(KEY) == {0.025: (0.1 / 3, 0.8 + 1e-13), 0.3: (0.0, 0.0)}
    assert json.loads(next(folder.iterdir()).read_text())["format"] == "vkg-reach-cache/1"


@pytest.mark.parametrize(
    "text",
    ["", "not json", "[]", '{"format": "vkg-reach-cache/0"}', '{"format": "vkg-reach-cache/1", "key": "x"}'],
)
def test_an_unusable_file_is_ignored_and_replaced(folder: Path, text: str) -> None:
    reach_cache.store(KEY, 0.025, (0.1, 0.8))
    path = next(folder.iterdir())
    path.write_text(text)
    assert reach_cache.load(KEY) == {}
    reach_cache.store(KEY, 0.03, (0.2, 0.7))
    assert reach_cache.load(KEY) == {0.03: (0.2, 0.7)}


def test_bad_values_are_ignored(folder: Path) -> None:
    reach_cache.store(KEY, 0.025, (0.1, 0.8))
    path = next(folder.iterdir())
    data = json.loads(path.read_text())
    data["reach"]["0.025"] = [0.1, "far"]
    path.write_text(json.dumps(data))
    assert reach_cache.load(KEY) == {}


def test_off_keeps_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(reach_cache.ENV_DIR, reach_cache.OFF)
    reach_cache.store(KEY, 0.025, (0.1, 0.8))
    assert reach_cache.load(KEY) == {} and reach_cache.cache_folder() is None


def test_an_unwritable_folder_is_not_an_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv(reach_cache.ENV_DIR, str(blocker / "below"))
    reach_cache.store(KEY, 0.025, (0.1, 0.8))
    assert reach_cache.load(KEY) == {}


_REACH_IN_A_NEW_PROCESS = """
import json, sys
import numpy as np
sys.path[:0] = sys.argv[1:]
from panda_fixtures import panda_robot
from vkgl.robot import Arm
from vkgl.robot import reach as reach_module
arm = Arm.load(panda_robot(), "fingertip", np.eye(4))
computed = []
original = reach_module.reach
reach_module.reach = lambda ik, height: computed.append(height) or original(ik, height)
print(json.dumps({"reach": arm.reach(0.041), "computed": computed}))
"""


def test_a_new_process_reads_the_reach_another_computed(folder: Path) -> None:
    paths = [str(REPO / "tests" / "support"), str(REPO / "tests")]
    runs = [
        json.loads(
            subprocess.run(
                [sys.executable, "-c", _REACH_IN_A_NEW_PROCESS, *paths], capture_output=True, text=True, check=True
            ).stdout
        )
        for _ in range(2)
    ]
    assert runs[0]["computed"] == [0.041] and runs[1]["computed"] == []
    assert runs[0]["reach"] == runs[1]["reach"]  # bit for bit: JSON floats round-trip


def test_the_key_changes_with_the_urdf(tmp_path: Path) -> None:
    urdf = tmp_path / "arm.urdf"
    urdf.write_text("<robot name='a'/>")
    first = reach_module._disk_key((str(urdf), "hand", b"offset"))
    urdf.write_text("<robot name='b'/>")
    assert reach_module._disk_key((str(urdf), "hand", b"offset")) != first
    assert reach_module._disk_key((str(urdf), "other", b"offset")) != reach_module._disk_key(
        (str(urdf), "hand", b"offset")
    )


def _cache_file(folder: Path) -> Path:
    reach_cache.store(KEY, 0.025, (0.1, 0.8))
    (path,) = folder.iterdir()
    return path


def test_deep_nesting_is_ignored_not_a_crash(folder: Path) -> None:
    """200,000 nested `[` made json raise RecursionError: every solve exited 4 until the file was deleted."""
    path = _cache_file(folder)
    path.write_text("[" * 200_000)
    assert reach_cache.load(KEY) == {}
    reach_cache.store(KEY, 0.03, (0.2, 0.7))
    assert reach_cache.load(KEY) == {0.03: (0.2, 0.7)}


@pytest.mark.parametrize("interval", [[0.8, 0.1], [-0.2, 0.5], [-0.5, -0.1], ["NaN", 0.5], [0.1, True]])
def test_implausible_intervals_are_dropped_and_the_rest_kept(folder: Path, interval: list) -> None:
    path = _cache_file(folder)
    data = json.loads(path.read_text())
    data["reach"]["0.300"] = [float(v) if v == "NaN" else v for v in interval]
    data["reach"]["nan"] = [0.1, 0.2]
    path.write_text(json.dumps(data))
    assert reach_cache.load(KEY) == {0.025: (0.1, 0.8)}


def test_nan_is_never_written(folder: Path) -> None:
    reach_cache.store(KEY, float("nan"), (0.1, 0.8))
    reach_cache.store(KEY, 0.05, (float("nan"), 0.8))
    reach_cache.store(KEY, 0.06, (0.9, 0.1))
    assert list(folder.iterdir()) == []
    path = _cache_file(folder)
    assert "nan" not in path.read_text().lower()


def test_a_file_larger_than_the_bound_is_not_read(folder: Path) -> None:
    path = _cache_file(folder)
    data = json.loads(path.read_text())
    data["pad"] = "x" * reach_cache.MAX_BYTES
    path.write_text(json.dumps(data))
    assert reach_cache.load(KEY) == {}


def test_a_fifo_in_its_place_neither_hangs_nor_is_written(folder: Path) -> None:
    path = _cache_file(folder)
    path.unlink()
    os.mkfifo(path)
    assert reach_cache.load(KEY) == {}  # opened without waiting for a writer
    reach_cache.store(KEY, 0.03, (0.2, 0.7))  # no reader: would fail; a reader: would be fed; neither happens
    assert stat.S_ISFIFO(os.lstat(path).st_mode)


def test_a_link_to_a_character_device_is_not_read(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A link to /dev/zero in the cache's place: `fstat` says character device, nothing is read from it."""
    path = _cache_file(folder)
    path.unlink()
    os.symlink("/dev/zero", path)
    reads = []
    real_read = os.read
    monkeypatch.setattr(reach_cache.os, "read", lambda fd, n: reads.append(n) or real_read(fd, n))
    assert reach_cache.load(KEY) == {}
    assert reads == []
    reach_cache.store(KEY, 0.03, (0.2, 0.7))  # never written through the link
    assert os.readlink(path) == "/dev/zero"
