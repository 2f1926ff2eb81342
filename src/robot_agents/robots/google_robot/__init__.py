"""Google Robot (Everyday Robots' mobile manipulator, the RT-1 robot):
:mod:`robot_agents.robots.google_robot.google_robot`."""
