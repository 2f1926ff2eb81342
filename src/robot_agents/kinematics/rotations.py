"""Rotation and pose arithmetic: the package's one home for quaternions, rotation
matrices, rotation vectors, poses and camera look-at orientations.

Conventions, the same as MuJoCo's:

- a quaternion is ``(w, x, y, z)``, unit norm, shape ``(..., 4)``; ``q`` and ``-q`` are
  the same rotation;
- a rotation matrix acts on column vectors (``v_outer = R @ v_local``): its columns
  are the rotated frame's axes, shape ``(..., 3, 3)``; MuJoCo's ``xmat`` is one
  flattened row by row;
- a rotation vector (axis-angle) is ``angle * axis``, angle in radians, shape ``(..., 3)``;
- a pose is ``(x, y, z, qw, qx, qy, qz)`` (position in metres, then a quaternion),
  shape ``(..., 7)``; it maps points of its own frame into the frame it is expressed in.

Two kinds of functions:

- **Batched** (numpy, vectorized over any leading batch shape, return new arrays):
  :func:`quat_multiply`, :func:`quat_conjugate`, :func:`quat_normalize`,
  :func:`quat_rotate`, :func:`quat_to_matrix`, :func:`rotvec_to_quat`,
  :func:`quat_to_rotvec`, :func:`euler_to_quat`, :func:`quat_to_euler`,
  :func:`quat_angle`, :func:`rotation_error`,
  :func:`pose_multiply`, :func:`pose_inverse`, :func:`relative_pose`. They also take a
  single ``(4,)`` / ``(3,)`` / ``(7,)`` value, but pay numpy's per-call overhead.
- **Single, with MuJoCo's C helpers** (one value at a time; ``*_into`` write into
  ``out`` and allocate at most a few scratch values; for the IK and controller hot
  paths): :func:`matrix_to_quat` (``mju_mat2Quat``, looped over a batch),
  :func:`rotvec_to_quat_into` (``mju_axisAngle2Quat``), :func:`rotation_error_into`
  (``mju_negQuat``, ``mju_mulQuat``, ``mju_quat2Vel``), :func:`compose_into`
  (``mju_mulPose``), :func:`relative_pose_into` (``mju_negPose``, ``mju_mulPose``).
  ``compose_into`` is the single-pose :func:`pose_multiply`, ``relative_pose_into``
  the single-pose :func:`relative_pose`, ``rotation_error_into`` the single-pose
  :func:`rotation_error`.

Yaw (rotations about +z): :func:`yaw_to_quat` and :func:`quat_to_yaw` (batched, numpy);
:func:`z_rotation_quat` and :func:`z_rotation_angle` (one value, Python's ``math``).

Cameras (MuJoCo / OpenGL camera axes: x right, y up, looking along -z):
:func:`look_at_quat`, :func:`look_at_xyaxes` and :data:`GL_TO_CV`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError

FloatArray = npt.NDArray[np.float64]

_TINY = 1e-12

#: OpenGL / MuJoCo camera axes (x right, y up, looking along -z) to OpenCV camera axes
#: (x right, y down, looking along +z): flip y and z. ``R_cv = R_gl @ GL_TO_CV`` for
#: camera-to-world rotations ``(..., 3, 3)``.
GL_TO_CV = np.diag([1.0, -1.0, -1.0])

#: A MuJoCo camera's orientation ``(w, x, y, z)`` in a link with ROS's body axes (x
#: forward, z up): the camera looks along the link's +x (its -z on the link's +x) with
#: image up along the link's +z. How a camera is mounted on a ROS ``camera_link``.
FORWARD_X_UP_Z_CAMERA_QUAT = (0.5, 0.5, -0.5, -0.5)


# -- batched (numpy) -----------------------------------------------------------------------
def quat_multiply(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """Hamilton product ``a * b`` (apply ``b`` first, then ``a``), shape ``(..., 4)``."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack(
        (
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ),
        axis=-1,
    )


