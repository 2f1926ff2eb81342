"""Camera conventions and input parsing for sensor declarations (rotations live in
:mod:`robot_agents.kinematics.rotations`)."""

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


def pose_matrix(pos: Sequence[float] | FloatArray, rot: FloatArray) -> FloatArray:
    """4x4 homogeneous transform from a position and a 3x3 rotation."""
    out = np.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = pos
    return out
