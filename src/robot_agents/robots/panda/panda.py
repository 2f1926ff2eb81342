"""Franka Emika Panda robots.

Sources of the numbers:
- Kinematics: Franka's published (modified) DH table; flange 0.107 m past joint 7;
  hand turned -45 deg about the flange z axis; TCP 0.1034 m past the hand.
- Joint position, velocity and torque limits: the Franka Emika robot datasheet
  (joints 1-4: 87 N*m, 2.175 rad/s; joints 5-7: 12 N*m, 2.61 rad/s).
- Franka Hand: 0-0.04 m per finger, 70 N continuous grasping force.
- Link masses: the publicly identified dynamic parameters of the Panda.
- Armature (reflected rotor inertia) 0.1 kg*m^2 on every arm joint: the value of the
  public MuJoCo Menagerie Panda model (``franka_emika_panda/panda.xml``, read as data).
  Without it the wrist joints (about 0.05 kg*m^2 of link inertia, 12 N*m limit,
  kv = 100) fall into a bang-bang cycle between their torque limits at 500 Hz: once a
  drive's force is clamped MuJoCo no longer integrates its damping implicitly, and
  kv * dt / I = 3.8 > 2 makes the explicit damping unstable (joint 7 left at 0.26 rad/s
  after random actions and 1 s of holding still; 0.013 rad/s with the armature; see
  ``tests/test_timestep.py``).
- Gains: kp = 1000, kv = 100 on the arm (the ManiSkill defaults, so ported policies
  see the same response), on top of exact gravity compensation of every link.
- ``ready`` is Franka's own default pose; ``rest`` is the ManiSkill rest pose.
- Composition: the arm (``panda_arm.xml``) and the hand (``panda_hand.xml``) are
  separate models; ``panda``, ``panda_wristcam``, ``panda_touch``, ``panda_stick`` and
  ``floating_panda_gripper`` attach pieces to them (the hand at the flange, turned
  -45 deg about its z axis; a stick tool; a camera housing; the hand on a mount).
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

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import EE_MODES
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, EndEffector, Gripper
from robot_agents.registry import register_agent
from robot_agents.robots.floating_mount import MOUNT_JOINTS, mount_arm
from robot_agents.sensors import CameraConfig, TouchSensorConfig

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")

#: The arm's drives: PD servos (kp = 1000 N*m/rad, kv = 100 N*m*s/rad) with the
#: datasheet's torque and speed limits and the motors' reflected inertia (armature).
PANDA_ARM_DRIVES = PDActuator(
    joints="panda_joint[1-7]",
    stiffness=1e3,
    damping=1e2,
    effort_limit=(87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0),
    velocity_limit=(2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61),
    armature=0.1,
)
#: The hand's drive (both fingers; 70 N continuous grasping force).
PANDA_HAND_DRIVES = PDActuator(joints="panda_finger_joint[12]", stiffness=1e3, damping=1e2, effort_limit=70.0)

#: End-effector commands: ManiSkill's delta bounds (10 cm, 0.1 rad per step); absolute
#: positions bounded by a box around the arm's reach (855 mm from the shoulder at
#: z = 0.333 m, plus the 0.21 m flange-to-TCP offset).
PANDA_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-1.1, -1.1, -0.8), upper=(1.1, 1.1, 1.4)),
    max_translation=0.1,
    max_rotation=0.1,
)
#: The arm part; its end effector is the flange until a tool is attached.
PANDA_ARM = Arm(
    name="arm",
    joints="panda_joint[1-7]",
    end_effectors=(EndEffector("panda_link8", name="flange"),),
    task_space=PANDA_TASK_SPACE,
    max_delta=0.1,
)
#: The hand: one action for both fingers, -1 closes 1 cm past contact (squeezes), +1 opens 8 cm.
PANDA_GRIPPER = Gripper(
    name="gripper",
    joints="panda_finger_joint[12]",
    open=0.04,
    closed=0.0,
    squeeze=0.01,
    fingers=("panda_leftfinger", "panda_rightfinger"),
)

#: High-friction finger pads, as rubber pads on the real fingertips.
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)

ARM_REST = (0.0, math.pi / 8, 0.0, -5 * math.pi / 8, 0.0, 3 * math.pi / 4, math.pi / 4)
ARM_READY = (0.0, -math.pi / 4, 0.0, -3 * math.pi / 4, 0.0, math.pi / 2, math.pi / 4)
#: The hand is mounted on the flange turned -45 deg about its z axis.
HAND_ON_FLANGE = (math.cos(-math.pi / 8), 0.0, 0.0, math.sin(-math.pi / 8))


class PandaArm(Agent):
    """The Panda arm alone, up to its flange (a piece to mount tools on)."""

    mjcf_path = ASSETS / "panda_arm.xml"
    actuators = (PANDA_ARM_DRIVES,)
    parts = (PANDA_ARM,)
    keyframes = {
        "rest": Keyframe(qpos={"panda_joint[1-7]": ARM_REST}),
        "ready": Keyframe(qpos={"panda_joint[1-7]": ARM_READY}),
    }
    default_control_mode = "pd_joint_delta_pos"


class PandaHand(Agent):
    """The Franka Hand alone: two mimic fingers, 0-0.04 m each (a piece)."""

    mjcf_path = ASSETS / "panda_hand.xml"
    tcp = "panda_hand_tcp"
    actuators = (PANDA_HAND_DRIVES,)
    parts = (PANDA_GRIPPER,)
    link_materials = {"panda_leftfinger": FINGER_PAD, "panda_rightfinger": FINGER_PAD}
    keyframes = {"open": Keyframe(qpos={"panda_finger_joint[12]": 0.04})}


def with_tool(tcp: str) -> tuple[Arm]:
    """The arm part with its end effector moved to a tool's TCP body."""
    return (dataclasses.replace(PANDA_ARM, end_effectors=(EndEffector(tcp, name="tcp"),)),)


