"""Trossen Robotics WidowX family: the WidowX 250 S (Interbotix X-series, DYNAMIXEL
servos) with its BridgeData V2 setups (:mod:`robot_agents.robots.widowx.widowx250s`),
and the WidowX AI (:mod:`robot_agents.robots.widowx.widowxai`)."""
