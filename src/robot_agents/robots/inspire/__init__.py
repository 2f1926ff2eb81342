"""Inspire Robots: the RH56DFX hand (:mod:`robot_agents.robots.inspire.inspire_hand`)."""
