"""A bound robot's joint state: reads, checked writes (resets, state restores) and
reset noise, all through the simulation backend.

Ball joints are handled as unit quaternions everywhere: written qpos must hold unit
quaternions (they are normalized, a zero one is rejected), and reset noise turns them
by a random rotation instead of adding to their entries.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import JointKind, RobotIndex
from robot_agents.errors import StateError
from robot_agents.limits import check_speeds
from robot_agents.validation import POSE_AXES, ball_angles, check_env_ids, check_quat_rows, outside_limits

if TYPE_CHECKING:
    from robot_agents.keyframe import ResolvedKeyframe
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]

#: How far a restored state's joints may lie beyond their limits (rad or m). Contacts
#: and limit constraints are soft, so a simulated state can be outside: saturated
#: random actions push built-in robots up to 0.18 rad past a limit (the Unitree Go2;
#: the Panda 0.13 in ``pd_ee_pose``, the WidowX AI 0.13), so a state saved by
#: :meth:`Agent.get_state` must restore there. A joint a whole radian or metre past a
#: limit is a mistake instead (degrees, another robot's joints).
STATE_LIMIT_MARGIN = 1.0


def mounted_pose(mount: FloatArray, base: FloatArray) -> FloatArray:
    """The world pose ``(7,)`` of a free base given as ``base`` ``(7,)`` relative to a
    mount at ``mount`` ``(7,)`` (both ``x, y, z`` in m, then a unit quaternion ``w, x, y,
    z``): ``mount * base`` with MuJoCo's quaternion functions, not renormalized."""
    pose = np.empty(7)
    mujoco.mju_rotVecQuat(pose[:3], base[:3], mount[3:])
    pose[:3] += mount[:3]
    mujoco.mju_mulQuat(pose[3:], mount[3:], base[3:])
    return pose


@dataclass(frozen=True)
class JointWrite:
    """A checked joint-state write (:meth:`JointState.prepare`): rows of ``qpos`` at
    model addresses ``qpos_adr`` and of ``qvel`` at ``dof_adr``, for envs ``ids``."""

    ids: IntArray
    qpos_adr: IntArray
    qpos: FloatArray
    dof_adr: IntArray
    qvel: FloatArray


@dataclass(frozen=True)
class StateWrite:
    """:meth:`Agent.set_state`'s joint part, checked (every array ``(num_envs, k)``):
    ``qpos`` / ``qvel`` of the joints, a free base's ``base`` pose and ``base_velocity``,
    the solver's ``warmstart`` of the robot's dofs (``None``: not in the state)."""

    qpos: FloatArray
    qvel: FloatArray
    base: FloatArray | None
    base_velocity: FloatArray | None
    warmstart: FloatArray | None


