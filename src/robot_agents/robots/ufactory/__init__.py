"""UFactory xArm family (see :mod:`robot_agents.robots.ufactory.xarm6`)."""
