"""Writing what the library shows: GIF (Pillow) or MP4 (imageio-ffmpeg) videos of RGB frames.

:func:`write_video` picks the format from the file suffix; :func:`draw_label` puts a
caption on a frame.
"""

from robot_agents.media.gif import write_gif
from robot_agents.media.label import draw_label
from robot_agents.media.mp4 import write_mp4
from robot_agents.media.video import SUPPORTED_SUFFIXES, check_output_path, write_video

__all__ = ["SUPPORTED_SUFFIXES", "check_output_path", "draw_label", "write_gif", "write_mp4", "write_video"]
