"""The built-in robot zoo, one subpackage per family; registered lazily by uid
(see :mod:`robot_agents.robots.catalog`)."""
