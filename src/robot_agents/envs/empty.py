"""``Empty-v1``: the robot alone on a floor; no reward, never terminates.

For trying control modes, benchmarking and demos.
"""

from __future__ import annotations

from robot_agents.envs.base_env import RobotEnv


class EmptyEnv(RobotEnv):
    """A robot on an empty floor. Observation: proprioception and tool pose."""
