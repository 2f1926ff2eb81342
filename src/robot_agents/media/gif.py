"""Animated GIFs of RGB frames, written with Pillow."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import numpy.typing as npt
from PIL import Image

from robot_agents.errors import MediaError
from robot_agents.media.frames import Frames, check_fps, check_frames

__all__ = ["PALETTE_SAMPLE_FRAMES", "gif_delay_ms", "write_gif"]

_MAX_DIMENSION = 0xFFFF  # GIF stores width and height in 16 bits
_MAX_DELAY_CS = 0xFFFF  # ... and the delay per frame in 16-bit centiseconds
PALETTE_SAMPLE_FRAMES = 16
"""How many evenly spaced frames :func:`write_gif` builds the shared palette from."""


def _shared_palette(frames: list[npt.NDArray[np.uint8]]) -> Image.Image:
    """A palette image of at most 256 colours (median cut) for all ``frames`` (each ``(H, W, 3)`` uint8)."""
    count = min(len(frames), PALETTE_SAMPLE_FRAMES)
    picks = np.linspace(0, len(frames) - 1, count).round().astype(int)
    montage = np.concatenate([frames[i] for i in picks], axis=0)
    return Image.fromarray(montage).quantize(256, method=Image.Quantize.MEDIANCUT)


def gif_delay_ms(fps: float) -> int:
    """The display time of one frame at ``fps`` frames per second, in milliseconds.

    GIF stores delays in hundredths of a second, so this is ``round(100 / fps)``
    centiseconds (at least 2: browsers play shorter delays slowly) times 10: fps=10
    gives 100 ms, fps=30 gives 30 ms, fps=100 gives 20 ms.

    Raises:
        MediaError: ``fps`` is not a finite number > 0, or so small that the delay
            exceeds GIF's 655.35 s.
    """
    value = check_fps(fps, "write_gif")
    delay_cs = max(2, math.floor(100.0 / value + 0.5))
    if delay_cs > _MAX_DELAY_CS:
        raise MediaError(
            f"write_gif: expected fps >= 100/65535 (about 0.0015; GIF's longest frame delay is 655.35 s), got {fps!r}"
        )
    return delay_cs * 10


def write_gif(path: str | os.PathLike[str], frames: Frames, fps: float) -> Path:
    """Write ``frames`` as an animated GIF that loops forever.

    Args:
        path: Output file, overwritten if it exists; its directory must exist.
        frames: At least one RGB frame of shape ``(H, W, 3)``, dtype uint8 (H, W
            in pixels, 1..65535), all of one shape; or one ``(N, H, W, 3)`` array.
        fps: Playback rate in frames per second, finite and > 0; each frame is
            shown for :func:`gif_delay_ms` milliseconds.

    Returns:
        The written path.

    Raises:
        MediaError: bad frames (see :func:`~robot_agents.media.frames.check_frames`),
            frames larger than 65535 pixels on a side, a bad ``fps``, or a file
            that cannot be written (the system's reason).

    GIF is paletted: every frame is drawn with one shared palette of at most 256
    colours, chosen by Pillow's median cut from up to :data:`PALETTE_SAMPLE_FRAMES`
    evenly spaced frames, and each pixel takes the nearest palette colour (no
    dithering). A pixel that does not change keeps its colour from frame to frame,
    so only the changed rectangle of each frame is stored. Colours come back exactly
    when the sampled frames hold every colour of the video and at most 256 in all;
    smooth shading comes back within a few levels. Pillow merges consecutive
    identical frames into one shown for their summed duration, so the file may hold
    fewer frames than given; the playing time is unchanged.
    """
    frame_list = check_frames(frames, "write_gif")
    height, width = frame_list[0].shape[:2]
    if height > _MAX_DIMENSION or width > _MAX_DIMENSION:
        raise MediaError(f"write_gif: expected frames at most 65535 pixels on a side, got shape {frame_list[0].shape}")
    duration_ms = gif_delay_ms(fps)
    palette = _shared_palette(frame_list)
    images = [Image.fromarray(frame).quantize(palette=palette, dither=Image.Dither.NONE) for frame in frame_list]
    out_path = Path(path)
    try:
        images[0].save(out_path, format="GIF", save_all=True, append_images=images[1:], duration=duration_ms, loop=0)
    except OSError as err:
        raise MediaError(f"write_gif: cannot write {str(out_path)!r}: {err.strerror or err}.") from None
    return out_path
