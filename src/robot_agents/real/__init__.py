"""The bridge to real robots: a robot definition's control modes driving hardware
through a joint interface (:mod:`robot_agents.real.bridge`)."""

from robot_agents.real.bridge import JointBus, RealRobot, SimulatedBus

__all__ = ["JointBus", "RealRobot", "SimulatedBus"]
