"""The built-in robots by uid, and the built-in pieces by name: where each one is
defined (``module:Class``).

Plain data, imported by the registry: a built-in robot's module is imported (and the
robot registered and checked) only when its uid is first asked for.
"""

BUILTIN_ROBOTS: dict[str, str] = {
    "panda": "robot_agents.robots.panda.panda:Panda",
    "panda_wristcam": "robot_agents.robots.panda.panda:PandaWristCam",
    "panda_touch": "robot_agents.robots.panda.panda:PandaTouch",
    "panda_stick": "robot_agents.robots.panda.panda:PandaStick",
    "floating_panda_gripper": "robot_agents.robots.panda.panda:FloatingPandaGripper",
    "koch-v1.1": "robot_agents.robots.servo_arms.koch:Koch",
    "so100": "robot_agents.robots.servo_arms.so100:SO100",
    "ur_10e": "robot_agents.robots.universal_robots.ur10e:UR10e",
    "xarm6_nogripper": "robot_agents.robots.ufactory.xarm6:XArm6NoGripper",
    "xarm6_nogripper_wristcam": "robot_agents.robots.ufactory.xarm6:XArm6NoGripperWristCam",
    "widowx250s": "robot_agents.robots.widowx.widowx250s:WidowX250S",
    "widowx250s_bridgedataset_flat_table": "robot_agents.robots.widowx.widowx250s:WidowX250SBridgeDatasetFlatTable",
    "widowx250s_bridgedataset_sink": "robot_agents.robots.widowx.widowx250s:WidowX250SBridgeDatasetSink",
    "widowxai": "robot_agents.robots.widowx.widowxai:WidowXAI",
    "widowxai_wristcam": "robot_agents.robots.widowx.widowxai:WidowXAIWristCam",
    "floating_robotiq_2f_85_gripper": "robot_agents.robots.robotiq.robotiq:FloatingRobotiq2F85Gripper",
    "xarm6_robotiq": "robot_agents.robots.ufactory.xarm6:XArm6Robotiq",
    "xarm6_robotiq_wristcam": "robot_agents.robots.ufactory.xarm6:XArm6RobotiqWristCam",
    "google_robot": "robot_agents.robots.google_robot.google_robot:GoogleRobot",
    "stretch": "robot_agents.robots.stretch.stretch:Stretch",
    "spot": "robot_agents.robots.spot.spot:Spot",
    "fetch": "robot_agents.robots.fetch.fetch:Fetch",
    "unitree_h1": "robot_agents.robots.unitree.h1:UnitreeH1",
    "allegro_hand_right": "robot_agents.robots.wonik.allegro:AllegroHandRight",
    "dclaw": "robot_agents.robots.robel.dclaw:DClaw",
    "allegro_hand_left": "robot_agents.robots.wonik.allegro_left:AllegroHandLeft",
    "allegro_hand_right_touch": "robot_agents.robots.wonik.allegro_touch:AllegroHandRightTouch",
    "anymal_c": "robot_agents.robots.anybotics.anymal_c:AnymalC",
    "trifingerpro": "robot_agents.robots.trifinger.trifingerpro:TriFingerPro",
    "unitree_go2": "robot_agents.robots.unitree.go2:UnitreeGo2",
    "floating_ability_hand_right": "robot_agents.robots.psyonic.ability_hand:FloatingAbilityHandRight",
    "xarm7_ability": "robot_agents.robots.ufactory.xarm7:XArm7Ability",
    "unitree_go2_simplified_locomotion": "robot_agents.robots.unitree.go2:UnitreeGo2Simplified",
    "unitree_h1_simplified": "robot_agents.robots.unitree.h1:UnitreeH1Simplified",
    "humanoid": "robot_agents.robots.humanoid.humanoid:Humanoid",
    "fixed_inspire_hand_right": "robot_agents.robots.inspire.inspire_hand:FixedInspireHandRight",
    "fixed_inspire_hand_left": "robot_agents.robots.inspire.inspire_hand:FixedInspireHandLeft",
    "floating_inspire_hand_right": "robot_agents.robots.inspire.inspire_hand:FloatingInspireHandRight",
    "floating_inspire_hand_left": "robot_agents.robots.inspire.inspire_hand:FloatingInspireHandLeft",
    "unitree_g1_simplified_upper_body": "robot_agents.robots.unitree.g1:UnitreeG1UpperBody",
    "unitree_g1_simplified_upper_body_with_head_camera": "robot_agents.robots.unitree.g1:UnitreeG1UpperBodyWithHeadCamera",
    "unitree_g1_simplified_upper_body_right_arm": "robot_agents.robots.unitree.g1:UnitreeG1UpperBodyRightArm",
    "stompy": "robot_agents.robots.kscale.stompy:Stompy",
    "unitree_g1": "robot_agents.robots.unitree.g1_full:UnitreeG1",
    "unitree_g1_simplified_legs": "robot_agents.robots.unitree.g1_full:UnitreeG1SimplifiedLegs",
    "xlerobot": "robot_agents.robots.xlerobot.xlerobot:Xlerobot",
}

#: Other names of built-in robots: the uids ManiSkill 3.0.1 registers them under where
#: ours differ, so that a uid copied from ManiSkill code works here (``get_agent``,
#: ``make_env(robot_uids=...)``, the command line). An alias gives the robot itself: the
#: class, and the robot id in a scene, are the uid's (``google_robot``). ``list_agents``
#: lists uids only.
BUILTIN_ALIASES: dict[str, str] = {
    "googlerobot": "google_robot",
}

#: Pieces (unregistered Agent classes) a robot can mount with ``Attachment``, by the name
#: the command line's ``--gripper`` takes: each declares its ``tcp``, and its root frame's
#: z axis points out of the flange it is mounted on.
BUILTIN_PIECES: dict[str, str] = {
    "robotiq_2f85": "robot_agents.robots.robotiq.robotiq:Robotiq2F85",
    "franka_hand": "robot_agents.robots.panda.panda:PandaHand",
    "panda_stick": "robot_agents.robots.panda.panda:PandaStickTool",
    "widowx250s_gripper": "robot_agents.robots.widowx.widowx250s:WidowX250SGripperPiece",
    "ability_hand_right": "robot_agents.robots.psyonic.ability_hand:AbilityHandRight",
    "inspire_hand_right": "robot_agents.robots.inspire.inspire_hand:InspireHandRight",
    "inspire_hand_left": "robot_agents.robots.inspire.inspire_hand:InspireHandLeft",
}
