"""Hello Robot Stretch (:mod:`robot_agents.robots.stretch.stretch`): a differential-drive
mobile manipulator with a lift, a telescoping arm, a dexterous wrist and a pan-tilt head."""
