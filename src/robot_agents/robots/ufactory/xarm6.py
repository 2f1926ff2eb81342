"""UFactory xArm6 robots.

Sources of the numbers:
- Kinematics: UFactory's published standard DH table of the xArm6 (d1 0.267, a2
  0.28948866 with the -1.3849179 rad / +1.3849179 rad joint 2 / joint 3 offsets, a3
  0.0775, d4 0.3425, a5 0.076, d6 0.097 m), written as the joint origins of UFactory's
  public ``xarm_description`` (joint1..joint6, link_base, link1..link6, link_eef).
- Joint ranges: the xArm6 datasheet (J1, J4, J6 +-360 deg; J2 -118..120 deg; J3
  -225..11 deg; J5 -97..180 deg); maximum joint speed 180 deg/s (3.14 rad/s, also the
  URDF's velocity limit). ManiSkill's xArm6 URDFs (haosulab/ManiSkill-XArm6 v0.1.1,
  commit 438e7e4) have the same ranges but J3's lower end, -3.8 rad (-217.7 deg; ours
  -3.927 rad as the datasheet and UFactory's ``xarm6.urdf.xacro``).
- Torques: the effort limits of ``xarm_description`` (50, 50, 32, 32, 32, 20 N*m).
- Inertials: ``xarm_description``'s default link parameters of the xArm6
  (``xarm6_type6_HT_BR2.yaml``: 2.3814, 2.2675, 1.875, 1.3192, 1.33854, 0.17 kg, with
  centres of mass and inertia tensors; base 2.7 kg), read as data: 12.05 kg in all
  (datasheet: 12.2 kg).
- Armature: 0.1 kg*m^2 per joint, the value MuJoCo Menagerie's xArm7 model gives the
  same UFactory joint modules (UFactory publishes no gear ratios or rotor inertias).
- Gains (our choice, by joint size as in Menagerie's xArm7): kp = 1500 / 1000 / 800
  N*m/rad on joints 1-2 / 3-5 / 6, kv = kp / 10, on top of exact gravity compensation.
  They hold every keyframe to < 1e-6 rad and settle a 0.1 rad step within ~0.25 s
  (tests/test_ur_xarm.py). ManiSkill's xarm6_nogripper uses kp 1000, kv 50.
- Keyframes: ManiSkill's ``rest``, ``zeros``, ``stretch_j1`` and ``stretch_j6``. Its
  ``stretch_j3`` (joint 3 at +pi/2) lies outside joint 3's range (-225..11 deg), and its
  ``stretch_j2``, ``stretch_j4`` and ``stretch_j5`` put the arm into itself (the folded
  forearm or the flange against the base column); they are left out.
- Wrist camera (``xarm6_nogripper_wristcam``): placed as ManiSkill's public
  ``xarm6_nogripper.urdf`` does (haosulab/ManiSkill-XArm6 v0.1.1, commit 438e7e4,
  ``camera_link_joint``: xyz (0.05, 0, 0), rpy (pi, 0, pi/2) on link6; re-read
  2026-11-29, tests/test_peer_assets.py): ``camera_link`` 0.05 m along the flange's x
  axis, turned (roll pi, yaw pi/2), the camera 0.05 m in front of it, looking out of the
  flange (link6 +z) with the image's up along link6 +y. The housing is an Intel RealSense D435 (90 x 25
  x 25 mm, 72 g; Intel D400 datasheet) around that camera as its colour camera
  (realsense2_description: 32.5 mm from the housing's centre, 4.3 mm behind its front),
  on a bracket of our own (30 g, an estimate) on the flange face.
- ``xarm6_robotiq``: ManiSkill's ``xarm6_robotiq`` (uid, ``rest`` keyframe, 11 modes) with
  our Robotiq 2F-85 piece (robot_agents/robots/robotiq/robotiq.py, its sources there)
  composed at load. Flange adapter: the 2F-85's own coupling plate (the piece's root
  ``base_mount``) on the flange face, as UFactory's ``xarm_description`` mounts tools:
  every end tool's root on ``link_eef`` = ``link6`` with no offset
  (``xarm_device_macro.xacro``, ``joint_eef`` origin 0); the xArm's tool flange is an
  ISO 9409-1-50-4-M6 pattern, which Robotiq's 2F-85 coupling for that pattern fits with
  no further plate. The fingers close along the flange's y axis (our choice: UFactory's
  camera stand holds the camera on the flange's x axis, which then sees both fingers). ManiSkill's
  ``zeros``, ``stretch_j1`` and ``stretch_j6`` are left out: the gripper would stand
  43 mm into the floor.
- Wrist camera (``xarm6_robotiq_wristcam``): UFactory's RealSense D435i on the xArm camera
  stand (``xarm_description/urdf/camera/realsense_d435i.urdf.xacro``, read as data):
  ``camera_link`` at (0.06746, -0.0175, 0.0237) m on ``link_eef``, rpy (pi, -pi/2, 0), the
  colour frame on it; the camera itself as ManiSkill's xarm6_robotiq_wristcam
  (``hand_camera``, 128 x 128, 90 deg field of view, near 0.01, far 100). (ManiSkill's
  ``xarm6_robotiq.urdf``, same commit, keeps the bare arm's ``camera_link``: the camera
  at (0.05, 0, 0.05) m on link6, looking along the gripper beside its housing.) Housing layout
  from realsense2_description; the stand's shape and 40 g are our estimate.
- Composition: :class:`XArm6` is the arm up to its flange body ``link_eef`` (= link6: the
  flange face, z out of it). A tool is attached there and the arm part re-pointed to the
  tool's TCP with :func:`with_tool` (see :class:`XArm6NoGripperWristCam` for a piece on
  the flange).
"""

