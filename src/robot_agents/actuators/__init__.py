"""Drives: actuator declarations per joint pattern, their MjSpec edits, and the stage
that turns joint targets into MuJoCo controls."""

from robot_agents.actuators.config import (
    ActuatorConfig,
    DCMotorActuator,
    DerivedActuators,
    FileActuators,
    MotorActuator,
    PDActuator,
    PIDActuator,
    VelocityActuator,
)
from robot_agents.actuators.drives import DriveOverride, Drives, JointTargets
from robot_agents.actuators.gains import SuggestedGains, gains_from_inertia
from robot_agents.actuators.spec import DriveDeclaration, DriveKind

__all__ = [
    "ActuatorConfig",
    "DCMotorActuator",
    "DerivedActuators",
    "DriveDeclaration",
    "DriveKind",
    "DriveOverride",
    "Drives",
    "FileActuators",
    "JointTargets",
    "MotorActuator",
    "PDActuator",
    "PIDActuator",
    "SuggestedGains",
    "VelocityActuator",
    "gains_from_inertia",
]
