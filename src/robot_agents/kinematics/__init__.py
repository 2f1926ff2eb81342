"""Kinematics without side effects: batched forward kinematics, Jacobians and IK."""

from robot_agents.kinematics.finite_difference import finite_difference_jacobian
from robot_agents.kinematics.forward import FrameKind, FrameRef, Kinematics, resolve_frame
from robot_agents.kinematics.ik import IKSolver, LinearFollowers, linear_followers
from robot_agents.kinematics.ik_config import IKConfig, IKResult

__all__ = [
    "FrameKind",
    "FrameRef",
    "IKConfig",
    "IKResult",
    "IKSolver",
    "Kinematics",
    "LinearFollowers",
    "finite_difference_jacobian",
    "linear_followers",
    "resolve_frame",
]