@register_agent()
class Panda(PandaArm):
    """Franka Emika Panda: 7-DoF arm and the Franka Hand with mimic fingers.

    qpos order: ``panda_joint1``..``panda_joint7`` (base to wrist), then the two fingers.
    """

    uid = "panda"
    #: Time-step sweep (robot_agents.tuning.timestep, 2026-11-23, 20 Hz control; the
    #: wrist camera, touch and stick variants alike): every claim (grasp: 0.68-0.78 mm
    #: of slip in the 2 s hold) holds from 2.5 ms (400 Hz) down to 1 ms; at 320 Hz the
    #: wrist is left in a torque-limit cycle (settle). With three random-action seeds
    #: (2026-11-23 14:00 UTC rerun) joint 7 also cycles at 400 Hz (0.16 rad/s, seed 2;
    #: ``panda_wristcam`` held there) and every claim holds from 500 Hz. That cycle is
    #: the one failure between them, and it cannot occur above 485 Hz (kv 100, 12 N*m,
    #: 0.103 kg*m^2 at its lightest; ``robot_agents.tuning.cycles``, checked in
    #: tests/test_cycles.py): 500 Hz, where the bound takes the place of the one-step
    #: margin.
    sim_freq: ClassVar[int | None] = 500
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(PandaHand, at="panda_link8", quat=HAND_ON_FLANGE),)
    parts = with_tool("panda_hand_tcp")
    keyframes = {
        "rest": Keyframe(qpos={"panda_joint[1-7]": ARM_REST}),
        "ready": Keyframe(qpos={"panda_joint[1-7]": ARM_READY}),
        # the second finger follows the first through the hand's coupling
        "closed_rest": Keyframe(qpos={"panda_joint[1-7]": ARM_REST, "panda_finger_joint1": 0.0}),
    }


