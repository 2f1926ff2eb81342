"""Robots: the :class:`Agent` base class and what a bound robot is made of."""

from robot_agents.agent.agent import Agent
from robot_agents.agent.declaration import SINGLE_PART, CheckedRobot

__all__ = ["SINGLE_PART", "Agent", "CheckedRobot"]
