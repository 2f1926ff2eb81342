"""Robotiq 2F-85 gripper (see :mod:`robot_agents.robots.robotiq.robotiq`)."""