from __future__ import annotations

import dataclasses
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
from robot_agents.parts.declaration import Arm, EndEffector
from robot_agents.registry import register_agent
from robot_agents.robots.robotiq import robotiq
from robot_agents.sensors import CameraConfig

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 7))
#: The flange body: tools are attached here (z out of the flange face).
FLANGE = "link_eef"

#: PD servos by joint size (kp N*m/rad, kv N*m*s/rad), the URDF's torque limits, 180 deg/s.
XARM6_DRIVES = PDActuator(
    joints="joint[1-6]",
    stiffness=(1500.0, 1500.0, 1000.0, 1000.0, 1000.0, 800.0),
    damping=(150.0, 150.0, 100.0, 100.0, 100.0, 80.0),
    effort_limit=(50.0, 50.0, 32.0, 32.0, 32.0, 20.0),
    velocity_limit=math.pi,
    armature=0.1,
)

#: End-effector commands: ManiSkill's delta bounds (10 cm, 0.1 rad per step); absolute
#: positions bounded by a box around the flange's reach (0.76 m from joint 2 at
#: z = 0.267 m; datasheet reach 700 mm).
XARM6_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-0.8, -0.8, -0.5), upper=(0.8, 0.8, 1.1)),
    max_translation=0.1,
    max_rotation=0.1,
)
#: The arm part; its end effector is the flange until a tool is attached.
XARM6_ARM = Arm(
    name="arm",
    joints="joint[1-6]",
    end_effectors=(EndEffector(FLANGE, name="flange"),),
    task_space=XARM6_TASK_SPACE,
    max_delta=0.1,
)

#: ManiSkill's keyframes (radians), less those outside the joint ranges or in self-contact.
XARM6_KEYFRAMES = {
    "rest": Keyframe(
        qpos={"joint[1-6]": (1.56280772e-03, -1.10912404, -9.71343926e-02, 1.52969832e-04, 1.20606723, 1.66234924e-03)}
    ),
    "zeros": Keyframe(qpos={"joint[1-6]": 0.0}),
    "stretch_j1": Keyframe(qpos={"joint[1-6]": (math.pi / 2, 0.0, 0.0, 0.0, 0.0, 0.0)}),
    "stretch_j6": Keyframe(qpos={"joint[1-6]": (0.0, 0.0, 0.0, 0.0, 0.0, math.pi / 2)}),
}


def with_tool(tcp: str, pos: Sequence[float] = (0.0, 0.0, 0.0), length: float = 0.0) -> tuple[Arm]:
    """The arm part with its end effector moved to a tool's TCP (a body or site of the
    tool, with an optional offset ``pos`` in its frame, m). ``length``: how far the TCP
    lies from the flange (m); the ``pd_ee_pose`` bounds grow by it on every side, since
    the tool reaches that much farther than the flange."""
    tool = EndEffector(tcp, name="tcp", pos=(float(pos[0]), float(pos[1]), float(pos[2])))
    arm = dataclasses.replace(XARM6_ARM, end_effectors=(tool,))
    if length:
        bounds = XARM6_TASK_SPACE.position_bounds
        grown = WorkspaceBox(
            lower=(bounds.lower[0] - length, bounds.lower[1] - length, bounds.lower[2] - length),
            upper=(bounds.upper[0] + length, bounds.upper[1] + length, bounds.upper[2] + length),
        )
        arm = dataclasses.replace(arm, task_space=dataclasses.replace(XARM6_TASK_SPACE, position_bounds=grown))
    return (arm,)


