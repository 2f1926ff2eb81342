"""Unitree H1 humanoid (uid ``unitree_h1``). DRAFT."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Arm, Legs, Torso
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

SIDES = ("left", "right")
LEG_PATTERN = "(left|right)_(hip_yaw|hip_roll|hip_pitch|knee|ankle)_joint"
LEFT_ARM_PATTERN = "left_(shoulder_pitch|shoulder_roll|shoulder_yaw|elbow)_joint"
RIGHT_ARM_PATTERN = "right_(shoulder_pitch|shoulder_roll|shoulder_yaw|elbow)_joint"
TORSO_JOINT = "torso_joint"
#: ManiSkill's ``UnitreeH1.body_joints``: the action order of its modes.
MANISKILL_JOINTS = (
    "left_hip_yaw_joint",
    "right_hip_yaw_joint",
    "torso_joint",
    "left_hip_roll_joint",
    "right_hip_roll_joint",
    "left_shoulder_pitch_joint",
    "right_shoulder_pitch_joint",
    "left_hip_pitch_joint",
    "right_hip_pitch_joint",
    "left_shoulder_roll_joint",
    "right_shoulder_roll_joint",
    "left_knee_joint",
    "right_knee_joint",
    "left_shoulder_yaw_joint",
    "right_shoulder_yaw_joint",
    "left_ankle_joint",
    "right_ankle_joint",
    "left_elbow_joint",
    "right_elbow_joint",
)
#: hip pitch, knee, ankle (rad) of ManiSkill's ``standing`` and Menagerie's ``home``.
STANDING_LEG = {"hip_pitch": -0.4, "knee": 0.8, "ankle": -0.4}
PELVIS_HEIGHT = 0.975

KP, KV, ARMATURE = 1000.0, 100.0, 0.1


LKP, LKV, AKP = 10000.0, 100.0, 2000.0


def _drive(pattern: str, effort: float, speed: float, kp: float = KP, kv: float = KV) -> PDActuator:
    return PDActuator(
        joints=pattern, stiffness=kp, damping=kv, effort_limit=effort, velocity_limit=speed, armature=ARMATURE
    )


H1_DRIVES = (
    _drive("(left|right)_hip_(yaw|roll|pitch)_joint", 200.0, 23.0, LKP, LKV),
    _drive("(left|right)_knee_joint", 300.0, 14.0, LKP, LKV),
    _drive("(left|right)_ankle_joint", 40.0, 9.0, AKP, KV),
    _drive(TORSO_JOINT, 200.0, 23.0),
    _drive("(left|right)_shoulder_(pitch|roll)_joint", 40.0, 9.0),
    _drive("(left|right)_(shoulder_yaw|elbow)_joint", 18.0, 20.0),
)
SPEEDS = {"hip_yaw": 23.0, "hip_roll": 23.0, "hip_pitch": 23.0, "knee": 14.0, "ankle": 9.0, "torso": 23.0,
          "shoulder_pitch": 9.0, "shoulder_roll": 9.0, "shoulder_yaw": 20.0, "elbow": 20.0}


def _speed(joint: str) -> float:
    stem = joint.removesuffix("_joint").removeprefix("left_").removeprefix("right_")
    return SPEEDS[stem]


BODY = JointGroup(MANISKILL_JOINTS, max_delta=0.2, max_velocity=tuple(_speed(j) for j in MANISKILL_JOINTS))
H1_MODES: dict[str, ModeConfig] = {mode: {"body": cfg} for mode, cfg in joint_control_modes(BODY).items()}


def _standing() -> Keyframe:
    return Keyframe(
        qpos={
            "(left|right)_hip_pitch_joint": STANDING_LEG["hip_pitch"],
            "(left|right)_knee_joint": STANDING_LEG["knee"],
            "(left|right)_ankle_joint": STANDING_LEG["ankle"],
        },
        base_pos=(0.0, 0.0, PELVIS_HEIGHT),
    )


@register_agent()
class UnitreeH1(Agent):
    uid = "unitree_h1"
    mjcf_path = ASSETS / "h1.xml"
    fix_root_link = False
    gravity_compensation = False
    actuators = H1_DRIVES
    parts = (
        Legs(name="legs", joints=LEG_PATTERN),
        Torso(name="torso", joints=TORSO_JOINT),
        Arm(name="left_arm", joints=LEFT_ARM_PATTERN),
        Arm(name="right_arm", joints=RIGHT_ARM_PATTERN),
    )
    control_modes: ClassVar[Mapping[str, ModeConfig]] = H1_MODES
    default_control_mode = "pd_joint_pos"
    keyframes: ClassVar[Mapping[str, Keyframe]] = {"standing": _standing(), "rest": _standing(), "home": _standing()}
