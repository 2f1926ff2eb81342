"""ROBEL (Robotics Benchmarks for Learning): the D'Claw (:mod:`robot_agents.robots.robel.dclaw`)."""
