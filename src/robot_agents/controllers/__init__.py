"""Controllers: frozen configs a robot declares, and the small objects they build."""

from robot_agents.controllers.base import Controller, ControllerConfig, JointBinding
from robot_agents.controllers.combined import CombinedController
from robot_agents.controllers.joint import (
    PDJointPosConfig,
    PDJointPosMimicConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
)
from robot_agents.controllers.passive import PassiveConfig
from robot_agents.controllers.rules import JointGroup, combine_parts, joint_control_modes

__all__ = [
    "CombinedController",
    "Controller",
    "ControllerConfig",
    "JointBinding",
    "JointGroup",
    "PDJointPosConfig",
    "PDJointPosMimicConfig",
    "PDJointPosVelConfig",
    "PDJointVelConfig",
    "PassiveConfig",
    "combine_parts",
    "joint_control_modes",
]
