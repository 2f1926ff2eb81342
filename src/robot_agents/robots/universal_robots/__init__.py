"""Universal Robots family (see :mod:`robot_agents.robots.universal_robots.ur10e`)."""
