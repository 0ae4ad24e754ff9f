"""Writing animations as GIFs (`vkgl.execute.gif`): every frame as a full redraw would draw it, one palette."""

from __future__ import annotations

import io

import matplotlib
import numpy as np
from PIL import Image

from vkgl.execute.gif import write_gif

matplotlib.use("Agg")


def _scene():
    """A small figure: a still square and bare axes; a moving dot and a moving line over them.

    Nothing is antialiased (but a few pixels of the dot's edge): the frames have a handful of colours, all in
    the one palette, so a frame of the GIF is what a full redraw draws, to the last level of grey.
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    fig, ax = plt.subplots(figsize=(2, 2), dpi=50)
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    ax.set_axis_off()
    ax.add_patch(Rectangle((2, 2), 6, 6, fc="tab:orange", zorder=1, antialiased=False))
    (dot,) = ax.plot([], [], "o", color="black", ms=8, zorder=3, antialiased=False)
    (line,) = ax.plot([], [], "--", color="tab:purple", lw=2, zorder=2, antialiased=False)

    def draw(i: int) -> None:
        dot.set_data([1.0 + i], [5.0])
        line.set_data([0.0, 1.0 + i], [1.0, 9.0])

    return fig, [dot, line], draw


def _full_redraw(i: int) -> np.ndarray:
    import matplotlib.pyplot as plt

    fig, _, draw = _scene()
    draw(i)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="rgba", dpi=fig.dpi)
    plt.close(fig)
    width, height = fig.canvas.get_width_height()
    return np.frombuffer(buffer.getvalue(), dtype=np.uint8).reshape(height, width, 4)[:, :, :3]


def _gif_frames(path) -> list[np.ndarray]:
    with Image.open(path) as gif:
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    return frames


def test_every_frame_is_what_a_full_redraw_draws(tmp_path) -> None:
    import matplotlib.pyplot as plt

    fig, moving, draw = _scene()
    write_gif(fig, moving, draw, [0, 2, 4, 6, 8], tmp_path / "dot.gif", fps=10)
    plt.close(fig)
    frames = _gif_frames(tmp_path / "dot.gif")
    assert len(frames) == 5
    for frame, i in zip(frames, [0, 2, 4, 6, 8]):
        difference = np.abs(frame.astype(int) - _full_redraw(i))
        assert difference.max() <= 1 and np.count_nonzero(difference) < 20, (i, difference.max())
    columns = [np.nonzero((frame < 40).all(axis=2).any(axis=0))[0].mean() for frame in frames]
    assert columns == sorted(columns) and columns[-1] - columns[0] > 50  # the dot moves right


def test_the_same_frames_give_the_same_bytes(tmp_path) -> None:
    """Both runs on one machine: determinism, not a golden value, so CPU differences cannot enter."""
    import matplotlib.pyplot as plt

    for name in ("a.gif", "b.gif"):
        fig, moving, draw = _scene()
        write_gif(fig, moving, draw, list(range(9)), tmp_path / name, fps=10)
        plt.close(fig)
    assert (tmp_path / "a.gif").read_bytes() == (tmp_path / "b.gif").read_bytes()
    with Image.open(tmp_path / "a.gif") as gif:
        assert gif.info["duration"] == 100 and gif.info["loop"] == 0
