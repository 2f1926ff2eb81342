"""Write animated GIFs (GIF89a, looping forever) from RGB frames.

Only numpy and the standard library are used. The encoder is built for rendered
simulation videos:

* **Colour** - every frame shares one global 256-entry palette: a uniform RGB grid
  of 6 red x 7 green x 6 blue levels (252 colours; entries 252-255 repeat black and
  are never produced). Pixels are mapped to the grid with ordered (Bayer 4x4)
  dithering, so smooth shading stays smooth instead of banding. The dither pattern
  is anchored to image coordinates, so a pixel that does not change between input
  frames maps to the same palette index in both.
  Colours that lie exactly on the grid (black, white, pure red/green/blue, ...)
  come back exactly.
* **Size** - after the first frame only the bounding rectangle of the palette
  indices that changed since the previous frame is encoded (disposal method 1,
  "do not dispose"); a frame identical to the previous one is written as a single
  unchanged pixel, so its display time is still kept.
* **Compression** - a standard GIF variable-code-size LZW encoder (minimum code size
  8, clear and end codes, dictionary reset at 4096 codes, data in sub-blocks of at
  most 255 bytes).

Example::

    import numpy as np
    from robot_agents.media.gif import write_gif

    frames = np.zeros((30, 64, 64, 3), dtype=np.uint8)  # 30 frames, 64 x 64 px
    frames[:, :, :, 0] = np.arange(30, dtype=np.uint8)[:, None, None] * 8
    write_gif("ramp.gif", frames, fps=15)
"""

from __future__ import annotations

import math
import numbers
import os
import pathlib
import struct
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from robot_agents.errors import MediaError

__all__ = ["PALETTE", "write_gif"]

# --------------------------------------------------------------------------- palette

_LEVELS_R = 6
_LEVELS_G = 7
_LEVELS_B = 6
_STRIDE_R = _LEVELS_G * _LEVELS_B  # palette index = r * 42 + g * 6 + b
_STRIDE_G = _LEVELS_B


def _levels(count: int) -> npt.NDArray[np.float64]:
    """Return ``count`` evenly spaced channel values from 0 to 255 (unrounded)."""
    return np.arange(count, dtype=np.float64) * (255.0 / (count - 1))


def _build_palette() -> npt.NDArray[np.uint8]:
    """Return the global palette, shape (256, 3), uint8 RGB."""
    r = np.floor(_levels(_LEVELS_R) + 0.5)
    g = np.floor(_levels(_LEVELS_G) + 0.5)
    b = np.floor(_levels(_LEVELS_B) + 0.5)
    grid = np.stack(np.meshgrid(r, g, b, indexing="ij"), axis=-1).reshape(-1, 3)
    palette = np.zeros((256, 3), dtype=np.uint8)  # unused tail entries stay black
    palette[: grid.shape[0]] = grid.astype(np.uint8)
    return palette


PALETTE: npt.NDArray[np.uint8] = _build_palette()
"""The global GIF palette, shape (256, 3), uint8 RGB (read-only)."""
PALETTE.setflags(write=False)

# 4x4 Bayer matrix; thresholds (value + 0.5) / 16 lie strictly inside (0, 1).
_BAYER4 = np.array([[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]], dtype=np.intp)


def _channel_lut(count: int, stride: int) -> npt.NDArray[np.uint8]:
    """Dithered level lookup for one channel, shape (16, 256), uint8.

    ``lut[t, v]`` is ``stride * floor(v / step + (t + 0.5) / 16)`` clipped to the
    ``count`` levels, where ``step = 255 / (count - 1)``: averaged over the 16
    thresholds this reproduces ``v`` (ordered dithering over one full level step).
    A value that is already a (rounded) level maps to that level for every
    threshold, because rounding moves it by less than 1/32 of a step.
    """
    thresholds = (np.arange(16, dtype=np.float64) + 0.5) / 16.0
    values = np.arange(256, dtype=np.float64) / (255.0 / (count - 1))
    level = np.floor(values[None, :] + thresholds[:, None])
    level = np.clip(level, 0, count - 1)
    return (level * stride).astype(np.uint8)


_LUT_R = _channel_lut(_LEVELS_R, _STRIDE_R)
_LUT_G = _channel_lut(_LEVELS_G, _STRIDE_G)
_LUT_B = _channel_lut(_LEVELS_B, 1)


def _threshold_map(height: int, width: int) -> npt.NDArray[np.intp]:
    """Bayer threshold index (0..15) of every pixel, shape (height, width)."""
    rows = np.arange(height) % 4
    cols = np.arange(width) % 4
    pattern: npt.NDArray[np.intp] = _BAYER4[rows[:, None], cols[None, :]]
    return pattern