class JointState:
    """Joint reads and writes of one robot (``index``) in ``world``.

    ``mount_pose`` ``(7,)`` is where the scene mounted the robot: a free robot's keyframe
    base poses are relative to it."""

    def __init__(self, world: SimBackend, index: RobotIndex, mount_pose: FloatArray, owner: str) -> None:
        self.world = world
        self.index = index
        self.mount_pose = mount_pose
        self.owner = owner
        self.num_envs = world.num_envs
        free = index.free_joint
        self._free_qpos = np.arange(free.qpos_adr, free.qpos_adr + 7) if free is not None else np.zeros(0, np.int64)
        self._free_dofs = np.arange(free.dof_adr, free.dof_adr + 6) if free is not None else np.zeros(0, np.int64)
        #: The dofs of the robot's state: its joints', then a free base's.
        self._state_dofs = np.concatenate([np.asarray(index.dof_adr, dtype=np.int64), self._free_dofs])
        self._balls = [(j.qpos_start, j.dof_start) for j in index.joints if j.kind is JointKind.BALL]
        self._limited_balls = [j for j in index.joints if j.kind is JointKind.BALL and j.limited]

    # -- input checks -----------------------------------------------------------------------
    def env_ids(self, env_ids: Any, where: str) -> IntArray:
        """``env_ids`` (``None``: all) as distinct ints in ``[0, num_envs)``."""
        return check_env_ids(env_ids, self.num_envs, where)

    def batch(self, value: Any, n_envs: int, size: int, what: str, where: str) -> FloatArray:
        """``value`` as finite float64 ``(n_envs, size)`` (a ``(size,)`` row applies to all)."""
        try:
            array = np.asarray(value)
        except Exception:  # whatever the input's own __array__ raises
            raise StateError(f"{where}: expected numeric {what}, got {type(value).__name__}.") from None
        if array.dtype.kind not in "fiu":
            raise StateError(f"{where}: expected numeric {what}, got dtype {array.dtype}.")
        if array.shape == (size,):
            array = np.broadcast_to(array, (n_envs, size))
        if array.shape != (n_envs, size):
            raise StateError(f"{where}: expected {what} of shape ({size},) or ({n_envs}, {size}), got {array.shape}.")
        array = array.astype(np.float64)
        if not np.all(np.isfinite(array)):
            bad = np.argwhere(~np.isfinite(array))
            raise StateError(
                f"{where}: {what} contains NaN or inf at (env, index) {bad[:4].tolist()}"
                f"{f' and {len(bad) - 4} more' if len(bad) > 4 else ''}; expected finite values."
            )
        return array

    def checked_qpos(self, value: Any, n_envs: int, where: str) -> FloatArray:
        """Joint positions ``(n_envs, nq)`` within the limits, ball quaternions normalized."""
        qpos = self.batch(value, n_envs, self.index.nq, "qpos", where)
        self.check_within_limits(qpos, np.arange(self.index.nq), where)
        for start, norms in self._ball_norms(qpos, where):
            qpos[:, start : start + 4] /= norms[:, None]
        for joint in self._limited_balls:
            angles = ball_angles(qpos[:, joint.qpos_start : joint.qpos_start + 4])
            beyond = np.flatnonzero(angles > joint.range[1] + 1e-9)
            if len(beyond):
                env = int(beyond[0])
                raise StateError(
                    f"{where}: ball joint {joint.name!r} turned {angles[env]:.6g} rad from its reference in env "
                    f"{env}, beyond its limit {joint.range[1]:.6g} rad."
                )
        return qpos

    def check_within_limits(self, rows: FloatArray, entries: IntArray, where: str) -> None:
        """Raise :class:`StateError` when a value of ``rows`` ``(n, k)``, for the robot's
        ``qpos`` ``entries`` ``(k,)``, lies outside its joint's limits (by more than 1e-9)."""
        low, high = self.index.qpos_limits[entries, 0], self.index.qpos_limits[entries, 1]
        outside = outside_limits(rows, low, high)
        if np.any(outside):
            env, k = np.argwhere(outside)[0]
            entry = int(entries[k])
            joint = next(j for j in self.index.joints if j.qpos_start <= entry < j.qpos_start + j.nq)
            raise StateError(
                f"{where}: qpos of joint {joint.name!r} is {rows[env, k]:.6g}, outside its limits "
                f"[{low[k]:.6g}, {high[k]:.6g}]."
            )

    def _ball_norms(self, qpos: FloatArray, where: str) -> list[tuple[int, FloatArray]]:
        """Each ball joint's ``qpos`` start and its quaternions' norms ``(n,)`` in ``qpos``
        ``(n, nq)``; :class:`StateError` for a zero quaternion."""
        out = []
        for start, _ in self._balls:
            what = f"qpos {start}-{start + 3} (a ball joint's (w, x, y, z))"
            out.append((start, check_quat_rows(qpos[:, start : start + 4], what, where)))
        return out

    # -- reads ----------------------------------------------------------------------------
    @property
    def qpos(self) -> FloatArray:
        qpos: FloatArray = self.world.qpos[:, self.index.qpos_sel].copy()
        return qpos

    @property
    def qvel(self) -> FloatArray:
        qvel: FloatArray = self.world.qvel[:, self.index.dof_sel].copy()
        return qvel

    @property
    def has_free_base(self) -> bool:
        """Whether the robot's root moves on a free joint (a legged robot, a floating hand)."""
        return len(self._free_dofs) > 0

    @property
    def base_velocity(self) -> FloatArray:
        """A free base's velocity ``(num_envs, 6)``: linear (m/s, world frame), then
        angular (rad/s, the base's own frame), MuJoCo's free-joint ``qvel`` (a copy)."""
        velocity: FloatArray = self.world.qvel[:, self._free_dofs].copy()
        return velocity

    @property
    def warmstart(self) -> FloatArray:
        """The constraint solver's warm start of the robot's dofs ``(num_envs, nv + 6)``
        for a free base, else ``(num_envs, nv)`` (rad/s^2, m/s^2: its joints', then the
        free base's; a copy)."""
        warm: FloatArray = self.world.qacc_warmstart[:, self._state_dofs].copy()
        return warm

    def views(self) -> list[FloatArray]:
        """``qpos`` and ``qvel`` as read-only views where possible."""
        return [self.world.qpos[:, self.index.qpos_sel], self.world.qvel[:, self.index.dof_sel]]

    def configurations(self, qpos: npt.ArrayLike | None, where: str) -> FloatArray:
        """Full scene configurations ``(num_envs, nq_model)``: the measured state with this
        robot's joints replaced by ``qpos`` ``(nq,)`` or ``(num_envs, nq)`` when given."""
        full = np.array(self.world.qpos, dtype=np.float64)
        if qpos is not None:
            full[:, self.index.qpos_adr] = self.batch(qpos, self.num_envs, self.index.nq, "qpos", where)
        return full

    # -- writes ---------------------------------------------------------------------------
    def keyframe_base(self, base: FloatArray) -> FloatArray:
        """World pose of a keyframe's base ``(7,)`` given relative to the mount."""
        return mounted_pose(self.mount_pose, base)

    def keyframe_base_vel(self, base_vel: FloatArray) -> FloatArray:
        """World velocity of a free base ``(6,)`` (MuJoCo's free joint: linear in the world,
        angular in the body's frame) from a keyframe's, whose linear part is in the mount's
        frame: turned by the mount's orientation."""
        if not np.any(base_vel):
            return np.zeros(6)  # (exact zeros: no -0.0 from the turn)
        turned = np.array(base_vel, dtype=np.float64)
        mujoco.mju_rotVecQuat(turned[:3], np.asarray(base_vel[:3], dtype=np.float64), self.mount_pose[3:])
        return turned

    def prepare(
        self,
        ids: IntArray,
        qpos: Any,
        qvel: Any,
        frame: ResolvedKeyframe | None,
        where: str,
    ) -> JointWrite:
        """Check a write of joints (and, with a keyframe, a free base) of ``ids`` and
        return it, ready for :meth:`apply`; nothing is written."""
        n = len(ids)
        source_qpos = qpos if qpos is not None else frame.qpos if frame is not None else None
        new_qpos = self.checked_qpos(source_qpos, n, where)
        if qvel is not None:
            new_qvel = self.batch(qvel, n, self.index.nv, "qvel", where)
            check_speeds(new_qvel, where, "qvel")
        else:
            row = frame.qvel if frame is not None else np.zeros(self.index.nv)
            new_qvel = np.broadcast_to(row, (n, self.index.nv))
        qpos_adr, dof_adr = self.index.qpos_adr, self.index.dof_adr
        if frame is not None and len(self._free_qpos):
            base = np.broadcast_to(self.keyframe_base(frame.base), (n, 7))
            new_qpos = np.concatenate([new_qpos, base], axis=1)
            base_vel = np.broadcast_to(self.keyframe_base_vel(frame.base_vel), (n, 6))
            new_qvel = np.concatenate([new_qvel, base_vel], axis=1)
            qpos_adr = np.concatenate([qpos_adr, self._free_qpos])
            dof_adr = np.concatenate([dof_adr, self._free_dofs])
        return JointWrite(ids, qpos_adr, new_qpos, dof_adr, np.asarray(new_qvel))

    def apply(self, write: JointWrite) -> None:
        """Write what :meth:`prepare` checked."""
        self.world.write_joint_state(write.ids, write.qpos_adr, write.qpos, write.dof_adr, write.qvel)

    def perturbed(self, env_ids: IntArray, std: float, rng: np.random.Generator) -> FloatArray:
        """Measured ``qpos`` of ``env_ids`` plus noise (``std`` rad or m), clipped to the limits."""
        qpos = self.qpos[env_ids]
        noise = rng.normal(0.0, std, (len(env_ids), self.index.nv))
        scalar = [j for j in self.index.joints if j.kind in (JointKind.HINGE, JointKind.SLIDE)]
        for joint in scalar:
            qpos[:, joint.qpos_start] += noise[:, joint.dof_start]
        for q_start, v_start in self._balls:
            for row in range(len(env_ids)):
                quat = qpos[row, q_start : q_start + 4].copy()
                mujoco.mju_quatIntegrate(quat, noise[row, v_start : v_start + 3], 1.0)
                qpos[row, q_start : q_start + 4] = quat
        clipped: FloatArray = np.clip(qpos, self.index.qpos_limits[:, 0], self.index.qpos_limits[:, 1])
        return clipped

    def check_state(self, state: Any, where: str) -> StateWrite:
        """Validate :meth:`Agent.get_state`'s joint part; returns what :meth:`write_state` takes."""
        if not isinstance(state, Mapping):
            raise StateError(f"{where}: expected a dict from get_state(), got {type(state).__name__}.")
        missing = [k for k in ("qpos", "qvel", "control_mode", "controller") if k not in state]
        if missing:
            raise StateError(f"{where}: expected keys qpos, qvel, control_mode, controller; missing {missing}.")
        qpos = self.batch(state["qpos"], self.num_envs, self.index.nq, "qpos", where)
        low, high = self.index.qpos_limits[:, 0], self.index.qpos_limits[:, 1]
        far = outside_limits(qpos, low, high, STATE_LIMIT_MARGIN)
        if np.any(far):
            env, entry = np.argwhere(far)[0]
            raise StateError(
                f"{where}: qpos entry {entry} of env {env} is {qpos[env, entry]:.6g}, more than {STATE_LIMIT_MARGIN} "
                f"beyond its limits [{low[entry]:.6g}, {high[entry]:.6g}] (rad or m; degrees, or another robot's joints?)."
            )
        self._ball_norms(qpos, where)
        qvel = self.batch(state["qvel"], self.num_envs, self.index.nv, "qvel", where)
        check_speeds(qvel, where, "qvel")
        base = self.batch(state["base_pose"], self.num_envs, 7, "base_pose", where) if "base_pose" in state else None
        if base is not None and len(self._free_qpos):
            norms = check_quat_rows(base[:, 3:], f"base_pose {POSE_AXES}", where)
            # a restored get_state() quaternion is unit to rounding and kept bit for bit
            off = np.abs(norms - 1.0) > 1e-9
            base[off, 3:] /= norms[off, None]
        velocity = None
        if "base_velocity" in state:  # an older state without it leaves the base moving as it is
            if not self.has_free_base:
                raise StateError(
                    f"{where}: got a base_velocity, but this robot has no free base (its root is fixed or moves "
                    "on joints of its own, in qvel)."
                )
            velocity = self.batch(state["base_velocity"], self.num_envs, 6, "base_velocity", where)
            check_speeds(velocity, where, "base_velocity")
        warm = None
        if "warmstart" in state:  # an older state without it: the warm start is cleared, as at a reset
            warm = self.batch(state["warmstart"], self.num_envs, len(self._state_dofs), "warmstart", where)
        return StateWrite(qpos, qvel, base, velocity, warm)

    def write_state(self, write: StateWrite) -> None:
        """Write joint state (a free base's pose and velocity, the solver's warm start of
        the robot's dofs) of every env, exactly as given; without a warm start every dof's
        is cleared, as at a reset."""
        qpos, qvel, qpos_adr, dof_adr = write.qpos, write.qvel, self.index.qpos_adr, self.index.dof_adr
        if write.base is not None and len(self._free_qpos):
            qpos = np.concatenate([qpos, write.base], axis=1)
            qpos_adr = np.concatenate([qpos_adr, self._free_qpos])
        velocity = write.base_velocity
        if velocity is None and write.warmstart is not None and self.has_free_base:
            velocity = self.base_velocity  # the warm start covers the base's dofs: its velocity stays
        if velocity is not None:
            qvel = np.concatenate([qvel, velocity], axis=1)
            dof_adr = self._state_dofs
        self.world.write_joint_state(np.arange(self.num_envs), qpos_adr, qpos, dof_adr, qvel, warmstart=write.warmstart)
