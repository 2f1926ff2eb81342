"""A bound robot's mobile base in Habitat's terms: where it stands on the ground
(``base_pos``) and which way it faces (``base_rot``, yaw about world +z), read and
set per env. Works for a ``Base`` part on planar joints (x and y slides, a yaw hinge)
and for a floating root."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import RobotIndex
from robot_agents.errors import ConfigError, StateError, did_you_mean
from robot_agents.kinematics.rotations import quat_to_yaw, z_rotation_angle
from robot_agents.validation import check_bool, check_state_keys, outside_limits

if TYPE_CHECKING:
    from robot_agents.agent.joint_state import JointState
    from robot_agents.parts.declaration import Base
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]


def wrap_angle(angle: FloatArray) -> FloatArray:
    """Angles wrapped to ``(-pi, pi]``."""
    wrapped: FloatArray = np.pi - np.mod(np.pi - angle, 2 * np.pi)
    return wrapped


def wrap_angle_float(angle: float) -> float:
    """:func:`wrap_angle` of one Python float, bit for bit (Python's ``%`` and NumPy's
    ``mod`` are both C's ``fmod`` with the result moved to the divisor's sign), without
    NumPy's per-call cost."""
    return math.pi - (math.pi - angle) % (2 * math.pi)


#: A kinematic move from a pose already in contact is refused when it takes the base more
#: than this much deeper (m) than it was: moves out of (or along) the contact go through.
#: (From a pose in no contact, any touch refuses the move.)
DEEPER = 1e-9


