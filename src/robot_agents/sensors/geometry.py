"""Rotations for camera poses (numpy only): quaternions are ``(w, x, y, z)`` as in
MuJoCo, rotation matrices act on column vectors."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError

FloatArray = npt.NDArray[np.float64]

#: OpenGL / MuJoCo camera axes (x right, y up, looking along -z) to OpenCV camera axes
#: (x right, y down, looking along +z): flip y and z.
GL_TO_CV = np.diag([1.0, -1.0, -1.0])


def float_tuple(value: Any, size: int, what: str, where: str) -> tuple[float, ...]:
    """``value`` as a tuple of ``size`` finite floats, or a ConfigError naming ``where``."""
    try:
        array = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: expected {what} as {size} numbers, got {value!r}.") from None
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ConfigError(f"{where}: expected {what} as {size} finite numbers, got {value!r}.")
    return tuple(float(v) for v in array)


def quat_to_mat(quat: Sequence[float] | FloatArray) -> FloatArray:
    """3x3 rotation matrix of a unit quaternion ``(w, x, y, z)``."""
    w, x, y, z = (float(v) for v in quat)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def mat_to_quat(mat: FloatArray) -> tuple[float, float, float, float]:
    """Unit quaternion ``(w, x, y, z)`` of a 3x3 rotation matrix, with ``w >= 0``."""
    m = np.asarray(mat, dtype=np.float64)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
    quat = np.array(q) / np.linalg.norm(q)
    if quat[0] < 0:
        quat = -quat
    return (float(quat[0]), float(quat[1]), float(quat[2]), float(quat[3]))


def look_at_quat(
    eye: Sequence[float], target: Sequence[float], up: Sequence[float] = (0.0, 0.0, 1.0), where: str = "look_at"
) -> tuple[float, float, float, float]:
    """Orientation ``(w, x, y, z)`` of a MuJoCo camera at ``eye`` looking at ``target``
    with ``up`` pointing up in the image (all in the mount's frame, metres)."""
    forward = np.asarray(target, dtype=np.float64) - np.asarray(eye, dtype=np.float64)
    norm = float(np.linalg.norm(forward))
    if forward.shape != (3,) or not np.isfinite(norm) or norm < 1e-9:
        raise ConfigError(
            f"{where}: expected distinct finite 3D points eye and target, got {list(eye)} and {list(target)}."
        )
    forward /= norm
    right = np.cross(forward, np.asarray(up, dtype=np.float64))
    if np.linalg.norm(right) < 1e-9:
        raise ConfigError(f"{where}: the view direction {forward.round(6).tolist()} is parallel to up {list(up)}.")
    right /= np.linalg.norm(right)
    camera_up = np.cross(right, forward)
    # Columns: camera x (right), y (up), z (backwards: the camera looks along -z).
    return mat_to_quat(np.column_stack([right, camera_up, -forward]))


def pose_matrix(pos: Sequence[float] | FloatArray, rot: FloatArray) -> FloatArray:
    """4x4 homogeneous transform from a position and a 3x3 rotation."""
    out = np.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = pos
    return out
