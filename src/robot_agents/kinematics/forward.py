"""Forward kinematics and Jacobians of any body or site, batched over envs.

Everything runs on a private scratch ``MjData``: the simulation's own data is never
read or written, so asking "where would the tool be at this ``qpos``?" has no side
effects on physics, contacts or sensors.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import StateError, UnknownNameError

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


class FrameKind(Enum):
    """What a kinematic frame is attached to."""

    BODY = "body"
    SITE = "site"


@dataclass(frozen=True)
class FrameRef:
    """A body or site of the compiled model, resolved once.

    Attributes:
        kind: body or site.
        id: its index in the model.
        name: its full name (for messages).
        offset: a fixed pose of the frame relative to the body or site, for frames
            that are not an object of the model (e.g. where a floating mount starts).
    """

    kind: FrameKind
    id: int
    name: str
    #: A fixed pose ``(7,)`` of the frame in the body or site (``None``: the origin itself).
    offset: tuple[float, ...] | None = None


def resolve_frame(model: mujoco.MjModel, name: str, prefix: str = "", where: str = "resolve_frame") -> FrameRef:
    """The body (first) or site called ``prefix + name``; raises :class:`UnknownNameError`
    listing the bodies and sites under ``prefix`` when there is none."""
    full = prefix + name
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, full)
    if body >= 0:
        return FrameRef(FrameKind.BODY, int(body), full)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, full)
    if site >= 0:
        return FrameRef(FrameKind.SITE, int(site), full)
    names = [model.body(b).name for b in range(model.nbody)] + [model.site(s).name for s in range(model.nsite)]
    available = [n[len(prefix) :] for n in names if n.startswith(prefix) and n]
    raise UnknownNameError(where, "body or site", name, available)


class BoundFrame:
    """One frame read off a :class:`Kinematics`' scratch data without per-call look-ups:
    what :meth:`Kinematics.loaded_pose` and :meth:`Kinematics.loaded_jacobian` read
    through. Hot loops (IK, end-effector control) keep their own, whose buffers no one
    else writes.

    Args:
        kinematics: whose scratch data is read (at the configuration last loaded).
        frame: the body or site.

    Attributes:
        pose: the world pose ``(7,)`` (m, quaternion w-x-y-z) written by :meth:`update`;
            ``position`` and ``quat`` are views of its parts.
        jacp / jacr: the translational and rotational Jacobians ``(3, nv)`` written by
            :meth:`jacobian` (m/rad, rad/rad or m): rows 0-2 and 3-5 of ``jacobians``
            ``(6, nv)``.
    """

    def __init__(self, kinematics: Kinematics, frame: FrameRef) -> None:
        model, data = kinematics.model, kinematics.data
        self.frame = frame
        self._model, self._data = model, data
        self._is_body = frame.kind is FrameKind.BODY
        self._id = frame.id
        self._body = frame.id if self._is_body else int(model.site_bodyid[frame.id])
        offset = None if frame.offset is None else np.asarray(frame.offset, dtype=np.float64)
        self._offset = offset
        # Views of the scratch data's rows of this frame (MjData's arrays do not move).
        self._source_position = data.xpos[frame.id] if self._is_body else data.site_xpos[frame.id]
        self._source_orientation = data.xquat[frame.id] if self._is_body else data.site_xmat[frame.id]
        self.pose: FloatArray = np.empty(7)
        self.position, self.quat = self.pose[:3], self.pose[3:]
        #: Both Jacobians in one array ``(6, nv)``: ``jacp`` is rows 0-2, ``jacr`` rows 3-5
        #: (views, so a caller can copy a column block of both at once).
        self.jacobians: FloatArray = np.zeros((6, model.nv))
        self.jacp: FloatArray = self.jacobians[:3]
        self.jacr: FloatArray = self.jacobians[3:]
        # With an offset: the body's or site's own pose, and the offset's parts.
        self._origin = np.empty(7)
        self._origin_parts = (self._origin[:3], self._origin[3:])
        self._offset_parts = None if offset is None else (offset[:3], offset[3:])
        self._point = np.empty(7)
        self._point_parts = (self._point[:3], self._point[3:])

    def update(self) -> FloatArray:
        """The frame's world pose at the loaded configuration, into :attr:`pose` (returned)."""
        offset = self._offset_parts
        if offset is None:  # the body's or site's own pose (_origin_into inlined)
            self.position[...] = self._source_position
            if self._is_body:
                self.quat[...] = self._source_orientation
            else:
                mujoco.mju_mat2Quat(self.quat, self._source_orientation)
        else:  # _pose_into inlined (the same calls)
            origin_position, origin_quat = self._origin_parts
            origin_position[...] = self._source_position
            if self._is_body:
                origin_quat[...] = self._source_orientation
            else:
                mujoco.mju_mat2Quat(origin_quat, self._source_orientation)
            mujoco.mju_mulPose(self.position, self.quat, origin_position, origin_quat, offset[0], offset[1])
        return self.pose

    def _pose_into(self, position: FloatArray, quat: FloatArray) -> None:
        """The pose's parts into ``position`` ``(3,)`` and ``quat`` ``(4,)`` (with an
        offset: the origin's pose composed with it, ``mju_mulPose``)."""
        if self._offset_parts is not None:
            origin_position, origin_quat = self._origin_parts
            self._origin_into(origin_position, origin_quat)
            offset_position, offset_quat = self._offset_parts
            # not the observation's offset arithmetic (state_obs.pose_entries): mju_mulPose renormalizes the quaternion when |norm - 1| > 1e-15
            mujoco.mju_mulPose(position, quat, origin_position, origin_quat, offset_position, offset_quat)
        else:
            self._origin_into(position, quat)

    def _origin_into(self, position: FloatArray, quat: FloatArray) -> None:
        position[...] = self._source_position
        if self._is_body:
            quat[...] = self._source_orientation
        else:
            mujoco.mju_mat2Quat(quat, self._source_orientation)

    def jacobian(self, updated: bool = False) -> tuple[FloatArray, FloatArray]:
        """Jacobians of the frame's origin at the loaded configuration, in world axes,
        into :attr:`jacp` and :attr:`jacr` (returned). ``updated``: :meth:`update` ran at
        this configuration, so :attr:`pose` holds the frame's position already."""
        if self._offset is not None:
            if updated:
                point = self.position
            else:
                point, point_quat = self._point_parts
                self._pose_into(point, point_quat)
            mujoco.mj_jac(self._model, self._data, self.jacp, self.jacr, point, self._body)
        elif self._is_body:
            mujoco.mj_jacBody(self._model, self._data, self.jacp, self.jacr, self._id)
        else:
            mujoco.mj_jacSite(self._model, self._data, self.jacp, self.jacr, self._id)
        return self.jacp, self.jacr