def _quantize(frame: npt.NDArray[np.uint8], tmap: npt.NDArray[np.intp]) -> npt.NDArray[np.uint8]:
    """Map an H x W x 3 uint8 RGB frame to H x W uint8 palette indices (dithered)."""
    return _LUT_R[tmap, frame[:, :, 0]] + _LUT_G[tmap, frame[:, :, 1]] + _LUT_B[tmap, frame[:, :, 2]]


# ------------------------------------------------------------------------------ LZW

_MIN_CODE_SIZE = 8
_CLEAR = 1 << _MIN_CODE_SIZE  # 256
_END = _CLEAR + 1  # 257
_FIRST_FREE = _CLEAR + 2  # 258
_MAX_CODES = 4096  # 12-bit codes
_SIZE_SHIFT = 12  # emitted codes are stored as ``code | size << 12``


def _lzw_codes(data: bytes) -> list[int]:
    """LZW-encode palette indices; return the codes as ``code | code_size << 12``.

    Follows the GIF flavour of LZW: starts with a clear code, code size 9 bits
    growing to 12, a clear code (and dictionary reset) when all 4096 codes are in
    use, and an end code. ``data`` must be non-empty.
    """
    table: dict[int, int] = {}
    lookup = table.get
    next_code = _FIRST_FREE
    size_tag = (_MIN_CODE_SIZE + 1) << _SIZE_SHIFT
    limit = 1 << (_MIN_CODE_SIZE + 1)
    out = [_CLEAR | size_tag]
    emit = out.append
    prefix = data[0]
    for i in range(1, len(data)):
        byte = data[i]
        key = (prefix << 8) | byte
        code = lookup(key)
        if code is not None:
            prefix = code
            continue
        emit(prefix | size_tag)
        if next_code < _MAX_CODES:
            table[key] = next_code
            next_code += 1
            # The decoder learns each entry one code later, so it widens its codes
            # once the entry *before* the newest one needs the extra bit.
            if next_code > limit:
                limit <<= 1
                size_tag += 1 << _SIZE_SHIFT
        else:
            emit(_CLEAR | size_tag)
            table.clear()
            next_code = _FIRST_FREE
            size_tag = (_MIN_CODE_SIZE + 1) << _SIZE_SHIFT
            limit = 1 << (_MIN_CODE_SIZE + 1)
        prefix = byte
    emit(prefix | size_tag)
    # On reading the last data code the decoder adds one more entry, which may
    # widen the code that the end code is read with.
    if next_code < _MAX_CODES and next_code + 1 > limit:
        size_tag += 1 << _SIZE_SHIFT
    emit(_END | size_tag)
    return out


def _pack_codes(tagged: list[int]) -> bytes:
    """Pack ``code | size << 12`` values into a little-endian (LSB-first) bit stream."""
    arr = np.asarray(tagged, dtype=np.uint32)
    codes = arr & np.uint32(0xFFF)
    sizes = arr >> np.uint32(_SIZE_SHIFT)
    bit = np.arange(12, dtype=np.uint32)
    bits = ((codes[:, None] >> bit[None, :]) & np.uint32(1)).astype(np.uint8)
    stream = bits[bit[None, :] < sizes[:, None]]
    return np.packbits(stream, bitorder="little").tobytes()


def _lzw_image_data(indices: npt.NDArray[np.uint8]) -> bytes:
    """GIF table-based image data: minimum code size byte, sub-blocks, terminator."""
    packed = _pack_codes(_lzw_codes(np.ascontiguousarray(indices).tobytes()))
    parts = [bytes([_MIN_CODE_SIZE])]
    for start in range(0, len(packed), 255):
        chunk = packed[start : start + 255]
        parts.append(bytes([len(chunk)]))
        parts.append(chunk)
    parts.append(b"\x00")
    return b"".join(parts)


# ------------------------------------------------------------------------ validation


def _validate_frames(
    frames: Sequence[npt.NDArray[np.uint8]] | npt.NDArray[np.uint8],
) -> list[npt.NDArray[np.uint8]]:
    """Check the frames and return them as a list of H x W x 3 uint8 arrays."""
    if isinstance(frames, np.ndarray):
        if frames.ndim != 4:
            raise MediaError(
                "write_gif: expected frames as an array of shape (N, H, W, 3) or a "
                f"sequence of H x W x 3 arrays, got an array of shape {frames.shape}"
            )
        frame_list = list(frames)
    else:
        try:
            frame_list = list(frames)
        except TypeError:
            raise MediaError(
                f"write_gif: expected frames as a sequence of H x W x 3 uint8 arrays, got {type(frames).__name__}"
            ) from None
    if not frame_list:
        raise MediaError("write_gif: expected at least one frame, got 0 frames")
    first_shape: tuple[int, ...] | None = None
    for i, frame in enumerate(frame_list):
        shape = frame.shape if isinstance(frame, np.ndarray) else None
        if shape is None or len(shape) != 3 or shape[2] != 3:
            given = type(frame).__name__ if shape is None else f"shape {shape}"
            raise MediaError(
                f"write_gif: expected frame {i} to be a numpy array of shape (H, W, 3) and dtype uint8, got {given}"
            )
        if frame.dtype != np.uint8:
            raise MediaError(f"write_gif: expected frame {i} to have dtype uint8, got dtype {frame.dtype}")
        height, width = int(frame.shape[0]), int(frame.shape[1])
        if not (1 <= height <= 0xFFFF and 1 <= width <= 0xFFFF):
            raise MediaError(
                f"write_gif: expected frame {i} height and width between 1 and 65535 pixels, got shape {frame.shape}"
            )
        if first_shape is None:
            first_shape = frame.shape
        elif frame.shape != first_shape:
            raise MediaError(
                f"write_gif: expected all frames to have shape {first_shape} like "
                f"frame 0, got shape {frame.shape} for frame {i}"
            )
    return frame_list