#: The wrist camera's optical centre in the ``panda_hand`` frame (m), and its
#: orientation: camera -z (view) = hand +z, camera y (image up) = hand +x, camera x
#: (image right) = hand +y; a half turn about (x + y) / sqrt(2).
WRIST_CAMERA_POS = (0.0465, -0.02, 0.036)
WRIST_CAMERA_QUAT = (0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0)
#: Centre of the D415 housing in the hand frame (m); its front face is 2.5 mm behind
#: the optical centre.
WRIST_CAMERA_HOUSING_POS = (0.0465, 0.0, 0.0235)

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


class RealSenseD415(Agent):
    """An Intel RealSense D415 housing (a piece; its camera is declared by the robot)."""

    mjcf_path = ASSETS / "realsense_d415.xml"


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
    attachments = (
        *Panda.attachments,
        Attachment(RealSenseD415, at="panda_hand", pos=WRIST_CAMERA_HOUSING_POS),
    )
    cameras = (HAND_CAMERA,)


@register_agent()
class PandaTouch(Panda):
    """The Panda with touch-sensing fingertip pads: ``touch`` ``(num_envs, 2)`` in the
    proprioception, the normal force (N) on the left and right pad."""

    uid = "panda_touch"
    touch_sensors = FINGERTIP_TOUCH


class PandaStickTool(Agent):
    """A stick on the flange (a piece); its TCP is ``panda_stick_tcp``."""

    mjcf_path = ASSETS / "panda_stick_tool.xml"
    tcp = "panda_stick_tcp"


@register_agent()
class PandaStick(PandaArm):
    """The Panda arm with a stick tool on its flange instead of the hand (7 DoF)."""

    uid = "panda_stick"
    #: As the Panda's (sweep 2026-11-23, three seeds: every claim holds at 500 Hz and
    #: finer; joint 7 cycles at 400 Hz, impossible above 495 Hz here): 500 Hz.
    sim_freq: ClassVar[int | None] = 500
    attachments = (Attachment(PandaStickTool, at="panda_link8", quat=HAND_ON_FLANGE),)
    parts = with_tool("panda_stick_tcp")


@register_agent()
class FloatingPandaGripper(Agent):
    """The Franka Hand on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges).

    qpos order: the six mount joints, then the two fingers.
    """

    uid = "floating_panda_gripper"
    #: Time-step sweep (2026-11-23, 20 Hz control): every claim holds from 100 Hz down to
    #: 1 kHz (grasp slip 1.8 mm at 100 Hz, 1.2 mm at 160 Hz; contact depth 4.7 mm at 100
    #: Hz, 2.0 mm at 160 Hz); at 80 Hz the cube is pressed 5.8 mm deep. Default one tried
    #: step finer, 160 Hz (margin: 6.25 ms against 10 ms). (With ManiSkill's 100 N / N*m
    #: limit on the mount the rotating joints, carrying only the hand's inertia, were
    #: left cycling between their limits below 320 Hz.)
    sim_freq: ClassVar[int | None] = 160
    mjcf_path = ASSETS / "floating_mount.xml"
    attachments = (Attachment(PandaHand, at="root", quat=(0.0, 1.0, 0.0, 0.0)),)
    #: The mount's slides and hinges: stiff enough to hold the hand against contact forces
    #: (ManiSkill's kp 1000, kv 100). The mount is a fixture, not a motor, so its drives
    #: have no effort limit: a clamped drive's damping is integrated explicitly, and on
    #: the hand's small inertia about the hinges ManiSkill's 100 N*m limit left the mount
    #: cycling between its limits at coarse steps (docs/timestep.md).
    actuators = (PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2),)
    #: pd_ee_pose's box is computed on the model at build: the TCP is 0.1034 m from the
    #: hinges' common point, so +-1.1034 m.
    parts = (mount_arm("panda_hand_tcp"),)
    keyframes = {
        "rest": Keyframe(qpos={"root_.*": 0.0}),
        "closed": Keyframe(qpos={"root_.*": 0.0, "panda_finger_joint1": 0.0}),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "EE_MODES",
    "FloatingPandaGripper",
    "Panda",
    "PandaArm",
    "PandaHand",
    "PandaStick",
    "PandaTouch",
    "PandaWristCam",
]
