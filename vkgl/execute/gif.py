"""Writing a matplotlib animation as a GIF: the still part of the figure drawn once, one palette for every frame.

    write_gif(fig, moving, draw, frames, "run.gif", fps=20)

matplotlib's PillowWriter redraws the whole figure for every frame (tick
labels, legends and all), and Pillow then gives every frame its own 256
colours, so that it must store every frame whole. Here instead:

- the figure is drawn once without its `moving` artists (they are marked
  animated, which the figure's own drawing skips); for each frame that
  background is restored and only the moving artists are drawn over it, in
  the order of their zorder (matplotlib's blitting). A frame's pixels are
  those of a full redraw unless a still artist lies above a moving one (the
  execution's animation of task a, written with PillowWriter's per-frame
  palettes, came out byte for byte the same);
- one palette for every frame, Pillow's maximum-coverage quantisation of
  `PALETTE_SAMPLES` frames spread over the animation, each frame mapped to
  it without dithering: Pillow then stores only the part of a frame that
  changed. (Median cut, Pillow's default, moved white to (252, 252, 253)
  and erred 2.0 levels per channel on average on the execution of task a;
  maximum coverage keeps white and erred 0.18.)

On the execution of task a (213 frames, 560 x 448), on a loaded 2-core
machine: 27.2 s and 759 kB with PillowWriter, 10.4 s and 769 kB with the
blitting alone (a palette per frame), 5.8 s and 319 kB this way
(docs/execution.md, "The animation", has tasks e and f).

Both are deterministic: the same figure and frames give the same bytes.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.atomic import write_bytes

PALETTE_SAMPLES = 5
"""Frames (the first, the last, and evenly between) whose colours make the animation's palette."""


def write_gif(
    fig: Any, moving: Sequence[Any], draw: Callable[[int], None], frames: Sequence[int], path: Path, *, fps: float
) -> None:
    """Write the frames `frames` of `fig` to `path`: `draw(i)` updates the `moving` artists for frame `i`."""
    from PIL import Image

    order = sorted(moving, key=lambda artist: artist.get_zorder())
    for artist in order:
        artist.set_animated(True)
    canvas = fig.canvas
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    size = canvas.get_width_height()

    def render(i: int) -> Any:
        draw(i)
        canvas.restore_region(background)
        for artist in order:
            fig.draw_artist(artist)
        return Image.frombuffer("RGBA", size, canvas.buffer_rgba(), "raw", "RGBA", 0, 1).convert("RGB")

    samples = [frames[k] for k in sorted(set(np.linspace(0, len(frames) - 1, PALETTE_SAMPLES).round().astype(int)))]
    sheet = Image.new("RGB", (size[0], size[1] * len(samples)))
    for k, i in enumerate(samples):
        sheet.paste(render(i), (0, size[1] * k))
    palette = sheet.quantize(256, method=Image.Quantize.MAXCOVERAGE)
    images = [render(i).quantize(palette=palette, dither=Image.Dither.NONE) for i in frames]
    buffer = io.BytesIO()
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
    write_bytes(path, buffer.getvalue())  # the one writer: whole or not at all, never over a device
