"""Text labels on video frames (Pillow's default font on a dark strip)."""

from __future__ import annotations

import functools
import math

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw, ImageFont

from robot_agents.errors import MediaError

__all__ = ["LABEL_BACKGROUND", "LABEL_COLOR", "draw_label"]

LABEL_COLOR = (255, 255, 255)
"""RGB colour of label text."""
LABEL_BACKGROUND = (24, 24, 24)
"""RGB colour of the strip behind label text."""
_PADDING = 3  # pixels between the text and the edge of its strip


@functools.lru_cache(maxsize=64)
def _label_pixels(text: str) -> npt.NDArray[np.uint8]:
    """The rendered label: text on its background strip, shape ``(h, w, 3)`` uint8, read-only."""
    font = ImageFont.load_default()
    left, top, right, bottom = (
        math.floor(v) if i < 2 else math.ceil(v)
        for i, v in enumerate(ImageDraw.Draw(Image.new("RGB", (1, 1))).textbbox((0, 0), text, font=font))
    )
    width = max(1, right - left) + 2 * _PADDING
    height = max(1, bottom - top) + 2 * _PADDING
    strip = Image.new("RGB", (width, height), LABEL_BACKGROUND)
    ImageDraw.Draw(strip).text((_PADDING - left, _PADDING - top), text, fill=LABEL_COLOR, font=font)
    pixels: npt.NDArray[np.uint8] = np.array(strip, dtype=np.uint8)
    pixels.setflags(write=False)
    return pixels


def draw_label(frame: npt.NDArray[np.uint8], text: str) -> npt.NDArray[np.uint8]:
    """Return a copy of ``frame`` with ``text`` in its top-left corner.

    The text is drawn in Pillow's default font (about 11 px high) in
    :data:`LABEL_COLOR` on a strip of :data:`LABEL_BACKGROUND` just large enough to
    hold it (3 px padding); a label wider or taller than the frame is cut off.

    Args:
        frame: RGB image of shape ``(H, W, 3)``, dtype uint8.
        text: The label, one line.

    Raises:
        MediaError: ``frame`` is not an ``(H, W, 3)`` uint8 array.
    """
    if not isinstance(frame, np.ndarray) or frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.uint8:
        given = f"shape {frame.shape}, dtype {frame.dtype}" if isinstance(frame, np.ndarray) else type(frame).__name__
        raise MediaError(f"draw_label: expected a frame of shape (H, W, 3) and dtype uint8, got {given}")
    label = _label_pixels(text)
    height, width = min(label.shape[0], frame.shape[0]), min(label.shape[1], frame.shape[1])
    out: npt.NDArray[np.uint8] = frame.copy()
    out[:height, :width] = label[:height, :width]
    return out
