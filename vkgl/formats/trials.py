"""The `vkg-trials/1` dataset: what exploration recorded, what inference reads.

One `.npz` file per explored body (ARCHITECTURE.md is the contract):

    format () str "vkg-trials/1" | body () str | t (N, T) | T_ro (N, T, 4, 4)
    T_ow (N, T, 4, 4) | contact (N, 3) | force (N, 3) | ok (N,) bool | reason (N,) str

Trials shorter than T are padded with NaN. NaN in a rotation block = orientation
not observed; an all-NaN `T_ro` = action not observed.
"""

from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vkgl.errors import InputError
from vkgl.formats.atomic import write_bytes

FORMAT = "vkg-trials/1"


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
        """Read and validate a dataset; any problem is an InputError naming the file."""
        path = Path(path)
        if not path.is_file():
            raise InputError(f"{path}: no such file")
        try:
            with np.load(path, allow_pickle=False) as data:
                arrays = {k: data[k] for k in data.files}
        except Exception as exc:  # numpy raises several types for a bad archive
            raise InputError(f"{path}: not a `{FORMAT}` .npz file ({exc})") from exc
        return cls._from_arrays(arrays, str(path))

    @classmethod
    def _from_arrays(cls, arrays: dict[str, np.ndarray], where: str) -> Trials:
        fmt = str(arrays.get("format", ""))
        if fmt != FORMAT:
            raise InputError(f"{where}: format is {fmt!r}, expected {FORMAT!r}")
        required = ["body", "t", "T_ro", "T_ow", "contact", "force", "ok"]
        missing = [k for k in required if k not in arrays]
        if missing:
            raise InputError(f"{where}: missing array(s) {', '.join(missing)}")
        t = np.asarray(arrays["t"], dtype=float)
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
        reason = arrays.get("reason", np.array([""] * n))
        if reason.shape != (n,):
            raise InputError(f"{where}: `reason` must have shape {(n,)}, got {reason.shape}")
        return cls(
            body=str(arrays["body"]),
            t=t,
            T_ro=np.asarray(arrays["T_ro"], dtype=float),
            T_ow=np.asarray(arrays["T_ow"], dtype=float),
            contact=np.asarray(arrays["contact"], dtype=float),
            force=np.asarray(arrays["force"], dtype=float),
            ok=np.asarray(arrays["ok"], dtype=bool),
            reason=np.asarray(reason, dtype=str),
        )


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
