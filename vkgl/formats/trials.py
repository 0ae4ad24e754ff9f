"""The `vkg-trials/1` dataset: what exploration recorded, what inference reads.

One `.npz` file per explored body (docs/formats.md is the contract):

    format () str "vkg-trials/1" | body () str | t (N, T) | T_ro (N, T, 4, 4)
    T_ow (N, T, 4, 4) | contact (N, 3) | force (N, 3) | ok (N,) bool | reason (N,) str

Trials shorter than T are padded with NaN. NaN in a rotation block = orientation
not observed; an all-NaN `T_ro` = action not observed.
"""

from __future__ import annotations

import io
import re
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vkgl.atomic import write_bytes
from vkgl.errors import InputError

FORMAT = "vkg-trials/1"

TIP_ANGLE = 5.0
"""deg: a lying body whose up axis tilts more than this from the vertical tipped over (docs/formats.md)."""
TIPPED = "the body tipped over"
"""How the `reason` of a trial that ended because its body tipped over begins."""


def tilt_deg(T_ow: np.ndarray) -> np.ndarray:
    """The angle (deg) between a body's z axis and the vertical, for poses (..., 4, 4) of a body that starts upright."""
    return np.degrees(np.arccos(np.clip(np.asarray(T_ow)[..., 2, 2], -1.0, 1.0)))


@dataclass
class Trials:
    """A `vkg-trials/1` dataset in memory."""

    body: str
    t: np.ndarray
    T_ro: np.ndarray
    T_ow: np.ndarray
    contact: np.ndarray
    force: np.ndarray
    ok: np.ndarray
    reason: np.ndarray

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def samples(self, i: int) -> int:
        """How many samples trial `i` has (its length before NaN padding)."""
        return int(np.count_nonzero(~np.isnan(self.t[i])))

    def save(self, path: str | Path) -> None:
        """Write the dataset; the bytes depend only on the data (no timestamps)."""
        arrays = {
            "format": np.array(FORMAT),
            "body": np.array(self.body),
            "t": np.asarray(self.t, dtype=float),
            "T_ro": np.asarray(self.T_ro, dtype=float),
            "T_ow": np.asarray(self.T_ow, dtype=float),
            "contact": np.asarray(self.contact, dtype=float),
            "force": np.asarray(self.force, dtype=float),
            "ok": np.asarray(self.ok, dtype=bool),
            "reason": np.asarray(self.reason, dtype=str),
        }
        write_bytes(path, _deterministic_npz(arrays))

    @classmethod
    def load(cls, path: str | Path) -> Trials:
        """Read and validate a dataset; any problem is an InputError naming the file and the array.

        Sizes are checked from the archive's directory before anything is
        read (a small file may unpack to gigabytes), every array's dtype and
        shape against the contract, `ok` must be boolean, times and
        transforms real numbers, and the body name an identifier.
        """
        path = Path(path)
        if not path.is_file():
            raise InputError(f"{path}: no such file (or not a regular file)")
        arrays = _read_arrays(path)
        return cls._from_arrays(arrays, str(path))

    @classmethod
    def _from_arrays(cls, arrays: dict[str, np.ndarray], where: str) -> Trials:
        fmt = _text(arrays, "format", where) if "format" in arrays else ""
        if fmt != FORMAT:
            raise InputError(f"{where}: format is {fmt[:40]!r}, expected {FORMAT!r}")
        required = ["body", "t", "T_ro", "T_ow", "contact", "force", "ok"]
        missing = [k for k in required if k not in arrays]
        if missing:
            raise InputError(f"{where}: missing array(s) {', '.join(missing)}")
        body = _text(arrays, "body", where)
        if not _IDENTIFIER.fullmatch(body):
            raise InputError(f"{where}: `body` must be a body name (letters, digits, _), got {body[:40]!r}")
        t = _real(arrays, "t", where)
        if t.ndim != 2:
            raise InputError(f"{where}: `t` must have shape (N, T), got {t.shape}")
        n, steps = t.shape
        expected = {
            "T_ro": (n, steps, 4, 4),
            "T_ow": (n, steps, 4, 4),
            "contact": (n, 3),
            "force": (n, 3),
            "ok": (n,),
        }
        for key, shape in expected.items():
            if arrays[key].shape != shape:
                raise InputError(f"{where}: `{key}` must have shape {shape}, got {arrays[key].shape}")
        if arrays["ok"].dtype != np.bool_:
            raise InputError(f"{where}: `ok` must be boolean (True/False), got dtype {arrays['ok'].dtype}")
        reason = arrays.get("reason", np.array([""] * n))
        if reason.shape != (n,) or reason.dtype.kind != "U":
            raise InputError(f"{where}: `reason` must be {n} strings, got {reason.dtype} {reason.shape}")
        return cls(
            body=body,
            t=t,
            T_ro=_real(arrays, "T_ro", where),
            T_ow=_real(arrays, "T_ow", where),
            contact=_real(arrays, "contact", where),
            force=_real(arrays, "force", where),
            ok=np.asarray(arrays["ok"], dtype=bool),
            reason=np.asarray(reason, dtype=str),
        )


MAX_BYTES = 512 * 2**20
"""Unpacked size of a dataset at most (bytes): 50,000 trials of 300 samples take ~1 GB of transforms."""

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}")


def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    try:
        with zipfile.ZipFile(path) as archive:
            total = sum(info.file_size for info in archive.infolist())
            if total > MAX_BYTES:
                raise InputError(
                    f"{path}: unpacks to {total / 2**20:.0f} MiB, more than the {MAX_BYTES / 2**20:.0f} MiB "
                    f"a `{FORMAT}` dataset may have"
                )
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except InputError:
        raise
    except Exception as exc:  # zipfile and numpy raise several types for a bad archive
        raise InputError(f"{path}: not a `{FORMAT}` .npz file ({type(exc).__name__}: {str(exc)[:120]})") from None


def _text(arrays: dict[str, np.ndarray], key: str, where: str) -> str:
    value = arrays[key]
    if value.shape != () or value.dtype.kind != "U":
        raise InputError(f"{where}: `{key}` must be one string, got {value.dtype} {value.shape}")
    return str(value)


def _real(arrays: dict[str, np.ndarray], key: str, where: str) -> np.ndarray:
    """The array as float64: real numbers only; NaN means "not observed" (the contract allows it), infinity never."""
    value = arrays[key]
    if value.dtype.kind not in "fiu" or value.dtype.kind == "c":
        raise InputError(f"{where}: `{key}` must hold real numbers, got dtype {value.dtype}")
    out = np.asarray(value, dtype=float)
    if np.isinf(out).any():
        raise InputError(f"{where}: `{key}` holds infinite values")
    return out


def _deterministic_npz(arrays: dict[str, np.ndarray]) -> bytes:
    """An uncompressed .npz whose zip entries carry a fixed timestamp, so equal data gives equal bytes."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_STORED) as zf:
        for key in sorted(arrays):
            member = io.BytesIO()
            np.lib.format.write_array(member, np.array(arrays[key], order="C"), allow_pickle=False)
            info = zipfile.ZipInfo(key + ".npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.external_attr = 0o644 << 16
            zf.writestr(info, member.getvalue())
    return buffer.getvalue()
