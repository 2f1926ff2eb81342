"""Fetch (Fetch Robotics' mobile manipulator): :mod:`robot_agents.robots.fetch.fetch`."""
