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
- Wrist camera (``panda_wristcam``): an Intel RealSense D415 on the hand, placed as
  in ManiSkill's public ``panda_v3.urdf`` (``camera_link``: 0.0465 m along the hand's
  x axis, -0.02 m along y, 0.036 m along z), looking along the gripper's approach
  axis (hand +z) with the image's up towards hand +x; housing 99 x 23 x 20 mm and
  72 g (Intel D415 datasheet).
- Fingertip touch pads (``panda_touch``): the rubber pads of the public Panda model
  (17.5 x 15.2 x 18.5 mm; ours 17 x 15 x 19 mm), each covered by a touch site 1 mm
  larger on every side.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import mujoco

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
from robot_agents.sensors import CameraConfig, TouchSensorConfig

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


#: The wrist camera's optical centre in the ``panda_hand`` frame (m), and its
#: orientation: camera -z (view) = hand +z, camera y (image up) = hand +x, camera x
#: (image right) = hand +y; a half turn about (x + y) / sqrt(2).
WRIST_CAMERA_POS = (0.0465, -0.02, 0.036)
WRIST_CAMERA_QUAT = (0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0)
#: D415 housing in the hand frame: centre (m), half extents (m), mass (kg). Its front
#: face is 2.5 mm behind the optical centre.
WRIST_CAMERA_HOUSING = ((0.0465, 0.0, 0.0235), (0.0115, 0.0495, 0.010), 0.072)

HAND_CAMERA = CameraConfig(
    uid="hand_camera",
    mount="panda_hand",
    pos=WRIST_CAMERA_POS,
    quat=WRIST_CAMERA_QUAT,
    width=128,
    height=128,
    fovy=90.0,
    near=0.01,
    far=10.0,
)

#: Touch sites over the finger pads (pad: centre (0, +-0.008, 0.0445), half extents
#: (0.0085, 0.0075, 0.0095) m in the finger frame), 1 mm larger on every side so the
#: contact points of the pad's faces (mid-penetration) fall inside.
FINGERTIP_TOUCH = (
    TouchSensorConfig(
        "left_pad_touch", link="panda_leftfinger", pos=(0.0, 0.008, 0.0445), size=(0.0095, 0.0085, 0.0105)
    ),
    TouchSensorConfig(
        "right_pad_touch", link="panda_rightfinger", pos=(0.0, -0.008, 0.0445), size=(0.0095, 0.0085, 0.0105)
    ),
)


@register_agent()
class PandaWristCam(Panda):
    """The Panda with a RealSense D415 on the hand: camera ``hand_camera`` (128 x 128,
    90 deg vertical field of view) looking along the gripper's approach axis."""

    uid = "panda_wristcam"
    cameras = (HAND_CAMERA,)

    @classmethod
    def build_spec(cls, cameras: Sequence[CameraConfig] | None = None) -> mujoco.MjSpec:
        """The Panda's spec plus the camera housing on the hand (collision and visual)."""
        spec = super().build_spec(cameras)
        (pos, half, mass) = WRIST_CAMERA_HOUSING
        hand = spec.body("panda_hand")
        box = mujoco.mjtGeom.mjGEOM_BOX
        hand.add_geom(name="wrist_camera_housing", type=box, pos=list(pos), size=list(half), mass=mass, group=3)
        hand.add_geom(
            type=box,
            pos=list(pos),
            size=list(half),
            group=2,
            contype=0,
            conaffinity=0,
            mass=0.0,
            rgba=[0.2, 0.2, 0.22, 1],
        )
        return spec


@register_agent()
class PandaTouch(Panda):
    """The Panda with touch-sensing fingertip pads: ``touch`` ``(num_envs, 2)`` in the
    proprioception, the normal force (N) on the left and right pad."""

    uid = "panda_touch"
    touch_sensors = FINGERTIP_TOUCH


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
