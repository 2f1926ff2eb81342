"""robot_agents: define a robot once, use it in any MuJoCo task.

Quick tour::

    import robot_agents as ra
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_delta_pos")
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from __future__ import annotations

import os
import sys

# Offscreen rendering without a display: prefer EGL unless the user chose a backend.
if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    os.environ.setdefault("MUJOCO_GL", "egl")

from robot_agents.agent import Agent
from robot_agents.controllers import (
    CommandFrame,
    JointGroup,
    PassiveConfig,
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
)
from robot_agents.envs import make_env
from robot_agents.errors import (
    ActionError,
    ConfigError,
    MediaError,
    ModelError,
    RegistryError,
    RobotAgentsError,
    StateError,
    UnknownNameError,
)
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics import IKConfig, IKSolver, Kinematics
from robot_agents.model.materials import FrictionMaterial
from robot_agents.model.scene import Prop
from robot_agents.registry import get_agent, list_agents, register_agent, unregister_agent
from robot_agents.sim import BatchedWorld, Scene

__version__ = "0.1.0"

__all__ = [
    "ActionError",
    "Agent",
    "BatchedWorld",
    "CommandFrame",
    "ConfigError",
    "FrictionMaterial",
    "IKConfig",
    "IKSolver",
    "JointGroup",
    "Keyframe",
    "Kinematics",
    "MediaError",
    "ModelError",
    "PDEEPosConfig",
    "PDEEPoseConfig",
    "PDJointPosConfig",
    "PDJointPosMimicConfig",
    "PDJointPosVelConfig",
    "PDJointVelConfig",
    "PassiveConfig",
    "Prop",
    "RegistryError",
    "RobotAgentsError",
    "RobotEnv",
    "RotationFormat",
    "Scene",
    "StateError",
    "TaskSpace",
    "UnknownNameError",
    "WorkspaceBox",
    "combine_parts",
    "ee_control_modes",
    "get_agent",
    "joint_control_modes",
    "list_agents",
    "make_env",
    "register_agent",
    "unregister_agent",
]
