"""Batched rotation and pose arithmetic (numpy, any leading batch shape).

Conventions, the same as MuJoCo's:
- quaternions are ``(w, x, y, z)``, unit norm, shape ``(..., 4)``;
- a rotation vector (axis-angle) is ``angle * axis`` in radians, shape ``(..., 3)``;
- a pose is ``(x, y, z, qw, qx, qy, qz)``, shape ``(..., 7)``, mapping points of its
  own frame into the frame it is expressed in.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

_TINY = 1e-12


def quat_multiply(a: FloatArray, b: FloatArray) -> FloatArray:
    """Hamilton product ``a * b`` (apply ``b`` first, then ``a``), shape ``(..., 4)``."""
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


def quat_conjugate(q: FloatArray) -> FloatArray:
    """The inverse of a unit quaternion, shape ``(..., 4)``."""
    out: FloatArray = q * np.array([1.0, -1.0, -1.0, -1.0])
    return out


def quat_normalize(q: FloatArray) -> FloatArray:
    """Unit quaternion with ``w >= 0`` (one canonical sign per rotation), shape ``(..., 4)``."""
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    unit = q / np.maximum(norm, _TINY)
    out: FloatArray = np.where(unit[..., :1] < 0.0, -unit, unit)
    return out


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    # Written out: np.cross costs ~20 us of argument handling per call on small arrays.
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def quat_rotate(q: FloatArray, v: FloatArray) -> FloatArray:
    """Rotate vectors ``v`` ``(..., 3)`` by unit quaternions ``q`` ``(..., 4)``."""
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * _cross(u, v)
    out: FloatArray = v + w * t + _cross(u, t)
    return out


def quat_to_matrix(q: FloatArray) -> FloatArray:
    """Rotation matrices ``(..., 3, 3)`` of unit quaternions ``(..., 4)``."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        (
            np.stack((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)), axis=-1),
            np.stack((2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)), axis=-1),
            np.stack((2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)), axis=-1),
        ),
        axis=-2,
    )


def rotvec_to_quat(r: FloatArray) -> FloatArray:
    """Unit quaternions ``(..., 4)`` of rotation vectors ``(..., 3)`` (radians)."""
    angle = np.linalg.norm(r, axis=-1, keepdims=True)
    half = 0.5 * angle
    # sin(half) / angle, with its limit 1/2 - angle^2/48 near zero.
    small = angle < 1e-6
    scale = np.where(small, 0.5 - angle * angle / 48.0, np.sin(half) / np.where(small, 1.0, angle))
    return np.concatenate((np.cos(half), r * scale), axis=-1)


def quat_to_rotvec(q: FloatArray) -> FloatArray:
    """Rotation vectors ``(..., 3)`` of unit quaternions, angles in ``[0, pi]``."""
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


def rotation_error(target: FloatArray, current: FloatArray) -> FloatArray:
    """Rotation vector ``(..., 3)`` that turns ``current`` into ``target`` about axes of
    the frame both are expressed in (``target = exp(error) * current``)."""
    return quat_to_rotvec(quat_multiply(target, quat_conjugate(current)))


def pose_multiply(a: FloatArray, b: FloatArray) -> FloatArray:
    """Compose poses ``a * b`` (``b`` expressed in ``a``'s frame), shape ``(..., 7)``."""
    position = a[..., :3] + quat_rotate(a[..., 3:], b[..., :3])
    return np.concatenate((position, quat_multiply(a[..., 3:], b[..., 3:])), axis=-1)


def pose_inverse(a: FloatArray) -> FloatArray:
    """The inverse pose, shape ``(..., 7)``."""
    inverse = quat_conjugate(a[..., 3:])
    return np.concatenate((-quat_rotate(inverse, a[..., :3]), inverse), axis=-1)


def relative_pose(pose: FloatArray, reference: FloatArray) -> FloatArray:
    """``pose`` expressed in the frame ``reference`` (both in the same outer frame)."""
    return pose_multiply(pose_inverse(reference), pose)


