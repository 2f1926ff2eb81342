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


def assert_camera_on_frame(camera_pose: np.ndarray, frame: np.ndarray) -> None:
    """A camera (MuJoCo pose ``(4, 4)``: it looks along its -z, image up along +y) sits at
    ``frame``'s origin, looking along the frame's x with the image's up along its z (1e-6)."""
    np.testing.assert_allclose(camera_pose[:3, 3], frame[:3, 3], atol=1e-6)
    np.testing.assert_allclose(-camera_pose[:3, 2], frame[:3, 0], atol=1e-6)  # view along x
    np.testing.assert_allclose(camera_pose[:3, 1], frame[:3, 2], atol=1e-6)  # image up along z


def assert_pan_turns_the_view(scene: ra.Scene, camera: int, base: list[int], head: list[int]) -> None:
    """With the base at the origin, panning the head (``head[0]``) by 0.8 rad turns the
    camera's view direction about world z by 0.8 rad (1e-9)."""
    agent = scene.agents[0]
    q = agent.qpos[0].copy()
    q[base], q[head] = 0.0, 0.0
    agent.reset(qpos=q)
    before = -scene.world.camera_poses(camera)[0][:3, 2]
    q[head[0]] = 0.8
    agent.reset(qpos=q)
    after = -scene.world.camera_poses(camera)[0][:3, 2]
    np.testing.assert_allclose(after, axis_rotation((0.0, 0.0, 1.0), 0.8) @ before, atol=1e-9)
