"""The built-in robots by uid: where each one is defined (``module:Class``).

Plain data, imported by the registry: a built-in robot's module is imported (and the
robot registered and checked) only when its uid is first asked for.
"""

BUILTIN_ROBOTS: dict[str, str] = {
    "panda": "robot_agents.robots.panda.panda:Panda",
    "panda_wristcam": "robot_agents.robots.panda.panda:PandaWristCam",
    "panda_touch": "robot_agents.robots.panda.panda:PandaTouch",
    "panda_stick": "robot_agents.robots.panda.panda:PandaStick",
    "floating_panda_gripper": "robot_agents.robots.panda.panda:FloatingPandaGripper",
    "floating_robotiq_2f_85_gripper": "robot_agents.robots.robotiq.robotiq:FloatingRobotiq2F85Gripper",
}