def quat_conjugate(q: npt.ArrayLike) -> FloatArray:
    """Conjugate ``(w, -x, -y, -z)``: the inverse of a unit quaternion, shape ``(..., 4)``."""
    out: FloatArray = np.asarray(q, dtype=np.float64) * np.array([1.0, -1.0, -1.0, -1.0])
    return out


def quat_normalize(q: npt.ArrayLike) -> FloatArray:
    """``q / |q|``, shape ``(..., 4)``, for a quaternion of any length (unit norm also for
    ``1e-300`` or ``1e300``); the sign is kept and a zero quaternion stays zero (check the
    norm first where zero is an error)."""
    q = np.asarray(q, dtype=np.float64)
    # Divided by the largest entry first: |q| of a tiny or huge q under- or overflows.
    largest = np.abs(q).max(axis=-1, keepdims=True)
    scaled = q / np.where(largest > 0.0, largest, 1.0)
    out: FloatArray = scaled / np.where(largest > 0.0, np.linalg.norm(scaled, axis=-1, keepdims=True), 1.0)
    return out


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    # Written out: np.cross costs ~20 us of argument handling per call on small arrays.
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def quat_rotate(q: npt.ArrayLike, v: npt.ArrayLike) -> FloatArray:
    """Vectors ``v`` ``(..., 3)`` rotated by unit quaternions ``q`` ``(..., 4)``."""
    q, v = np.asarray(q, dtype=np.float64), np.asarray(v, dtype=np.float64)
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * _cross(u, v)
    out: FloatArray = v + w * t + _cross(u, t)
    return out


def quat_to_matrix(q: npt.ArrayLike) -> FloatArray:
    """Rotation matrices ``(..., 3, 3)`` of unit quaternions ``(..., 4)``."""
    q = np.asarray(q, dtype=np.float64)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        (
            np.stack((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)), axis=-1),
            np.stack((2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)), axis=-1),
            np.stack((2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)), axis=-1),
        ),
        axis=-2,
    )


def rotvec_to_quat(r: npt.ArrayLike) -> FloatArray:
    """Unit quaternions ``(..., 4)`` of rotation vectors ``(..., 3)`` (rad)."""
    r = np.asarray(r, dtype=np.float64)
    angle = np.linalg.norm(r, axis=-1, keepdims=True)
    half = 0.5 * angle
    # sin(half) / angle, with its limit 1/2 - angle^2/48 near zero.
    small = angle < 1e-6
    scale = np.where(small, 0.5 - angle * angle / 48.0, np.sin(half) / np.where(small, 1.0, angle))
    return np.concatenate((np.cos(half), r * scale), axis=-1)