class Kinematics:
    """Poses and Jacobians of a compiled model at given joint positions.

    Args:
        model: the compiled model; the scratch data is made from it.

    All methods take ``qpos`` of shape ``(num_envs, nq)`` (a full configuration per env)
    and loop over envs with MuJoCo's C kinematics (``mj_kinematics`` + ``mj_comPos``);
    outputs carry the leading ``num_envs`` axis.
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self._qpos = self.data.qpos  # (MjData's arrays do not move)
        #: The frames :meth:`loaded_pose` / :meth:`loaded_jacobian` have read, bound once.
        self._frames: dict[FrameRef, BoundFrame] = {}

    # -- single configuration (the hot path of IK) --------------------------------------
    def load(self, qpos: FloatArray) -> None:
        """Put one configuration ``(nq,)`` into the scratch data and compute positions,
        orientations and the quantities Jacobians need."""
        self._qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)

    def loaded_pose(self, frame: FrameRef, out: FloatArray) -> None:
        """World pose of ``frame`` at the loaded configuration into ``out`` ``(7,)``."""
        out[:] = self._bound(frame).update()

    def loaded_jacobian(self, frame: FrameRef) -> tuple[FloatArray, FloatArray]:
        """Translational and rotational Jacobians ``(3, nv)`` each of ``frame``'s origin at
        the loaded configuration, in world axes (internal buffers: copy to keep)."""
        return self._bound(frame).jacobian()

    def _bound(self, frame: FrameRef) -> BoundFrame:
        bound = self._frames.get(frame)
        if bound is None:
            bound = self._frames[frame] = BoundFrame(self, frame)
        return bound

    # -- batched ------------------------------------------------------------------------
    def _check(self, qpos: npt.ArrayLike, where: str) -> FloatArray:
        array = np.asarray(qpos, dtype=np.float64)
        if array.ndim == 1:
            array = array[None]
        if array.ndim != 2 or array.shape[1] != self.model.nq:
            raise StateError(f"{where}: expected qpos of shape (num_envs, {self.model.nq}), got {np.shape(qpos)}.")
        if not np.all(np.isfinite(array)):
            raise StateError(f"{where}: qpos contains NaN or inf.")
        return array

    def poses(self, qpos: npt.ArrayLike, frames: Sequence[FrameRef]) -> FloatArray:
        """World poses ``(num_envs, len(frames), 7)`` of several frames, one FK per env."""
        array = self._check(qpos, "Kinematics.poses")
        out = np.empty((array.shape[0], len(frames), 7))
        for env, row in enumerate(array):
            self.load(row)
            for k, frame in enumerate(frames):
                self.loaded_pose(frame, out[env, k])
        return out

    def pose(self, qpos: npt.ArrayLike, frame: FrameRef) -> FloatArray:
        """World pose ``(num_envs, 7)`` of ``frame``: position (m), quaternion (w, x, y, z)."""
        return self.poses(qpos, (frame,))[:, 0]

    def jacobian(self, qpos: npt.ArrayLike, frame: FrameRef, dofs: npt.ArrayLike | None = None) -> FloatArray:
        """Jacobian ``(num_envs, 6, k)`` of ``frame``'s origin: rows 0-2 map joint
        velocities to its linear velocity (m/s), rows 3-5 to its angular velocity
        (rad/s), both in world axes. Columns are the ``dofs`` (default all ``nv``)."""
        array = self._check(qpos, "Kinematics.jacobian")
        columns = np.arange(self.model.nv) if dofs is None else np.asarray(dofs, dtype=np.int64)
        out = np.empty((array.shape[0], 6, len(columns)))
        for env, row in enumerate(array):
            self.load(row)
            jacp, jacr = self.loaded_jacobian(frame)
            out[env, :3] = jacp[:, columns]
            out[env, 3:] = jacr[:, columns]
        return out
