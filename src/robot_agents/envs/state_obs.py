"""State observations: float32 trees and their Gymnasium spaces, and the pose views the
one-env fast path of :class:`~robot_agents.envs.base_env.RobotEnv` concatenates."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.kinematics.forward import FrameKind, FrameRef

FloatArray = npt.NDArray[np.float64]


def to_float32(tree: Any) -> Any:
    """A (nested) dict of arrays as float32 arrays."""
    if isinstance(tree, Mapping):
        return {k: to_float32(v) for k, v in tree.items()}
    return np.asarray(tree, dtype=np.float32)


def space_for(tree: Any) -> gym.Space[Any]:
    """The Gymnasium space of an observation tree (``Dict`` of float32 ``Box``)."""
    if isinstance(tree, Mapping):
        return gym.spaces.Dict({k: space_for(v) for k, v in tree.items()})
    # Finite bounds (the largest float32): observations are unbounded physical quantities.
    limit = np.finfo(np.float32).max
    return gym.spaces.Box(-limit, limit, shape=np.shape(tree), dtype=np.float32)


def pose_entries(frame: FrameRef, data: mujoco.MjData) -> list[Any]:
    """The world pose of ``frame`` in ``data`` for :meth:`~robot_agents.envs.base_env.RobotEnv._single_state_obs`:
    position then quaternion (w, x, y, z), as ``(1, k)`` views of ``data`` where MuJoCo
    stores them, else a callable that computes them into reused buffers with the same arithmetic as
    :meth:`~robot_agents.agent.frames.RobotFrames.measured_pose`."""
    if frame.kind is FrameKind.BODY:
        position, quat = data.xpos[frame.id], data.xquat[frame.id]
        if frame.offset is None:
            return [position[None], quat[None]]
    else:
        position, matrix = data.site_xpos[frame.id], data.site_xmat[frame.id]
        quat = np.empty(4)
        if frame.offset is None:
            site_quat_row = [quat[None]]

            def site_quat() -> list[FloatArray]:
                mujoco.mju_mat2Quat(quat, matrix)
                return site_quat_row

            return [position[None], site_quat]
    offset = np.asarray(frame.offset, dtype=np.float64)
    offset_position, offset_quat = offset[:3].copy(), offset[3:].copy()
    shifted, out_position, out_quat = np.empty(3), np.empty(3), np.empty(4)
    rows = [out_position[None], out_quat[None]]

    def offset_pose() -> list[FloatArray]:
        if frame.kind is not FrameKind.BODY:
            mujoco.mju_mat2Quat(quat, matrix)
        mujoco.mju_rotVecQuat(shifted, offset_position, quat)
        np.add(position, shifted, out=out_position)
        mujoco.mju_mulQuat(out_quat, quat, offset_quat)
        return rows

    return [offset_pose]