def quat_to_rotvec(q: npt.ArrayLike) -> FloatArray:
    """Rotation vectors ``(..., 3)`` (rad) of unit quaternions ``(..., 4)``, angles in
    ``[0, pi]`` (``q`` and ``-q`` give the same vector)."""
    q = np.asarray(q, dtype=np.float64)
    q = np.where(q[..., :1] < 0.0, -q, q)
    w = q[..., :1]
    v = q[..., 1:]
    sin_half = np.linalg.norm(v, axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(sin_half, w)
    # angle / sin(half) -> 2 / w as the rotation vanishes.
    small = sin_half < 1e-9
    scale = np.where(small, 2.0 / np.maximum(w, _TINY), angle / np.where(small, 1.0, sin_half))
    out: FloatArray = v * scale
    return out


def euler_to_quat(angles: npt.ArrayLike) -> FloatArray:
    """Unit quaternions ``(..., 4)`` of intrinsic x-y-z Euler angles ``(a, b, c)`` (rad,
    ``(..., 3)``): turn ``a`` about x, then ``b`` about the turned y, then ``c`` about
    the twice-turned z, ``R = Rx(a) Ry(b) Rz(c)`` (PyTorch3D's and ManiSkill's ``"XYZ"``,
    MuJoCo's ``eulerseq="xyz"``)."""
    angles = np.asarray(angles, dtype=np.float64)
    half = 0.5 * angles
    cos, sin = np.cos(half), np.sin(half)
    zero = np.zeros(half.shape[:-1])
    x = np.stack((cos[..., 0], sin[..., 0], zero, zero), axis=-1)
    y = np.stack((cos[..., 1], zero, sin[..., 1], zero), axis=-1)
    z = np.stack((cos[..., 2], zero, zero, sin[..., 2]), axis=-1)
    return quat_multiply(quat_multiply(x, y), z)


def quat_to_euler(q: npt.ArrayLike) -> FloatArray:
    """Intrinsic x-y-z Euler angles ``(..., 3)`` (rad) of unit quaternions ``(..., 4)``,
    the inverse of :func:`euler_to_quat`: ``a`` and ``c`` in ``[-pi, pi]``, ``b`` in
    ``[-pi/2, pi/2]``. At gimbal lock (``b = +-pi/2``, where only ``a +- c`` is
    defined) ``c`` is 0."""
    matrix = quat_to_matrix(q)
    # R = Rx(a) Ry(b) Rz(c): R[0, 2] = sin b, R[1, 2] = -sin a cos b, R[2, 2] = cos a cos b,
    # R[0, 1] = -cos b sin c, R[0, 0] = cos b cos c.
    sin_b = np.clip(matrix[..., 0, 2], -1.0, 1.0)
    cos_b = np.hypot(matrix[..., 0, 0], matrix[..., 0, 1])
    locked = cos_b < 1e-9
    a = np.where(
        locked,
        np.arctan2(matrix[..., 2, 1], matrix[..., 1, 1]),
        np.arctan2(-matrix[..., 1, 2], matrix[..., 2, 2]),
    )
    b = np.arctan2(sin_b, cos_b)
    c = np.where(locked, 0.0, np.arctan2(-matrix[..., 0, 1], matrix[..., 0, 0]))
    return np.stack((a, b, c), axis=-1)


def quat_angle(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """Angle (rad, in ``[0, pi]``) of the rotation between unit quaternions ``a`` and
    ``b`` ``(..., 4)``, shape ``(...)``: the norm of :func:`rotation_error`, accurate
    for small angles too."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    b = np.where(np.sum(a * b, axis=-1, keepdims=True) < 0.0, -b, b)
    # With phi the angle between a and b as 4-vectors: |a - b| = 2 sin(phi/2),
    # |a + b| = 2 cos(phi/2), and the rotation angle is 2 phi.
    out: FloatArray = 4.0 * np.arctan2(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))
    return out


def rotation_error(target: npt.ArrayLike, current: npt.ArrayLike) -> FloatArray:
    """Rotation vector ``(..., 3)`` (rad) that turns ``current`` into ``target`` about axes
    of the frame both are expressed in (``target = exp(error) * current``), the shorter
    way round."""
    return quat_to_rotvec(quat_multiply(target, quat_conjugate(current)))


def pose_multiply(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """Composed poses ``a * b`` (``b`` expressed in ``a``'s frame), shape ``(..., 7)``."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    position = a[..., :3] + quat_rotate(a[..., 3:], b[..., :3])
    return np.concatenate((position, quat_multiply(a[..., 3:], b[..., 3:])), axis=-1)


def pose_inverse(a: npt.ArrayLike) -> FloatArray:
    """Inverse poses (``pose_multiply(a, pose_inverse(a))`` is the identity), shape ``(..., 7)``."""
    a = np.asarray(a, dtype=np.float64)
    inverse = quat_conjugate(a[..., 3:])
    return np.concatenate((-quat_rotate(inverse, a[..., :3]), inverse), axis=-1)


def relative_pose(pose: npt.ArrayLike, reference: npt.ArrayLike) -> FloatArray:
    """``pose`` expressed in the frame ``reference`` (both ``(..., 7)`` in the same outer
    frame): ``reference^-1 * pose``."""
    return pose_multiply(pose_inverse(reference), pose)


def quat_to_yaw(q: npt.ArrayLike) -> FloatArray:
    """Heading (rad, in ``[-pi, pi]``) of unit quaternions ``(..., 4)``, shape ``(...)``:
    the angle about +z of the rotated x axis projected onto the xy-plane (the yaw of a
    z-y-x Euler decomposition), ``atan2(2 (w z + x y), 1 - 2 (y^2 + z^2))``."""
    q = np.asarray(q, dtype=np.float64)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out: FloatArray = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y**2 + z**2))
    return out


def yaw_to_quat(yaw: npt.ArrayLike) -> FloatArray:
    """Unit quaternions ``(..., 4)`` ``(cos(yaw/2), 0, 0, sin(yaw/2))`` of rotations by
    ``yaw`` (rad, shape ``(...)``) about +z (NumPy's ``cos`` / ``sin``; one Python float:
    :func:`z_rotation_quat`)."""
    half = np.asarray(yaw, dtype=np.float64) / 2
    zero = np.zeros(half.shape)
    return np.stack((np.cos(half), zero, zero, np.sin(half)), axis=-1)


# -- single values, with Python's math module -----------------------------------------------
def z_rotation_quat(yaw: float) -> FloatArray:
    """Unit quaternion ``(4,)`` ``(cos(yaw/2), 0, 0, sin(yaw/2))`` of one rotation by
    ``yaw`` (rad) about +z, with ``math.cos`` / ``math.sin`` (:func:`yaw_to_quat` is the
    batched form, with NumPy's)."""
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


def z_rotation_angle(quat: Sequence[float] | FloatArray) -> float:
    """Angle (rad, in ``[-2 pi, 2 pi]``) of one rotation about +z given as its unit
    quaternion ``(w, 0, 0, z)`` ``(4,)``: ``2 atan2(z, w)``, the inverse of
    :func:`z_rotation_quat` on ``(-2 pi, 2 pi]``. Ignores ``x`` and ``y``: for any other
    rotation use :func:`quat_to_yaw`."""
    return 2.0 * math.atan2(float(quat[3]), float(quat[0]))


# -- single values, with MuJoCo's C helpers (no numpy per-call overhead) -------------------
def matrix_to_quat(matrix: npt.ArrayLike) -> FloatArray:
    """Unit quaternions ``(..., 4)`` with ``w >= 0`` of rotation matrices ``(..., 3, 3)``,
    one ``mju_mat2Quat`` per matrix."""
    matrices = np.asarray(matrix, dtype=np.float64)
    if matrices.shape[-2:] != (3, 3):
        raise ConfigError(f"matrix_to_quat: expected rotation matrices (..., 3, 3), got shape {matrices.shape}.")
    flat = np.ascontiguousarray(matrices.reshape(-1, 9))
    out = np.empty((flat.shape[0], 4))
    for row, quat in zip(flat, out, strict=True):
        mujoco.mju_mat2Quat(quat, row)
    out[out[:, 0] < 0.0] *= -1.0
    return out.reshape((*matrices.shape[:-2], 4))


def rotvec_to_quat_into(out: FloatArray, rotvec: FloatArray, axis: FloatArray | None = None) -> None:
    """Unit quaternion ``(4,)`` of one rotation vector ``(3,)`` (rad), written into ``out``
    (``axis``: a scratch ``(3,)`` for the unit axis, so hot loops allocate nothing)."""
    angle = math.sqrt(float(rotvec.dot(rotvec)))  # (dot: the same BLAS ddot as @, without its dispatch)
    if angle < 1e-12:
        out[:] = (1.0, 0.0, 0.0, 0.0)
        return
    mujoco.mju_axisAngle2Quat(out, rotvec / angle if axis is None else np.divide(rotvec, angle, out=axis), angle)


def rotation_error_into(
    out: FloatArray, target: FloatArray, current: FloatArray, difference: FloatArray | None = None
) -> None:
    """Rotation vector ``(3,)`` (rad) turning unit quaternion ``current`` into ``target``
    (both ``(4,)``) about the outer frame's axes, the shorter way round, into ``out``
    (``difference``: a scratch ``(4,)``, so hot loops allocate nothing)."""
    if difference is None:
        difference = np.empty(4)
    mujoco.mju_negQuat(difference, current)
    mujoco.mju_mulQuat(difference, target, difference)
    mujoco.mju_quat2Vel(out, difference, 1.0)


def compose_into(out: FloatArray, a: FloatArray, b: FloatArray) -> None:
    """``out = a * b`` for single poses ``(7,)`` (``b`` expressed in ``a``'s frame); the
    quaternion is renormalized. ``out`` may be ``a`` or ``b``."""
    position, quat = np.empty(3), np.empty(4)
    mujoco.mju_mulPose(position, quat, a[:3], a[3:], b[:3], b[3:])
    out[:3] = position
    out[3:] = quat


def relative_pose_into(out: FloatArray, pose: FloatArray, reference: FloatArray) -> None:
    """``out = reference^-1 * pose`` for single poses ``(7,)``: ``pose`` expressed in the
    frame ``reference``. ``out`` may be ``pose`` or ``reference``."""
    inverse = np.empty(7)
    mujoco.mju_negPose(inverse[:3], inverse[3:], reference[:3], reference[3:])
    compose_into(out, inverse, pose)


# -- cameras -------------------------------------------------------------------------------
def _look_at_axes(
    eye: Sequence[float], target: Sequence[float], up: Sequence[float], where: str
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Camera right, up and viewing direction (unit vectors) of a camera at ``eye``
    looking at ``target`` with ``up`` up in the image."""
    try:
        points = [np.asarray(value, dtype=np.float64) for value in (eye, target, up)]
    except (TypeError, ValueError):
        points = []
    if len(points) != 3 or any(p.shape != (3,) or not np.all(np.isfinite(p)) for p in points):
        raise ConfigError(
            f"{where}: expected eye, target and up as 3 finite numbers each, got {eye!r}, {target!r}, {up!r}."
        )
    forward = points[1] - points[0]
    norm = float(np.linalg.norm(forward))
    if norm < 1e-9:
        raise ConfigError(f"{where}: expected distinct points eye and target, got {list(eye)} and {list(target)}.")
    forward /= norm
    right = _cross(forward, points[2])
    length = float(np.linalg.norm(right))
    if length < 1e-9:
        raise ConfigError(f"{where}: the view direction {forward.round(6).tolist()} is parallel to up {list(up)}.")
    right /= length
    return right, _cross(right, forward), forward


def look_at_quat(
    eye: Sequence[float], target: Sequence[float], up: Sequence[float] = (0.0, 0.0, 1.0), where: str = "look_at_quat"
) -> tuple[float, float, float, float]:
    """Orientation ``(w, x, y, z)`` (``w >= 0``) of a MuJoCo camera at ``eye`` looking at
    ``target`` (its -z axis points at it) with ``up`` pointing up in the image (points and
    direction in the mount's frame, metres). ConfigError naming ``where`` if eye and
    target coincide or the view is parallel to ``up``."""
    right, camera_up, forward = _look_at_axes(eye, target, up, where)
    # Columns: camera x (right), y (up), z (backwards: the camera looks along -z).
    w, x, y, z = matrix_to_quat(np.column_stack((right, camera_up, -forward)))
    return (float(w), float(x), float(y), float(z))


def look_at_xyaxes(
    eye: Sequence[float], target: Sequence[float], up: Sequence[float] = (0.0, 0.0, 1.0), where: str = "look_at_xyaxes"
) -> list[float]:
    """MuJoCo camera ``xyaxes`` (its x / right and y / up axes, 6 numbers) of the same
    camera as :func:`look_at_quat`, for an MJCF / MjSpec ``camera`` element."""
    right, camera_up, _ = _look_at_axes(eye, target, up, where)
    return [*right.tolist(), *camera_up.tolist()]
