"""Jacobians by central differences of a pose function: the numbers the analytic
Jacobians (:meth:`~robot_agents.agent.agent.Agent.frame_jacobian`) are checked against."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from robot_agents.kinematics.rotations import rotation_error

FloatArray = npt.NDArray[np.float64]

#: Central-difference step (rad or m): the truncation error (step^2) and the rounding
#: error (1e-16 / step) of a pose differenced in float64 meet near 1e-6.
DIFFERENCE_STEP = 1e-6


def finite_difference_jacobian(
    pose: Callable[[FloatArray], FloatArray], qpos: FloatArray, step: float = DIFFERENCE_STEP
) -> FloatArray:
    """The Jacobian of ``pose`` at ``qpos`` by central differences, ``(num_envs, 6, n)``:
    per joint coordinate, the position's rate (m per rad or m), then the rotation's as a
    rotation vector in the pose's own reference axes (rad per rad or m).

    ``pose`` maps joint positions ``(num_envs, n)`` to poses ``(num_envs, 7)`` (position,
    quaternion w, x, y, z), e.g. ``lambda q: agent.frame_pose("ee", q, relative_to="root")``;
    each of the ``n`` coordinates of ``qpos`` is moved by ``+- step`` alone (joints whose
    position is one coordinate: hinges and slides, not a free or ball joint's
    quaternion)."""
    qpos = np.asarray(qpos, dtype=np.float64)
    jacobian = np.zeros((qpos.shape[0], 6, qpos.shape[1]))
    for coordinate in range(qpos.shape[1]):
        plus, minus = qpos.copy(), qpos.copy()
        plus[:, coordinate] += step
        minus[:, coordinate] -= step
        ahead, behind = pose(plus), pose(minus)
        jacobian[:, :3, coordinate] = (ahead[:, :3] - behind[:, :3]) / (2 * step)
        jacobian[:, 3:, coordinate] = rotation_error(ahead[:, 3:], behind[:, 3:]) / (2 * step)
    return jacobian
