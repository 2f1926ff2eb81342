"""Wonik Robotics: the Allegro Hand (:mod:`robot_agents.robots.wonik.allegro`)."""
