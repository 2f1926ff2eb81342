"""``num_envs`` copies of one compiled MuJoCo model, stepped together: the CPU backend.

This is the one place that touches ``MjData``: every read and write of simulation
state (joint state, body poses, contacts, sensors, controls, reset, step, state save
and restore) goes through its methods, so a GPU backend or a real-robot driver can
take its place behind the same interface (:class:`~robot_agents.sim.backend.SimBackend`).

Physics state lives in the MjData objects; this class owns the batched ``ctrl``
buffer (shape ``(num_envs, nu)``) that controllers write, steps every env by a
number of substeps (threads release the GIL inside ``mj_step``), and reads or writes
the exact integration state for save / restore.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, StateError
from robot_agents.limits import MAX_SPEED, check_speeds
from robot_agents.notes import RUNTIME, install, pass_on
from robot_agents.sim.allocation import allocate_datas
from robot_agents.sim.render_mirror import RenderMirror
from robot_agents.validation import check_array, is_whole

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]

#: Everything needed for a bit-identical continuation: time, qpos, qvel, act, warm-start
#: accelerations, controls, applied forces, mocap poses, plugin and user data.
STATE_SPEC = mujoco.mjtState.mjSTATE_INTEGRATION


#: Island sleeping (MuJoCo 4.0): the per-tree counters and what a step derives from
#: them, all outside the integration state (:meth:`BatchedWorld.get_sleep_state`).
SLEEP_ARRAYS = ("tree_asleep", "tree_awake", "body_awake", "body_awake_ind", "dof_awake_ind", "parent_awake_ind")
SLEEP_COUNTS = ("nbody_awake", "nparent_awake", "ntree_awake", "nv_awake")
_SLEEP_FLAG = int(mujoco.mjtEnableBit.mjENBL_SLEEP)
#: The lowest ``tree_asleep`` of an awake tree: a woken tree counts up from
#: ``-(1 + mjMINAWAKE)`` to ``-1`` (then it may fall asleep).
_AWAKE_COUNTDOWN = -(1 + int(mujoco.mjMINAWAKE))


def _sync_poses(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Body, geom, site and camera poses at the stepped ``qpos`` (``mj_step`` leaves them
    at the start of its last substep): observed poses then match observed joints, and a
    state restore changes no observation (about 2 us for a 9-DoF arm)."""
    mujoco.mj_kinematics(model, data)
    mujoco.mj_camlight(model, data)


_MAX_SPEED_SQUARED = MAX_SPEED**2

_INSTABILITY_WARNINGS = (
    int(mujoco.mjtWarning.mjWARN_BADQACC),
    int(mujoco.mjtWarning.mjWARN_BADQVEL),
    int(mujoco.mjtWarning.mjWARN_BADQPOS),
)


def _derive(model: mujoco.MjModel, data: mujoco.MjData, forward: bool) -> None:
    """After a joint-state write: everything ``mj_forward`` derives, or (``forward=False``)
    body and camera poses only, as after a step (``mj_kinematics``, ``mj_camlight``)."""
    if forward:
        mujoco.mj_forward(model, data)
    else:
        _sync_poses(model, data)


