"""Checks shared by the video writers: the frames and the frame rate."""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from robot_agents.errors import MediaError

__all__ = ["Frames", "check_fps", "check_frames"]

Frames = Sequence[npt.NDArray[np.uint8]] | npt.NDArray[np.uint8]
"""RGB frames: a sequence of ``(H, W, 3)`` uint8 arrays or one ``(N, H, W, 3)`` uint8 array."""


def check_frames(frames: Frames, where: str) -> list[npt.NDArray[np.uint8]]:
    """Return ``frames`` as a list of ``(H, W, 3)`` uint8 arrays of one shape.

    Args:
        frames: At least one RGB frame, each of shape ``(H, W, 3)`` (H, W >= 1
            pixels) and dtype uint8, all of the same shape; or one array of shape
            ``(N, H, W, 3)``.
        where: The caller's name, used to start error messages.

    Raises:
        MediaError: no frames, a frame that is not an ``(H, W, 3)`` uint8 array with
            H, W >= 1, or frames of different shapes; the message says what was
            expected and what was given.
    """
    if isinstance(frames, np.ndarray):
        if frames.ndim != 4:
            raise MediaError(
                f"{where}: expected frames as an array of shape (N, H, W, 3) or a "
                f"sequence of (H, W, 3) arrays, got an array of shape {frames.shape}"
            )
        frame_list = list(frames)
    elif isinstance(frames, (str, bytes)):
        raise MediaError(
            f"{where}: expected frames as a sequence of (H, W, 3) uint8 arrays, got {type(frames).__name__}"
        )
    else:
        try:
            frame_list = list(frames)
        except TypeError:
            raise MediaError(
                f"{where}: expected frames as a sequence of (H, W, 3) uint8 arrays, got {type(frames).__name__}"
            ) from None
    if not frame_list:
        raise MediaError(f"{where}: expected at least one frame, got 0 frames")
    first_shape: tuple[int, ...] | None = None
    for i, frame in enumerate(frame_list):
        if not isinstance(frame, np.ndarray):
            raise MediaError(
                f"{where}: expected frame {i} to be a numpy array of shape (H, W, 3) and dtype uint8, "
                f"got {type(frame).__name__}"
            )
        if frame.ndim != 3 or frame.shape[2] != 3 or frame.shape[0] < 1 or frame.shape[1] < 1:
            raise MediaError(f"{where}: expected frame {i} of shape (H, W, 3) with H, W >= 1, got shape {frame.shape}")
        if frame.dtype != np.uint8:
            raise MediaError(f"{where}: expected frame {i} of dtype uint8 (0..255), got dtype {frame.dtype}")
        if first_shape is None:
            first_shape = frame.shape
        elif frame.shape != first_shape:
            raise MediaError(
                f"{where}: expected every frame of shape {first_shape} like frame 0, got shape {frame.shape} for frame {i}"
            )
    return frame_list


def check_fps(fps: float, where: str) -> float:
    """Return ``fps`` (frames per second) as a float; it must be a finite number > 0.

    Raises:
        MediaError: ``fps`` is not a real number, is not finite, or is <= 0.
    """
    is_number = isinstance(fps, numbers.Real) and not isinstance(fps, bool)
    value = float(fps) if is_number else math.nan
    if not math.isfinite(value) or value <= 0.0:
        raise MediaError(f"{where}: expected fps (frames per second) as a finite number > 0, got {fps!r}")
    return value
