"""The drive stage: joint targets in, MuJoCo controls out.

Control modes write *targets* per driven joint into :class:`JointTargets`: position
(rad or m), velocity (rad/s or m/s) and effort (N*m or N), each ``(num_envs, n)``.
:class:`Drives` turns them into ``ctrl`` for the robot's actuators, whatever their
kind. For MuJoCo's affine actuators (PD servo, velocity servo, motor) with joint-space
stiffness ``kp``, damping ``kv``, gain ``g`` and constant bias ``b0`` it solves
``g * ctrl + b0 - kp q - kv qd = kp q* + kv qd* + tau* - kp q - kv qd`` for ``ctrl``:

    ctrl = (kp q* + (kv + b) qd* + tau* - b0) / g

so the PD law runs inside physics (implicitly integrated) at every substep. ``b`` is
the joint's own damping (the model's ``dof_damping``, plus that of the joints that
follow it through linear joint equalities, times their ratio squared), fed forward so
that a joint meets its velocity target at steady state: physics damps it by ``b qd``
on top of the drive, and a velocity servo alone settles at ``kv / (kv + b)`` of its
target. A motor under explicit PD gets ``ctrl = kp (q* - q) + kv (qd* - qd) + b qd* +
tau*`` before every substep; MuJoCo's ``pid`` and ``dcmotor`` take the targets as their
inputs.

A real-robot driver or another backend consumes the same :class:`JointTargets`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.spec import DriveDeclaration, DriveKind
from robot_agents.errors import ConfigError, ModelError, StateError, UnknownNameError
from robot_agents.indexing import index_selector
from robot_agents.kinematics.ik import linear_followers
from robot_agents.validation import check_array, check_real, check_state_keys

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


#: Checked drive targets of a state: ``position``, ``velocity``, ``effort`` ``(num_envs, n)``.
DriveTargetState = tuple[FloatArray, FloatArray, FloatArray]


class JointTargets:
    """What a control mode asks of each driven joint, per env: ``position``,
    ``velocity`` and ``effort``, each ``(num_envs, n)`` in joint units."""

    def __init__(self, num_envs: int, n: int) -> None:
        self.position: FloatArray = np.zeros((num_envs, n))
        self.velocity: FloatArray = np.zeros((num_envs, n))
        self.effort: FloatArray = np.zeros((num_envs, n))


@dataclass(frozen=True)
class DriveOverride:
    """Drive settings a control mode imposes on some joints while it is active.

    Each array is ``(n,)`` over the robot's drives; ``NaN`` keeps the declared value."""

    stiffness: FloatArray
    damping: FloatArray
    effort_limit: FloatArray

    @staticmethod
    def none(n: int) -> DriveOverride:
        return DriveOverride(np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan))


