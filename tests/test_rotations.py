"""The one rotation and pose module, against MuJoCo's own helpers and matrix algebra."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics import rotations as rot

RNG = np.random.default_rng(7)


def random_quats(n: int) -> np.ndarray:
    q = RNG.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def mat(q: np.ndarray) -> np.ndarray:
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, q)
    return out.reshape(3, 3)


def test_batched_quaternion_algebra_matches_mujoco() -> None:
    a, b = random_quats(50), random_quats(50)
    product = rot.quat_multiply(a, b)
    for qa, qb, qp in zip(a, b, product, strict=True):
        expected = np.zeros(4)
        mujoco.mju_mulQuat(expected, qa, qb)
        np.testing.assert_allclose(qp, expected, atol=1e-12)
    np.testing.assert_allclose(rot.quat_to_matrix(a), np.stack([mat(q) for q in a]), atol=1e-12)
    vectors = RNG.normal(size=(50, 3))
    np.testing.assert_allclose(
        rot.quat_rotate(a, vectors), np.einsum("nij,nj->ni", rot.quat_to_matrix(a), vectors), atol=1e-12
    )
    np.testing.assert_allclose(
        rot.quat_multiply(a, rot.quat_conjugate(a)), np.tile([1.0, 0, 0, 0], (50, 1)), atol=1e-12
    )


def test_rotation_vectors_round_trip() -> None:
    vectors = RNG.uniform(-1, 1, size=(50, 3)) * 3.0 / np.sqrt(3)  # angles below pi
    quats = rot.rotvec_to_quat(vectors)
    np.testing.assert_allclose(rot.quat_to_rotvec(quats), vectors, atol=1e-9)
    for r, q in zip(vectors, quats, strict=True):  # against MuJoCo's axis-angle
        angle = np.linalg.norm(r)
        expected = np.zeros(4)
        mujoco.mju_axisAngle2Quat(expected, r / angle, angle)
        np.testing.assert_allclose(q, expected, atol=1e-12)


def test_poses_compose_invert_and_relate() -> None:
    poses = np.concatenate([RNG.normal(size=(20, 3)), random_quats(20)], axis=1)
    others = np.concatenate([RNG.normal(size=(20, 3)), random_quats(20)], axis=1)

    def homogeneous(p: np.ndarray) -> np.ndarray:
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = mat(p[3:]), p[:3]
        return out

    composed = rot.pose_multiply(poses, others)
    relative = rot.relative_pose(poses, others)
    for p, o, c, r in zip(poses, others, composed, relative, strict=True):
        np.testing.assert_allclose(homogeneous(c), homogeneous(p) @ homogeneous(o), atol=1e-12)
        np.testing.assert_allclose(homogeneous(r), np.linalg.inv(homogeneous(o)) @ homogeneous(p), atol=1e-12)
        single = np.empty(7)
        rot.compose_into(single, p, o)
        np.testing.assert_allclose(single, c, atol=1e-12)  # the in-place single-pose variant agrees
    identity = rot.pose_multiply(poses, rot.pose_inverse(poses))
    np.testing.assert_allclose(identity[:, :3], 0.0, atol=1e-12)


def test_look_at_points_the_camera_at_its_target() -> None:
    eye, target = np.array([1.0, -0.5, 0.8]), np.array([0.2, 0.3, 0.1])
    axes = rot.look_at_axes(eye, target)
    forward = (target - eye) / np.linalg.norm(target - eye)
    np.testing.assert_allclose(-axes[:, 2], forward, atol=1e-12)  # MuJoCo cameras look along -z
    assert abs(axes[2, 0]) < 1e-12  # image right stays horizontal
    assert axes[2, 1] > 0  # image up points up
    np.testing.assert_allclose(axes.T @ axes, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(mat(np.array(rot.look_at_quat(eye, target))), axes, atol=1e-9)
    np.testing.assert_allclose(rot.look_at_xyaxes(eye, target), [*axes[:, 0], *axes[:, 1]], atol=1e-12)
    with pytest.raises(ra.ConfigError, match="parallel to up"):
        rot.look_at_axes((0, 0, 1), (0, 0, 0))
    with pytest.raises(ra.ConfigError, match="distinct"):
        rot.look_at_axes((0, 0, 1), (0, 0, 1))
