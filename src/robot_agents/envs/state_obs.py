"""State observations: what :class:`~robot_agents.envs.base_env.RobotEnv` observes of
its robots and task (:class:`StateObservation`, which also appends the camera part of a
visual mode), float32 trees and their Gymnasium spaces, and the pose views the one-env
fast path concatenates."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.controllers.ee import PDEEController
from robot_agents.controllers.joint import PDJointPosController, PDJointVelController
from robot_agents.kinematics.forward import FrameKind, FrameRef
from robot_agents.sim.world import BatchedWorld

if TYPE_CHECKING:
    from robot_agents.envs.observations import SensorObservation
    from robot_agents.sim.scene import Scene

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
    """The world pose of ``frame`` in ``data`` for :meth:`StateObservation._single_state`:
    position then quaternion (w, x, y, z), as ``(1, k)`` views of ``data`` where MuJoCo
    stores them, else a :class:`Refreshed` piece that computes them into fixed rows with
    the same arithmetic as :meth:`~robot_agents.agent.frames.RobotFrames.measured_pose`."""
    if frame.kind is FrameKind.BODY:
        position, quat = data.xpos[frame.id], data.xquat[frame.id]
        if frame.offset is None:
            return [position[None], quat[None]]
    else:
        position, matrix = data.site_xpos[frame.id], data.site_xmat[frame.id]
        quat = np.empty(4)
        if frame.offset is None:
            to_quat = mujoco.mju_mat2Quat

            def site_quat() -> None:
                to_quat(quat, matrix)

            return [position[None], Refreshed(site_quat, [quat[None]])]
    offset = np.asarray(frame.offset, dtype=np.float64)
    offset_position, offset_quat = offset[:3].copy(), offset[3:].copy()
    shifted, out_position, out_quat = np.empty(3), np.empty(3), np.empty(4)
    rows = [out_position[None], out_quat[None]]

    # the arithmetic of RobotFrames.measured_pose (which batches the additions over
    # envs), written out: a helper call would add to every one-env step; the functions
    # bound once (no module lookups per step). Each pose is refreshed into the two fixed
    # rows (a :class:`Refreshed` piece: the planned row copies them with the views).
    rotate, multiply, add = mujoco.mju_rotVecQuat, mujoco.mju_mulQuat, np.add

    def offset_pose() -> None:
        rotate(shifted, offset_position, quat)
        add(position, shifted, out=out_position)
        multiply(out_quat, quat, offset_quat)

    pose: Callable[[], None] = offset_pose
    if offset_quat.tolist() == [1.0, 0.0, 0.0, 0.0]:  # an offset that only shifts (the SO-100's jaw)
        # The product by the identity has in each component one term q_k * 1 = q_k and
        # three products by zero (+-0): it is q_k itself, bit for bit, unless q_k is a
        # zero (the sign may change) or a component is not finite (inf * 0 is NaN).
        # Where neither occurs the frame's own quaternion is copied (the call saved).
        components, isfinite = quat.tolist, math.isfinite

        def shifted_pose() -> None:
            rotate(shifted, offset_position, quat)
            add(position, shifted, out=out_position)
            q = components()
            if 0.0 in q or not isfinite(q[0] + q[1] + q[2] + q[3]):  # (an overflowing sum falls back too)
                multiply(out_quat, quat, offset_quat)
            else:
                out_quat[...] = quat

        pose = shifted_pose

    if frame.kind is FrameKind.BODY:
        return [Refreshed(pose, rows)]
    to_quat = mujoco.mju_mat2Quat
    shifted_or_offset = pose

    def site_offset_pose() -> None:
        to_quat(quat, matrix)
        shifted_or_offset()

    return [Refreshed(site_offset_pose, rows)]


class Refreshed:
    """A piece of :meth:`StateObservation._single_state` that MuJoCo does not store,
    computed into fixed buffers: :attr:`refresh` ``()`` rewrites the ``(1, k)`` float64
    arrays :attr:`rows` in place (a site's quaternion from its rotation matrix). Called,
    it refreshes and returns :attr:`rows`, as the other callable pieces return theirs; the
    planned row refreshes it first and then copies the rows as it copies views of the
    simulation (no list of results to walk each step)."""

    __slots__ = ("refresh", "rows")

    def __init__(self, refresh: Callable[[], None], rows: list[FloatArray]) -> None:
        self.refresh = refresh
        self.rows = rows

    def __call__(self) -> list[FloatArray]:
        self.refresh()
        return self.rows


class StateObservation:
    """The observation of a :class:`~robot_agents.envs.base_env.RobotEnv` and its space:
    per robot its proprioception and tool pose, then the task's extras; ``state`` as one
    float32 array ``(num_envs, D)``, otherwise the ``state_dict`` tree (``agent``,
    ``extra``) plus, in a visual mode, the camera part from ``sensors``.

    Args:
        scene: the env's scene (its robots and simulation backend).
        flat: ``obs_mode == "state"``.
        sensors: the camera part of a visual mode (``None`` for the state modes).
        extra_obs: the task's :meth:`~robot_agents.envs.base_env.RobotEnv._extra_obs`
            (``None``: the task adds none).
        where: the env's name, for errors.

    :attr:`observe` is chosen once: the one-env ``state`` observation concatenates
    views planned once per control mode (see :meth:`_single_state`).
    """

    def __init__(
        self,
        scene: Scene,
        flat: bool,
        sensors: SensorObservation | None,
        extra_obs: Callable[[], Mapping[str, FloatArray]] | None,
        where: str,
    ) -> None:
        self.scene = scene
        self.agents = scene.agents
        self.num_envs = scene.num_envs
        self._sensors = sensors
        self._extra_obs = extra_obs
        self._where = where
        self._agent0 = scene.agents[0]
        self._one_robot = len(scene.agents) == 1
        #: The single-env state observation's sources, rebuilt when a control mode changes.
        self._plan: tuple[tuple[Any, ...], list[Any]] | None = None
        #: The plan's float32 row and each entry's columns in it (:meth:`_plan_columns`);
        #: ``None``: the pieces are concatenated.
        self._out: npt.NDArray[np.float32] | None = None
        #: The row's writes by kind of entry (the order of the writes does not matter: the
        #: columns are disjoint and nothing is written but the row): views of the
        #: simulation as ``(columns, array)``, ``(columns, owner, attribute)`` and
        #: ``(columns list, callable)``.
        self._copies: list[tuple[Any, FloatArray]] = []
        self._attributes: list[tuple[Any, Any, str]] = []
        #: Each of :attr:`_attributes`' columns ``(start, stop)`` in the row.
        self._attribute_columns: list[tuple[int, int]] = []
        self._calls: list[tuple[list[Any], Callable[[], Any]]] = []
        #: The :class:`Refreshed` pieces' refreshes, run before the copies (their rows are among them).
        self._refreshes: list[Callable[[], None]] = []
        #: The observation of every env (float32 arrays; see the class doc).
        self.observe: Callable[[], Any]
        if flat:
            self.observe = self._single_state if self.num_envs == 1 else self._flat_state
        else:
            self.observe = self._tree

    def space(self) -> gym.Space[Any]:
        """The Gymnasium space of :attr:`observe` (it observes once)."""
        if self._sensors is None:
            return space_for(self.observe())
        state = space_for(self.state_dict())
        return gym.spaces.Dict({**state.spaces, **self._sensors.spaces(self.num_envs)})  # type: ignore[attr-defined]

    def state_arrays(self) -> list[FloatArray]:
        """The pieces of the ``state`` observation, each ``(num_envs, k)``, in order."""
        arrays: list[FloatArray] = []
        for agent in self.agents:
            arrays.extend(agent.proprioception_arrays())
            if agent.has_end_effector:
                arrays.append(agent.tcp_pose)
        if self._extra_obs is not None:
            arrays.extend(v.reshape(self.num_envs, -1) for v in self._extra_obs().values())
        return arrays

    def state_dict(self) -> dict[str, Any]:
        """The ``state_dict`` observation: ``agent`` (one robot's proprioception, or one
        per robot id) and ``extra`` (tool poses and the task's extras), float32."""
        robot_ids = self.scene.robot_ids
        agents = {rid: a.get_proprioception() for rid, a in zip(robot_ids, self.agents, strict=True)}
        extra = {
            f"{rid}/tcp_pose": a.tcp_pose for rid, a in zip(robot_ids, self.agents, strict=True) if a.has_end_effector
        }
        if self._extra_obs is not None:
            extra.update(self._extra_obs())
        agent_obs = next(iter(agents.values())) if len(agents) == 1 else agents
        if len(agents) == 1:
            extra = {k.split("/", 1)[1] if k.startswith(robot_ids[0] + "/") else k: v for k, v in extra.items()}
        return dict(to_float32({"agent": agent_obs, "extra": extra}))

    def _flat_state(self) -> npt.NDArray[np.float32]:
        obs: npt.NDArray[np.float32] = np.concatenate(self.state_arrays(), axis=1, dtype=np.float32)
        return obs

    def _tree(self) -> dict[str, Any]:
        obs = self.state_dict()
        if self._sensors is not None:
            obs.update(self._sensors.observe(self.scene.world))
        return obs

    def _single_state(self) -> npt.NDArray[np.float32]:
        """The ``state`` observation ``(1, D)`` of one env: the concatenation of
        :meth:`state_arrays` (same values, order and float32 rounding), from ``(1, k)``
        views planned once (no per-piece copies, name lookups or dicts)."""
        plan = self._plan  # (the check of _single_state_plan inlined for one robot)
        if plan is not None and self._one_robot and plan[0][0] is self._agent0.control.active:
            entries = plan[1]
        else:
            entries = self._single_state_plan()
        out = self._out
        if out is not None:  # each piece rounded into its columns of one float32 row
            for refresh in self._refreshes:  # (buffers that the copies below read)
                refresh()
            for dest, array in self._copies:
                dest[...] = array
            for dest, owner, name in self._attributes:  # the one array a controller observes
                dest[...] = getattr(owner, name)
            for views, call in self._calls:
                for view, array in zip(views, call(), strict=True):
                    view[...] = array
            row: npt.NDArray[np.float32] = out.copy()  # a new array: the caller may keep it
            return row
        arrays: list[Any] = []
        for entry in entries:
            kind = entry.__class__
            if kind is np.ndarray:
                arrays.append(entry)
            elif kind is tuple:
                arrays.append(getattr(entry[0], entry[1]))
            else:
                arrays.extend(entry())
        obs: npt.NDArray[np.float32] = np.concatenate(arrays, axis=1, dtype=np.float32)
        return obs

    def single_state_reading(
        self, owners: list[Any], source: FloatArray
    ) -> Callable[[], npt.NDArray[np.float32]] | None:
        """One robot, one env: :meth:`_single_state` for its active control mode, made
        now, with the targets of the controllers ``owners`` (the mode's parts, in order:
        every attribute the row reads) copied in one piece from ``source`` ``(1, n)``
        (rad or m), which the caller keeps equal to their ``target_qpos`` concatenated
        (:attr:`CombinedController.single_targets
        <robot_agents.controllers.combined.CombinedController.single_targets>` after the
        fused call): the same row, one copy instead of one per part. Valid while that
        mode stays active (the caller plans again when it changes). ``None`` where the
        row is not planned (a task's extras, another backend) or reads other attributes."""
        if not self._one_robot or self._sensors is not None or self.observe != self._single_state:
            return None
        self._single_state_plan()
        out = self._out
        if out is None or [(owner, name) for _, owner, name in self._attributes] != [
            (o, "target_qpos") for o in owners
        ]:
            return None
        columns = self._attribute_columns
        adjacent = all(a[1] == b[0] for a, b in itertools.pairwise(columns))
        if not columns or not adjacent or columns[-1][1] - columns[0][0] != source.shape[1]:
            return None
        targets = out[:, columns[0][0] : columns[-1][1]]
        refreshes, copies, calls = list(self._refreshes), list(self._copies), list(self._calls)

        def single_state() -> npt.NDArray[np.float32]:
            for refresh in refreshes:
                refresh()
            for dest, array in copies:
                dest[...] = array
            targets[...] = source
            for views, call in calls:
                for view, array in zip(views, call(), strict=True):
                    view[...] = array
            row: npt.NDArray[np.float32] = out.copy()  # a new array: the caller may keep it
            return row

        return single_state

    def _plan_columns(self, entries: list[Any]) -> None:
        """The float32 row :meth:`_single_state` fills and, per entry, the view of its
        columns (a list of views for an entry that gives several arrays): the same
        values and rounding as the concatenation (each float64 value rounded to float32
        once), with one copy per piece and no joined list."""
        pieces = []
        for entry in entries:
            kind = entry.__class__
            if kind is np.ndarray:
                pieces.append([entry])
            elif kind is tuple:
                pieces.append([getattr(entry[0], entry[1])])
            else:
                pieces.append(list(entry()))
        out = np.empty((1, sum(a.shape[1] for arrays in pieces for a in arrays)), dtype=np.float32)
        writes: list[tuple[Any, Any]] = []
        start = 0
        self._attribute_columns = []
        for entry, arrays in zip(entries, pieces, strict=True):
            views = []
            for array in arrays:
                views.append(out[:, start : start + array.shape[1]])
                start += array.shape[1]
            writes.append((views if callable(entry) else views[0], entry))
            if entry.__class__ is tuple:
                self._attribute_columns.append((start - arrays[0].shape[1], start))
        self._out = out
        self._copies = [(dest, entry) for dest, entry in writes if entry.__class__ is np.ndarray]
        self._attributes = [(dest, entry[0], entry[1]) for dest, entry in writes if entry.__class__ is tuple]
        self._calls = [(dest, entry) for dest, entry in writes if callable(entry) and entry.__class__ is not Refreshed]
        self._refreshes = [entry.refresh for _, entry in writes if entry.__class__ is Refreshed]
        for dest, entry in writes:
            if entry.__class__ is Refreshed:
                self._copies.extend(zip(dest, entry.rows, strict=True))

    def _single_state_plan(self) -> list[Any]:
        """What the ``state`` observation of one env concatenates, in order: read-only
        views of the simulation's arrays that stay valid across steps (joint state, a
        tool body's pose; an end-effector controller's targets, written in place), ``(controller, attribute)`` pairs for a joint-position or
        joint- or base-velocity controller's targets (a new array every step), and callables for what else
        changes identity every step (other controllers' observations, touch, the task's
        extras; :class:`Refreshed` ones for a site's or offset frame's pose, computed
        into fixed rows).
        Rebuilt only when a robot's active controller changes."""
        plan = self._plan
        if plan is not None:
            if self._one_robot:
                if plan[0][0] is self._agent0.control.active:
                    return plan[1]
            elif all(a.control.active is c for a, c in zip(self.agents, plan[0], strict=True)):
                return plan[1]
        key = tuple(a.control.active for a in self.agents)
        world = self.scene.world
        entries: list[Any] = []
        self._out = None
        self._copies, self._attributes, self._calls, self._refreshes = [], [], [], []
        self._attribute_columns = []
        if not isinstance(world, BatchedWorld):  # another backend: the generic reads
            entries.append(self.state_arrays)
            self._plan = (key, entries)
            return entries
        data = world.datas[0]
        for agent, controller in zip(self.agents, key, strict=True):
            index = agent.index
            for source, sel in ((data.qpos, index.qpos_sel), (data.qvel, index.dof_sel)):
                if isinstance(sel, slice):
                    entries.append(source[None, sel])
                else:
                    entries.append(lambda source=source, sel=sel: [source[sel][None]])
            for part in controller.parts.values():
                if type(part).observe is PDJointPosController.observe:  # {"target_qpos": its attribute}
                    entries.append((part, "target_qpos"))
                elif type(part).observe is PDJointVelController.observe:  # {"target_qvel": ...} (bases too)
                    entries.append((part, "target_qvel"))
                elif isinstance(part, PDEEController) and type(part).observe is PDEEController.observe:
                    entries.extend((part.target_qpos, part.target_pose))  # its two arrays, written in place
                else:
                    entries.append(lambda observe=part.observe: observe().values())
            if agent.touch_reader.names:
                entries.append(lambda agent=agent: [agent.touch])
            if agent.has_end_effector:
                entries.extend(pose_entries(agent.frames.end_effector(None, self._where), data))
        extra_obs = self._extra_obs
        if extra_obs is not None:
            entries.append(lambda: [v.reshape(1, -1) for v in extra_obs().values()])
        else:  # pieces of fixed widths: written into one row (a task's extras may vary)
            self._plan_columns(entries)
        self._plan = (key, entries)
        return entries
