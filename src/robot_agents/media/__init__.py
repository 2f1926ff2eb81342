"""Writing what the library shows: animated GIFs of rendered frames."""

from robot_agents.media.gif import write_gif

__all__ = ["write_gif"]
