"""Parts of a robot (arm, gripper, hand, head, torso, base, legs) and their roles."""

from robot_agents.parts.declaration import (
    Arm,
    Base,
    Body,
    EndEffector,
    Gripper,
    Hand,
    Head,
    Legs,
    Part,
    PartKind,
    PowerGrasp,
    Torso,
)
from robot_agents.parts.grasp import grasped

__all__ = [
    "Arm",
    "Base",
    "Body",
    "EndEffector",
    "Gripper",
    "Hand",
    "Head",
    "Legs",
    "Part",
    "PartKind",
    "PowerGrasp",
    "Torso",
    "grasped",
]