class BatchedWorld:
    """A compiled model and ``num_envs`` MjData.

    Args:
        model: the compiled scene, as simulated.
        num_envs: number of independent copies (>= 1).
        substeps: physics steps per control step (>= 1).
        num_threads: worker threads for ``num_envs > 1``; default ``min(num_envs,
            os.cpu_count())``. Each env's result does not depend on the thread count.
        render_model: the model renderers draw, when it is not ``model``: the same
            scene with the visual-only geoms the simulated twin leaves out
            (:mod:`robot_agents.model.physics_twin`); each env's state is copied into
            its own ``MjData`` of it when rendered.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        num_envs: int,
        substeps: int,
        num_threads: int | None = None,
        render_model: mujoco.MjModel | None = None,
    ) -> None:
        if not is_whole(num_envs) or num_envs < 1:
            raise ConfigError(f"BatchedWorld: expected num_envs to be a whole number >= 1, got {num_envs!r}.")
        if not is_whole(substeps) or substeps < 1:
            raise ConfigError(f"BatchedWorld: expected substeps to be a whole number >= 1, got {substeps!r}.")
        if num_threads is not None and (not is_whole(num_threads) or num_threads < 1):
            raise ConfigError(
                f"BatchedWorld: expected num_threads to be a whole number >= 1 or None, got {num_threads!r}."
            )
        install()  # MuJoCo's run-time warnings: collected, passed on as notes after each step
        self.model = model
        #: The model renderers draw (``model`` itself unless a fuller one was given).
        self.render_model = model if render_model is None else render_model
        self.num_envs = int(num_envs)
        self._mirror = None if self.render_model is model else RenderMirror(self.render_model, model, self.num_envs)
        self.substeps = int(substeps)
        self.datas = allocate_datas(model, self.num_envs)
        self.ctrl = np.zeros((self.num_envs, model.nu))
        #: Set by :meth:`close` (the robots bound to this world then refuse writes).
        self.closed = False
        self.state_size = mujoco.mj_stateSize(model, STATE_SPEC)
        #: Length of one env's :meth:`get_sleep_state`.
        self.sleep_size = sum(getattr(self.datas[0], name).size for name in SLEEP_ARRAYS) + len(SLEEP_COUNTS)
        threads = num_threads if num_threads is not None else min(self.num_envs, os.cpu_count() or 1)
        self.num_threads = max(1, min(int(threads), self.num_envs))
        # The calling thread steps the first chunk itself; the pool steps the others.
        self._pool = ThreadPoolExecutor(self.num_threads - 1) if self.num_threads > 1 else None
        bounds = np.linspace(0, self.num_envs, self.num_threads + 1).astype(int)
        self._chunks = [range(bounds[i], bounds[i + 1]) for i in range(self.num_threads)]
        self._cache: dict[str, FloatArray] = {}
        #: Per env: MuJoCo reset it during the last step (NaN / inf / huge values), or a
        #: joint moved faster than :data:`MAX_SPEED`.
        self.last_step_unstable = np.zeros(self.num_envs, dtype=bool)
        #: Per env: how many steps had an instability since the world was made (never cleared).
        self.unstable_steps = np.zeros(self.num_envs, dtype=np.int64)
        # Hot-path handles, resolved once: MjData's arrays are views whose memory never
        # moves, and ``model.opt`` reads the live time step.
        self._data0 = self.datas[0]
        #: Per field, each env's MjData array (views made once: their memory never moves).
        self._arrays: dict[str, list[FloatArray]] = {}
        self._ctrl0 = self.ctrl[0]
        # the first env's views, for the one-env paths
        self._qvel0 = self._env_arrays("qvel")[0]
        self._qpos0 = self._env_arrays("qpos")[0]
        self._warmstart0 = self._env_arrays("qacc_warmstart")[0]
        self._data_ctrl0 = self._env_arrays("ctrl")[0]
        self._opt = model.opt
        #: Whether :meth:`_step_all` and :meth:`_step_single` update poses after stepping
        #: (off between substeps, and for :meth:`step`'s ``sync_poses=False``).
        self._sync_after_step = True
        self.forward()

    def _env_arrays(self, field: str) -> list[FloatArray]:
        """Each env's MjData array ``field`` (``qpos``, ``xpos``, ...): views made once per
        field, since reading the attribute makes a new view every time."""
        arrays = self._arrays.get(field)
        if arrays is None:
            arrays = self._arrays[field] = [getattr(data, field) for data in self.datas]
        return arrays

    # -- stepping ---------------------------------------------------------------------
    def _step_chunk(self, envs: range, nstep: int) -> None:
        model, datas, ctrl, sync = self.model, self.datas, self.ctrl, self._sync_after_step
        data_ctrl = self._env_arrays("ctrl")
        # the MuJoCo functions looked up once per chunk (not per env), _sync_poses written out
        mj_step, kinematics, camlight = mujoco.mj_step, mujoco.mj_kinematics, mujoco.mj_camlight
        for i in envs:
            data = datas[i]
            data_ctrl[i][:] = ctrl[i]
            mj_step(model, data, nstep)
            if sync:
                kinematics(model, data)
                camlight(model, data)

    def _step_all(self, nstep: int) -> None:
        """``nstep`` physics steps of every env, then (unless :attr:`_sync_after_step` is
        off) the poses at the stepped ``qpos``: needed after a control step's last
        substep only, since ``mj_step`` recomputes them from ``qpos`` first and substep
        hooks read joint state only."""
        if self.num_envs == 1:
            data = self._data0
            self._data_ctrl0[:] = self._ctrl0
            mujoco.mj_step(self.model, data, nstep)
            if self._sync_after_step:
                _sync_poses(self.model, data)
            return
        if self._pool is None:
            self._step_chunk(self._chunks[0], nstep)
            return
        futures = [self._pool.submit(self._step_chunk, chunk, nstep) for chunk in self._chunks[1:]]
        self._step_chunk(self._chunks[0], nstep)
        for future in futures:
            future.result()

    def step(self, before_substep: Callable[[int, int], None] | None = None, sync_poses: bool = True) -> None:
        """Advance every env by ``substeps`` physics steps with the current ``ctrl``.

        ``before_substep(i, substeps)``, when given, runs before substep ``i`` and may
        change ``self.ctrl`` (e.g. interpolated targets); without it all substeps run in
        one ``mj_step`` call per env. ``sync_poses=False`` leaves the poses where
        ``mj_step`` leaves them (one substep behind), for a caller whose next act is a
        joint-state write in every env, which recomputes them from the same ``qpos``
        (a moving base's wheels): the poses it ends with are the same either way.
        """
        if self.num_envs == 1 and before_substep is None:
            if sync_poses:
                self._step_single()
                return
            self._sync_after_step = False
            try:
                self._step_single()
            finally:
                self._sync_after_step = True
            return
        started = np.array([data.time for data in self.datas])
        if before_substep is None:
            self._sync_after_step = sync_poses
            try:
                self._step_all(self.substeps)
            finally:
                self._sync_after_step = True
        else:
            last = self.substeps - 1
            try:
                for i in range(self.substeps):
                    before_substep(i, self.substeps)
                    self._sync_after_step = sync_poses and i == last
                    self._step_all(1)
                    self._cache.clear()  # the hook reads the state of every substep
            finally:
                self._sync_after_step = True
        self._cache.clear()
        # MuJoCo's reset after a blow-up sets time back to 0, so a step that did not
        # advance time by all its substeps was reset (a cheap test; instability_counts()
        # reads the warnings). Joint speeds whose norm passes MAX_SPEED are flagged
        # before MuJoCo's own guard would reset the env, and so are NaN speeds: the
        # implicit integrators can leave them after MuJoCo's checks of a substep (its
        # guard resets the env only at the next step). ``not x <= y`` is true for NaN.
        #
        # Per env, the same comparisons as ``time < start + advance or not qvel @ qvel <=
        # MAX_SPEED**2``, batched: the times in one array; the squared norms (NumPy's dot
        # of each env's own qvel, as before) only when the fastest joint of any env could
        # bring one near the limit: ``qvel @ qvel <= nv max|qvel|^2``, so below half the
        # limit no rounding can flag it, and NaN / inf fail that screen. The gathered
        # speeds stay in the read cache (the observation reads them next).
        advance = (self.substeps - 0.5) * float(self.model.opt.timestep)
        flags = self.last_step_unstable
        np.less(np.array([data.time for data in self.datas]), started + advance, out=flags)
        speeds = self._gather("qvel")
        peak = float(np.abs(speeds).max(initial=0.0))
        if not peak * peak * speeds.shape[1] <= 0.5 * _MAX_SPEED_SQUARED:
            for env, qvel in enumerate(self._env_arrays("qvel")):
                if not qvel @ qvel <= _MAX_SPEED_SQUARED:
                    flags[env] = True
        if flags.any():
            self.unstable_steps += flags
        if RUNTIME:
            pass_on(RUNTIME, "BatchedWorld.step")

    def _step_single(self) -> None:
        """:meth:`step` of one env without substep hooks: the same MuJoCo calls (poses
        updated unless :attr:`_sync_after_step` is off) and the same instability test,
        without the per-env lists and loops."""
        data, model = self._data0, self.model
        started = data.time
        self._data_ctrl0[...] = self._ctrl0  # (``[...]``: the same copy as ``[:]``, without a slice)
        mujoco.mj_step(model, data, self.substeps)
        if self._sync_after_step:
            mujoco.mj_kinematics(model, data)
            mujoco.mj_camlight(model, data)
        self._cache.clear()
        qvel = self._qvel0
        # ``qvel.dot(qvel)``: the sum ``qvel @ qvel`` computes (both call NumPy's dot of
        # two vectors), without matmul's dispatch
        unstable = (
            data.time < started + (self.substeps - 0.5) * self._opt.timestep or not qvel.dot(qvel) <= _MAX_SPEED_SQUARED
        )
        self.last_step_unstable[0] = unstable
        if unstable:
            self.unstable_steps[0] += 1
        if RUNTIME:
            pass_on(RUNTIME, "BatchedWorld.step", stacklevel=3)

    def forward(self) -> None:
        """Recompute derived quantities (poses, contacts, sensors) of every env."""
        for data in self.datas:
            mujoco.mj_forward(self.model, data)
        self._cache.clear()
        if RUNTIME:
            pass_on(RUNTIME, "BatchedWorld.forward")

    def live_view(self, field: str) -> FloatArray | None:
        """One env only: its MjData array ``field`` (``"qpos"``, ``"qvel"``, ...) as a
        read-only ``(1, k)`` view that follows the simulation (it is never copied and
        stays valid for the world's life; read it, never keep it), for the one-env hot
        paths (no cached copy per step, unlike :attr:`qpos`); ``None`` with several envs."""
        if self.num_envs != 1:
            return None
        view: FloatArray = self._env_arrays(field)[0][None]
        view.setflags(write=False)
        return view

    # -- batched reads (read-only caches, invalidated by step / writes) ---------------
    def _gather(self, field: str) -> FloatArray:
        cached = self._cache.get(field)
        if cached is None:
            if self.num_envs == 1:
                cached = self._env_arrays(field)[0].copy()[None]
            else:
                # np.array of the equal-shaped views: the same copy as np.stack, without
                # its per-array checks (2 us instead of 7 for 16 envs)
                cached = np.array(self._env_arrays(field))
            cached.setflags(write=False)  # as flags.writeable = False, without the flags object
            self._cache[field] = cached
        return cached

    @property
    def qpos(self) -> FloatArray:
        """All joint positions, shape ``(num_envs, nq)`` (read-only)."""
        cached = self._cache.get("qpos")  # (the cache looked up here: read several times a step)
        return cached if cached is not None else self._gather("qpos")

    @property
    def qvel(self) -> FloatArray:
        """All joint velocities, shape ``(num_envs, nv)`` (read-only)."""
        return self._gather("qvel")

    @property
    def qacc_warmstart(self) -> FloatArray:
        """The constraint solver's warm start, shape ``(num_envs, nv)`` (rad/s^2, m/s^2;
        read-only): the accelerations the next step's solver starts from."""
        return self._gather("qacc_warmstart")

    @property
    def time(self) -> FloatArray:
        """Simulated time of each env in seconds, shape ``(num_envs,)``."""
        return np.array([d.time for d in self.datas])

    def invalidate(self) -> None:
        """Forget cached reads after writing into MjData directly."""
        self._cache.clear()

    def instability_counts(self) -> npt.NDArray[np.int64]:
        """How often MuJoCo found NaN / inf / huge values in each env, shape ``(num_envs,)``.

        MuJoCo does not raise on a blow-up: it warns and resets that env's state. A
        non-zero count means the model or the gains are unstable at this time step.
        Counts start at zero and are cleared by a full reset of the env (see
        :attr:`unstable_steps` for a count that is never cleared, and
        :attr:`last_step_unstable` for the last step).
        """
        kinds = _INSTABILITY_WARNINGS
        return np.array([sum(d.warning[k].number for k in kinds) for d in self.datas], dtype=np.int64)

    # -- reads of derived quantities ---------------------------------------------------
    def body_poses(self, body_ids: int | npt.ArrayLike) -> FloatArray:
        """World poses of bodies, shape ``(num_envs, k, 7)``: position (m), quaternion (w, x, y, z)."""
        if self.num_envs == 1 and type(body_ids) is int:  # the common read, without array indexing
            data = self.datas[0]
            single: FloatArray = np.concatenate((data.xpos[body_ids], data.xquat[body_ids])).reshape(1, 1, 7)
            return single
        if type(body_ids) is int:  # (a tool body's pose, read every step)
            ids = [body_ids]
        else:
            ids = [int(b) for b in np.asarray(body_ids, dtype=np.int64).reshape(-1)]
        out = np.empty((self.num_envs, len(ids), 7))
        xposes, xquats = self._env_arrays("xpos"), self._env_arrays("xquat")
        for k, body in enumerate(ids):
            # one body's rows of every env, copied in two NumPy calls
            out[:, k, :3] = [xpos[body] for xpos in xposes]
            out[:, k, 3:] = [xquat[body] for xquat in xquats]
        return out

    def site_poses(self, site_ids: npt.ArrayLike) -> FloatArray:
        """World poses of sites, shape ``(num_envs, k, 7)``: position (m), quaternion (w, x, y, z)."""
        sites = np.asarray(site_ids, dtype=np.int64).reshape(-1).tolist()
        out = np.empty((self.num_envs, len(sites), 7))
        site_xposes, site_xmats = self._env_arrays("site_xpos"), self._env_arrays("site_xmat")
        mat2quat = mujoco.mju_mat2Quat
        for k, site in enumerate(sites):
            out[:, k, :3] = [site_xpos[site] for site_xpos in site_xposes]  # every env's in one copy
            for quat, site_xmat in zip(out[:, k, 3:], site_xmats, strict=True):
                mat2quat(quat, site_xmat[site])
        return out

    def sensor_values(self, adr: npt.ArrayLike) -> FloatArray:
        """``sensordata`` entries at ``adr`` of every env, shape ``(num_envs, k)``."""
        index = np.asarray(adr, dtype=np.int64).reshape(-1)
        return np.array([data.sensordata[index] for data in self.datas], dtype=np.float64).reshape(self.num_envs, -1)

    def contact_forces(self, sources: Sequence[Sequence[int]], target: int) -> FloatArray:
        """World-frame force (N) each group of bodies in ``sources`` exerts on body
        ``target`` through their active contacts (normal and friction), shape
        ``(num_envs, len(sources), 3)``."""
        groups = [frozenset(int(b) for b in group) for group in sources]
        out = np.zeros((self.num_envs, len(groups), 3))
        wrench = np.zeros(6)
        model = self.model
        body_of = model.geom_bodyid
        for env, data in enumerate(self.datas):
            for i in range(data.ncon):
                contact = data.contact[i]
                b1, b2 = int(body_of[contact.geom1]), int(body_of[contact.geom2])
                if target not in (b1, b2):
                    continue
                other = b2 if b1 == target else b1
                for k, group in enumerate(groups):
                    if other in group:
                        mujoco.mj_contactForce(model, data, i, wrench)  # contact frame, acting on geom2
                        force = contact.frame.reshape(3, 3).T @ wrench[:3]
                        out[env, k] += force if b1 == other else -force
        return out

    def camera_poses(self, camera_id: int) -> FloatArray:
        """World pose of a camera in every env as a 4x4 matrix, shape ``(num_envs, 4, 4)``
        (MuJoCo's ``cam_xpos`` / ``cam_xmat``: -z is the viewing direction)."""
        out = np.zeros((self.num_envs, 4, 4))
        for pose, data in zip(out, self.datas, strict=True):
            pose[:3, :3] = data.cam_xmat[camera_id].reshape(3, 3)
            pose[:3, 3] = data.cam_xpos[camera_id]
            pose[3, 3] = 1.0
        return out

    def physics_sources(self, env_ids: Sequence[int] | None = None) -> list[mujoco.MjData]:
        """Each env's simulated MjData (of :attr:`model`), for reading (contacts,
        inspection); never to be written."""
        return list(self.datas) if env_ids is None else [self.datas[i] for i in env_ids]

    def render_sources(self, env_ids: Sequence[int] | None = None) -> list[mujoco.MjData]:
        """What a ``mujoco.Renderer`` of :attr:`render_model` draws for each env: the
        simulated MjData itself, or (with a separate render model) an MjData of the
        render model holding the env's current state (joint state, actuator state,
        mocap poses, time; ``mj_forward`` derives the rest). For renderers only."""
        ids = range(self.num_envs) if env_ids is None else env_ids
        if self._mirror is None:
            return [self.datas[i] for i in ids]
        return self._mirror.fill(self.datas, ids)

    # -- writes ---------------------------------------------------------------------------
    def write_joint_state(
        self,
        env_ids: npt.ArrayLike,
        qpos_adr: npt.ArrayLike,
        qpos: FloatArray,
        dof_adr: npt.ArrayLike,
        qvel: FloatArray,
        forward: bool = True,
        warmstart: FloatArray | None = None,
    ) -> None:
        """Set ``qpos[qpos_adr]`` and ``qvel[dof_adr]`` of the ``n`` envs ``env_ids``
        (``(n,)`` ints): ``qpos`` ``(n, len(qpos_adr))`` (rad, m, unit quaternions) and
        ``qvel`` ``(n, len(dof_adr))`` (rad/s, m/s), one row per env in ``env_ids`` order;
        copy the ``ctrl`` buffer into those envs' controls, clear the solver's warm start
        (or, given ``warmstart`` ``(n, len(dof_adr))`` in rad/s^2 and m/s^2, set that of
        ``dof_adr`` and keep the other dofs': a saved state restored) and recompute derived
        quantities (``forward=False``: body and camera poses only, as after a step:
        ``mj_kinematics``, ``mj_camlight``)."""
        qa, da = np.asarray(qpos_adr, dtype=np.int64), np.asarray(dof_adr, dtype=np.int64)
        model = self.model
        if self.num_envs == 1 and env_ids.__class__ is np.ndarray and env_ids.shape == (1,) and env_ids[0] == 0:
            # the one env (the per-step writes of wheels, kinematic bases and held legs):
            # the same writes and calls, without the id conversion, the loop and the
            # helper calls (_derive written out)
            data = self._data0
            self._qpos0[qa] = qpos[0]
            self._qvel0[da] = qvel[0]
            if warmstart is None:
                self._warmstart0.fill(0.0)
            else:
                self._warmstart0[da] = warmstart[0]
            self._data_ctrl0[...] = self._ctrl0  # (the same copy as ``[:]``, without a slice)
            if forward:
                mujoco.mj_forward(model, data)
            else:
                mujoco.mj_kinematics(model, data)
                mujoco.mj_camlight(model, data)
            self._cache.clear()
            return
        ids = self._ids(env_ids, "BatchedWorld.write_joint_state")
        datas, ctrl = self.datas, self.ctrl
        data_qpos, data_qvel = self._env_arrays("qpos"), self._env_arrays("qvel")
        warmstarts, data_ctrl = self._env_arrays("qacc_warmstart"), self._env_arrays("ctrl")
        # the MuJoCo functions looked up once (not per env), _derive written out
        mj_forward, kinematics, camlight = mujoco.mj_forward, mujoco.mj_kinematics, mujoco.mj_camlight
        for row, env in enumerate(ids):
            data_qpos[env][qa] = qpos[row]
            data_qvel[env][da] = qvel[row]
            if warmstart is None:
                warmstarts[env].fill(0.0)
            else:
                warmstarts[env][da] = warmstart[row]
            data_ctrl[env][:] = ctrl[env]
            data = datas[env]
            if forward:
                mj_forward(model, data)
            else:
                kinematics(model, data)
                camlight(model, data)
        self._cache.clear()

    def write_joint_row(
        self, qpos_adr: IntArray, qpos: FloatArray, dof_adr: IntArray, qvel: FloatArray, forward: bool = True
    ) -> None:
        """One env only: :meth:`write_joint_state` of env 0, for the per-step writes
        (wheels, kinematic bases, held legs) whose addresses are resolved once:
        ``qpos_adr`` and ``dof_adr`` int64 arrays, ``qpos`` ``(len(qpos_adr),)`` (rad, m)
        and ``qvel`` ``(len(dof_adr),)`` (rad/s, m/s), one row each. The same writes and
        MuJoCo calls in the same order (the controls copied, the solver's warm start
        cleared, then ``mj_forward``, or ``mj_kinematics`` and ``mj_camlight`` with
        ``forward=False``), without converting the addresses and checking env ids.
        Raises :class:`StateError` with several envs, or where ``qpos`` / ``qvel`` is not
        one value per address (nothing written)."""
        if self.num_envs != 1:
            raise StateError(
                f"BatchedWorld.write_joint_row: expected a world of one env, got {self.num_envs} envs; "
                "use write_joint_state."
            )
        if qpos.shape != qpos_adr.shape or qvel.shape != dof_adr.shape:
            raise StateError(
                "BatchedWorld.write_joint_row: expected qpos of shape "
                f"{qpos_adr.shape} and qvel of shape {dof_adr.shape} (one value per address), "
                f"got {np.shape(qpos)} and {np.shape(qvel)}; nothing written."
            )
        data = self._data0
        self._qpos0[qpos_adr] = qpos
        self._qvel0[dof_adr] = qvel
        self._warmstart0.fill(0.0)
        self._data_ctrl0[...] = self._ctrl0  # (the same copy as ``[:]``, without a slice)
        if forward:
            mujoco.mj_forward(self.model, data)
        else:
            mujoco.mj_kinematics(self.model, data)
            mujoco.mj_camlight(self.model, data)
        self._cache.clear()

    def _ids(self, env_ids: npt.ArrayLike, where: str) -> list[int]:
        """``env_ids`` as a list of ints, each in ``[0, num_envs)`` (a negative id would
        index the env list from its end): cheap, for the per-step writes' batched path."""
        ids: list[int] = np.asarray(env_ids, dtype=np.int64).reshape(-1).tolist()
        if ids and (min(ids) < 0 or max(ids) >= self.num_envs):
            raise StateError(f"{where}: expected env ids in [0, {self.num_envs}), got {ids}.")
        return ids

    def reset_envs(self, env_ids: npt.ArrayLike, state: FloatArray) -> None:
        """Reset the envs ``env_ids`` (``(n,)`` ints) to one integration ``state``
        ``(state_size,)`` (MuJoCo's ``mjSTATE_INTEGRATION`` layout: time in s, ``qpos``,
        ``qvel``, activations, ...) and take their controls as the ``ctrl`` buffer's rows
        (MuJoCo's warning counters are cleared too)."""
        for env in self._ids(env_ids, "BatchedWorld.reset_envs"):
            data = self.datas[env]
            mujoco.mj_resetData(self.model, data)
            mujoco.mj_setState(self.model, data, state, STATE_SPEC)
            self.ctrl[env] = data.ctrl
        self._cache.clear()

    def sync_ctrl(self, env_ids: npt.ArrayLike | None = None) -> None:
        """Copy the ``ctrl`` buffer's rows (``(num_envs, nu)``, the actuators' units) into
        the controls of envs ``env_ids`` (``(n,)`` ints; all by default) now, before the
        next step would, and run a forward pass so that it sees the actuator forces."""
        ids = range(self.num_envs) if env_ids is None else self._ids(env_ids, "BatchedWorld.sync_ctrl")
        for env in ids:
            self.datas[env].ctrl[:] = self.ctrl[env]
            mujoco.mj_forward(self.model, self.datas[env])
        self._cache.clear()

    # -- exact state ------------------------------------------------------------------
    def get_state(self) -> FloatArray:
        """The integration state of every env, shape ``(num_envs, state_size)``."""
        out = np.empty((self.num_envs, self.state_size))
        for i, data in enumerate(self.datas):
            mujoco.mj_getState(self.model, data, out[i], STATE_SPEC)
        return out

    def check_state(self, state: npt.ArrayLike, where: str = "BatchedWorld.set_state") -> FloatArray:
        """Validate a state array (shape and finiteness) without applying it."""
        array = np.asarray(state)
        expected = (self.num_envs, self.state_size)
        if array.shape != expected:
            raise StateError(f"{where}: expected a physics state of shape {expected}, got {array.shape}.")
        if array.dtype.kind not in "fiu":
            raise StateError(f"{where}: expected a float array, got dtype {array.dtype}.")
        array = array.astype(np.float64, copy=False)
        if not np.all(np.isfinite(array)):
            raise StateError(f"{where}: the physics state contains NaN or inf.")
        nq, nv = self.model.nq, self.model.nv
        check_speeds(array[:, 1 + nq : 1 + nq + nv], where, "the physics state's qvel")  # after time and qpos
        return array

    def get_sleep_state(self) -> npt.NDArray[np.int64]:
        """Each env's island-sleep state, shape ``(num_envs, sleep_size)``: the per-tree
        counters (``MjData.tree_asleep``) and what MuJoCo derives from them during a step
        (``SLEEP_ARRAYS``, ``SLEEP_COUNTS``). MuJoCo's integration state leaves these out
        and ``mj_forward`` does not rebuild them; with sleeping enabled
        (``mjENBL_SLEEP``) an exact continuation needs them all."""
        out = np.empty((self.num_envs, self.sleep_size), dtype=np.int64)
        for row, data in zip(out, self.datas, strict=True):
            row[:] = np.concatenate(
                [getattr(data, name).reshape(-1) for name in SLEEP_ARRAYS]
                + [np.array([getattr(data, name) for name in SLEEP_COUNTS])]
            )
        return out

    def sleep_ranges(self) -> list[tuple[str, int, int, int]]:
        """``(name, size, lowest, highest)`` of each entry of a :meth:`get_sleep_state`
        row, in order (MuJoCo's ``mjData`` documentation): ``tree_asleep`` ``< 0`` an
        awake tree's countdown from ``-(1 + mjMINAWAKE)``, ``>= 0`` the next tree of its
        sleep cycle; ``tree_awake`` 0 / 1; ``body_awake`` an ``mjtSleepState`` (-1
        static, 0 asleep, 1 awake); the ``*_ind`` index lists of bodies / dofs; the
        counts (``n*_awake``) up to the number of trees, bodies or dofs."""
        ntree, nbody, nv = int(self.model.ntree), int(self.model.nbody), int(self.model.nv)
        return [
            ("tree_asleep", ntree, _AWAKE_COUNTDOWN, ntree - 1),
            ("tree_awake", ntree, 0, 1),
            ("body_awake", nbody, int(mujoco.mjtSleepState.mjS_STATIC), int(mujoco.mjtSleepState.mjS_AWAKE)),
            ("body_awake_ind", nbody, 0, nbody - 1),
            ("dof_awake_ind", nv, 0, nv - 1),
            ("parent_awake_ind", nbody, 0, nbody - 1),
            ("nbody_awake", 1, 0, nbody),
            ("nparent_awake", 1, 0, nbody),
            ("ntree_awake", 1, 0, ntree),
            ("nv_awake", 1, 0, nv),
        ]

    def check_sleep_state(self, state: npt.ArrayLike, where: str = "BatchedWorld.set_state") -> npt.NDArray[np.int64]:
        """Validate :meth:`get_sleep_state`'s array without applying it: its shape, whole
        numbers, every entry within :meth:`sleep_ranges`, and the sleeping trees'
        ``tree_asleep`` entries a permutation of the sleeping trees (closed sleep cycles;
        MuJoCo follows them). Raises :class:`StateError` naming the entry and env."""
        array = np.asarray(state)
        expected = (self.num_envs, self.sleep_size)
        if array.shape != expected or array.dtype.kind not in "iu":
            raise StateError(
                f"{where}: expected the sleep state as integers of shape {expected}, got "
                f"{array.dtype} of shape {array.shape}."
            )
        array = array.astype(np.int64, copy=False)
        start = 0
        for name, size, lowest, highest in self.sleep_ranges():
            block = array[:, start : start + size]
            outside = (block < lowest) | (block > highest)
            if outside.any():
                env, k = (int(i) for i in np.argwhere(outside)[0])
                raise StateError(
                    f"{where}: expected the sleep state's {name} entries in [{lowest}, {highest}], got "
                    f"{int(block[env, k])} at {name}[{k}] in env {env} (columns {start}:{start + size} of the sleep "
                    "state from get_state())."
                )
            start += size
        ntree = int(self.model.ntree)
        for env, cycles in enumerate(array[:, :ntree]):
            asleep = np.flatnonzero(cycles >= 0)
            if not np.array_equal(np.sort(cycles[asleep]), asleep):
                raise StateError(
                    f"{where}: expected the sleeping trees' tree_asleep entries (the next tree of each one's sleep "
                    f"cycle) to be a permutation of the sleeping trees {asleep.tolist()}, got "
                    f"{cycles[asleep].tolist()} in env {env}."
                )
        return array

    def _set_sleep_state(self, data: mujoco.MjData, row: npt.NDArray[np.int64]) -> None:
        start = 0
        for name in SLEEP_ARRAYS:
            target = getattr(data, name)
            target[:] = row[start : start + target.size]
            start += target.size
        for k, name in enumerate(SLEEP_COUNTS):
            setattr(data, name, int(row[start + k]))

    def get_sensor_state(self) -> FloatArray:
        """Each env's sensor readings, ``(num_envs, nsensordata)``: what the last step
        measured (a step ends with poses updated, not sensors), which the forward pass
        of a restore would recompute at the restored state instead."""
        return np.array([data.sensordata for data in self.datas], dtype=np.float64).reshape(self.num_envs, -1)

    def check_sensor_state(self, state: npt.ArrayLike, where: str = "BatchedWorld.set_state") -> FloatArray:
        """Validate :meth:`get_sensor_state`'s array (shape, finite) without applying it."""
        return check_array(state, (self.num_envs, int(self.model.nsensordata)), "sensor readings", where)

    def set_state(
        self, state: npt.ArrayLike, sleep: npt.ArrayLike | None = None, sensors: npt.ArrayLike | None = None
    ) -> None:
        """Restore :meth:`get_state`'s ``(num_envs, state_size)`` (and, when given,
        :meth:`get_sleep_state`'s ``(num_envs, sleep_size)`` integers and
        :meth:`get_sensor_state`'s ``(num_envs, nsensordata)`` readings) in every env; the
        continuation is bit-identical, and so are the observations (sensor readings as
        saved)."""
        array = self.check_state(state)
        counters = None if sleep is None else self.check_sleep_state(sleep)
        readings = None if sensors is None else self.check_sensor_state(sensors)
        for i, data in enumerate(self.datas):
            mujoco.mj_setState(self.model, data, array[i], STATE_SPEC)
            self.ctrl[i] = data.ctrl
        self.forward()
        if counters is not None and self.model.opt.enableflags & _SLEEP_FLAG:
            # after the forward pass, which advances the sleep countdowns as a step's
            # would: the continuation starts from the saved ones (without sleeping
            # enabled there is nothing asleep to restore)
            for data, row in zip(self.datas, counters, strict=True):
                self._set_sleep_state(data, row)
        if readings is not None:
            for data, row in zip(self.datas, readings, strict=True):
                data.sensordata[:] = row
            self._cache.clear()

    def close(self) -> None:
        """Stop the stepping threads; the world is :attr:`closed` from then on."""
        self.closed = True
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def __del__(self) -> None:
        pool = getattr(self, "_pool", None)
        if pool is not None:
            pool.shutdown(wait=False)
