"""Franka Emika Panda family (see :mod:`robot_agents.robots.panda.panda`)."""
