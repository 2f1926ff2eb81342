"""Franka Emika Panda robots.

Sources of the numbers:
- Kinematics: Franka's published (modified) DH table; flange 0.107 m past joint 7;
  hand turned -45 deg about the flange z axis; TCP 0.1034 m past the hand.
- Joint position, velocity and torque limits: the Franka Emika robot datasheet
  (joints 1-4: 87 N*m, 2.175 rad/s; joints 5-7: 12 N*m, 2.61 rad/s).
- Franka Hand: 0-0.04 m per finger, 70 N continuous grasping force.
- Link masses: the publicly identified dynamic parameters of the Panda.
- Gains: kp = 1000, kv = 100 on the arm (the ManiSkill defaults, so ported policies
  see the same response), on top of exact gravity compensation of every link.
- ``ready`` is Franka's own default pose; ``rest`` is the ManiSkill rest pose.
"""

from __future__ import annotations

import math
from pathlib import Path

from robot_agents.agent import Agent
from robot_agents.controllers import (
    JointGroup,
    PDJointPosMimicConfig,
    TaskSpace,
    WorkspaceBox,
    combine_parts,
    ee_control_modes,
    joint_control_modes,
)
from robot_agents.keyframe import Keyframe
from robot_agents.model.materials import FrictionMaterial
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")

PANDA_ARM = JointGroup(
    joint_names=ARM_JOINTS,
    stiffness=1e3,
    damping=1e2,
    force_limit=(87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0),
    max_delta=0.1,
    max_velocity=(2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61),
)

#: End-effector commands: ManiSkill's delta bounds (10 cm, 0.1 rad per step); absolute
#: positions bounded by a box around the arm's reach (855 mm from the shoulder at
#: z = 0.333 m, plus the 0.21 m flange-to-TCP offset).
PANDA_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-1.1, -1.1, -0.8), upper=(1.1, 1.1, 1.4)),
    max_translation=0.1,
    max_rotation=0.1,
)

#: One action in [-1, 1] for both fingers: -1 closes past contact (squeezes), +1 opens 8 cm.
PANDA_GRIPPER = PDJointPosMimicConfig(
    joint_names=FINGER_JOINTS,
    lower=-0.01,
    upper=0.04,
    stiffness=1e3,
    damping=1e2,
    force_limit=70.0,
    clip_target=False,
)

#: High-friction finger pads, as rubber pads on the real fingertips.
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)

ARM_REST = (0.0, math.pi / 8, 0.0, -5 * math.pi / 8, 0.0, 3 * math.pi / 4, math.pi / 4)
ARM_READY = (0.0, -math.pi / 4, 0.0, -3 * math.pi / 4, 0.0, math.pi / 2, math.pi / 4)
FINGERS_OPEN = (0.04, 0.04)


@register_agent()
class Panda(Agent):
    """Franka Emika Panda: 7-DoF arm and the Franka Hand with mimic fingers.

    qpos order: ``panda_joint1``..``panda_joint7`` (base to wrist), then the two fingers.
    """

    uid = "panda"
    mjcf_path = ASSETS / "panda.xml"
    link_materials = {"panda_leftfinger": FINGER_PAD, "panda_rightfinger": FINGER_PAD}
    keyframes = {
        "rest": Keyframe(qpos=(*ARM_REST, *FINGERS_OPEN)),
        "ready": Keyframe(qpos=(*ARM_READY, *FINGERS_OPEN)),
        "closed_rest": Keyframe(qpos=(*ARM_REST, 0.0, 0.0)),
    }
    control_modes = combine_parts(
        "arm",
        {**joint_control_modes(PANDA_ARM), **ee_control_modes(PANDA_ARM, PANDA_TASK_SPACE)},
        gripper=PANDA_GRIPPER,
    )
    default_control_mode = "pd_joint_delta_pos"
    tcp_link = "panda_hand_tcp"
    finger_links = ("panda_leftfinger", "panda_rightfinger")
    gripper_joint_names = FINGER_JOINTS


@register_agent()
class PandaStick(Agent):
    """The Panda arm with a stick tool on its flange instead of the hand (7 DoF)."""

    uid = "panda_stick"
    mjcf_path = ASSETS / "panda_stick.xml"
    keyframes = {"rest": Keyframe(qpos=ARM_REST), "ready": Keyframe(qpos=ARM_READY)}
    control_modes = {**joint_control_modes(PANDA_ARM), **ee_control_modes(PANDA_ARM, PANDA_TASK_SPACE)}
    default_control_mode = "pd_joint_delta_pos"
    tcp_link = "panda_stick_tcp"


MOUNT_JOINTS = (
    "root_x_axis_joint",
    "root_y_axis_joint",
    "root_z_axis_joint",
    "root_x_rot_joint",
    "root_y_rot_joint",
    "root_z_rot_joint",
)


#: The mount's slides and hinges: stiff enough to hold the hand against contact forces.
FLOATING_MOUNT = JointGroup(joint_names=MOUNT_JOINTS, stiffness=1e3, damping=1e2, force_limit=100.0, max_delta=0.1)
#: The mount's slide range bounds absolute positions.
FLOATING_TASK_SPACE = TaskSpace(position_bounds=WorkspaceBox(lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0)))


@register_agent()
class FloatingPandaGripper(Agent):
    """The Franka Hand on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges).

    qpos order: the six mount joints, then the two fingers.
    """

    uid = "floating_panda_gripper"
    mjcf_path = ASSETS / "floating_panda_gripper.xml"
    link_materials = {"panda_leftfinger": FINGER_PAD, "panda_rightfinger": FINGER_PAD}
    keyframes = {
        "rest": Keyframe(qpos=(0.0,) * 6 + FINGERS_OPEN),
        "closed": Keyframe(qpos=(0.0,) * 6 + (0.0, 0.0)),
    }
    control_modes = combine_parts(
        "arm",
        {
            **joint_control_modes(FLOATING_MOUNT),
            **ee_control_modes(FLOATING_MOUNT, FLOATING_TASK_SPACE, modes=("pd_ee_delta_pose", "pd_ee_pose")),
        },
        gripper=PANDA_GRIPPER,
    )
    default_control_mode = "pd_joint_delta_pos"
    tcp_link = "panda_hand_tcp"
    finger_links = ("panda_leftfinger", "panda_rightfinger")
    gripper_joint_names = FINGER_JOINTS