def _delay_centiseconds(fps: float) -> int:
    """GIF frame delay in hundredths of a second for ``fps`` frames per second."""
    is_number = isinstance(fps, numbers.Real) and not isinstance(fps, bool)
    value = float(fps) if is_number else math.nan
    if not math.isfinite(value) or value <= 0.0:
        raise MediaError(f"write_gif: expected fps to be a positive finite number, got {fps!r}")
    delay = max(2, math.floor(100.0 / value + 0.5))
    if delay > 0xFFFF:
        raise MediaError(
            f"write_gif: expected fps >= 100/65535 (about 0.0015, the longest GIF frame delay of 655.35 s), got {fps!r}"
        )
    return delay


# ---------------------------------------------------------------------------- writer


def write_gif(
    path: str | os.PathLike[str],
    frames: Sequence[npt.NDArray[np.uint8]] | npt.NDArray[np.uint8],
    fps: float,
) -> pathlib.Path:
    """Write ``frames`` as an animated GIF89a that loops forever.

    Args:
        path: Output file; overwritten if it exists. Its directory must exist.
        frames: At least one RGB frame, each an array of shape (H, W, 3) and dtype
            uint8 (H, W in pixels, 1..65535), all of the same shape; either a
            sequence of such arrays or one array of shape (N, H, W, 3).
        fps: Playback rate in frames per second, finite and > 0. GIF stores the
            delay per frame in hundredths of a second, so the delay is
            ``round(100 / fps)`` centiseconds, at least 2 (browsers play shorter
            delays slowly): e.g. fps=30 gives 0.03 s per frame, fps=100 gives 0.02 s.

    Returns:
        The written path as a :class:`pathlib.Path`.

    Raises:
        MediaError (a ValueError): no frames; a frame that is not an H x W x 3 uint8 array (or
            is empty or larger than 65535 pixels on a side); frames of differing
            shapes; fps that is not a finite number > 0 (or below 100/65535).

    The colours are reduced to the fixed 252-colour :data:`PALETTE` with ordered
    dithering; colours that are exactly palette entries are reproduced exactly.
    """
    frame_list = _validate_frames(frames)
    delay = _delay_centiseconds(fps)
    out_path = pathlib.Path(path)

    height, width = int(frame_list[0].shape[0]), int(frame_list[0].shape[1])
    tmap = _threshold_map(height, width)

    parts: list[bytes] = [
        b"GIF89a",
        # Logical screen: global colour table present, 8-bit colour resolution,
        # 256 entries (0xF7); background index 0; no aspect ratio.
        struct.pack("<HHBBB", width, height, 0xF7, 0, 0),
        PALETTE.tobytes(),
        # NETSCAPE2.0 application extension: loop count 0 = forever.
        b"\x21\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00",
    ]
    # Graphic control extension: disposal method 1 (do not dispose), no
    # transparency, no user input.
    control = b"\x21\xf9\x04" + struct.pack("<BHB", 1 << 2, delay, 0) + b"\x00"

    previous: npt.NDArray[np.uint8] | None = None
    for frame in frame_list:
        indices = _quantize(frame, tmap)
        if previous is None:
            top, left, bottom, right = 0, 0, height, width
        else:
            changed = indices != previous
            rows = np.flatnonzero(changed.any(axis=1))
            if rows.size == 0:
                # Unchanged: redraw one pixel with its current index to keep timing.
                top, left, bottom, right = 0, 0, 1, 1
            else:
                cols = np.flatnonzero(changed[rows[0] : rows[-1] + 1].any(axis=0))
                top, bottom = int(rows[0]), int(rows[-1]) + 1
                left, right = int(cols[0]), int(cols[-1]) + 1
        parts.append(control)
        # Image descriptor: position and size of the rectangle, no local colour
        # table, not interlaced.
        parts.append(b"\x2c" + struct.pack("<HHHHB", left, top, right - left, bottom - top, 0))
        parts.append(_lzw_image_data(indices[top:bottom, left:right]))
        previous = indices
    parts.append(b"\x3b")

    out_path.write_bytes(b"".join(parts))
    return out_path
