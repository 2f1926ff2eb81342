"""K-Scale Labs' Stompy humanoid (uid ``stompy``, ManiSkill's): 37 joints on a free
torso, two arms ending in two-finger rack-and-pinion grippers, a two-joint head.

DOC_PLACEHOLDER
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.rotations import FORWARD_X_UP_Z_CAMERA_QUAT, quat_multiply
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, Gripper, Head, Legs, Torso
from robot_agents.registry import register_agent
from robot_agents.sensors.camera import CameraConfig

ASSETS = Path(__file__).parent / "assets"

#: ManiSkill's ``Stompy`` joint order (SAPIEN's active joints of the URDF): the action
#: order of every mode, and the order of :data:`STANDING_QPOS`.
MANISKILL_JOINTS = (
    "joint_right_arm_1_x8_1_dof_x8",
    "joint_left_arm_2_x8_1_dof_x8",
    "joint_head_1_x4_1_dof_x4",
    "joint_torso_1_x8_1_dof_x8",
    "joint_right_arm_1_x8_2_dof_x8",
    "joint_left_arm_2_x8_2_dof_x8",
    "joint_legs_1_x8_1_dof_x8",
    "joint_legs_1_x8_2_dof_x8",
    "joint_head_1_x4_2_dof_x4",
    "joint_right_arm_1_x6_1_dof_x6",
    "joint_left_arm_2_x6_1_dof_x6",
    "joint_legs_1_right_leg_1_x8_1_dof_x8",
    "joint_legs_1_left_leg_1_x8_1_dof_x8",
    "joint_right_arm_1_x6_2_dof_x6",
    "joint_left_arm_2_x6_2_dof_x6",
    "joint_legs_1_right_leg_1_x10_2_dof_x10",
    "joint_legs_1_left_leg_1_x10_1_dof_x10",
    "joint_legs_1_right_leg_1_knee_revolute",
    "joint_legs_1_left_leg_1_knee_revolute",
    "joint_right_arm_1_x4_1_dof_x4",
    "joint_left_arm_2_x4_1_dof_x4",
    "joint_legs_1_right_leg_1_x10_1_dof_x10",
    "joint_legs_1_right_leg_1_ankle_revolute",
    "joint_legs_1_left_leg_1_x10_2_dof_x10",
    "joint_legs_1_left_leg_1_ankle_revolute",
    "joint_legs_1_right_leg_1_x6_1_dof_x6",
    "joint_legs_1_left_leg_1_x6_1_dof_x6",
    "joint_legs_1_right_leg_1_x4_1_dof_x4",
    "joint_legs_1_left_leg_1_x4_1_dof_x4",
    "joint_right_arm_1_hand_1_x4_1_dof_x4",
    "joint_left_arm_2_hand_1_x4_1_dof_x4",
    "joint_right_arm_1_hand_1_slider_1",
    "joint_right_arm_1_hand_1_slider_2",
    "joint_left_arm_2_hand_1_slider_1",
    "joint_left_arm_2_hand_1_slider_2",
    "joint_right_arm_1_hand_1_x4_2_dof_x4",
    "joint_left_arm_2_hand_1_x4_2_dof_x4",
)
#: ManiSkill's ``standing`` keyframe qpos, in :data:`MANISKILL_JOINTS` order (rad, m).
#: ``joint_head_1_x4_2_dof_x4``'s 0.5 rad lies past the URDF's upper limit 0.2618 rad
#: (SAPIEN sets it anyway, its limit then pushes it back); ours is the limit.
MANISKILL_STANDING_QPOS = (
    1.5, -1.5, -0.942, 0.0, 1.5, -1.5, -0.25, 0.25, 0.5, 0.65, -0.65, -0.5, -0.5, 0.0, 0.0, -0.5, 0.5,
    0.78, -0.78, 0.25, -0.25, 0.0, -0.2, 0.0, 0.2, 0.0, 0.0, -0.2, 0.2, 0.2, -2.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
)  # fmt: skip
HEAD_PITCH_JOINT = "joint_head_1_x4_2_dof_x4"
#: The URDF's upper limit of :data:`HEAD_PITCH_JOINT` (rad).
HEAD_PITCH_UPPER = 0.26179939
#: ManiSkill's ``standing`` root height (m): the torso link's origin.
STANDING_HEIGHT = 0.965 + 0.007

LEG_PATTERN = r"joint_legs_1_.*"
TORSO_JOINT = "joint_torso_1_x8_1_dof_x8"
HEAD_PATTERN = r"joint_head_1_x4_[12]_dof_x4"
RIGHT_ARM_PATTERN = r"joint_right_arm_1_.*_dof_x[468]"
LEFT_ARM_PATTERN = r"joint_left_arm_2_.*_dof_x[468]"
RIGHT_GRIPPER_PATTERN = r"joint_right_arm_1_hand_1_slider_[12]"
LEFT_GRIPPER_PATTERN = r"joint_left_arm_2_hand_1_slider_[12]"
#: The finger bodies (the sliders' links; each carries the URDF's ``gripper_1`` or
#: ``gripper_2`` link, merged in).
RIGHT_FINGERS = ("link_right_arm_1_hand_1_slide_1", "link_right_arm_1_hand_1_slide_2")
LEFT_FINGERS = ("link_left_arm_2_hand_1_slide_1", "link_left_arm_2_hand_1_slide_2")
#: Slider positions (m): open at the URDF's upper limit 0 (68 mm between the finger
#: boxes), closed at its lower limit -0.034 (the boxes meet).
GRIPPER_OPEN, GRIPPER_CLOSED = 0.0, -0.034

#: ManiSkill's ``pd_joint_pos`` gains: stiffness (N*m/rad, N/m) and damping (N*m*s/rad,
#: N*s/m), ours for the torso, head, arms and grippers.
MANISKILL_KP, MANISKILL_KV = 100.0, 10.0
#: Our leg gains (N*m/rad, N*m*s/rad): with ManiSkill's 100 the robot falls over forwards
#: from ``standing`` within 1 s; see the module doc.
LEG_KP, LEG_KV = 2000.0, 200.0
#: Armature on every joint (kg*m^2; kg on the sliders): an estimate, see the module doc.
ARMATURE = 0.01
#: ManiSkill's ``pd_joint_delta_pos`` bound (rad or m per step).
MANISKILL_DELTA = 0.1
#: The URDF's effort limits per actuator kind (N*m; the sliders N), documented, not applied
#: (ManiSkill's drives are unlimited; see the module doc), and velocity limits (rad/s; the
#: sliders m/s), the bounds of the velocity modes.
URDF_EFFORT = {"x4": 1.5, "x6": 3.0, "x8": 6.0, "x10": 12.0, "knee": 13.9, "ankle": 6.0, "slider": 80.0}
SPEED = {"x4": 31.4, "x6": 31.4, "x8": 31.4, "x10": 31.4, "knee": 31.4, "ankle": 31.4, "slider": 5.0}


def joint_kind(joint: str) -> str:
    """The actuator kind of a Stompy joint (a key of :data:`SPEED`)."""
    if "slider" in joint:
        return "slider"
    if joint.endswith("knee_revolute"):
        return "knee"
    if joint.endswith("ankle_revolute"):
        return "ankle"
    return joint.rsplit("_", 1)[-1]


STOMPY_DRIVES = (
    PDActuator(
        joints=LEG_PATTERN,
        stiffness=LEG_KP,
        damping=LEG_KV,
        velocity_limit=SPEED["x10"],
        armature=ARMATURE,
    ),
    PDActuator(
        joints=f"{TORSO_JOINT}|{HEAD_PATTERN}|{RIGHT_ARM_PATTERN}|{LEFT_ARM_PATTERN}",
        stiffness=MANISKILL_KP,
        damping=MANISKILL_KV,
        velocity_limit=SPEED["x8"],
        armature=ARMATURE,
    ),
    PDActuator(
        joints=f"{RIGHT_GRIPPER_PATTERN}|{LEFT_GRIPPER_PATTERN}",
        stiffness=MANISKILL_KP,
        damping=MANISKILL_KV,
        velocity_limit=SPEED["slider"],
        armature=ARMATURE,
    ),
)

STOMPY_BODY = JointGroup(
    MANISKILL_JOINTS,
    max_delta=MANISKILL_DELTA,
    max_velocity=tuple(SPEED[joint_kind(j)] for j in MANISKILL_JOINTS),
)
STOMPY_MODES: dict[str, ModeConfig] = {
    mode: {"body": config} for mode, config in joint_control_modes(STOMPY_BODY).items()
}

#: ManiSkill's gripper material (static and dynamic friction 2.0) on the fingers.
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)
#: The feet (the bodies carrying the URDF's ``foot_1`` and ``rubber_1`` links): MuJoCo's
#: default friction 1.0, near-rigid contact (``solref`` 5 ms, as PhysX's rigid contacts):
#: ManiSkill's ``standing`` sets the soles 4.3 deg rolled, so the robot lands on their
#: edges; with MuJoCo's default 20 ms the edges sink and the robot rocks (see the module doc).
FOOT_SOLE = FrictionMaterial(sliding=1.0, solref=(0.005, 1.0))
FEET = ("link_legs_1_right_leg_1_x4_1_outer_1", "link_legs_1_left_leg_1_x4_1_outer_1")

#: ManiSkill's ``head_camera``: 0.12 m along ``link_head_1_head_1``'s x and 0.02 m along
#: its z, turned ``euler2quat(-pi/2, 0, 0)`` (about x) in SAPIEN's camera axes (x
#: forward, z up); 128 x 128, field of view 1.57 rad, near 0.01 m, far 100 m.
_HEAD_CAMERA_QUAT = quat_multiply((math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0), FORWARD_X_UP_Z_CAMERA_QUAT)
HEAD_CAMERA = CameraConfig(
    uid="head_camera",
    mount="link_head_1_head_1",
    pos=(0.12, 0.0, 0.02),
    quat=tuple(float(v) for v in _HEAD_CAMERA_QUAT),  # type: ignore[arg-type]
    width=128,
    height=128,
    fovy=math.degrees(1.57),
    near=0.01,
    far=100.0,
)


def standing_keyframe() -> Keyframe:
    """ManiSkill's ``standing``: the torso link 0.965 m up, level, the joints as
    :data:`MANISKILL_STANDING_QPOS` (the head pitch at its limit)."""
    qpos = dict(zip(MANISKILL_JOINTS, MANISKILL_STANDING_QPOS, strict=True))
    qpos[HEAD_PITCH_JOINT] = min(qpos[HEAD_PITCH_JOINT], HEAD_PITCH_UPPER)
    return Keyframe(qpos=qpos, base_pos=(0.0, 0.0, STANDING_HEIGHT))


@register_agent()
class Stompy(Agent):
    """K-Scale Labs' Stompy: legs, torso, head, two arms and two grippers (37 joints) on
    a free torso. Actions follow ManiSkill's joint order (:data:`MANISKILL_JOINTS`)."""

    uid = "stompy"
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "stompy.xml"
    fix_root_link = False
    gravity_compensation = False
    disable_self_collisions = True
    actuators = STOMPY_DRIVES
    parts = (
        Legs(name="legs", joints=LEG_PATTERN, max_delta=MANISKILL_DELTA),
        Torso(name="torso", joints=TORSO_JOINT, max_delta=MANISKILL_DELTA),
        Head(name="head", joints=HEAD_PATTERN, max_delta=MANISKILL_DELTA),
        Arm(name="right_arm", joints=RIGHT_ARM_PATTERN, max_delta=MANISKILL_DELTA),
        Arm(name="left_arm", joints=LEFT_ARM_PATTERN, max_delta=MANISKILL_DELTA),
        Gripper(
            name="right_gripper",
            joints=RIGHT_GRIPPER_PATTERN,
            open=GRIPPER_OPEN,
            closed=GRIPPER_CLOSED,
            fingers=RIGHT_FINGERS,
            tolerance=0.002,
        ),
        Gripper(
            name="left_gripper",
            joints=LEFT_GRIPPER_PATTERN,
            open=GRIPPER_OPEN,
            closed=GRIPPER_CLOSED,
            fingers=LEFT_FINGERS,
            tolerance=0.002,
        ),
    )
    control_modes: ClassVar[Mapping[str, ModeConfig]] = STOMPY_MODES
    default_control_mode = "pd_joint_pos"
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {
        **{name: FINGER_PAD for name in (*RIGHT_FINGERS, *LEFT_FINGERS)},
        **{name: FOOT_SOLE for name in FEET},
    }
    cameras = (HEAD_CAMERA,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "standing": standing_keyframe(),
        "rest": standing_keyframe(),
    }


__all__ = [
    "MANISKILL_JOINTS",
    "MANISKILL_STANDING_QPOS",
    "STANDING_HEIGHT",
    "Stompy",
    "joint_kind",
]
