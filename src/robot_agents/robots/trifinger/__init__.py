"""The TriFinger Pro (:mod:`robot_agents.robots.trifinger.trifingerpro`)."""
