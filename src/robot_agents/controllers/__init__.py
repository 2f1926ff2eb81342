"""Controllers: frozen configs a robot declares, and the small objects they build."""

from robot_agents.controllers.base import Controller, ControllerConfig, ControllerContext, JointBinding
from robot_agents.controllers.base_vel import PDBaseVelConfig
from robot_agents.controllers.combined import CombinedController
from robot_agents.controllers.ee import (
    CommandFrame,
    PDEEController,
    PDEEPosConfig,
    PDEEPoseConfig,
    RotationFormat,
)
from robot_agents.controllers.joint import (
    JointEffortConfig,
    PDJointPosConfig,
    PDJointPosMimicConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
)
from robot_agents.controllers.passive import PassiveConfig
from robot_agents.controllers.rules import (
    EE_MODES,
    JointGroup,
    combine_parts,
    ee_control_modes,
    gripper_config,
    joint_control_modes,
    modes_from_parts,
)
from robot_agents.controllers.task_space import FloatingMountTaskSpace, MeasuredTaskSpace, TaskSpace, WorkspaceBox

__all__ = [
    "EE_MODES",
    "CombinedController",
    "CommandFrame",
    "Controller",
    "ControllerConfig",
    "ControllerContext",
    "FloatingMountTaskSpace",
    "JointBinding",
    "JointEffortConfig",
    "JointGroup",
    "MeasuredTaskSpace",
    "PDBaseVelConfig",
    "PDEEController",
    "PDEEPosConfig",
    "PDEEPoseConfig",
    "PDJointPosConfig",
    "PDJointPosMimicConfig",
    "PDJointPosVelConfig",
    "PDJointVelConfig",
    "PassiveConfig",
    "RotationFormat",
    "TaskSpace",
    "WorkspaceBox",
    "combine_parts",
    "ee_control_modes",
    "gripper_config",
    "joint_control_modes",
    "modes_from_parts",
]
