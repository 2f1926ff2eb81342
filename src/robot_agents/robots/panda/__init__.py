"""The Franka Emika Panda family: arm + hand, arm + stick, and the floating hand."""

from robot_agents.robots.panda.panda import FloatingPandaGripper, Panda, PandaStick, PandaTouch, PandaWristCam

__all__ = ["FloatingPandaGripper", "Panda", "PandaStick", "PandaTouch", "PandaWristCam"]
