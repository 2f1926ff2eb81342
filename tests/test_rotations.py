"""robot_agents.kinematics.rotations, checked against independent computations: MuJoCo's
C helpers and compiler, Rodrigues' formula, 4x4 homogeneous matrices."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics.rotations import (
    FORWARD_X_UP_Z_CAMERA_QUAT,
    GL_TO_CV,
    compose_into,
    euler_to_quat,
    look_at_quat,
    look_at_xyaxes,
    matrix_to_quat,
    pose_inverse,
    pose_multiply,
    quat_angle,
    quat_conjugate,
    quat_multiply,
    quat_normalize,
    quat_rotate,
    quat_to_euler,
    quat_to_matrix,
    quat_to_rotvec,
    quat_to_yaw,
    relative_pose,
    relative_pose_into,
    rotation_error,
    rotation_error_into,
    rotvec_to_quat,
    rotvec_to_quat_into,
    yaw_to_quat,
    z_rotation_angle,
    z_rotation_quat,
)


def random_quats(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniformly random unit quaternions, both signs of w."""
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def random_poses(rng: np.random.Generator, n: int) -> np.ndarray:
    return np.concatenate((rng.uniform(-2, 2, (n, 3)), random_quats(rng, n)), axis=1)


def rodrigues(rotvec: np.ndarray) -> np.ndarray:
    """Rotation matrix of one rotation vector: I + sin(t) K + (1 - cos(t)) K^2."""
    angle = np.linalg.norm(rotvec)
    if angle == 0:
        return np.eye(3)
    x, y, z = rotvec / angle
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def mj_matrix(quat: np.ndarray) -> np.ndarray:
    out = np.empty(9)
    mujoco.mju_quat2Mat(out, quat)
    return out.reshape(3, 3)


