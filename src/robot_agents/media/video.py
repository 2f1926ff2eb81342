"""One entry point for videos: the format follows the output file's suffix."""

from __future__ import annotations

import os
from pathlib import Path

from robot_agents.errors import MediaError
from robot_agents.media.frames import Frames
from robot_agents.media.gif import write_gif
from robot_agents.media.mp4 import require_mp4_backend, write_mp4

__all__ = ["SUPPORTED_SUFFIXES", "check_output_path", "write_video"]

SUPPORTED_SUFFIXES = (".gif", ".mp4")
"""Video formats :func:`write_video` writes, by file suffix (case-insensitive)."""


def check_output_path(path: str | os.PathLike[str]) -> Path:
    """Check, before any frame is made, that a video can be written to ``path``.

    The suffix must be one of :data:`SUPPORTED_SUFFIXES`, ``path`` must not be a
    directory, its parent directory must exist and be writable, and for ``.mp4``
    imageio and imageio-ffmpeg must be installed.

    Returns:
        ``path`` as a :class:`~pathlib.Path`.

    Raises:
        MediaError: naming what is wrong and what is expected.
    """
    out_path = Path(path)
    suffix = out_path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        given = f"suffix {out_path.suffix!r}" if out_path.suffix else "no suffix"
        raise MediaError(
            f"video output {str(out_path)!r}: expected a file name ending in {' or '.join(SUPPORTED_SUFFIXES)}, got {given}"
        )
    if out_path.is_dir():
        raise MediaError(f"video output {str(out_path)!r}: expected a file name, got an existing directory")
    parent = out_path.parent
    if not parent.is_dir():
        what = "is not a directory" if parent.exists() else "does not exist"
        raise MediaError(f"video output {str(out_path)!r}: expected an existing directory, but {str(parent)!r} {what}")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise MediaError(f"video output {str(out_path)!r}: expected a writable directory, but {str(parent)!r} is not")
    if suffix == ".mp4":
        require_mp4_backend()
    return out_path


def write_video(path: str | os.PathLike[str], frames: Frames, fps: float) -> Path:
    """Write ``frames`` as a video whose format follows ``path``'s suffix.

    ``.gif`` goes through :func:`~robot_agents.media.gif.write_gif` (Pillow, a core
    dependency), ``.mp4`` through :func:`~robot_agents.media.mp4.write_mp4`
    (imageio + imageio-ffmpeg: ``pip install 'robot-agents[video]'``).

    Args:
        path: Output file ending in ``.gif`` or ``.mp4``; overwritten if it exists.
        frames: At least one RGB frame of shape ``(H, W, 3)``, dtype uint8 (pixels),
            all of one shape; or one ``(N, H, W, 3)`` array.
        fps: Playback rate in frames per second, finite and > 0.

    Returns:
        The written path.

    Raises:
        MediaError: an unsupported suffix (the message lists the supported ones), a
            missing or read-only directory, ``.mp4`` without imageio-ffmpeg (the
            message names the pip command), bad frames or a bad ``fps``.
    """
    out_path = check_output_path(path)
    if out_path.suffix.lower() == ".mp4":
        return write_mp4(out_path, frames, fps)
    return write_gif(out_path, frames, fps)