class XArm6(Agent):
    """The xArm6 arm up to its flange ``link_eef`` (a piece to mount tools on).

    qpos order: ``joint1``..``joint6`` (base to wrist).
    """

    mjcf_path = ASSETS / "xarm6.xml"
    actuators = (XARM6_DRIVES,)
    parts = (XARM6_ARM,)
    keyframes = XARM6_KEYFRAMES
    default_control_mode = "pd_joint_delta_pos"


@register_agent()
class XArm6NoGripper(XArm6):
    """UFactory xArm6 with a bare flange; its end effector ``flange`` is ``link_eef``."""

    uid = "xarm6_nogripper"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23 and 2026-11-28, 20 Hz
    #: control, every step; docs/timestep.md): every claim holds from 2 ms (500 Hz) down
    #: to 1 ms (the wrist-camera variant from 400 Hz); at 400 Hz a wrist drive (kv 100, 32
    #: N*m, 0.1 kg*m^2 armature: kv * dt / I 1.6-1.8 at 2 ms) is left in a torque-limit
    #: cycle (settle 0.34 rad/s). 500 Hz has no margin: default one tried step finer, 640
    #: Hz (margin: 1.5625 ms against 2 ms; 800 Hz until 640 Hz joined the sweep's steps,
    #: 2026-11-28), for both variants, above joint 1's cycle bound (599-604 Hz,
    #: ``robot_agents.tuning.cycles``).
    sim_freq: ClassVar[int | None] = 640


class RealSenseD435OnStand(Agent):
    """An Intel RealSense D435 housing on a bracket (a piece; its root body is
    ``camera_link``, its camera is declared by the robot)."""

    mjcf_path = ASSETS / "realsense_d435_stand.xml"


#: ``camera_link`` on the flange (ManiSkill's xarm6 URDF: xyz (0.05, 0, 0), rpy (pi, 0, pi/2)).
CAMERA_LINK_POS = (0.05, 0.0, 0.0)
CAMERA_LINK_QUAT = (0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0)
#: The camera in ``camera_link`` (ManiSkill: p (0, 0, -0.05), a quarter turn about y in
#: SAPIEN's x-forward camera axes), in MuJoCo's camera axes (looks along -z, y up): a
#: quarter turn about -z. It looks along link6 +z with the image's up along link6 +y.
WRIST_CAMERA_POS = (0.0, 0.0, -0.05)
WRIST_CAMERA_QUAT = (math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))

HAND_CAMERA = CameraConfig(
    uid="hand_camera",
    mount="camera_link",
    pos=WRIST_CAMERA_POS,
    quat=WRIST_CAMERA_QUAT,
    width=128,
    height=128,
    fovy=90.0,
    near=0.01,
    far=100.0,
)


@register_agent()
class XArm6NoGripperWristCam(XArm6NoGripper):
    """The xArm6 with a RealSense D435 on its flange: camera ``hand_camera`` (128 x 128,
    90 deg vertical field of view) looking out of the flange."""

    uid = "xarm6_nogripper_wristcam"
    attachments: ClassVar[Sequence[Attachment]] = (
        Attachment(RealSenseD435OnStand, at=FLANGE, pos=CAMERA_LINK_POS, quat=CAMERA_LINK_QUAT),
    )
    cameras = (HAND_CAMERA,)


#: ManiSkill's xarm6_robotiq ``rest`` (arm joints, rad; the gripper open).
ROBOTIQ_REST = (0.0, 0.22, -1.23, 0.0, 1.01, 0.0)


def robotiq_keyframe(arm: Sequence[float], driver: float = robotiq.OPEN) -> Keyframe:
    """The arm at ``arm`` (rad) and the gripper's drivers at ``driver`` (rad; closing is
    positive), every linkage joint filled in (the loops are closed by equalities)."""
    return Keyframe(qpos={"joint[1-6]": tuple(float(v) for v in arm), **robotiq.linkage_qpos(driver)})


