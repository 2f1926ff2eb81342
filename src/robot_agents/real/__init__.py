"""The bridge to real robots: a robot definition's control modes driving hardware
through a joint interface (:mod:`robot_agents.real.bridge`; the interface:
:mod:`robot_agents.real.bus`; a simulated stand-in: :mod:`robot_agents.real.simulated_bus`)."""

from robot_agents.real.bridge import RealRobot
from robot_agents.real.bus import JointBus
from robot_agents.real.simulated_bus import SimulatedBus

__all__ = ["JointBus", "RealRobot", "SimulatedBus"]