class MobileBase:
    """The base of one robot: planar joints ``(x, y, yaw)`` of a ``Base`` part, or the
    root's free joint. Poses are in the world frame; planar joints are taken relative
    to where the scene mounted the robot."""

    def __init__(
        self,
        world: SimBackend,
        index: RobotIndex,
        state: JointState,
        planar: tuple[str, ...] | None,
        owner: str,
        part: Base | None = None,
        held: Sequence[str] = (),
    ) -> None:
        self.world = world
        self.index = index
        self.state = state
        self.owner = owner
        self.planar = tuple(index.joint(j, owner) for j in planar) if planar else None
        self.wheels = tuple(index.joint(j, owner) for j in part.wheels) if part is not None else ()
        self.dynamics = part.dynamics if part is not None else "dynamic"  # (sets _moves: planar and wheels first)
        self.refuse_collisions = part.refuse_collisions if part is not None else False
        self.wheel_radius = part.wheel_radius if part is not None else 0.0
        self.wheel_separation = part.wheel_separation if part is not None else 0.0
        #: Joints pinned while the base moves kinematically (held legs): rigid with it.
        self._held_ids = frozenset(index.joint(j, owner).id for j in held)
        # Addresses of the per-step reads and writes, resolved once.
        self._planar_adr = np.array([j.qpos_adr for j in self.planar or ()], dtype=np.int64)
        self._planar_dofs = np.array([j.dof_adr for j in self.planar or ()], dtype=np.int64)
        self._wheel_qadr = np.array([w.qpos_adr for w in self.wheels], dtype=np.int64)
        self._wheel_dadr = np.array([w.dof_adr for w in self.wheels], dtype=np.int64)
        self._all_envs = np.arange(world.num_envs)
        self._planar_list = [int(a) for a in self._planar_adr]
        self._wheel_qlist = [int(a) for a in self._wheel_qadr]
        self._half_wheels = len(self.wheels) // 2  # the first half roll on the left
        # one env: the wheel angles (rad) and speeds (rad/s) of a step's write, ``(1, wheels)``
        self._wheel_angles = np.zeros((1, len(self.wheels)))
        self._wheel_speeds = np.zeros((1, len(self.wheels)))
        # one env: the planar joints' positions (m, m, rad) of a kinematic move, ``(1, 3)``
        self._planar_end = np.zeros((1, len(self._planar_list)))
        # one env: the wheels' and the planar joints' state written as rows
        # (write_joint_row: addresses resolved here, no env ids)
        self._write_rows = world.num_envs == 1
        self._wheel_angles_row, self._wheel_speeds_row = self._wheel_angles[0], self._wheel_speeds[0]
        self._planar_end_row = self._planar_end[0]
        #: One env without the collision check: its ``qpos`` at the step's start (Python floats), else None.
        self._start_row: list[float] | None = None
        # one env: a read-only view of its live qpos, ``(1, nq)``, looked up on first use
        # (``None`` where the backend has none: :attr:`world.qpos` is read instead)
        self._live_qpos: FloatArray | None = None
        self._live_looked_up = False
        n = world.num_envs
        #: Kinematic moves refused because they would collide, per env (a running count).
        self.refused_moves = np.zeros(n, dtype=np.int64)
        #: Whether the last control step's kinematic move was refused, per env.
        self.last_refused = np.zeros(n, dtype=bool)
        self._start: FloatArray | None = None
        #: Per env, how deep the base was in the world at the step's start (m).
        self._start_depth: FloatArray | None = None
        self._base_geoms = self._rigid_geoms() if self.planar is not None else np.zeros(0, dtype=np.int64)
        robot_bodies = index.subtree_bodies(index.root_body_id)
        # contacts with these never refuse a move: the robot itself and the ground (planes)
        self._ignored_geoms = np.flatnonzero(
            np.isin(index.model.geom_bodyid, robot_bodies) | (index.model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE)
        )
        self._wheel_start: FloatArray | None = None
        if self.planar is None and index.free_joint is None:
            self.kind = "fixed"
        else:
            self.kind = "planar" if self.planar is not None else "free"
        mount = state.mount_pose
        self._mount_xy = np.array(mount[:2])
        self._mount_yaw = z_rotation_angle(mount[3:])
        # cos and sin of the mount's yaw, for the per-step wheel kinematics
        self._mount_cos, self._mount_sin = math.cos(self._mount_yaw), math.sin(self._mount_yaw)

    def _require(self, where: str) -> None:
        if self.kind == "fixed":
            raise ConfigError(f"{where}: {self.owner} has no mobile base (a Base part or a floating root).")

    @property
    def yaw(self) -> FloatArray:
        """``base_rot``: yaw (rad) about world +z, ``(num_envs,)``, in ``(-pi, pi]``."""
        self._require(f"{self.owner}.base_rot")
        return wrap_angle(quat_to_yaw(self.world.body_poses(self._base_body())[:, 0, 3:]))

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

    def ground_xy(self, value: npt.ArrayLike, where: str) -> FloatArray:
        """A ``base_pos`` given as ``(2,)`` / ``(num_envs, 2)`` (x, y) or ``(3,)`` /
        ``(num_envs, 3)`` (x, y, z with z the base's own, :attr:`position`'s: the base
        moves in its plane) as ``(num_envs, 2)`` (m, world)."""
        self._require(where)
        n = self.world.num_envs
        try:
            array = np.asarray(value)
        except Exception:  # whatever the input's own __array__ raises
            raise StateError(f"{where}: expected numeric base position, got {type(value).__name__}.") from None
        width = array.shape[-1] if array.ndim in (1, 2) else 0
        if width not in (2, 3):
            raise StateError(
                f"{where}: expected the base position (x, y) or (x, y, z) (m, world) of shape (2,), (3,), "
                f"({n}, 2) or ({n}, 3), got {array.shape}."
            )
        rows = self.state.batch(array, n, width, "base position (m, world)", where)
        height = float(self.state.mount_pose[2])
        if width == 3 and not np.all(np.abs(rows[:, 2] - height) <= 1e-9):
            given = float(rows[np.argmax(np.abs(rows[:, 2] - height)), 2])
            raise StateError(
                f"{where}: the base moves in its plane at z = {height:.6g} m (base_pos's z); expected that z or "
                f"(x, y) alone, got z = {given:.6g}."
            )
        return rows[:, :2]

    def _yaws(self, yaw: npt.ArrayLike, n: int, where: str) -> FloatArray:
        """``yaw`` (a number, or one per env) as finite angles ``(n,)`` (rad)."""
        try:
            if np.asarray(yaw).dtype.kind == "b":  # True is not an angle
                raise TypeError
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
        """Teleport the base of envs ``env_ids`` (all by default; ``n`` of them) to ``xy``
        (m, in the world: ``(2,)`` for every env or ``(n, 2)``) and ``yaw`` (rad about the
        world's z: a number or ``(n,)``); ``None`` keeps the current value. A kinematic write
        of the base joints (planar joints, or the free root at its current height), their
        velocities set to zero; ``where`` names the caller in errors."""
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
            # a coordinate not given keeps its joint's value bit for bit (read back through
            # the body's pose it could come back an ulp off: an xy teleport turned the base)
            current = self.world.qpos[ids][:, self._planar_adr]
            if xy is None:
                values[:, :2] = current[:, :2]
            if yaw is None:
                values[:, 2] = current[:, 2]
            for k, joint in enumerate((x, y, turn)):
                low, high = joint.range
                outside = outside_limits(values[:, k], low, high)
                if joint.limited and outside.any():
                    value = values[outside, k][0]
                    raise StateError(
                        f"{where}: qpos of base joint {joint.name!r} would be {value:.6g}, outside its limits "
                        f"[{low:.6g}, {high:.6g}]."
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

    # ------------------------------------------------------------------ per-step motion
    def set_dynamics(self, dynamics: str, refuse_collisions: bool | None = None) -> None:
        """Switch this robot's base to ``"dynamic"`` or ``"kinematic"`` (and optionally
        turn the collision check of kinematic moves on or off)."""
        where = f"{self.owner}.set_base_dynamics"
        if not isinstance(dynamics, str) or dynamics not in ("dynamic", "kinematic"):
            raise ConfigError(
                f"{where}: expected 'dynamic' or 'kinematic', got {dynamics!r}."
                + did_you_mean(dynamics, ("dynamic", "kinematic"))
            )
        if dynamics == "kinematic" and self.planar is None:
            raise ConfigError(f"{where}: a kinematic base needs a Base part on planar joints.")
        refuse = None if refuse_collisions is None else check_bool(refuse_collisions, "refuse_collisions", where)
        self.dynamics = dynamics
        if refuse is not None:
            self.refuse_collisions = refuse

    def get_state(self) -> dict[str, Any]:
        """The base's settings and counters, for an exact state: ``dynamics``,
        ``refuse_collisions``, ``refused_moves`` ``(num_envs,)`` int64 and ``last_refused``
        ``(num_envs,)`` bool (copies)."""
        return {
            "dynamics": self.dynamics,
            "refuse_collisions": self.refuse_collisions,
            "refused_moves": self.refused_moves.copy(),
            "last_refused": self.last_refused.copy(),
        }

    def check_state(self, state: Any, where: str) -> tuple[str, bool, npt.NDArray[np.int64], npt.NDArray[np.bool_]]:
        """Validate :meth:`get_state`'s dict without applying it."""
        keys = ("dynamics", "refuse_collisions", "refused_moves", "last_refused")
        if not isinstance(state, Mapping) or any(k not in state for k in keys):
            raise StateError(f"{where}: expected the base state as a dict with keys {keys}, got {state!r:.80}.")
        check_state_keys(state, keys, "base state", where)
        dynamics = state["dynamics"]
        if (
            not isinstance(dynamics, str)
            or dynamics not in ("dynamic", "kinematic")
            or (dynamics == "kinematic" and self.planar is None)
        ):
            raise StateError(
                f"{where}: expected base dynamics 'dynamic' or 'kinematic' (planar bases), got {dynamics!r}."
            )
        refuse = check_bool(state["refuse_collisions"], "refuse_collisions", where, StateError)
        n = self.world.num_envs
        moves, last = np.asarray(state["refused_moves"]), np.asarray(state["last_refused"])
        if moves.shape != (n,) or moves.dtype.kind not in "iu" or np.any(moves < 0):
            raise StateError(f"{where}: expected refused_moves as {n} counts >= 0, got {state['refused_moves']!r:.80}.")
        if last.shape != (n,) or last.dtype != np.bool_:
            raise StateError(f"{where}: expected last_refused as {n} bools, got {state['last_refused']!r:.80}.")
        return dynamics, refuse, moves.astype(np.int64), last.copy()

    def set_state(self, checked: tuple[str, bool, npt.NDArray[np.int64], npt.NDArray[np.bool_]]) -> None:
        """Restore what :meth:`check_state` returned."""
        self.dynamics, self.refuse_collisions = checked[0], checked[1]
        self.refused_moves[:], self.last_refused[:] = checked[2], checked[3]

    @property
    def dynamics(self) -> str:
        """``"dynamic"`` (physics moves the base) or ``"kinematic"`` (each step puts it at
        the commanded velocity's pose)."""
        return self._dynamics

    @dynamics.setter
    def dynamics(self, dynamics: str) -> None:
        self._dynamics = dynamics
        # what moves_each_step reads on every step (planar and wheels are fixed)
        self._moves = self.planar is not None and (dynamics == "kinematic" or bool(self.wheels))

    @property
    def moves_each_step(self) -> bool:
        """True when :meth:`before_step` / :meth:`after_step` have work to do."""
        return self._moves

    def _rigid_geoms(self) -> npt.NDArray[np.int64]:
        """Geoms of the base body and of the bodies attached to it with no joint, or with
        wheel joints or held legs' joints only (what a kinematic move must not push into
        the world: Spot's legs, pinned as its body moves, included)."""
        model = self.index.model
        planar = self.planar
        if planar is None:
            return np.zeros(0, dtype=np.int64)
        base = int(model.jnt_bodyid[planar[-1].id])
        wheel_ids = {w.id for w in self.wheels} | self._held_ids
        bodies = [base]
        for body in self.index.subtree_bodies(base):
            if body == base:
                continue
            joints = range(model.body_jntadr[body], model.body_jntadr[body] + model.body_jntnum[body])
            parent = int(model.body_parentid[body])
            if parent in bodies and all(j in wheel_ids for j in joints):
                bodies.append(body)
        return np.flatnonzero(np.isin(model.geom_bodyid, bodies))

    def _planar_qpos(self) -> FloatArray:
        if self.planar is None:
            raise StateError(f"{self.owner}: no planar base joints.")
        values: FloatArray = self.world.qpos.take(self._planar_adr, axis=1)  # a new array
        return values

    def before_step(self) -> None:
        """Remember the planar pose at the start of a control step."""
        if not self._moves:
            return
        if self.world.num_envs == 1 and not (self._dynamics == "kinematic" and self.refuse_collisions):
            # one env, no collision check: its joint positions as Python floats (what the
            # scalar move and wheel roll read; no fancy indexing of one-row arrays)
            self._start_row = self._row_single()
            return
        self._start_row = None
        qpos = self.world.qpos
        self._start = qpos.take(self._planar_adr, axis=1)  # new arrays (as fancy indexing gives)
        self._wheel_start = qpos.take(self._wheel_qadr, axis=1)
        if self.dynamics == "kinematic" and self.refuse_collisions:
            # how deep the base already is in the world (something came to touch it, or it
            # was put there): a move is refused only if it goes deeper
            self._start_depth = self._penetration()

    def _row_single(self) -> list[float]:
        """The one env's joint positions now (rad, m; Python floats ``(nq,)``): from a
        view of its live ``qpos`` (:meth:`BatchedWorld.live_view
        <robot_agents.sim.world.BatchedWorld.live_view>`, the same numbers as
        :attr:`world.qpos <robot_agents.sim.world.BatchedWorld.qpos>`, without filling the
        read cache that the step's next write clears), made once."""
        if not self._live_looked_up:
            live_view = getattr(self.world, "live_view", None)
            self._live_qpos = None if live_view is None else live_view("qpos")
            self._live_looked_up = True
        live = self._live_qpos
        row: list[float] = (self.world.qpos if live is None else live)[0].tolist()
        return row

    def after_step(self, commanded: FloatArray | None, control_dt: float) -> None:
        """After the physics substeps: a kinematic base is put at the start pose plus
        ``commanded`` (mount-frame joint velocities ``(num_envs, 3)``) times
        ``control_dt`` (a refused move leaves it at the start pose); wheels turn by the
        base's actual motion."""
        if not self._moves:  # (False without planar joints)
            return
        start_row = self._start_row
        if start_row is not None:
            if self._dynamics == "kinematic":
                self._move_single(start_row, commanded, control_dt)
            if self.wheels:
                self._turn_wheels_single(start_row, control_dt)
            return
        if self._start is None:
            return
        start = self._start
        n = start.shape[0]
        adr, dofs = self._planar_adr, self._planar_dofs
        ids = self._all_envs  # start holds a row per env
        if self.dynamics == "kinematic":
            velocity = np.zeros((n, 3)) if commanded is None else np.asarray(commanded, dtype=np.float64)
            end = start + velocity * control_dt
            self.world.write_joint_state(ids, adr, end, dofs, velocity)
            self.last_refused[:] = False
            if self.refuse_collisions:
                start_depth = self._start_depth if self._start_depth is not None else np.zeros(n)
                # clear at the start: any touch refuses; touching: only a deeper one
                hit = self._penetration() > np.where(start_depth > 0, start_depth + DEEPER, 0.0)
                if hit.any():
                    back = np.flatnonzero(hit)
                    self.world.write_joint_state(back, adr, start[back], dofs, np.zeros((len(back), 3)))
                    self.last_refused[back] = True
                    self.refused_moves[back] += 1
        if self.wheels and self._wheel_start is not None:
            self._turn_wheels(start, self._planar_qpos(), self._wheel_start, control_dt)

    def _move_single(self, start_row: list[float], commanded: FloatArray | None, control_dt: float) -> None:
        """The kinematic move of :meth:`after_step` for one env without the collision
        check: the base joints at their positions at the step's start (``start_row``,
        Python floats ``(nq,)``) plus ``commanded`` ``(1, 3)`` times ``control_dt`` (the
        same IEEE products and sums as the batched ``start + velocity * control_dt``),
        written through a row kept for it (the world copies it)."""
        velocity = np.zeros((1, 3)) if commanded is None else np.asarray(commanded, dtype=np.float64)
        end = self._planar_end_row
        (x, y, yaw), speeds = self._planar_list, velocity[0]
        vx, vy, wz = speeds.tolist()
        end[0] = start_row[x] + vx * control_dt
        end[1] = start_row[y] + vy * control_dt
        end[2] = start_row[yaw] + wz * control_dt
        if self._write_rows:
            self.world.write_joint_row(self._planar_adr, end, self._planar_dofs, speeds)
        else:
            self.world.write_joint_state(
                self._all_envs, self._planar_adr, self._planar_end, self._planar_dofs, velocity
            )
        self.last_refused[0] = False

    def _penetration(self) -> FloatArray:
        """Per env: how deep (m) a base geom is in a geom outside the robot (not the
        ground), the deepest contact's; 0 where none touches."""
        datas = self.world.physics_sources()
        base, robot = self._base_geoms, self._ignored_geoms
        depth = np.zeros(len(datas))
        for env, data in enumerate(datas):
            if data.ncon == 0:
                continue
            g1, g2 = data.contact.geom1, data.contact.geom2
            touching = data.contact.dist < 0
            one = np.isin(g1, base) & ~np.isin(g2, robot)
            two = np.isin(g2, base) & ~np.isin(g1, robot)
            mine = touching & (one | two)
            if mine.any():
                depth[env] = float(-np.min(data.contact.dist[mine]))
        return depth

    def _turn_wheels(self, start: FloatArray, end: FloatArray, wheel_start: FloatArray, control_dt: float) -> None:
        """Turn the wheels by the base's motion from ``start`` to ``end`` (``(num_envs, 3)``),
        from their angles at the step's start (physics does not turn passive wheels)."""
        rolled = self._wheel_roll_single(start[0], end[0]) if start.shape[0] == 1 else self._wheel_roll(start, end)
        angles = wheel_start + rolled  # what physics did to the wheels is overwritten
        self.world.write_joint_state(
            self._all_envs, self._wheel_qadr, angles, self._wheel_dadr, rolled / control_dt, forward=False
        )

    def _turn_wheels_single(self, start_row: list[float], control_dt: float) -> None:
        """:meth:`_turn_wheels` of one env from its joint positions at the step's start
        (``start_row``, Python floats ``(nq,)``): the same values, from
        :meth:`_side_rolls`' Python floats (IEEE additions and divisions, as NumPy's),
        written through two rows kept for it (the world copies them)."""
        end_row = self._row_single()  # the stepped positions
        x, y, yaw = self._planar_list
        left, right = self._side_rolls(start_row[x], start_row[y], start_row[yaw], end_row[x], end_row[y], end_row[yaw])
        half = self._half_wheels
        angles, speeds = self._wheel_angles_row, self._wheel_speeds_row
        for k, q in enumerate(self._wheel_qlist):
            roll = left if k < half else right
            angles[k] = start_row[q] + roll
            speeds[k] = roll / control_dt
        if self._write_rows:
            self.world.write_joint_row(self._wheel_qadr, angles, self._wheel_dadr, speeds, forward=False)
            return
        self.world.write_joint_state(
            self._all_envs, self._wheel_qadr, self._wheel_angles, self._wheel_dadr, self._wheel_speeds, forward=False
        )

    def _wheel_roll(self, start: FloatArray, end: FloatArray) -> FloatArray:
        """Differential kinematics: left wheels roll ``v - w b / 2``, right wheels
        ``v + w b / 2`` (``v`` forward travel, ``w`` yaw change, ``b`` separation), in
        rad, ``(num_envs, wheels)``."""
        n = start.shape[0]
        turn = wrap_angle(end[:, 2] - start[:, 2])
        heading = start[:, 2] + self._mount_yaw + 0.5 * turn
        # the slides move along the mount frame's axes; the heading is world yaw
        c, s = self._mount_cos, self._mount_sin
        moved_x, moved_y = end[:, 0] - start[:, 0], end[:, 1] - start[:, 1]
        dx = c * moved_x - s * moved_y
        dy = s * moved_x + c * moved_y
        forward = np.cos(heading) * dx + np.sin(heading) * dy
        half = len(self.wheels) // 2
        differential = 0.5 * self.wheel_separation * turn
        travel = np.empty((n, 2 * half))
        travel[:, :half] = (forward - differential)[:, None]
        travel[:, half:] = (forward + differential)[:, None]
        rolled: FloatArray = travel / self.wheel_radius
        return rolled

    def _wheel_roll_single(self, start: FloatArray, end: FloatArray) -> FloatArray:
        """:meth:`_wheel_roll` of one env (``start`` / ``end`` ``(3,)``), ``(1, wheels)``:
        the same operations in the same order on scalars (Python floats for the
        arithmetic, NumPy's own ``mod`` / ``cos`` / ``sin``), so bit for bit the same,
        without a dozen calls on one-element arrays."""
        return np.array([self._wheel_rolls_single(start, end)])

    def _wheel_rolls_single(
        self, start: Sequence[float] | FloatArray, end: Sequence[float] | FloatArray
    ) -> list[float]:
        """:meth:`_wheel_roll_single` as a list of Python floats, one per wheel (the turn
        wrapped by :func:`wrap_angle_float`)."""
        left, right = self._side_rolls(
            float(start[0]), float(start[1]), float(start[2]), float(end[0]), float(end[1]), float(end[2])
        )
        half = self._half_wheels
        return [left] * half + [right] * half

    def _side_rolls(self, x0: float, y0: float, yaw0: float, x1: float, y1: float, yaw1: float) -> tuple[float, float]:
        """The left and right wheels' roll (rad) for one env's planar move from ``(x0, y0,
        yaw0)`` to ``(x1, y1, yaw1)`` (m, m, rad; Python floats): :meth:`_wheel_roll`'s
        operations in the same order on Python floats (NumPy's own ``cos`` / ``sin``), so
        the same bits."""
        turn = wrap_angle_float(yaw1 - yaw0)
        heading = yaw0 + self._mount_yaw + 0.5 * turn
        c, s = self._mount_cos, self._mount_sin
        moved_x, moved_y = x1 - x0, y1 - y0
        dx = c * moved_x - s * moved_y
        dy = s * moved_x + c * moved_y
        forward = float(np.cos(heading)) * dx + float(np.sin(heading)) * dy
        differential = 0.5 * self.wheel_separation * turn
        radius = self.wheel_radius
        return (forward - differential) / radius, (forward + differential) / radius