#: ManiSkill's xarm6_robotiq ``rest`` (which differs from xarm6_nogripper's) and ``rest``
#: with the gripper closed. Its ``zeros``, ``stretch_j1`` and ``stretch_j6`` hold the
#: flange 0.112 m above the base's floor, facing down: the 2F-85 reaches 0.155 m past the
#: flange, so the fingers would stand 43 mm into the floor; the other stretches are left
#: out as for the bare arm.
XARM6_ROBOTIQ_KEYFRAMES = {
    "rest": robotiq_keyframe(ROBOTIQ_REST),
    "closed_rest": robotiq_keyframe(ROBOTIQ_REST, robotiq.CLOSED),
}


@register_agent()
class XArm6Robotiq(XArm6):
    """The xArm6 with a Robotiq 2F-85 on its flange, composed at load: the gripper's
    coupling plate on the flange face, fingers closing along the flange's y axis; end
    effector ``tcp`` = ``robotiq_tcp`` (0.1553 m out of the flange face).

    qpos order: ``joint1``..``joint6``, then the gripper's linkage hinges
    (``right_driver_joint``, ``right_spring_link_joint``, ``right_follower_joint``, then
    the left ones). The gripper action is absolute in every control mode (-1 closes and
    squeezes, +1 opens); only the arm's slice changes with the mode.
    """

    uid = "xarm6_robotiq"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23, 20 Hz control, every
    #: step; docs/timestep.md): every claim holds from 2.5 ms (400 Hz) down to 1 ms (grasp
    #: slip 0.6-1.5 mm), both variants, with the 2F-85's spring links damped as in
    #: Menagerie (0.00125 N*m*s/rad; without it they jittered at 0.10 rad/s at 500 Hz and
    #: the default had to be 1 kHz); at 320 Hz a wrist drive cycles (settle 0.52 rad/s).
    #: Default one tried step finer, 500 Hz (margin: 2 ms against 2.5 ms).
    sim_freq: ClassVar[int | None] = 500
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(robotiq.Robotiq2F85, at=FLANGE),)
    #: ``pd_ee_pose`` bounds: the flange's box grown by the Robotiq's 0.155 m (0.16), so that
    #: every reachable TCP position can be commanded (before, the flange's box: 3 % of the
    #: TCP points of random configurations, out to 0.88 m and up to 1.16 m, were clipped).
    parts = with_tool(robotiq.TCP, length=0.16)
    keyframes = XARM6_ROBOTIQ_KEYFRAMES


class RealSenseD435OnUFactoryStand(Agent):
    """An Intel RealSense D435 on UFactory's xArm camera stand (a piece; root body
    ``camera_stand`` on the flange, camera frame ``camera_link``)."""

    mjcf_path = ASSETS / "realsense_d435_ufactory_stand.xml"


#: The colour camera on ``camera_link`` (ROS axes: x forward, y left, z up) in MuJoCo's
#: camera axes (looks along -z, y up): view = camera_link +x (the flange's +z), image up =
#: camera_link +z (the flange's +x, away from the gripper's axis).
UFACTORY_STAND_CAMERA = CameraConfig(
    uid="hand_camera",
    mount="camera_link",
    quat=FORWARD_X_UP_Z_CAMERA_QUAT,
    width=128,
    height=128,
    fovy=90.0,
    near=0.01,
    far=100.0,
)


@register_agent()
class XArm6RobotiqWristCam(XArm6Robotiq):
    """``xarm6_robotiq`` with a RealSense D435 on UFactory's camera stand: camera
    ``hand_camera`` (128 x 128, 90 deg vertical field of view) 67 mm off the flange's
    axis, looking along the gripper's approach axis at the fingers."""

    uid = "xarm6_robotiq_wristcam"
    attachments = (*XArm6Robotiq.attachments, Attachment(RealSenseD435OnUFactoryStand, at=FLANGE))
    cameras = (UFACTORY_STAND_CAMERA,)


__all__ = [
    "FLANGE",
    "HAND_CAMERA",
    "UFACTORY_STAND_CAMERA",
    "XARM6_ROBOTIQ_KEYFRAMES",
    "RealSenseD435OnStand",
    "RealSenseD435OnUFactoryStand",
    "XArm6",
    "XArm6NoGripper",
    "XArm6NoGripperWristCam",
    "XArm6Robotiq",
    "XArm6RobotiqWristCam",
    "with_tool",
]
