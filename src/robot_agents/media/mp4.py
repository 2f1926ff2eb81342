"""MP4 (H.264) videos of RGB frames, written with imageio + imageio-ffmpeg (optional)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import numpy.typing as npt

from robot_agents.errors import MediaError
from robot_agents.media.frames import Frames, check_fps, check_frames

__all__ = ["INSTALL_HINT", "require_mp4_backend", "write_mp4"]

INSTALL_HINT = "pip install 'robot-agents[video]' (or: pip install imageio imageio-ffmpeg)"
"""The command that installs what :func:`write_mp4` needs."""


def require_mp4_backend() -> None:
    """Check that imageio and imageio-ffmpeg, which :func:`write_mp4` needs, are importable.

    Raises:
        MediaError: either package is missing; the message names the pip command.
    """
    try:
        import imageio.v2  # noqa: F401
        import imageio_ffmpeg  # noqa: F401  (the ffmpeg binary imageio writes MP4 with)
    except ImportError as err:
        raise MediaError(
            f"writing .mp4 needs imageio and imageio-ffmpeg ({err.name or 'a module'} is not installed); "
            f"install them with: {INSTALL_HINT}"
        ) from None


def _even(frame: npt.NDArray[np.uint8]) -> npt.NDArray[np.uint8]:
    """Pad an ``(H, W, 3)`` frame to even H and W by repeating its last row / column."""
    pad_h, pad_w = frame.shape[0] % 2, frame.shape[1] % 2
    if not (pad_h or pad_w):
        return frame
    return np.pad(frame, ((0, pad_h), (0, pad_w), (0, 0)), mode="edge")


def write_mp4(path: str | os.PathLike[str], frames: Frames, fps: float) -> Path:
    """Write ``frames`` as an H.264 MP4 video (yuv420p, plays in browsers).

    Args:
        path: Output file, overwritten if it exists; its directory must exist.
        frames: At least one RGB frame of shape ``(H, W, 3)``, dtype uint8 (pixels),
            all of one shape; or one ``(N, H, W, 3)`` array. H.264 in yuv420p needs
            even sizes: an odd height or width is padded by one pixel, repeating the
            last row or column.
        fps: Playback rate in frames per second, finite and > 0.

    Returns:
        The written path.

    Raises:
        MediaError: imageio or imageio-ffmpeg is not installed (the message names
            the pip command), bad frames, or a bad ``fps``.

    The encoding is lossy: colours come back close to, not equal to, the input.
    """
    frame_list = check_frames(frames, "write_mp4")
    rate = check_fps(fps, "write_mp4")
    require_mp4_backend()
    import imageio.v2 as iio

    out_path = Path(path)
    writer = iio.get_writer(
        out_path,
        format="FFMPEG",
        mode="I",
        fps=rate,
        codec="libx264",
        pixelformat="yuv420p",
        quality=8,
        macro_block_size=1,  # sizes are made even here; no rescaling by imageio
    )
    try:
        for frame in frame_list:
            writer.append_data(_even(frame))
    finally:
        writer.close()
    return out_path