# -- one pose at a time, with MuJoCo's C helpers (no numpy per-call overhead) ---------------
def rotvec_to_quat_into(out: FloatArray, rotvec: FloatArray) -> None:
    """Unit quaternion ``(4,)`` of one rotation vector ``(3,)`` (rad), written into ``out``."""
    angle = math.sqrt(float(rotvec @ rotvec))
    if angle < 1e-12:
        out[:] = (1.0, 0.0, 0.0, 0.0)
        return
    mujoco.mju_axisAngle2Quat(out, rotvec / angle, angle)


def compose_into(out: FloatArray, a: FloatArray, b: FloatArray) -> None:
    """``out = a * b`` for single poses ``(7,)`` (``b`` expressed in ``a``'s frame)."""
    position = np.empty(3)
    mujoco.mju_rotVecQuat(position, b[:3], a[3:])
    quat = np.empty(4)
    mujoco.mju_mulQuat(quat, a[3:], b[3:])
    out[:3] = a[:3] + position
    out[3:] = quat


def relative_pose_into(out: FloatArray, pose: FloatArray, reference: FloatArray) -> None:
    """``out = reference^-1 * pose`` for single poses ``(7,)``."""
    inverse = np.empty(4)
    mujoco.mju_negQuat(inverse, reference[3:])
    position = np.empty(3)
    mujoco.mju_rotVecQuat(position, pose[:3] - reference[:3], inverse)
    quat = np.empty(4)
    mujoco.mju_mulQuat(quat, inverse, pose[3:])
    out[:3] = position
    out[3:] = quat


# -- cameras ----------------------------------------------------------------------------
def look_at_axes(
    eye: npt.ArrayLike, target: npt.ArrayLike, up: npt.ArrayLike = (0.0, 0.0, 1.0), where: str = "look_at"
) -> FloatArray:
    """Rotation matrix ``(3, 3)`` of a MuJoCo camera at ``eye`` looking at ``target`` with
    ``up`` pointing up in the image; its columns are the camera's x (right), y (up) and
    z axes (MuJoCo cameras look along -z). Raises :class:`ConfigError` for coincident
    points or a view direction parallel to ``up``."""
    from robot_agents.errors import ConfigError

    eye_, target_ = np.asarray(eye, dtype=np.float64), np.asarray(target, dtype=np.float64)
    forward = target_ - eye_
    norm = float(np.linalg.norm(forward))
    if forward.shape != (3,) or not math.isfinite(norm) or norm < 1e-9:
        raise ConfigError(f"{where}: expected distinct finite 3D points eye and target, got {eye!r} and {target!r}.")
    forward /= norm
    right = _cross(forward, np.asarray(up, dtype=np.float64))
    if float(np.linalg.norm(right)) < 1e-9:
        raise ConfigError(f"{where}: the view direction {forward.round(6).tolist()} is parallel to up {up!r}.")
    right /= np.linalg.norm(right)
    camera_up = _cross(right, forward)
    axes: FloatArray = np.column_stack([right, camera_up, -forward])
    return axes


def look_at_quat(
    eye: npt.ArrayLike, target: npt.ArrayLike, up: npt.ArrayLike = (0.0, 0.0, 1.0), where: str = "look_at"
) -> tuple[float, float, float, float]:
    """Orientation ``(w, x, y, z)``, ``w >= 0``, of a MuJoCo camera at ``eye`` looking at ``target``."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, look_at_axes(eye, target, up, where).reshape(-1))
    if quat[0] < 0:
        quat = -quat
    return (float(quat[0]), float(quat[1]), float(quat[2]), float(quat[3]))


def look_at_xyaxes(
    eye: npt.ArrayLike, target: npt.ArrayLike, up: npt.ArrayLike = (0.0, 0.0, 1.0), where: str = "look_at"
) -> list[float]:
    """MuJoCo camera ``xyaxes`` (right and up axes, 6 numbers) of a camera at ``eye`` looking at ``target``."""
    axes = look_at_axes(eye, target, up, where)
    return [*axes[:, 0].tolist(), *axes[:, 1].tolist()]
