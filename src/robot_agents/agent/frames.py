"""A bound robot's kinematic frames: its root (command) frame, its end effectors, and
poses and Jacobians of any of its bodies or sites, computed on scratch data."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import RobotIndex
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.kinematics.forward import FrameKind, FrameRef, Kinematics, resolve_frame
from robot_agents.kinematics.rotations import quat_to_matrix, relative_pose
from robot_agents.parts.declaration import EndEffector

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]


class RobotFrames:
    """Frames of one robot in a compiled scene.

    Attributes:
        root_frame: the frame of root-relative commands: the robot's fixed (or
            free-floating) base; when the root body itself moves on joints (a floating
            mount), where that body sits with its joints at zero.
        end_effectors: name -> ``(tool frame, command frame)``; the first is the default.
    """

    def __init__(
        self, model: mujoco.MjModel, index: RobotIndex, end_effectors: Sequence[EndEffector], owner: str
    ) -> None:
        self.model = model
        self.index = index
        self.owner = owner
        self.kinematics = Kinematics(model)
        root = index.root_body_id
        if model.body_jntnum[root] > 0 and index.free_joint is None:
            home = (*model.body_pos[root], *model.body_quat[root])
            parent = int(model.body_parentid[root])
            self.root_frame = FrameRef(FrameKind.BODY, parent, model.body(root).name + " (home)", tuple(home))
        else:
            self.root_frame = FrameRef(FrameKind.BODY, root, model.body(root).name)
        self.end_effectors: dict[str, tuple[FrameRef, FrameRef]] = {}
        for ee in end_effectors:
            where = f"{owner} end effector {ee.name!r}"
            base = resolve_frame(model, ee.link, index.prefix, where)
            tool = FrameRef(base.kind, base.id, base.name, (*ee.pos, *ee.quat)) if ee.has_offset else base
            command = (
                self.root_frame
                if ee.command_frame is None
                else resolve_frame(model, ee.command_frame, index.prefix, where + " command_frame")
            )
            self.end_effectors[ee.name] = (tool, command)

    def end_effector(self, name: str | None, where: str) -> FrameRef:
        """The tool frame of end effector ``name`` (``None``: the first)."""
        if not self.end_effectors:
            raise ConfigError(f"{where}: {self.owner} declares no end effector (an Arm part's end_effectors).")
        if name is None:
            return next(iter(self.end_effectors.values()))[0]
        if name not in self.end_effectors:
            raise UnknownNameError(where, "end effector", str(name), self.end_effectors)
        return self.end_effectors[name][0]

    def frame(self, name: str, where: str) -> FrameRef:
        """A body or site of the robot, or one of its end effectors, by name."""
        if not isinstance(name, str):
            raise ConfigError(f"{where}: expected a body, site or end-effector name, got {name!r}.")
        if name in self.end_effectors:
            return self.end_effectors[name][0]
        try:
            return resolve_frame(self.model, name, self.index.prefix, where)
        except UnknownNameError as err:
            available = dict.fromkeys([*self.end_effectors, *err.available])
            raise UnknownNameError(where, "body, site or end effector", name, available) from None

    def reference(self, relative_to: str, where: str) -> FrameRef | None:
        """The frame poses are given in: ``"world"`` (``None``), ``"root"`` (the root
        frame), or a body, site or end effector of the robot."""
        if not isinstance(relative_to, str):
            raise ConfigError(
                f"{where}: expected relative_to to be 'world', 'root' or a body, site or end-effector name, "
                f"got {relative_to!r}."
            )
        if relative_to == "world":
            return None
        if relative_to == "root":
            return self.root_frame
        try:
            return self.frame(relative_to, where)
        except UnknownNameError as err:
            available = dict.fromkeys(["world", "root", *self.end_effectors, *err.available])
            raise UnknownNameError(
                where, "relative_to frame ('world', 'root', body, site or end effector)", relative_to, available
            ) from None

    def measured_pose(self, frame: FrameRef, world: SimBackend) -> FloatArray:
        """World pose ``(num_envs, 7)`` of ``frame`` in the simulation's current state
        (read from the backend, no kinematics of its own)."""
        if frame.kind is FrameKind.BODY:
            pose: FloatArray = world.body_poses(frame.id)[:, 0]
        else:
            pose = world.site_poses([frame.id])[:, 0]
        if frame.offset is not None:
            offset = np.asarray(frame.offset)
            offset_position, offset_quat = offset[:3], offset[3:]
            # MuJoCo's quaternion functions per env (the arithmetic of the one-env
            # observation, state_obs.pose_entries), the additions and copies once for all
            # envs (the same bits; per env, 256 envs took 430 us instead of 329)
            shifted, turned = np.empty((len(pose), 3)), np.empty((len(pose), 4))
            for row, shift, turn in zip(pose, shifted, turned, strict=True):
                quat = row[3:]
                mujoco.mju_rotVecQuat(shift, offset_position, quat)
                mujoco.mju_mulQuat(turn, quat, offset_quat)
            pose[:, :3] += shifted
            pose[:, 3:] = turned
        return pose

    def pose(self, frame: FrameRef, reference: FrameRef | None, configurations: FloatArray) -> FloatArray:
        """Pose ``(num_envs, 7)`` of ``frame`` in ``reference`` (world when ``None``)."""
        if reference is None:
            return self.kinematics.pose(configurations, frame)
        poses = self.kinematics.poses(configurations, (frame, reference))
        return relative_pose(poses[:, 0], poses[:, 1])

    def jacobian(
        self,
        frame: FrameRef,
        reference: FrameRef | None,
        configurations: FloatArray,
        dofs: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Jacobian ``(num_envs, 6, k)`` over the ``dofs`` (model velocity addresses;
        default the robot's joints', ``k = nv``) of ``frame``'s pose in
        world axes, or relative to ``reference`` (in its axes; the derivative of
        :meth:`pose` relative to it, a reference the joints move included):

            J_v = R^T (J_v,frame - J_v,ref + [p - p_ref]x J_w,ref),   J_w = R^T (J_w,frame - J_w,ref)

        with ``R``, ``p_ref`` the reference's world orientation and origin, ``p`` the
        frame's origin."""
        columns = self.index.dof_adr if dofs is None else dofs
        jacobian = self.kinematics.jacobian(configurations, frame, columns)
        if reference is None:
            return jacobian
        reference_pose = self.kinematics.pose(configurations, reference)
        rotation = np.swapaxes(quat_to_matrix(reference_pose[:, 3:]), 1, 2)
        moving = self.kinematics.jacobian(configurations, reference, columns)
        linear, angular = jacobian[:, :3] - moving[:, :3], jacobian[:, 3:] - moving[:, 3:]
        if np.any(moving[:, 3:]):  # the reference turns with the joints: the frame's origin swings with it
            offset = self.kinematics.pose(configurations, frame)[:, :3] - reference_pose[:, :3]
            linear = linear + np.cross(offset[:, :, None], moving[:, 3:], axis=1)
        relative: FloatArray = np.concatenate((rotation @ linear, rotation @ angular), axis=1)
        return relative
