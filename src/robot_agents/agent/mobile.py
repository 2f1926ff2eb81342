"""A bound robot's mobile base in Habitat's terms: where it stands on the ground
(``base_pos``) and which way it faces (``base_rot``, yaw about world +z), read and
set per env. Works for a ``Base`` part on planar joints (x and y slides, a yaw hinge)
and for a floating root."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import RobotIndex
from robot_agents.errors import ConfigError, StateError

if TYPE_CHECKING:
    from robot_agents.agent.joint_state import JointState
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]


def wrap_angle(angle: FloatArray) -> FloatArray:
    """Angles wrapped to ``(-pi, pi]``."""
    wrapped: FloatArray = np.pi - np.mod(np.pi - angle, 2 * np.pi)
    return wrapped


class MobileBase:
    """The base of one robot: planar joints ``(x, y, yaw)`` of a ``Base`` part, or the
    root's free joint. Poses are in the world frame; planar joints are taken relative
    to where the scene mounted the robot."""

    def __init__(
        self, world: SimBackend, index: RobotIndex, state: JointState, planar: tuple[str, ...] | None, owner: str
    ) -> None:
        self.world = world
        self.index = index
        self.state = state
        self.owner = owner
        self.planar = tuple(index.joint(j, owner) for j in planar) if planar else None
        if self.planar is None and index.free_joint is None:
            self.kind = "fixed"
        else:
            self.kind = "planar" if self.planar is not None else "free"
        mount = state.mount_pose
        self._mount_xy = np.array(mount[:2])
        self._mount_yaw = 2.0 * math.atan2(float(mount[6]), float(mount[3]))  # yaw of a z-rotation quaternion

    def _require(self, where: str) -> None:
        if self.kind == "fixed":
            raise ConfigError(f"{where}: {self.owner} has no mobile base (a Base part or a floating root).")

    @property
    def yaw(self) -> FloatArray:
        """``base_rot``: yaw (rad) about world +z, ``(num_envs,)``, in ``(-pi, pi]``."""
        self._require(f"{self.owner}.base_rot")
        quat = self.world.body_poses(self._base_body())[:, 0, 3:]
        yaw = np.arctan2(
            2 * (quat[:, 0] * quat[:, 3] + quat[:, 1] * quat[:, 2]), 1 - 2 * (quat[:, 2] ** 2 + quat[:, 3] ** 2)
        )
        return wrap_angle(yaw)

    def _base_body(self) -> int:
        """The body the base joints move (the root for a floating robot)."""
        if self.planar is None:
            return self.index.root_body_id
        return int(self.index.model.jnt_bodyid[self.planar[-1].id])

    @property
    def position(self) -> FloatArray:
        """``base_pos``: the ground point under the base, ``(num_envs, 3)`` (m, world; z of the mount)."""
        self._require(f"{self.owner}.base_pos")
        body = self._base_body()
        pos: FloatArray = self.world.body_poses(body)[:, 0, :3].copy()
        pos[:, 2] = self.state.mount_pose[2]
        return pos

    def _yaws(self, yaw: npt.ArrayLike, n: int, where: str) -> FloatArray:
        """``yaw`` (a number, or one per env) as finite angles ``(n,)`` (rad)."""
        try:
            values = np.asarray(yaw, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise StateError(f"{where}: expected yaw as a number or {n} numbers (rad), got {yaw!r}.") from None
        if values.size == 1:
            values = np.full(n, values[0])
        if values.size != n or not np.all(np.isfinite(values)):
            raise StateError(f"{where}: expected yaw as a finite number or {n} finite numbers (rad), got {yaw!r}.")
        return values

    def set(
        self, xy: npt.ArrayLike | None, yaw: npt.ArrayLike | None, env_ids: npt.ArrayLike | None, where: str
    ) -> None:
        """Teleport the base (kinematic write; velocities of the base set to zero)."""
        self._require(where)
        ids = self.state.env_ids(env_ids, where)
        n = len(ids)
        new_xy = self.position[ids, :2] if xy is None else self.state.batch(xy, n, 2, "base position (x, y)", where)
        new_yaw = self.yaw[ids] if yaw is None else self._yaws(yaw, n, where)
        if self.planar is not None:
            x, y, turn = self.planar
            local = new_xy - self._mount_xy
            c, s = math.cos(-self._mount_yaw), math.sin(-self._mount_yaw)
            values = np.stack(
                (
                    c * local[:, 0] - s * local[:, 1],
                    s * local[:, 0] + c * local[:, 1],
                    wrap_angle(new_yaw - self._mount_yaw),
                ),
                axis=1,
            )
            qpos_adr = [x.qpos_adr, y.qpos_adr, turn.qpos_adr]
            dof_adr = [x.dof_adr, y.dof_adr, turn.dof_adr]
            self.world.write_joint_state(ids, qpos_adr, values, dof_adr, np.zeros((n, 3)))
            return
        free = self.index.free_joint
        if free is None:
            raise StateError(f"{where}: no base joints.")
        pose = self.world.body_poses(self.index.root_body_id)[ids, 0]
        quat = np.empty((n, 4))
        for row, angle in enumerate(new_yaw):
            mujoco.mju_axisAngle2Quat(quat[row], np.array([0.0, 0.0, 1.0]), float(angle))
        values = np.concatenate([new_xy, pose[:, 2:3], quat], axis=1)
        qpos_adr = list(range(free.qpos_adr, free.qpos_adr + 7))
        dof_adr = list(range(free.dof_adr, free.dof_adr + 6))
        self.world.write_joint_state(ids, qpos_adr, values, dof_adr, np.zeros((n, 6)))
