"""A picture of an exploration: what every trial did to the body, seen from above.

Left: the path of the body frame's origin in the table plane, one line per
trial, coloured by where the effector touched the body (the contact position
along the axis on which the contacts differ most), with the heading at the end
drawn as a short tick, the contact point at the start as a dot, and the
effector's own path dotted. Right: the
body's turn (yaw, deg) over time, same colours. Failed trials are grey and
dashed, and named in the legend.
"""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display needed

import matplotlib.pyplot as plt
import numpy as np

from vkgl.atomic import write_bytes
from vkgl.errors import InputError
from vkgl.figure_text import fit_lines
from vkgl.formats.trials import Trials

AXES = "xyz"


def plot_trials(trials: Trials, path: str | Path) -> None:
    """Write a PNG (or any format matplotlib knows from the suffix) of the trials to `path`."""
    if len(trials) == 0:
        raise InputError("there are no trials to plot")
    colours, label = _contact_colours(trials)
    fig, (top, turn) = plt.subplots(1, 2, figsize=(12, 5.5), gridspec_kw={"width_ratios": [1.2, 1]})
    for i in range(len(trials)):
        n = trials.samples(i)
        if n == 0:
            continue
        T = trials.T_ow[i, :n]
        style = {"color": colours[i], "lw": 1.4} if trials.ok[i] else {"color": "0.6", "lw": 1.0, "ls": "--"}
        top.plot(T[:, 0, 3], T[:, 1, 3], **style)
        effector = np.einsum("nij,nj->ni", T, trials.T_ro[i, :n, :, 3])
        top.plot(effector[:, 0], effector[:, 1], ls=":", lw=0.8, color=style["color"])
        _heading_tick(top, T[-1], style["color"])
        contact = T[0] @ np.append(trials.contact[i], 1.0)
        top.plot(contact[0], contact[1], "o", ms=3, color=style["color"])
        yaw = np.degrees(np.unwrap(np.arctan2(T[:, 1, 0], T[:, 0, 0]) - np.arctan2(T[0, 1, 0], T[0, 0, 0])))
        turn.plot(trials.t[i, :n], yaw, **style)
    top.set_aspect("equal", adjustable="datalim")
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    # the body's name may be long: the title wraps within its panel (5.9 of the figure's 12 inches)
    top.set_title(fit_lines(f"{trials.body}: body paths from above ({len(trials)} trials)", 5.9 * 72, 12))
    turn.set_xlabel("t (s)")
    turn.set_ylabel("yaw change (deg)")
    turn.set_title("turn of the body over time")
    mappable = plt.cm.ScalarMappable(cmap="viridis", norm=plt.Normalize(*_range(trials)))
    fig.colorbar(mappable, ax=turn, label=label)
    failed = int((~trials.ok).sum())
    if failed:
        reasons = sorted(set(str(r) for r, ok in zip(trials.reason, trials.ok) if not ok))
        fig.text(0.01, 0.01, f"{failed} failed (grey): " + "; ".join(reasons)[:200], fontsize=8, color="0.3")
    fig.tight_layout()
    buffer = io.BytesIO()
    try:  # rendered in memory, then written by the one writer (never over a device, never half a file)
        fig.savefig(buffer, format=Path(path).suffix.lstrip(".").lower() or "png", dpi=110)
        write_bytes(path, buffer.getvalue())
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: cannot write the picture: {exc}") from exc
    finally:
        plt.close(fig)


def _contact_axis(trials: Trials) -> int | None:
    spread = np.ptp(trials.contact, axis=0)
    return int(np.argmax(spread)) if float(spread.max()) > 1e-9 else None


def _contact_colours(trials: Trials) -> tuple[list[tuple[float, ...]], str]:
    axis = _contact_axis(trials)
    if axis is None:  # one contact for all (a grasp): colour by trial
        values = np.arange(len(trials), dtype=float)
        label = "trial"
    else:
        values = trials.contact[:, axis]
        label = f"contact {AXES[axis]} in the body frame (m)"
    lo, hi = float(values.min()), float(values.max())
    scaled = (values - lo) / (hi - lo) if hi > lo else np.zeros_like(values)
    return [plt.cm.viridis(float(s)) for s in scaled], label


def _range(trials: Trials) -> tuple[float, float]:
    axis = _contact_axis(trials)
    values = np.arange(len(trials), dtype=float) if axis is None else trials.contact[:, axis]
    lo, hi = float(values.min()), float(values.max())
    return (lo, hi) if hi > lo else (lo - 0.5, hi + 0.5)


def _heading_tick(ax: plt.Axes, pose: np.ndarray, colour: object) -> None:
    length = 0.015
    x, y = pose[0, 3], pose[1, 3]
    ax.plot([x, x + length * pose[0, 0]], [y, y + length * pose[1, 0]], color=colour, lw=2.0)
