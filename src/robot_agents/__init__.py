"""robot_agents: define a robot once, use it in any MuJoCo task.

Quick tour::

    import robot_agents as ra
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_delta_pos")
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from __future__ import annotations

from robot_agents.gl_backend import configure as _configure_gl

# Before anything imports mujoco, which reads MUJOCO_GL once: without a display,
# EGL if it works here, else OSMesa (see robot_agents.gl_backend).
_configure_gl()

from robot_agents.actuators import (
    DCMotorActuator,
    DerivedActuators,
    FileActuators,
    MotorActuator,
    PDActuator,
    PIDActuator,
    VelocityActuator,
)
from robot_agents.agent import Agent
from robot_agents.controllers import (
    CommandFrame,
    FloatingMountTaskSpace,
    JointEffortConfig,
    JointGroup,
    MeasuredTaskSpace,
    PassiveConfig,
    PDBaseVelConfig,
    PDEEPosConfig,
    PDEEPoseConfig,
    PDJointPosConfig,
    PDJointPosMimicConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
    RotationFormat,
    TaskSpace,
    WorkspaceBox,
    combine_parts,
    ee_control_modes,
    joint_control_modes,
    modes_from_parts,
)
from robot_agents.envs import RobotEnv, make_env
from robot_agents.errors import (
    ActionError,
    ConfigError,
    MediaError,
    ModelError,
    PhysicsError,
    RegistryError,
    RenderError,
    RobotAgentsError,
    StateError,
    UnknownNameError,
)
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics import IKConfig, IKSolver, Kinematics
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.model.scene import Prop
from robot_agents.parts import Arm, Base, Body, EndEffector, Gripper, Hand, Head, Legs, PowerGrasp, Torso
from robot_agents.registry import get_agent, get_piece, list_agents, register_agent, unregister_agent
from robot_agents.sensors import CameraConfig, SegmentationEntry, TouchSensorConfig
from robot_agents.sim import BatchedWorld, Scene

__version__ = "0.1.0"

__all__ = [
    "ActionError",
    "Agent",
    "Arm",
    "Attachment",
    "Base",
    "BatchedWorld",
    "Body",
    "CameraConfig",
    "CommandFrame",
    "CompilerSettings",
    "ConfigError",
    "DCMotorActuator",
    "DerivedActuators",
    "EndEffector",
    "FileActuators",
    "FloatingMountTaskSpace",
    "FrictionMaterial",
    "Gripper",
    "Hand",
    "Head",
    "IKConfig",
    "IKSolver",
    "JointEffortConfig",
    "JointGroup",
    "Keyframe",
    "Kinematics",
    "Legs",
    "MeasuredTaskSpace",
    "MediaError",
    "ModelError",
    "MotorActuator",
    "PDActuator",
    "PDBaseVelConfig",
    "PDEEPosConfig",
    "PDEEPoseConfig",
    "PDJointPosConfig",
    "PDJointPosMimicConfig",
    "PDJointPosVelConfig",
    "PDJointVelConfig",
    "PIDActuator",
    "PassiveConfig",
    "PhysicsError",
    "PowerGrasp",
    "Prop",
    "RegistryError",
    "RenderError",
    "RobotAgentsError",
    "RobotEnv",
    "RotationFormat",
    "Scene",
    "SegmentationEntry",
    "StateError",
    "TaskSpace",
    "Torso",
    "TouchSensorConfig",
    "UnknownNameError",
    "VelocityActuator",
    "WorkspaceBox",
    "combine_parts",
    "ee_control_modes",
    "get_agent",
    "get_piece",
    "joint_control_modes",
    "list_agents",
    "make_env",
    "modes_from_parts",
    "register_agent",
    "unregister_agent",
]