def homogeneous(pose: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = mj_matrix(pose[3:]), pose[:3]
    return out


def assert_same_rotation(a: np.ndarray, b: np.ndarray, atol: float = 1e-12) -> None:
    """Quaternions ``(..., 4)`` equal up to their sign."""
    sign = np.where(np.sum(a * b, axis=-1, keepdims=True) < 0, -1.0, 1.0)
    np.testing.assert_allclose(a, sign * b, atol=atol)


def rotvecs(rng: np.random.Generator, n: int) -> np.ndarray:
    """Rotation vectors with angles over [0, pi), plus zero, small, tiny and near-pi ones."""
    vectors = rng.normal(size=(n, 3))
    vectors *= (rng.uniform(0, math.pi, n) / np.linalg.norm(vectors, axis=1))[:, None]
    vectors[0] = 0.0
    vectors[1] = [1e-9, 0, 0]
    vectors[2] = [0, -3e-7, 2e-7]
    vectors[3] = [0, 0, math.pi - 1e-9]
    vectors[4] = [1.5e-3, 0, 0]
    vectors[5] = [0, 4e-6, -3e-6]
    return vectors


# ------------------------------------------------------------------ quaternions
def test_quat_to_matrix_matches_mujoco_and_is_a_rotation() -> None:
    quats = random_quats(np.random.default_rng(0), 50)
    matrices = quat_to_matrix(quats)
    assert matrices.shape == (50, 3, 3)
    for quat, matrix in zip(quats, matrices, strict=True):
        np.testing.assert_allclose(matrix, mj_matrix(quat), atol=1e-14)
    np.testing.assert_allclose(
        matrices @ np.swapaxes(matrices, 1, 2), np.broadcast_to(np.eye(3), (50, 3, 3)), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(matrices), 1.0, atol=1e-13)
    np.testing.assert_allclose(quat_to_matrix((1, 0, 0, 0)), np.eye(3))  # a plain tuple works too
    # 90 degrees about z takes x to y.
    np.testing.assert_allclose(
        quat_to_matrix((math.sqrt(0.5), 0, 0, math.sqrt(0.5))) @ [1, 0, 0], [0, 1, 0], atol=1e-15
    )


def test_multiply_conjugate_rotate_agree_with_matrices_and_mujoco() -> None:
    rng = np.random.default_rng(1)
    a, b = random_quats(rng, 40), random_quats(rng, 40)
    vectors = rng.normal(size=(40, 3))
    product = quat_multiply(a, b)
    # a * b applies b first: R(a b) = R(a) R(b).
    np.testing.assert_allclose(quat_to_matrix(product), quat_to_matrix(a) @ quat_to_matrix(b), atol=1e-14)
    np.testing.assert_allclose(quat_to_matrix(quat_conjugate(a)), np.swapaxes(quat_to_matrix(a), 1, 2), atol=1e-14)
    np.testing.assert_allclose(quat_rotate(a, vectors), np.einsum("nij,nj->ni", quat_to_matrix(a), vectors), atol=1e-14)
    for qa, qb, v, ab, av in zip(a, b, vectors, product, quat_rotate(a, vectors), strict=True):
        expected = np.empty(4)
        mujoco.mju_mulQuat(expected, qa, qb)
        np.testing.assert_allclose(ab, expected, atol=1e-14)
        rotated = np.empty(3)
        mujoco.mju_rotVecQuat(rotated, v, qa)
        np.testing.assert_allclose(av, rotated, atol=1e-14)
    # Broadcasting: one quaternion against a batch of vectors.
    np.testing.assert_allclose(quat_rotate(a[0], vectors), vectors @ quat_to_matrix(a[0]).T, atol=1e-14)


def test_quat_normalize_keeps_direction_and_sign() -> None:
    rng = np.random.default_rng(2)
    raw = rng.normal(size=(30, 4)) * rng.uniform(0.01, 100, (30, 1))
    unit = quat_normalize(raw)
    np.testing.assert_allclose(np.linalg.norm(unit, axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(unit * np.linalg.norm(raw, axis=1, keepdims=True), raw, rtol=1e-14)
    np.testing.assert_array_equal(quat_normalize(np.zeros(4)), np.zeros(4))


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("size", [1e-13, 1e-300, 1e200, 1e308])
def test_quat_normalize_gives_a_unit_quaternion_of_any_length(size: float) -> None:
    """Tiny and huge quaternions normalize to unit length in their direction (before,
    a norm under 1e-12 was divided by 1e-12: 1e-13 came back with norm 0.1; 1e200
    overflowed to a zero quaternion with a warning)."""
    direction = np.array([0.5, -0.5, 0.5, 0.5])
    unit = quat_normalize(size * direction / np.abs(direction).max())
    np.testing.assert_allclose(unit, direction, atol=1e-15)


def test_euler_angles_are_intrinsic_xyz_and_round_trip() -> None:
    """``euler_to_quat`` is ``R = Rx(a) Ry(b) Rz(c)`` (MuJoCo's ``"xyz"``, PyTorch3D's
    ``"XYZ"``), and ``quat_to_euler`` inverts it: the angles back within 1e-12 (b within
    +-pi/2), any rotation back to itself, also at gimbal lock (b = +-pi/2)."""
    rng = np.random.default_rng(4)
    angles = rng.uniform((-np.pi, -np.pi / 2, -np.pi), (np.pi, np.pi / 2, np.pi), (200, 3))

    def axis_matrix(axis: int, angle: float) -> np.ndarray:
        c, s = math.cos(angle), math.sin(angle)
        i, j = [(1, 2), (2, 0), (0, 1)][axis]
        m = np.eye(3)
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
        return m

    quats = euler_to_quat(angles)
    for (a, b, c), quat in zip(angles, quats, strict=True):
        expected = axis_matrix(0, a) @ axis_matrix(1, b) @ axis_matrix(2, c)
        np.testing.assert_allclose(quat_to_matrix(quat), expected, atol=1e-14)
        mine = np.empty(4)
        mujoco.mju_euler2Quat(mine, np.array([a, b, c]), "xyz")
        assert min(np.abs(mine - quat).max(), np.abs(mine + quat).max()) < 1e-15
    np.testing.assert_allclose(quat_to_euler(quats), angles, atol=1e-12)
    # Any rotation (random quaternions, both signs) and gimbal lock come back to themselves.
    random = rng.normal(size=(200, 4))
    random /= np.linalg.norm(random, axis=1, keepdims=True)
    locked = euler_to_quat([[0.4, np.pi / 2, -0.3], [-1.0, -np.pi / 2, 2.0], [3.0, np.pi / 2, 3.0]])
    for quat in (random, -random, locked):
        back = euler_to_quat(quat_to_euler(quat))
        assert np.abs(quat_angle(back, quat)).max() < 1e-7
    assert np.all(np.abs(quat_to_euler(random)[:, 1]) <= np.pi / 2)


def test_matrix_to_quat_round_trips_up_to_sign() -> None:
    rng = np.random.default_rng(3)
    quats = random_quats(rng, 200)
    # Also rotations by ~pi (a negative trace: the formula's other branches).
    quats[0], quats[1], quats[2] = [1e-3, 1, 0, 0], [0, 1e-3, -1, 0], [-1e-3, 0, 0.6, 0.8]
    quats[3] = [math.cos(3.1 / 2), 0.0, 0.0, math.sin(3.1 / 2)]
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    back = matrix_to_quat(quat_to_matrix(quats))
    assert np.all(back[:, 0] >= 0)
    assert_same_rotation(back, quats, atol=1e-13)
    # Independent: the matrix of the result is the matrix we started from.
    for quat, original in zip(back, quats, strict=True):
        np.testing.assert_allclose(mj_matrix(quat), mj_matrix(original), atol=1e-13)
    # Any batch shape.
    assert matrix_to_quat(quat_to_matrix(quats[:10]).reshape(2, 5, 3, 3)).shape == (2, 5, 4)
    with pytest.raises(ValueError, match=r"\(\.\.\., 3, 3\)"):
        matrix_to_quat(np.eye(4))


# ------------------------------------------------------------------ rotation vectors
def test_rotvec_round_trip_and_rodrigues() -> None:
    vectors = rotvecs(np.random.default_rng(4), 200)
    quats = rotvec_to_quat(vectors)
    np.testing.assert_allclose(np.linalg.norm(quats, axis=1), 1.0, atol=1e-15)
    np.testing.assert_allclose(quat_to_rotvec(quats), vectors, atol=1e-12)
    np.testing.assert_allclose(quat_to_rotvec(-quats), vectors, atol=1e-12)  # q and -q: one rotation
    for vector, quat in zip(vectors, quats, strict=True):
        np.testing.assert_allclose(quat_to_matrix(quat), rodrigues(vector), atol=1e-14)
        single = np.empty(4)
        rotvec_to_quat_into(single, vector)
        np.testing.assert_allclose(single, quat, atol=1e-12)
    # A turn past pi comes back as the shorter turn the other way.
    past_pi = np.array([0.0, 0.0, math.pi + 0.5])
    np.testing.assert_allclose(quat_to_rotvec(rotvec_to_quat(past_pi)), [0.0, 0.0, 0.5 - math.pi], atol=1e-12)


def test_rotation_error_turns_current_into_target() -> None:
    rng = np.random.default_rng(5)
    target, current = random_quats(rng, 100), random_quats(rng, 100)
    error = rotation_error(target, current)
    assert np.all(np.linalg.norm(error, axis=1) <= math.pi + 1e-12)
    # target = exp(error) * current, about the outer frame's axes.
    assert_same_rotation(quat_multiply(rotvec_to_quat(error), current), target)
    np.testing.assert_allclose(
        quat_to_matrix(rotvec_to_quat(error)) @ quat_to_matrix(current), quat_to_matrix(target), atol=1e-12
    )
    for t, c, e in zip(target, current, error, strict=True):
        single = np.empty(3)
        rotation_error_into(single, t, c)
        np.testing.assert_allclose(single, e, atol=1e-12)
    # Its norm is the angle, also from the matrices: cos(angle) = (trace(Rt Rc^T) - 1) / 2.
    traces = np.trace(quat_to_matrix(target) @ np.swapaxes(quat_to_matrix(current), 1, 2), axis1=1, axis2=2)
    np.testing.assert_allclose(quat_angle(target, current), np.arccos(np.clip((traces - 1) / 2, -1, 1)), atol=1e-7)
    np.testing.assert_allclose(quat_angle(target, -current), np.linalg.norm(error, axis=1), atol=1e-12)


def test_quat_angle_is_accurate_for_tiny_angles() -> None:
    start = random_quats(np.random.default_rng(6), 1)[0]
    for angle in (0.0, 1e-10, 1e-7, 0.3, math.pi - 1e-6):
        turned = quat_multiply(rotvec_to_quat(np.array([0.6, 0.0, 0.8]) * angle), start)
        assert quat_angle(turned, start) == pytest.approx(angle, rel=1e-9, abs=1e-15)
        assert quat_angle(start, -turned) == pytest.approx(angle, rel=1e-9, abs=1e-15)


# ------------------------------------------------------------------ poses
def test_pose_algebra_matches_homogeneous_matrices() -> None:
    rng = np.random.default_rng(7)
    a, b = random_poses(rng, 30), random_poses(rng, 30)
    composed, inverse, relative = pose_multiply(a, b), pose_inverse(a), relative_pose(b, a)
    for pa, pb, ab, ia, ba in zip(a, b, composed, inverse, relative, strict=True):
        np.testing.assert_allclose(homogeneous(ab), homogeneous(pa) @ homogeneous(pb), atol=1e-13)
        np.testing.assert_allclose(homogeneous(ia), np.linalg.inv(homogeneous(pa)), atol=1e-13)
        np.testing.assert_allclose(homogeneous(ba), np.linalg.inv(homogeneous(pa)) @ homogeneous(pb), atol=1e-13)
    identity = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    for both in (pose_multiply(a, inverse), pose_multiply(inverse, a), relative_pose(a, a)):
        np.testing.assert_allclose(both[:, :3], 0.0, atol=1e-14)
        assert_same_rotation(both[:, 3:], np.broadcast_to(identity[3:], (30, 4)), atol=1e-14)


def test_single_pose_helpers_agree_with_batched() -> None:
    rng = np.random.default_rng(8)
    a, b = random_poses(rng, 30), random_poses(rng, 30)
    composed, relative = pose_multiply(a, b), relative_pose(b, a)
    for pa, pb, ab, ba in zip(a, b, composed, relative, strict=True):
        out = np.empty(7)
        compose_into(out, pa, pb)
        np.testing.assert_allclose(out, ab, atol=1e-12)
        relative_pose_into(out, pb, pa)
        np.testing.assert_allclose(out, ba, atol=1e-12)
        # out may be one of the inputs.
        alias = pa.copy()
        compose_into(alias, alias, pb)
        np.testing.assert_allclose(alias, ab, atol=1e-12)
        alias = pb.copy()
        compose_into(alias, pa, alias)
        np.testing.assert_allclose(alias, ab, atol=1e-12)
        alias = pb.copy()
        relative_pose_into(alias, alias, pa)
        np.testing.assert_allclose(alias, ba, atol=1e-12)
        alias = pa.copy()
        relative_pose_into(alias, pb, alias)
        np.testing.assert_allclose(alias, ba, atol=1e-12)


def test_rotation_error_into_with_scratch_gives_the_same_bits() -> None:
    rng = np.random.default_rng(12)
    targets, currents = random_quats(rng, 20), random_quats(rng, 20)
    scratch, with_scratch, without = np.empty(4), np.empty(3), np.empty(3)
    for target, current in zip(targets, currents, strict=True):
        rotation_error_into(without, target, current)
        rotation_error_into(with_scratch, target, current, scratch)
        assert with_scratch.tobytes() == without.tobytes()


# ------------------------------------------------------------------ yaw
def test_yaw_quats_are_rotations_about_z_and_round_trip() -> None:
    rng = np.random.default_rng(13)
    yaws = np.concatenate((rng.uniform(-math.pi, math.pi, 40), [0.0, math.pi / 2, -math.pi / 2, 3.0, -3.0]))
    quats = yaw_to_quat(yaws)
    assert quats.shape == (len(yaws), 4)
    assert yaw_to_quat(0.5).shape == (4,)
    assert yaw_to_quat(np.zeros((2, 3))).shape == (2, 3, 4)
    assert_same_rotation(quats, rotvec_to_quat(yaws[:, None] * np.array([0.0, 0.0, 1.0])))
    np.testing.assert_allclose(quat_to_yaw(quats), yaws, atol=1e-12)
    for yaw, quat in zip(yaws, quats, strict=True):
        np.testing.assert_allclose(z_rotation_quat(float(yaw)), quat, atol=1e-15)
        assert z_rotation_angle(quat) == pytest.approx(yaw, abs=1e-12)
    # beyond half a turn the single-value angle is not wrapped: 2 atan2(z, w)
    assert z_rotation_angle(z_rotation_quat(5.0)) == pytest.approx(5.0, abs=1e-12)


def test_quat_to_yaw_is_the_heading_of_the_rotated_x_axis() -> None:
    quats = random_quats(np.random.default_rng(14), 50)
    x_axes = quat_to_matrix(quats)[:, :, 0]
    np.testing.assert_allclose(quat_to_yaw(quats), np.arctan2(x_axes[:, 1], x_axes[:, 0]), atol=1e-12)
    np.testing.assert_array_equal(quat_to_yaw(-quats), quat_to_yaw(quats))


# ------------------------------------------------------------------ cameras
LOOKS = [
    ((1.0, -0.5, 0.8), (0.2, 0.1, 0.3), (0.0, 0.0, 1.0)),
    ((1.25, -1.0, 0.9), (0.25, 0.0, 0.35), (0.0, 0.0, 1.0)),
    ((3.0, 3.0, 0.7), (3.0, 3.0, 0.0), (1.0, 0.0, 0.0)),  # straight down
    ((0.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),  # along -x: a negative trace
    ((0.0, 0.0, 0.0), (0.0, 2.0, 0.0), (0.0, 0.0, -1.0)),  # upside down
    ((0.2, -0.3, 0.5), (0.1, 0.4, 2.0), (0.0, 1.0, 0.0)),
]


@pytest.mark.parametrize(("eye", "target", "up"), LOOKS)
def test_look_at_views_the_target_with_up_up(
    eye: tuple[float, ...], target: tuple[float, ...], up: tuple[float, ...]
) -> None:
    quat = np.array(look_at_quat(eye, target, up))
    assert quat[0] >= 0 and np.linalg.norm(quat) == pytest.approx(1.0, abs=1e-15)
    rotation = mj_matrix(quat)
    view = np.subtract(target, eye) / np.linalg.norm(np.subtract(target, eye))
    np.testing.assert_allclose(rotation @ [0, 0, -1], view, atol=1e-12)  # the camera looks along its -z
    assert abs(rotation[:, 0] @ up) < 1e-12  # no roll: image x is perpendicular to up
    assert rotation[:, 1] @ up > 0  # up is up in the image
    # The xyaxes of the same camera, compiled by MuJoCo, give the same orientation.
    xyaxes = look_at_xyaxes(eye, target, up)
    np.testing.assert_allclose(xyaxes, np.concatenate((rotation[:, 0], rotation[:, 1])), atol=1e-12)
    spec = mujoco.MjSpec()
    spec.worldbody.add_camera(name="c", pos=list(eye), xyaxes=xyaxes)
    spec.worldbody.add_camera(name="q", pos=list(eye), quat=quat.tolist())
    model = spec.compile()
    assert_same_rotation(model.cam_quat[0], quat, atol=1e-9)
    # OpenCV axes: +z is the view direction, +y points down in the image.
    rotation_cv = rotation @ GL_TO_CV
    np.testing.assert_allclose(rotation_cv[:, 2], view, atol=1e-12)
    assert rotation_cv[:, 1] @ up < 0
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.cam_xmat[1].reshape(3, 3), rotation, atol=1e-12)


def test_look_at_rejects_degenerate_views() -> None:
    for look in (look_at_quat, look_at_xyaxes):
        with pytest.raises(ra.ConfigError, match="my camera: expected distinct points"):
            look((0, 0, 1), (0, 0, 1.0 + 1e-12), where="my camera")
        with pytest.raises(ra.ConfigError, match="parallel to up"):
            look((0, 0, 1), (0, 0, 0))
        with pytest.raises(ra.ConfigError, match="3 finite numbers"):
            look((0, 0), (1, 0, 0))
        with pytest.raises(ra.ConfigError, match="3 finite numbers"):
            look((0, 0, math.nan), (1, 0, 0))


def test_forward_x_up_z_camera_looks_along_link_x_with_image_up_along_link_z() -> None:
    rotation = quat_to_matrix(FORWARD_X_UP_Z_CAMERA_QUAT)  # camera axes in the link frame
    np.testing.assert_allclose(rotation @ [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], atol=1e-12)  # view direction
    np.testing.assert_allclose(rotation @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], atol=1e-12)  # image up
