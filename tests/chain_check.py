"""Forward kinematics written out for the robots' tests: a chain of joint origins (a
translation in the parent's frame, no rotation) and joint axes, so a test can check
a model against a public model's numbers without using the model itself."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

import robot_agents as ra

#: A joint of a chain: its origin in the parent link (m) and its unit axis.
ChainJoint = tuple[tuple[float, float, float], np.ndarray]


def axis_rotation(axis: Sequence[float] | np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix ``(3, 3)`` of ``angle`` (rad) about the unit ``axis`` (Rodrigues)."""
    x, y, z = (float(v) for v in axis)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def transform(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Homogeneous transform ``(4, 4)``."""
    result = np.eye(4)
    result[:3, :3], result[:3, 3] = rotation, position
    return result


def chain(pose: np.ndarray, joints: Sequence[ChainJoint], q: Sequence[float] | np.ndarray) -> np.ndarray:
    """``pose`` ``(4, 4)`` carried through each joint: its origin, then its rotation by ``q``."""
    for (origin, axis), angle in zip(joints, q, strict=True):
        pose = pose @ transform(axis_rotation(axis, float(angle)), np.array(origin))
    return pose


def index(agent: ra.Agent, names: Sequence[str]) -> list[int]:
    """Positions of joints ``names`` in the robot's ``qpos``."""
    return [agent.joint_names.index(n) for n in names]
