"""`vkg-trials/1` reading: everything is validated before inference sees it (issue: infer trusted the npz)."""

from __future__ import annotations

import numpy as np
import pytest

import vkgl.formats.trials as trials_format
from vkgl.errors import InputError
from vkgl.formats.trials import FORMAT, Trials


def _arrays(n: int = 2, steps: int = 3) -> dict[str, np.ndarray]:
    return {
        "format": np.array(FORMAT),
        "body": np.array("Block"),
        "t": np.tile(np.linspace(0, 1, steps), (n, 1)),
        "T_ro": np.tile(np.eye(4), (n, steps, 1, 1)),
        "T_ow": np.tile(np.eye(4), (n, steps, 1, 1)),
        "contact": np.zeros((n, 3)),
        "force": np.zeros((n, 3)),
        "ok": np.ones(n, dtype=bool),
        "reason": np.array([""] * n),
    }


def _saved(tmp_path, **changes) -> str:
    arrays = _arrays()
    arrays.update(changes)
    path = tmp_path / "t.npz"
    np.savez(path, **arrays)
    return str(path)


def test_a_good_dataset_round_trips(tmp_path) -> None:
    data = Trials.load(_saved(tmp_path))
    data.save(tmp_path / "again.npz")
    assert Trials.load(tmp_path / "again.npz").body == "Block"


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ({"ok": np.array(["no", "yes"])}, "`ok` must be boolean"),
        ({"ok": np.array([np.nan, 1.0])}, "`ok` must be boolean"),
        ({"t": np.ones((2, 3), dtype=complex)}, "`t` must hold real numbers"),
        ({"t": np.array([["a", "b", "c"]] * 2)}, "`t` must hold real numbers"),
        ({"T_ro": np.full((2, 3, 4, 4), np.inf)}, "`T_ro` holds infinite values"),
        ({"body": np.array("Block {}\ncorrespondences { X.tip ~ fingertip }")}, "`body` must be a body name"),
        ({"body": np.array("../../etc")}, "`body` must be a body name"),
        ({"body": np.array(["Block", "Stick"])}, "`body` must be one string"),
        ({"format": np.array("vkg-trials/9")}, "expected 'vkg-trials/1'"),
        ({"contact": np.zeros((3, 3))}, "`contact` must have shape (2, 3)"),
        ({"reason": np.array([1, 2])}, "`reason` must be 2 strings"),
    ],
)
def test_a_bad_array_is_named(tmp_path, change, says) -> None:
    with pytest.raises(InputError, match=None) as error:
        Trials.load(_saved(tmp_path, **change))
    assert says in str(error.value)


def test_sizes_are_checked_before_anything_is_unpacked(tmp_path, monkeypatch) -> None:
    path = tmp_path / "big.npz"
    np.savez_compressed(path, **{**_arrays(), "t": np.zeros((2, 200_000))})  # 3.2 MB unpacked, tiny packed
    monkeypatch.setattr(trials_format, "MAX_BYTES", 2**20)
    with pytest.raises(InputError, match="unpacks to 3 MiB, more than the 1 MiB"):
        Trials.load(path)


def test_not_an_archive_is_an_input_error(tmp_path) -> None:
    path = tmp_path / "t.npz"
    path.write_bytes(b"PK\x03\x04 nonsense")
    with pytest.raises(InputError, match=r"not a `vkg-trials/1` \.npz file"):
        Trials.load(path)


def test_a_directory_is_not_a_dataset(tmp_path) -> None:
    with pytest.raises(InputError, match="not a regular file"):
        Trials.load(tmp_path)


@pytest.mark.parametrize(
    "use",
    ["stdlib.bodies.block\ncorrespondences { Block.x ~ fingertip }", '"x.vkg"', "a b", "../x.txt", "x.vkg\n"],
)
def test_infer_refuses_a_use_that_is_not_a_module(tmp_path, use) -> None:
    import vkgl

    data = Trials.load(_saved(tmp_path))
    with pytest.raises(InputError, match="not a module"):
        vkgl.infer(data, body_use=use)