class Drives:
    """The bound drives of one robot in a compiled scene.

    Args:
        model: the compiled scene.
        declarations: one per driven joint (from :func:`~robot_agents.actuators.spec.apply_actuators`).
        prefix: the robot's name prefix in the scene.
        num_envs: number of envs.
        owner: the robot, for messages.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        declarations: Sequence[DriveDeclaration],
        prefix: str,
        num_envs: int,
        owner: str,
    ) -> None:
        self.model = model
        self.owner = owner
        self.declarations = tuple(declarations)
        self.joint_names: tuple[str, ...] = tuple(d.joint for d in declarations)
        self._column = {name: i for i, name in enumerate(self.joint_names)}
        n = len(declarations)
        joint_ids = []
        for decl in declarations:
            joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, prefix + decl.joint)
            if joint < 0 or int(model.jnt_type[joint]) not in (
                int(mujoco.mjtJoint.mjJNT_HINGE),
                int(mujoco.mjtJoint.mjJNT_SLIDE),
            ):
                raise ModelError(
                    f"{owner}: drive of {decl.joint!r} needs a hinge or slide joint in the compiled model."
                )
            joint_ids.append(joint)
        self.joint_ids = np.array(joint_ids, dtype=np.int64)
        self.qpos_adr = model.jnt_qposadr[self.joint_ids].astype(np.int64)
        self.dof_adr = model.jnt_dofadr[self.joint_ids].astype(np.int64)
        self.actuator_ids = self._find_actuators(model, self.joint_ids)
        adr = getattr(model, "actuator_ctrladr", None)
        self.ctrl_adr = (np.asarray(adr)[self.actuator_ids] if adr is not None else self.actuator_ids).astype(np.int64)
        self.kinds = [d.kind for d in declarations]
        self.gear = model.actuator_gear[self.actuator_ids, 0].copy()
        # Declared joint-space settings of every drive, read back from the compiled model
        # (a file's own actuators included), restored whenever a mode is activated.
        g_act = model.actuator_gainprm[self.actuator_ids, 0]
        bias = model.actuator_biasprm[self.actuator_ids, :3]
        gear = self.gear
        affine = np.array([k is DriveKind.AFFINE for k in self.kinds], dtype=bool)
        self._affine = np.flatnonzero(affine)
        self._declared_gain = np.where(affine, g_act * gear, 1.0)
        self._declared_b0 = np.where(affine, bias[:, 0] * gear, 0.0)
        explicit = np.array([d.stiffness for d in declarations]), np.array([d.damping for d in declarations])
        self.declared_stiffness = np.where(affine, -bias[:, 1] * gear**2, explicit[0])
        self.declared_damping = np.where(affine, -bias[:, 2] * gear**2, explicit[1])
        self.declared_effort_limit = np.array([d.effort_limit for d in declarations], dtype=np.float64)
        self.velocity_limit = np.array([d.velocity_limit for d in declarations], dtype=np.float64)
        #: The joints' own damping (N*m*s/rad or N*s/m), ``(n,)``: ``dof_damping`` plus that
        #: of the joints following each one through linear joint equalities (Stretch's
        #: telescope segments), times their ratio squared; fed forward with velocity targets.
        self.passive_damping = np.array(model.dof_damping[self.dof_adr], dtype=np.float64)
        for _, follower_dof, column, _, slope in linear_followers(model, self.dof_adr):
            self.passive_damping[column] += slope**2 * float(model.dof_damping[follower_dof])
        # a plain PD loop (damping_feedforward=False) does not compensate it
        self.passive_damping *= np.array([d.damping_feedforward for d in declarations], dtype=np.float64)
        self._declared_biastype = model.actuator_biastype[self.actuator_ids].copy()
        self._declared_forcelimited = model.actuator_forcelimited[self.actuator_ids].copy()
        self._declared_forcerange = model.actuator_forcerange[self.actuator_ids].copy()
        self.targets = JointTargets(num_envs, n)
        self._explicit = np.flatnonzero([k is DriveKind.EXPLICIT for k in self.kinds])
        self._pid = np.flatnonzero([k is DriveKind.PID for k in self.kinds])
        self._dcmotor = np.flatnonzero([k is DriveKind.DCMOTOR for k in self.kinds])
        self._affine_sel = index_selector(self._affine)
        self._affine_ctrl = index_selector(self.ctrl_adr[self._affine])
        # Hot-path handles for write(), resolved once: Python lists of the MuJoCo-driven
        # columns (iterating an empty ndarray costs more than the loop body's absence),
        # and, when the affine drives are consecutive in the targets, views of the targets
        # (never replaced) and scratch rows, so that the affine controls are summed in
        # place (the same products and sums, in the same order).
        self._pid_columns = [(int(self.ctrl_adr[c]), int(c)) for c in self._pid]
        self._dcmotor_columns = [(int(self.ctrl_adr[c]), int(c)) for c in self._dcmotor]
        self._affine_only = not self._pid_columns and not self._dcmotor_columns  # write() ends after them
        self._affine_views: tuple[FloatArray, FloatArray, FloatArray] | None = None
        if len(self._affine) and isinstance(self._affine_sel, slice):
            sel = self._affine_sel
            targets = self.targets
            self._affine_views = (targets.position[:, sel], targets.velocity[:, sel], targets.effort[:, sel])
        self._affine_sum = np.zeros((num_envs, len(self._affine)))
        self._affine_term = np.zeros((num_envs, len(self._affine)))
        #: The ``ctrl`` array of the last :meth:`write`, where its affine controls go (a
        #: view of it or the scratch row) and, for the scratch row, their flat indices.
        self._ctrl_seen: FloatArray | None = None
        self._ctrl_dest = self._affine_sum
        self._ctrl_flat: npt.NDArray[np.intp] | None = None
        self.stiffness = self.declared_stiffness.copy()
        self.damping = self.declared_damping.copy()
        self.effort_limit = self.declared_effort_limit.copy()
        self._uses_velocity = self._uses_effort = True
        self.activate(DriveOverride.none(n), uses_velocity=True, uses_effort=True)

    @staticmethod
    def _find_actuators(model: mujoco.MjModel, joint_ids: IntArray) -> IntArray:
        by_joint: dict[int, int] = {}
        for actuator in range(getattr(model, "nactuator", model.nu)):
            if int(model.actuator_trntype[actuator]) == int(mujoco.mjtTrn.mjTRN_JOINT):
                by_joint.setdefault(int(model.actuator_trnid[actuator, 0]), actuator)
        missing = [model.joint(j).name for j in joint_ids if int(j) not in by_joint]
        if missing:
            raise ModelError(f"Drives: no actuator drives joint(s) {missing} in the compiled model.")
        return np.array([by_joint[int(j)] for j in joint_ids], dtype=np.int64)

    # -- names ----------------------------------------------------------------------------
    @property
    def size(self) -> int:
        return len(self.joint_names)

    @property
    def needs_substep(self) -> bool:
        """True when an explicit PD loop must be closed before every physics substep."""
        return len(self._explicit) > 0

    def columns(self, joints: Sequence[str], where: str) -> IntArray:
        """The drive column of each joint; a joint without a drive raises, listing the driven ones."""
        out = []
        for joint in joints:
            if joint not in self._column:
                raise UnknownNameError(where, "driven joint", joint, self.joint_names)
            out.append(self._column[joint])
        return np.array(out, dtype=np.int64)

    # -- modes ----------------------------------------------------------------------------
    def check_targets(self, columns: IntArray, writes: Sequence[str], override: DriveOverride, where: str) -> None:
        """Raise :class:`ConfigError` unless these drives, with ``override``, can follow
        the target kinds in ``writes`` (``"position"``, ``"velocity"``, ``"effort"``)."""
        kp = np.where(np.isnan(override.stiffness), self.declared_stiffness, override.stiffness)
        kv = np.where(np.isnan(override.damping), self.declared_damping, override.damping)
        for column in columns:
            kind, joint = self.kinds[column], self.joint_names[column]
            overridden = not (np.isnan(override.stiffness[column]) and np.isnan(override.damping[column]))
            if kind in (DriveKind.PID, DriveKind.DCMOTOR) and overridden:
                raise ConfigError(
                    f"{where}: joint {joint!r} is driven by MuJoCo's {kind.value} actuator ({self.declarations[column].source}); "
                    "its gains cannot be overridden by a control mode."
                )
            if kind in (DriveKind.PID, DriveKind.DCMOTOR):
                continue
            if "position" in writes and kp[column] <= 0:
                raise ConfigError(
                    f"{where}: sets position targets for joint {joint!r}, but its drive "
                    f"({self.declarations[column].source}) has no stiffness; declare a PDActuator or override "
                    "stiffness in the mode."
                )
            # a joint's own damping fed forward (a motor's back-EMF) follows velocity targets too
            velocity_gain = kv[column] + self.passive_damping[column]
            if "velocity" in writes and "position" not in writes and velocity_gain <= 0 and kp[column] <= 0:
                raise ConfigError(
                    f"{where}: sets velocity targets for joint {joint!r}, but its drive "
                    f"({self.declarations[column].source}) has no damping and its joint none fed forward; "
                    "override damping in the mode."
                )

    def activate(self, override: DriveOverride, uses_velocity: bool, uses_effort: bool) -> None:
        """Apply the declared settings with ``override`` on top (every time: switching
        modes always restores what the robot declares), and remember which target kinds
        the active mode writes."""
        self.stiffness = np.where(np.isnan(override.stiffness), self.declared_stiffness, override.stiffness)
        self.damping = np.where(np.isnan(override.damping), self.declared_damping, override.damping)
        self.effort_limit = np.where(np.isnan(override.effort_limit), self.declared_effort_limit, override.effort_limit)
        overridden = ~(np.isnan(override.stiffness) & np.isnan(override.damping))
        gain = np.where(
            overridden,
            np.where(self.stiffness > 0, self.stiffness, np.where(self.damping > 0, self.damping, self._declared_gain)),
            self._declared_gain,
        )
        model, ids, gear = self.model, self.actuator_ids, self.gear
        a = self._affine
        if len(a):
            model.actuator_gainprm[ids[a], 0] = gain[a] / gear[a]
            model.actuator_biasprm[ids[a], 0] = self._declared_b0[a] / gear[a]
            model.actuator_biasprm[ids[a], 1] = -self.stiffness[a] / gear[a] ** 2
            model.actuator_biasprm[ids[a], 2] = -self.damping[a] / gear[a] ** 2
            pd = (self.stiffness[a] > 0) | (self.damping[a] > 0)
            model.actuator_biastype[ids[a]] = np.where(
                pd, int(mujoco.mjtBias.mjBIAS_AFFINE), self._declared_biastype[a]
            )
        limited = np.isfinite(self.effort_limit)
        changed = limited & ~np.isnan(override.effort_limit)
        for column in range(self.size):
            actuator = ids[column]
            if changed[column] or (limited[column] and self.kinds[column] is not DriveKind.AFFINE):
                limit = self.effort_limit[column] / abs(gear[column])
                model.actuator_forcelimited[actuator] = 1
                model.actuator_forcerange[actuator] = (-limit, limit)
            else:
                model.actuator_forcelimited[actuator] = self._declared_forcelimited[column]
                model.actuator_forcerange[actuator] = self._declared_forcerange[column]
        with np.errstate(divide="ignore", invalid="ignore"):
            self._a = (self.stiffness / gain)[a]
            self._b = ((self.damping + self.passive_damping) / gain)[a]
            self._c = (1.0 / gain)[a]
            self._d = (-self._declared_b0 / gain)[a]
        # (1, k) rows of the factors: NumPy's loop without broadcasting against (1, k)
        # targets (faster on small arrays; the same products and sums, the same bits)
        self._a_row, self._b_row, self._c_row, self._d_row = self._a[None], self._b[None], self._c[None], self._d[None]
        self._unit_position = bool(np.all(self._a == 1.0))
        self._has_bias = bool(np.any(self._d))
        self._uses_velocity = uses_velocity
        self._uses_effort = uses_effort

    def retune(
        self,
        columns: IntArray,
        stiffness: float | None = None,
        damping: float | None = None,
        effort_limit: float | None = None,
    ) -> None:
        """Change the active settings of the drives ``columns`` (``None`` keeps each):
        stiffness (N*m/rad or N/m), damping (N*m*s/rad or N*s/m), effort limit (N*m or N),
        until the next mode activation restores the declared ones with the mode's
        overrides. For trying gains (:mod:`robot_agents.tuning.step_response`); only PD
        drives (MuJoCo's affine servos and explicit PD on a motor) take them."""
        where = f"{self.owner}.retune"
        values = {"stiffness": stiffness, "damping": damping, "effort_limit": effort_limit}
        for field, value in values.items():
            if value is not None:
                check_real(value, field, where, minimum=0.0 if field != "effort_limit" else 1e-12)
        if all(value is None for value in values.values()):
            return
        fixed = [c for c in columns if self.kinds[int(c)] not in (DriveKind.AFFINE, DriveKind.EXPLICIT)]
        if fixed:
            names = [f"{self.joint_names[int(c)]} ({self.kinds[int(c)].value})" for c in fixed]
            raise ConfigError(
                f"{where}: expected PD drives (affine or explicit), got {', '.join(names)}: "
                "their gains are the MuJoCo actuator's own."
            )
        override = DriveOverride(self.stiffness.copy(), self.damping.copy(), self.effort_limit.copy())
        for field, value in values.items():
            if value is not None:
                getattr(override, field)[columns] = float(value)
        self.activate(override, self._uses_velocity, self._uses_effort)

    # -- the targets as state ----------------------------------------------------------------
    def get_target_state(self) -> dict[str, FloatArray]:
        """Copies of the targets, ``position`` / ``velocity`` / ``effort`` ``(num_envs, n)``:
        part of an exact state, since joints no action writes (held legs) keep theirs."""
        targets = self.targets
        return {
            "position": targets.position.copy(),
            "velocity": targets.velocity.copy(),
            "effort": targets.effort.copy(),
        }

    def check_target_state(self, state: Any, where: str) -> DriveTargetState:
        """Validate :meth:`get_target_state`'s dict (shapes, finite values) without applying it."""
        shape = self.targets.position.shape
        if not isinstance(state, Mapping) or any(k not in state for k in ("position", "velocity", "effort")):
            raise StateError(
                f"{where}: expected drive targets as a dict with position, velocity, effort; got {state!r:.80}."
            )
        check_state_keys(state, ("position", "velocity", "effort"), "drive target", where)
        position, velocity, effort = (
            check_array(state[key], shape, f"drive {key} targets", where) for key in ("position", "velocity", "effort")
        )
        return position, velocity, effort

    def set_target_state(self, checked: DriveTargetState) -> None:
        """Restore what :meth:`check_target_state` returned."""
        targets = self.targets
        targets.position[...], targets.velocity[...], targets.effort[...] = checked

    # -- targets -> ctrl ------------------------------------------------------------------
    def hold(self, env_ids: IntArray, qpos: FloatArray) -> None:
        """Targets that hold the measured pose in ``env_ids`` (``qpos`` ``(len(env_ids), nq)``)."""
        targets = self.targets
        targets.position[env_ids] = qpos[:, self.qpos_adr]
        targets.velocity[env_ids] = 0.0
        targets.effort[env_ids] = 0.0

    def write(self, ctrl: FloatArray, qpos: FloatArray | None = None, qvel: FloatArray | None = None) -> None:
        """Controls ``ctrl`` ``(num_envs, nu)`` from the targets (explicit drives also need
        the measured ``qpos`` / ``qvel``; they are written in :meth:`write_explicit`)."""
        targets = self.targets
        views = self._affine_views
        if views is not None:
            self._write_affine_in_place(ctrl, views)
            if self._affine_only and qpos is None:  # nothing else to write (the common case)
                return
        elif len(self._affine):
            sel = self._affine_sel
            out = targets.position[:, sel] if self._unit_position else targets.position[:, sel] * self._a_row
            if self._uses_velocity:
                out = out + targets.velocity[:, sel] * self._b_row
            if self._uses_effort:
                out = out + targets.effort[:, sel] * self._c_row
            if self._has_bias:
                out = out + self._d_row
            ctrl[:, self._affine_ctrl] = out
        for adr, column in self._pid_columns:
            ctrl[:, adr] = targets.position[:, column]
            ctrl[:, adr + 1] = targets.velocity[:, column]
        for adr, column in self._dcmotor_columns:
            ctrl[:, adr] = targets.position[:, column]
            ctrl[:, adr + 1] = targets.velocity[:, column]
            ctrl[:, adr + 2] = targets.effort[:, column]
        if qpos is not None and qvel is not None:
            self.write_explicit(ctrl, qpos, qvel)

    def _write_affine_in_place(self, ctrl: FloatArray, views: tuple[FloatArray, FloatArray, FloatArray]) -> None:
        """The affine drives' controls ``((P a + V b) + E c) + d`` (``P``, ``V``, ``E`` the
        position, velocity and effort targets; each term only where the mode uses it, in
        that order, as the general path sums them), summed into preallocated rows: straight
        into ``ctrl``'s affine columns where they are consecutive, else into a scratch row
        put into them."""
        if ctrl is not self._ctrl_seen:
            self._bind_ctrl(ctrl)
        dest, flat = self._ctrl_dest, self._ctrl_flat
        position, velocity, effort = views
        term = self._affine_term
        # the running sum: the position targets themselves (unit factors) or their product
        out = position if self._unit_position else np.multiply(position, self._a_row, out=dest)
        if self._uses_velocity:
            out = np.add(out, np.multiply(velocity, self._b_row, out=term), out=dest)
        if self._uses_effort:
            out = np.add(out, np.multiply(effort, self._c_row, out=term), out=dest)
        if self._has_bias:
            out = np.add(out, self._d_row, out=dest)
        if flat is not None:
            ctrl.put(flat, out)
        elif dest is self._affine_sum:  # the scratch row, ctrl not contiguous
            ctrl[:, self._affine_ctrl] = out
        elif out is not dest:
            dest[...] = out

    def _bind_ctrl(self, ctrl: FloatArray) -> None:
        """Where :meth:`_write_affine_in_place` puts the affine controls of ``ctrl``
        ``(num_envs, nu)``: a view of its consecutive affine columns, or the scratch row
        and the flat indices of the columns in each row (``ndarray.put`` writes the same
        entries as fancy indexing, faster on small arrays) when ``ctrl`` is contiguous."""
        self._ctrl_seen = ctrl
        self._ctrl_flat = None
        if isinstance(self._affine_ctrl, slice):
            self._ctrl_dest = ctrl[:, self._affine_ctrl]
            return
        self._ctrl_dest = self._affine_sum
        if ctrl.flags.c_contiguous:
            rows = np.arange(ctrl.shape[0], dtype=np.intp)[:, None] * ctrl.shape[1]
            self._ctrl_flat = (rows + np.asarray(self._affine_ctrl, dtype=np.intp)).reshape(-1)

    def write_explicit(self, ctrl: FloatArray, qpos: FloatArray, qvel: FloatArray) -> None:
        """Close the explicit PD loops: ``ctrl`` of motor drives from the measured state."""
        e = self._explicit
        if not len(e):
            return
        targets = self.targets
        effort = (
            self.stiffness[e] * (targets.position[:, e] - qpos[:, self.qpos_adr[e]])
            + self.damping[e] * (targets.velocity[:, e] - qvel[:, self.dof_adr[e]])
            + self.passive_damping[e] * targets.velocity[:, e]
            + targets.effort[:, e]
        )
        limit = self.effort_limit[e]
        ctrl[:, self.ctrl_adr[e]] = np.clip(effort, -limit, limit) / self.gear[e]

    def describe(self) -> list[tuple[str, str]]:
        """``(joint, drive)`` rows for CLIs and docs."""
        return [(d.joint, d.source) for d in self.declarations]


def override_for(
    drives: Drives, columns: IntArray, stiffness: object, damping: object, effort_limit: object, into: DriveOverride
) -> None:
    """Write a controller config's gain overrides (scalars or per-joint tuples, ``None``
    to keep) for its ``columns`` into ``into``."""
    for field, value in (("stiffness", stiffness), ("damping", damping), ("effort_limit", effort_limit)):
        if value is None:
            continue
        array = np.asarray(value, dtype=np.float64).reshape(-1)
        if array.size not in (1, len(columns)):
            raise ConfigError(
                f"{drives.owner}.{field}: expected 1 or {len(columns)} values (one per joint), got {array.size}."
            )
        getattr(into, field)[columns] = array
