"""The built-in robot zoo; importing it registers every robot."""

from robot_agents.robots.panda import FloatingPandaGripper, Panda, PandaStick, PandaTouch, PandaWristCam

__all__ = ["FloatingPandaGripper", "Panda", "PandaStick", "PandaTouch", "PandaWristCam"]
