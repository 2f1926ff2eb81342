"""Trossen Robotics WidowX AI (``widowxai``, ``widowxai_wristcam``).

Sources of the numbers:
- Kinematics, joint and link names, joint ranges, masses, centres of mass and inertias:
  MuJoCo Menagerie's ``trossen_wxai/wxai_follower.xml`` (derived from Trossen's URDF),
  equal to Trossen's own MuJoCo model ``trossen_arm_mujoco/assets/wxai/wxai_base.xml``
  (github TrossenRobotics/trossen_arm_mujoco) for the arm, the carriages at
  (0.0865, +-0.023, 0) m on ``link_6`` and the tool point 0.156 m along it. Trossen's
  URDF (``trossen_arm_description/urdf/wxai.urdf.xacro``) gives the carriage travel
  (0..0.044 m) and speed (0.0875 m/s). See ``assets/wxai.xml``.
- Drives (Trossen's ``wxai_base.xml``): position servos kp = 200 / 200 / 200 / 100 / 50 /
  50 N*m/rad, kv = 10 / 10 / 10 / 5 / 5 / 5 N*m*s/rad, torque limits 27 N*m (joints 0-2)
  and 7 N*m (joints 3-5), armature 0.032 kg*m^2 (joints 0-2) and 0.0018 kg*m^2 (joints
  3-5), friction 0.1 N*m; the gripper drives ``left_carriage_joint`` (kp = 1000 N/m,
  kv = 50 N*s/m, 400 N) and the right carriage follows through a joint equality; both
  carriages carry 0.1 kg of armature and 0.1 N of friction (set in ``wxai.xml``). Joint speed limit pi rad/s (Trossen's URDF).
- Link contacts (ours, not from a source): the links are rigid aluminium and plastic, so
  contacts between them use a 4 ms time constant (``widowx_rigid`` in
  ``assets/widowx_defaults.xml``: four physics steps at the 1 kHz default) instead of
  MuJoCo's 20 ms, under which the 27 N*m shoulder drives pressed the gripper 33 mm into
  the base link (1.9 mm now; ``tests/test_widowx.py``).
- Keyframes: ``ready_to_grasp`` is ManiSkill 3.0.1's (``widowxai.py``), the gripper
  0.026 m open per carriage; ``home`` is Trossen's (every joint at zero: the arm
  folded), with the gripper open.
- Wrist camera (``widowxai_wristcam``): an Intel RealSense D405 on Trossen's camera
  mount, a piece (``assets/realsense_d405_mount.xml``) fixed to ``link_6`` 0.012 m along
  its x axis, ``camera_link`` pitched 20 deg down towards the fingers (Menagerie's
  ``wxai_follower.xml``; Trossen's URDF mounts the D405 at 20 deg about y). The camera
  ``wrist_camera`` looks along ``camera_link``'s x axis with z up (ManiSkill's uid and
  mount: ``camera_link``, 128 x 128, 90 deg field of view, near 0.01 m, far 100 m).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.rotations import FORWARD_X_UP_Z_CAMERA_QUAT
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, EndEffector, Gripper
from robot_agents.registry import register_agent
from robot_agents.sensors import CameraConfig

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = tuple(f"joint_{i}" for i in range(6))
ARM_PATTERN = "joint_[0-5]"
CARRIAGE_PATTERN = "left_carriage_joint|right_carriage_joint"

#: The arm's drives (Trossen's MuJoCo model of the WidowX AI).
WXAI_ARM_DRIVES = PDActuator(
    joints=ARM_PATTERN,
    stiffness=(200.0, 200.0, 200.0, 100.0, 50.0, 50.0),
    damping=(10.0, 10.0, 10.0, 5.0, 5.0, 5.0),
    effort_limit=(27.0, 27.0, 27.0, 7.0, 7.0, 7.0),
    velocity_limit=math.pi,
    armature=(0.032, 0.032, 0.032, 0.0018, 0.0018, 0.0018),
    friction=0.1,
)
#: The gripper's drive on the left carriage; the right one follows through the equality.
WXAI_GRIPPER_DRIVE = PDActuator(
    joints="left_carriage_joint",
    stiffness=1000.0,
    damping=50.0,
    effort_limit=400.0,
    velocity_limit=0.0875,
)

#: One action for both carriages: -1 closes 5 mm past contact of the pads (squeezes), +1
#: opens them 88 mm apart.
WXAI_GRIPPER = Gripper(
    name="gripper",
    joints=CARRIAGE_PATTERN,
    open=0.044,
    closed=0.0,
    squeeze=0.005,
    fingers=(("carriage_left", "gripper_left"), ("carriage_right", "gripper_right")),
)
#: ManiSkill's gripper material for the WidowX AI (static and dynamic friction 2.0).
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)

#: End-effector commands: 5 cm and 0.1 rad per step; absolute positions within a box
#: around the reach (upper arm 0.264 m, forearm 0.25 m, wrist to tip 0.25 m).
WXAI_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-0.8, -0.8, -0.5), upper=(0.8, 0.8, 0.9)),
    max_translation=0.05,
    max_rotation=0.1,
)
WXAI_ARM = Arm(
    name="arm",
    joints=ARM_PATTERN,
    end_effectors=(EndEffector("ee_gripper_link", name="tcp"),),
    task_space=WXAI_TASK_SPACE,
)

READY_TO_GRASP = (0.0, 1.38, 1.04, -1.26, 0.0, 0.0)


@register_agent()
class WidowXAI(Agent):
    """Trossen Robotics WidowX AI: 6-DoF arm and a parallel gripper on two carriages.

    qpos order: ``joint_0`` .. ``joint_5``, ``right_carriage_joint``,
    ``left_carriage_joint`` (model order; the right carriage follows the left).
    """

    uid = "widowxai"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py widowxai widowxai_wristcam``,
    #: 2026-11-23 22:27 UTC, 20 Hz control, random-action seeds 0-2; see
    #: docs/timestep.md): every claim holds at 800 Hz and 1 kHz (and at 200 Hz, where no
    #: seed happened to enter the cycle below); at 320-640 Hz and 160 Hz joint 5 (wrist
    #: roll: Trossen's kv 5 N*m*s/rad and 7 N*m limit on 0.0018 kg*m^2 of armature plus
    #: ~0.001 of link, kv * dt / I = 3.4 at 2 ms) is left in a torque-limit cycle after
    #: random actions (settle 2.4-2.7 rad/s); the analysis puts the cycle below 948 Hz.
    #: Trossen's model gives these gains and armature and no rotor data exists to replace
    #: them, so the step is finer instead: one tried step finer than 800 Hz and above the
    #: cycle bound, 1 kHz (kv * dt / I = 1.7 there). The wrist-camera variant (its mount
    #: adds to the wrist's inertia; cycle bound 868 Hz) held every claim at 1 kHz only
    #: (800 Hz: settle 0.28 rad/s); with the settle claim asking the robot to stay where
    #: it is (2026-11-28 sweep) it holds them at 800 Hz-1 kHz, 500, 320 and 160 Hz; joint
    #: 5 cycles at 400 and 200 Hz (3.3 and 2.1 rad/s) and at 640 Hz random actions push a
    #: joint 0.26 rad past its limit (bound 0.25): it keeps 1 kHz, above the bound. Before the links' contacts were
    #: made stiff (``widowx_rigid``) no step passed: random actions folded the arm until
    #: the gripper sank 33 mm into the base link and the jammed contact jittered
    #: (settle 0.09 rad/s at 1 kHz). Rerun 2026-11-29 21:00 UTC after the arm joints'
    #: limits took a 5 ms time constant (``solreflimit``, wxai.xml): at MuJoCo's 20 ms,
    #: absolute end-effector targets drove joint_3 / joint_4 up to 0.32 rad past a stop
    #: at 1 kHz (0.27 at 2 kHz: the soft limit, not the step), one of ten random-action
    #: seeds over the bound for the wrist-camera variant; now at most 0.048 over seeds
    #: 0-9. Largest passing steps 800 Hz (widowxai) and 500 Hz (the wrist-camera variant,
    #: whose joint 5 cycles at 400 Hz); both keep 1 kHz, above the cycle bounds.
    sim_freq: ClassVar[int | None] = 1000
    mjcf_path = ASSETS / "wxai.xml"
    actuators = (WXAI_ARM_DRIVES, WXAI_GRIPPER_DRIVE)
    parts = (WXAI_ARM, WXAI_GRIPPER)
    link_materials = {"gripper_left": FINGER_PAD, "gripper_right": FINGER_PAD}
    keyframes = {
        "ready_to_grasp": Keyframe(qpos={ARM_PATTERN: READY_TO_GRASP, "left_carriage_joint": 0.026}),
        "home": Keyframe(qpos={ARM_PATTERN: 0.0, "left_carriage_joint": 0.044}),
        # the name every built-in robot has, for tasks that reset to it: the peer's start pose
        "rest": Keyframe(qpos={ARM_PATTERN: READY_TO_GRASP, "left_carriage_joint": 0.026}),
    }
    default_control_mode = "pd_joint_delta_pos"


class RealSenseD405Mount(Agent):
    """Trossen's D405 camera mount with the camera housing (a piece; its camera is
    declared by the robot)."""

    mjcf_path = ASSETS / "realsense_d405_mount.xml"


#: The wrist camera: at ``camera_link``, looking along its x axis, image up along its z.
WRIST_CAMERA = CameraConfig(
    uid="wrist_camera",
    mount="camera_link",
    quat=FORWARD_X_UP_Z_CAMERA_QUAT,
    width=128,
    height=128,
    fovy=90.0,
    near=0.01,
    far=100.0,
)


@register_agent()
class WidowXAIWristCam(WidowXAI):
    """The WidowX AI with an Intel RealSense D405 on its gripper: camera ``wrist_camera``
    (128 x 128, 90 deg vertical field of view) looking past the fingers."""

    uid = "widowxai_wristcam"
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(RealSenseD405Mount, at="link_6", pos=(0.012, 0.0, 0.0)),)
    cameras = (WRIST_CAMERA,)


__all__ = ["RealSenseD405Mount", "WidowXAI", "WidowXAIWristCam"]
