"""Named robot poses used for resets."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError


def _as_floats(name: str, values: Sequence[float] | npt.ArrayLike, size: int | None = None) -> tuple[float, ...]:
    array = np.asarray(values, dtype=np.float64).reshape(-1)
    if size is not None and array.size != size:
        raise ConfigError(f"Keyframe.{name}: expected {size} values, got {array.size}: {array.tolist()}.")
    if not np.all(np.isfinite(array)):
        raise ConfigError(f"Keyframe.{name}: expected finite values, got {array.tolist()}.")
    return tuple(float(v) for v in array)


@dataclass(frozen=True)
class Keyframe:
    """A named pose of one robot.

    Attributes:
        qpos: joint positions, shape ``(dof,)``, in the robot's joint order (radians for
            hinges, metres for slides). The root pose of a free-floating robot is *not*
            part of ``qpos``; it is ``base_pos`` / ``base_quat``.
        qvel: joint velocities, shape ``(dof,)``; zeros when omitted.
        base_pos: root position (m), shape ``(3,)``, relative to where the scene mounts
            the robot (``Scene(robot_poses=...)``; the world origin by default). Applied
            to free-root robots on reset; a fixed-root robot stays on its mount.
        base_quat: root orientation as a unit quaternion ``(w, x, y, z)``, relative to
            the mount's orientation.
    """

    qpos: tuple[float, ...]
    qvel: tuple[float, ...] | None = None
    base_pos: tuple[float, ...] = (0.0, 0.0, 0.0)
    base_quat: tuple[float, ...] = field(default=(1.0, 0.0, 0.0, 0.0))

    def __post_init__(self) -> None:
        object.__setattr__(self, "qpos", _as_floats("qpos", self.qpos))
        if self.qvel is not None:
            object.__setattr__(self, "qvel", _as_floats("qvel", self.qvel, len(self.qpos)))
        object.__setattr__(self, "base_pos", _as_floats("base_pos", self.base_pos, 3))
        quat = _as_floats("base_quat", self.base_quat, 4)
        norm = math.sqrt(sum(q * q for q in quat))
        if norm < 1e-9:
            raise ConfigError(f"Keyframe.base_quat: expected a unit quaternion (w, x, y, z), got {quat}.")
        object.__setattr__(self, "base_quat", tuple(q / norm for q in quat))

    @property
    def dof(self) -> int:
        """Number of joint positions in this keyframe."""
        return len(self.qpos)

    def qpos_array(self) -> npt.NDArray[np.float64]:
        """``qpos`` as a new float64 array of shape ``(dof,)``."""
        return np.array(self.qpos, dtype=np.float64)

    def qvel_array(self) -> npt.NDArray[np.float64]:
        """``qvel`` (zeros when omitted) as a new float64 array of shape ``(dof,)``."""
        if self.qvel is None:
            return np.zeros(self.dof, dtype=np.float64)
        return np.array(self.qvel, dtype=np.float64)
