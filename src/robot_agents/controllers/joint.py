"""Joint-space controllers: position (absolute, delta, delta-from-target), velocity,
position + velocity, and mimic (one action drives coupled joints).

They produce joint targets; the robot's drives track them (for PD drives the law
``kp (q* - q) + kv (qd* - qd) + b qd*`` runs inside physics at every substep, clamped to
the drive's effort limit; ``b``, the joint's own damping, is fed forward so that a
velocity target is met).

An unlimited hinge (a continuous joint: a wheel, a roll joint without stops) is treated
as a continuous-rotation servo: its angle ``q`` may run past ``2 pi`` (in velocity or
delta modes), and an *absolute* target ``a`` is taken modulo ``2 pi`` to the angle nearest
the measured one, ``q* = a + 2 pi round((q - a) / 2 pi)``, so that the joint turns the
short way (at most ``pi``) and never unwinds the turns it has made. Delta modes add to the
measured angle or to the current target, with no bound. Limited joints (and unlimited
slides) take absolute targets as they are, clipped to their limits. An unlimited joint
tied to a limited one (a joint equality, :mod:`robot_agents.agent.coupling`; a mimic
mode's follower, :func:`mimic_leader_range`) is limited by it; a mimic's followers take
their targets from the leader's after it is taken to its turn.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from robot_agents.actuators.config import PerJoint, per_joint
from robot_agents.controllers.base import (
    Controller,
    ControllerConfig,
    ControllerContext,
    FloatArray,
    IntArray,
    JointBinding,
    SimView,
    check_bounds,
    clip_ufunc,
    one_pass_clip_exact,
)
from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords

#: Absolute targets of an unlimited joint are bounded to +-2 pi rad (+-2 pi m for a slide);
#: an unlimited hinge takes them modulo 2 pi (see the module docstring).
UNBOUNDED_TARGET = 2 * np.pi

#: One turn (rad): the period of an unlimited hinge's angle.
TURN = 2 * np.pi


def _has_negative_zero(values: FloatArray) -> bool:
    """Whether any of ``values`` is ``-0.0``."""
    return bool(np.any((values == 0.0) & np.signbit(values)))


def nearest_turn(targets: FloatArray, reference: FloatArray) -> FloatArray:
    """``targets`` shifted by whole turns to the angles nearest ``reference`` (rad, both
    ``(num_envs, k)``): ``targets + 2 pi round((reference - targets) / 2 pi)``, a new
    array; a target already within half a turn of its reference comes back unchanged (the
    same value; ``-0.0`` becomes ``0.0``), one exactly half a turn away stays too
    (``round`` halves to even)."""
    shifted: FloatArray = targets + TURN * np.round((reference - targets) / TURN)
    return shifted


def within_bounds_by_turns(angles: FloatArray, low: FloatArray, high: FloatArray) -> FloatArray:
    """``angles`` (rad, ``(num_envs, k)``) where they lie within ``[low, high]`` (each
    ``(k,)``), otherwise the same angle modulo ``2 pi`` within them when one is (first the
    one in ``[-pi, pi]``, then a turn up or down), else the angle in ``[-pi, pi]``; a new
    array. The absolute target of an unlimited hinge that holds it where it is."""
    wrapped = angles - TURN * np.round(angles / TURN)
    wrapped = np.where(wrapped < low, wrapped + TURN, np.where(wrapped > high, wrapped - TURN, wrapped))
    wrapped = np.where((wrapped < low) | (wrapped > high), angles - TURN * np.round(angles / TURN), wrapped)
    held: FloatArray = np.where((angles < low) | (angles > high), wrapped, angles)
    return held


def mimic_leader_range(
    limits: FloatArray, periodic: npt.NDArray[np.bool_], multipliers: FloatArray, offsets: FloatArray
) -> tuple[FloatArray, bool]:
    """A mimic leader's range ``(2,)`` (rad or m) and whether it is periodic, from the
    joints' ``limits`` ``(n, 2)`` and ``periodic`` flags ``(n,)`` (leader first) and the
    followers' ``target_i = multipliers[i] * leader + offsets[i]``. A limited leader keeps
    its own limits (and is not periodic). An unlimited one takes the intersection of the
    ranges its limited followers' limits give it (a follower stops at its limit, and a
    leader past the matching point would leave it behind); it is periodic (its absolute
    targets taken to the turn nearest the measured angle) only when it is an unlimited
    hinge and every follower is one that a whole turn of the leader turns by whole turns
    (an integer multiplier). Ranges that do not overlap leave it unlimited."""
    low, high = float(limits[0, 0]), float(limits[0, 1])
    if np.isfinite(low) or np.isfinite(high):
        return limits[0].copy(), False
    turns = bool(periodic[0])
    for (lo, hi), follows, m, o in zip(limits[1:], periodic[1:], multipliers[1:], offsets[1:], strict=True):
        if m == 0.0:
            continue
        if np.isfinite(lo) or np.isfinite(hi):
            ends = ((lo - o) / m, (hi - o) / m)
            low, high = max(low, min(ends)), min(high, max(ends))
            turns = False
        elif not (follows and m == round(m)):
            turns = False
    if low > high:
        return np.array([-np.inf, np.inf]), False
    return np.array([low, high]), turns


@dataclass(frozen=True)
class SingleTerms:
    """A plain or mimic joint-position part's one-env arithmetic
    (:meth:`PDJointPosController.single_terms`), as Python numbers.

    Attributes:
        base: what the change adds to: ``PDJointPosController._ABSOLUTE`` (0: nothing),
            ``_FROM_TARGET`` (1: the current targets), ``_FROM_MEASURED`` (2: the measured
            positions; plain parts only).
        multipliers: a mimic's ``m_i`` (its one action entry times each), ``None`` for a
            plain part (one entry per joint, taken as it is).
        offsets: a mimic's ``o_i`` added to an absolute change, ``None`` where none is.
        bounds: each joint's ``(lower, upper)`` limits (rad or m) for a one-pass clip,
            ``None`` where the part does not clip.
        qpos: each joint's ``qpos`` address (the measured positions read).
        columns: each joint's column in the drives' target buffer.
    """

    base: int
    multipliers: list[float] | None
    offsets: list[float] | None
    bounds: list[tuple[float, float]] | None
    qpos: list[int]
    columns: list[int]


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDJointPosConfig(ControllerConfig):
    """PD joint position control.

    Attributes:
        lower, upper: action bounds (rad or m). For absolute targets ``None`` means the
            joint limits (``+-2 pi`` for an unlimited joint, whose absolute targets, for
            a hinge, are taken modulo ``2 pi`` to the angle nearest the measured one: see
            the module docstring); delta modes must give them (e.g. ``-0.1``/``0.1``).
        use_delta: the action is a change of the target, not the target.
        use_target: with ``use_delta``, add the change to the previous *target* instead
            of the measured position (``pd_joint_target_delta_pos``).
        interpolate: move the target linearly over the control step's substeps instead
            of jumping to it (smoother, costs a Python call per substep).
        clip_target: keep targets within the joint limits. A gripper turns this off so
            that a target below its closed limit keeps squeezing a grasped object.
    """

    lower: PerJoint | None = None
    upper: PerJoint | None = None
    use_delta: bool = False
    use_target: bool = False
    interpolate: bool = False
    clip_target: bool = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.use_target and not self.use_delta:
            raise ConfigError(
                f"{type(self).__name__}({', '.join(self.joint_names)}): use_target=True needs use_delta=True."
            )
        if self.use_delta and (self.lower is None or self.upper is None):
            raise ConfigError(
                f"{type(self).__name__}({', '.join(self.joint_names)}): delta control needs explicit lower/upper bounds, "
                f"got lower={self.lower}, upper={self.upper}."
            )
        check_bounds(self, "lower", "upper")

    @property
    def keeps_targets(self) -> bool:
        """Absolute and target-delta modes keep the targets; a delta from the measured pose does not."""
        return not (self.use_delta and not self.use_target)

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PDJointPosController(self, binding, context)


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDJointPosMimicConfig(PDJointPosConfig):
    """One action drives several coupled joints (e.g. both fingers of a parallel gripper).

    The first joint in ``joint_names`` leads; joint ``i`` follows with target
    ``multipliers[i] * leader_target + offsets[i]`` (defaults 1 and 0). Bounds are in
    the leader's units. With ``use_delta`` (from the measured position), the action is
    added to the leader's measured position, ``a = (q_0 - offsets[0]) / multipliers[0]``,
    and every joint takes ``multipliers[i] * (a + delta) + offsets[i]``: the followers
    keep the relation to the leader wherever their own drives left them (before
    2026-11-29 each joint added ``multipliers[i] * delta`` to its own measured position,
    and independently driven followers drifted from the relation); with ``use_target``
    each joint adds ``multipliers[i] * delta`` to its previous target, and a reset (or
    the mode's activation) puts the followers' targets on the relation to the leader's
    measured position (since 2026-11-29; before, each took its own measured position and
    kept its offset from the relation in every later target).
    """

    multipliers: tuple[float, ...] | None = None
    offsets: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if len(self.joint_names) < 2:
            raise ConfigError(
                f"PDJointPosMimicConfig: expected at least 2 joints (leader + followers), got {self.joint_names}."
            )
        for field in ("multipliers", "offsets"):
            values = getattr(self, field)
            if values is not None and len(values) != len(self.joint_names):
                raise ConfigError(
                    f"PDJointPosMimicConfig.{field}: expected {len(self.joint_names)} values (one per joint), got {len(values)}."
                )
        if self.use_delta and not self.use_target and self.multipliers is not None and self.multipliers[0] == 0.0:
            raise ConfigError(
                f"PDJointPosMimicConfig({', '.join(self.joint_names)}).multipliers: a delta from the measured position "
                "adds to the leader's, which needs a nonzero multipliers[0] (the leader's position in action units "
                f"is (q - offsets[0]) / multipliers[0]), got {self.multipliers}."
            )

    @property
    def keeps_targets(self) -> bool:
        """Absolute and target-delta modes keep the targets; a delta from the measured pose does not."""
        return not (self.use_delta and not self.use_target)

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PDJointPosController(self, binding, context)


class PDJointPosController(Controller):
    """Position targets for joints, one per action entry or, for mimic joints, all of
    them from one entry: ``target_i = multiplier_i * action + offset_i``.
    """

    config: PDJointPosConfig

    _ABSOLUTE, _FROM_TARGET, _FROM_MEASURED = 0, 1, 2

    def __init__(self, config: PDJointPosConfig, binding: JointBinding, context: ControllerContext) -> None:
        n, num_envs = binding.size, context.num_envs
        self._plain = not isinstance(config, PDJointPosMimicConfig)
        if isinstance(config, PDJointPosMimicConfig):
            self.multipliers = (
                np.ones(n) if config.multipliers is None else np.asarray(config.multipliers, dtype=np.float64)
            )
            self.offsets = np.zeros(n) if config.offsets is None else np.asarray(config.offsets, dtype=np.float64)
        else:
            self.multipliers = np.ones(n)
            self.offsets = np.zeros(n)
        self._action_joints = n if self._plain else 1
        self.binding = binding
        self.config = config
        # each joint's limits; a mimic's unlimited leader takes those its limited
        # followers give it (target_i = m_i a + o_i within the follower's limits)
        self._limits = binding.qpos_range.copy()
        periodic = binding.periodic
        if not self._plain:
            self._limits[0], leader_periodic = mimic_leader_range(
                self._limits, binding.periodic, self.multipliers, self.offsets
            )
            periodic = np.zeros(n, dtype=bool)  # followers follow: never wrapped on their own
            periodic[0] = leader_periodic
        super().__init__(config, binding, context)
        self.target_qpos: FloatArray = np.zeros((num_envs, n))
        self._previous_target: FloatArray = np.zeros((num_envs, n))
        # Hot-path constants, resolved once.
        self._lower_limit = self._limits[:, 0].copy()
        self._upper_limit = self._limits[:, 1].copy()
        self._clip = config.clip_target
        self._has_offsets = bool(np.any(self.offsets))
        self._write_now = not config.interpolate
        self._columns = binding.column_sel
        self._qpos_sel = binding.qpos_sel
        self._position = self.targets.position  # the drives' buffer (never replaced)
        # Joints not contiguous in qpos / in the drives' columns: ndarray.take and
        # ndarray.put with precomputed indices read and write the same entries as
        # fancy indexing, several times faster on small arrays.
        sel = binding.qpos_sel
        self._qpos_take = None if isinstance(sel, slice) else np.asarray(sel, dtype=np.intp)
        columns = binding.column_sel
        self._column_put: IntArray | None = None
        if not isinstance(columns, slice) and self._position.flags.c_contiguous:
            width = self._position.shape[1]
            rows = np.arange(num_envs, dtype=np.intp)[:, None] * width
            self._column_put = (rows + np.asarray(columns, dtype=np.intp)).reshape(-1)
        self._one_pass_clip = self._clip and one_pass_clip_exact(self._lower_limit, self._upper_limit)
        # (1, n) rows for the exact operations (one-pass clip without a zero bound,
        # products, sums): NumPy's loop without broadcasting, faster, the same bits
        self._lower_row, self._upper_row = self._lower_limit[None], self._upper_limit[None]
        self._multipliers_row, self._offsets_row = self.multipliers[None], self.offsets[None]
        # two-pass clip: a row for each bound with no zero (max / min of unequal values, or
        # of equal nonzero ones, have one answer whichever loop computes them)
        self._max_bound = self._lower_row if np.all(self._lower_limit != 0.0) else self._lower_limit
        self._min_bound = self._upper_row if np.all(self._upper_limit != 0.0) else self._upper_limit
        if not config.use_delta:
            self._base = self._ABSOLUTE
        else:
            self._base = self._FROM_TARGET if config.use_target else self._FROM_MEASURED
        # A mimic's delta from the measured position adds to the leader's: every joint's
        # target is m_i (a + delta) + o_i with a the leader's measured position in action
        # units, (q_0 - o_0) / m_0, so the followers keep the relation (each adding
        # m_i delta to its own measured position let them drift from it). The leader's
        # qpos column, (1,), and (m_0, o_0) where they are not (1, 0).
        self._leader_measured: IntArray | None = None
        self._leader_map: tuple[float, float] | None = None
        if not self._plain and self._base == self._FROM_MEASURED:
            self._leader_measured = binding.qpos_adr[:1].astype(np.int64)
            m0, o0 = float(self.multipliers[0]), float(self.offsets[0])
            self._leader_map = None if (m0, o0) == (1.0, 0.0) else (m0, o0)
        # A mimic adding its deltas to its targets starts them on the relation: a reset
        # (and a mode's activation) sets the followers' targets from the leader's measured
        # position, m_i (q_0 - o_0) / m_0 + o_i, not from their own (followers whose own
        # drives left them off the relation kept that offset in every later target). With
        # m_0 = 0 the action does not move the leader and the relation does not say
        # where it stands: the measured positions, as for other modes. (m_0, o_0), or None.
        self._relation_map: tuple[float, float] | None = None
        if not self._plain and self._base == self._FROM_TARGET and float(self.multipliers[0]) != 0.0:
            self._relation_map = (float(self.multipliers[0]), float(self.offsets[0]))
        # Unlimited hinges among the joints (absolute targets are taken modulo a turn):
        # their positions in the joint list and in qpos; None when there is none (limited
        # joints take the path they always took, bit for bit). A mimic's leader alone:
        # its action is taken to the turn, and the followers follow it.
        turning = np.flatnonzero(periodic)
        self._periodic: IntArray | None = turning.astype(np.int64) if turning.size else None
        self._periodic_qpos: IntArray = binding.qpos_adr[turning].astype(np.int64)
        leaders = turning[turning < self._action_joints]
        self._periodic_leaders: IntArray | None = leaders.astype(np.int64) if leaders.size else None

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        cfg, name = self.config, type(self.config).__name__
        dim = self._action_joints
        # Unlimited (continuous) joints get one turn either way: an absolute target must
        # be finite, and a policy's output range must be too.
        leader_range = np.clip(self._limits[:dim], -UNBOUNDED_TARGET, UNBOUNDED_TARGET)
        low = leader_range[:, 0] if cfg.lower is None else per_joint(name, "lower", cfg.lower, dim)
        high = leader_range[:, 1] if cfg.upper is None else per_joint(name, "upper", cfg.upper, dim)
        return low.copy(), high.copy()

    def _clip_to_limits(self, targets: FloatArray) -> FloatArray:
        if not self._clip:
            return targets
        clipped: FloatArray = np.minimum(np.maximum(targets, self._lower_limit), self._upper_limit)
        return clipped

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        measured = sim.qpos[env_ids][:, self.binding.qpos_adr]
        relation = self._relation_map
        self.target_qpos[env_ids] = measured if relation is None else self._on_relation(measured, relation)
        self._previous_target[env_ids] = measured

    def _on_relation(self, measured: FloatArray, relation: tuple[float, float]) -> FloatArray:
        """A mimic's targets ``(k, n)`` on its relation to the leader's ``measured``
        position (``(k, n)``, every joint's; ``relation``: the leader's ``(m_0, o_0)``):
        the leader's own, exactly, and each follower's ``m_i (q_0 - o_0) / m_0 + o_i``,
        clipped as the mode clips."""
        m0, o0 = relation
        leader = (measured[:, :1] - o0) / m0
        targets: FloatArray = leader * self._multipliers_row + self._offsets_row
        if self._clip:
            targets = np.minimum(np.maximum(targets, self._lower_limit), self._upper_limit)
        targets[:, 0] = measured[:, 0]
        return targets

    def hold_raw(self, sim: SimView) -> FloatArray:
        """Absolute modes: the measured positions of the action's joints (the leader alone
        for mimic joints), ``(num_envs, action_dim)`` in rad or m; delta modes: zero. An
        unlimited hinge turned past its action bounds (``+-2 pi``) holds with the same
        angle modulo ``2 pi`` within them, which :meth:`apply` takes back to the measured
        angle (a clipped one would unwind it)."""
        if self.config.use_delta:
            return super().hold_raw(sim)
        held: FloatArray = sim.qpos[:, self.binding.qpos_adr[: self._action_joints]]
        return self._fold_periodic(held)

    def _fold_periodic(self, held: FloatArray) -> FloatArray:
        """``held`` (absolute positions of the action's leading joints, a new array) with
        each unlimited hinge's angle brought within the action bounds by whole turns."""
        leaders = self._periodic_leaders
        if leaders is None:
            return held
        held[:, leaders] = within_bounds_by_turns(held[:, leaders], self.raw_low[leaders], self.raw_high[leaders])
        return held

    def _nearest_to_measured(self, targets: FloatArray, sim: SimView) -> FloatArray:
        """Absolute ``targets`` ``(num_envs, n)`` with each unlimited hinge's moved by whole
        turns to the angle nearest its measured one (a new array where any is moved)."""
        periodic = self._periodic
        if periodic is None:
            return targets
        targets = np.array(targets, dtype=np.float64)  # never write into the caller's action
        measured = sim.qpos.take(self._periodic_qpos, axis=1)
        targets[:, periodic] = nearest_turn(targets[:, periodic], measured)
        return targets

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        if self._base == self._ABSOLUTE and self._periodic is not None:
            raw = self._nearest_to_measured(raw, sim)  # (a mimic: the leader's, the followers follow)
        if self._leader_measured is not None:  # a mimic's delta from the leader's measured position
            leader = sim.qpos[:, self._leader_measured]  # (N, 1): the leader's action coordinate, m_0 = 1, o_0 = 0
            if self._leader_map is not None:
                leader = (leader - self._leader_map[1]) / self._leader_map[0]
            raw = leader + raw  # then as an absolute action: m_i (a + delta) + o_i
        change = raw if self._plain else raw * self._multipliers_row  # (N, 1) * (1, n) -> (N, n)
        if self._base == self._ABSOLUTE or self._leader_measured is not None:
            targets = change + self._offsets_row if self._has_offsets else change
        elif self._base == self._FROM_TARGET:
            targets = self.target_qpos + change
        elif self._qpos_take is None:
            targets = sim.qpos[:, self._qpos_sel] + change
        else:
            targets = sim.qpos.take(self._qpos_take, axis=1) + change
        self._previous_target = self.target_qpos
        if self._one_pass_clip:
            targets = clip_ufunc(targets, self._lower_row, self._upper_row)
        elif self._clip:
            targets = np.maximum(targets, self._max_bound)  # a new array: clipped in place
            np.minimum(targets, self._min_bound, out=targets)
        self.target_qpos = targets
        if self._write_now:
            if self._column_put is None:
                self._position[:, self._columns] = targets
            else:
                self._position.put(self._column_put, targets)

    def single_apply(
        self, raw: FloatArray, qpos: FloatArray, raw_never_negative_zero: bool = False
    ) -> Callable[[], None] | None:
        """One env: :meth:`apply` of the action entries ``raw`` (a ``(1, action_dim)``
        view of a buffer the caller rewrites before each call) as a call of no arguments,
        reading the measured positions from ``qpos``, a ``(1, nq)`` view that follows the
        simulation: the same operations on the same values, so the same targets, bit for
        bit, without the per-call branches, slicing and cached copies of the state. Each
        call leaves a new :attr:`target_qpos` array (never a view of ``raw``). ``None``
        where :meth:`apply` has more to do (interpolated targets, unlimited hinges with
        absolute targets, a mimic's delta from the leader's measured position).

        ``raw_never_negative_zero``: the caller's entries are never ``-0.0`` (the combined
        controller's raw actions, whose last operation adds offsets that are not
        ``-0.0``). A plain part's targets (``raw``, ``raw`` plus offsets, measured
        positions or previous targets; a sum is ``-0.0`` only when both terms are) are
        then never ``-0.0`` either, so with no bound ``-0.0`` no target and bound are
        zeros of opposite signs, the one case where the one-pass clip and the two-pass
        ``maximum`` / ``minimum`` may return different bits: the one-pass clip is taken
        even with a zero bound (a zero joint limit), the same targets for less."""
        base = self._base
        if not self._single_supported():
            return None
        plain, multipliers = self._plain, self._multipliers_row
        offsets = self._offsets_row if self._has_offsets else None
        one_pass = self._single_one_pass(raw_never_negative_zero)
        two_pass = self._clip and not one_pass
        lower, upper, max_bound, min_bound = self._lower_row, self._upper_row, self._max_bound, self._min_bound
        # the measured positions: a view of the live qpos, or the indices to take
        take = self._qpos_take
        measured = qpos[:, self._qpos_sel] if take is None else None
        take_indices = np.zeros(0, dtype=np.intp) if take is None else take
        from_target, from_measured = base == self._FROM_TARGET, base == self._FROM_MEASURED
        # an absolute plain target without offsets or a clip is the action itself: copied
        copy_raw = plain and offsets is None and not self._clip and not (from_target or from_measured)
        # the drives' buffer (never replaced): a view of the joints' columns, or the
        # buffer and the flat indices :meth:`apply` puts into (columns not consecutive)
        put = self._column_put if not isinstance(self._columns, slice) else None
        position = self._position if put is not None else self._position[:, self._columns]
        # a mimic's one action entry times each joint's multiplier: the entry read as a
        # Python float (exact) and multiplied into the (1, n) row, the same products as
        # the broadcast (1, 1) * (1, n), which costs twice as much
        entry = raw.item if not plain and raw.shape[1] == 1 else None

        def apply_single() -> None:
            if plain:
                change = raw
            elif entry is not None:
                change = multipliers * entry(0)
            else:
                change = raw * multipliers
            if from_measured:
                targets = (qpos.take(take_indices, axis=1) if measured is None else measured) + change
            elif from_target:
                targets = self.target_qpos + change
            elif offsets is not None:
                targets = change + offsets
            else:
                targets = change.copy() if copy_raw else change
            self._previous_target = self.target_qpos
            if one_pass:
                targets = clip_ufunc(targets, lower, upper)
            elif two_pass:
                targets = np.maximum(targets, max_bound)  # a new array: clipped in place
                np.minimum(targets, min_bound, out=targets)
            self.target_qpos = targets
            if put is None:
                position[...] = targets
            else:
                position.put(put, targets)

        return apply_single

    def _single_supported(self) -> bool:
        """Whether :meth:`single_apply` (and :meth:`single_terms`) can make a call: one env,
        targets written at once, no unlimited hinge with absolute targets, no mimic's delta
        from the leader's measured position, drive columns consecutive or put by index."""
        return not (
            type(self) is not PDJointPosController
            or not self._write_now
            or self._leader_measured is not None
            or (self._base == self._ABSOLUTE and self._periodic is not None)
            or (not isinstance(self._columns, slice) and self._column_put is None)
            or self._position.shape[0] != 1
        )

    def _single_one_pass(self, raw_never_negative_zero: bool) -> bool:
        """Whether the one-env call clips in one pass (see :meth:`single_apply`)."""
        return bool(
            self._one_pass_clip
            or (
                self._clip
                and self._plain
                and raw_never_negative_zero
                and not _has_negative_zero(self._lower_limit)
                and not _has_negative_zero(self._upper_limit)
            )
        )

    def single_terms(self, raw_never_negative_zero: bool = False) -> SingleTerms | None:
        """One env: what :meth:`single_apply`'s call computes, as Python numbers for
        :meth:`CombinedController._fuse_single
        <robot_agents.controllers.combined.CombinedController._fuse_single>`, which
        computes the targets of several parts on Python floats in one call. ``None`` where
        :meth:`single_apply` makes no call or would clip in two passes (``maximum`` then
        ``minimum``, whose zero of two opposite-sign zeros is not a comparison's)."""
        if not self._single_supported() or (self._clip and not self._single_one_pass(raw_never_negative_zero)):
            return None
        columns = self._columns
        column_list = list(range(columns.start, columns.stop)) if isinstance(columns, slice) else list(columns)
        return SingleTerms(
            base=self._base,
            multipliers=None if self._plain else self.multipliers.tolist(),
            offsets=self.offsets.tolist() if self._has_offsets and self._base == self._ABSOLUTE else None,
            bounds=list(zip(self._lower_limit.tolist(), self._upper_limit.tolist(), strict=True))
            if self._clip
            else None,
            qpos=self.binding.qpos_adr.tolist(),
            columns=[int(c) for c in column_list],
        )

    @property
    def needs_substep(self) -> bool:
        return self.config.interpolate

    def before_substep(self, substep: int, substeps: int, sim: SimView) -> None:
        fraction = (substep + 1) / substeps
        self.targets.position[:, self._columns] = self._previous_target + fraction * (
            self.target_qpos - self._previous_target
        )

    def observe(self) -> dict[str, FloatArray]:
        return {"target_qpos": self.target_qpos}

    def get_state(self) -> dict[str, FloatArray]:
        return {"target_qpos": self.target_qpos.copy(), "previous_target_qpos": self._previous_target.copy()}

    def set_state(self, state: dict[str, FloatArray]) -> None:
        self.target_qpos = np.array(state["target_qpos"], dtype=np.float64)
        self._previous_target = np.array(state["previous_target_qpos"], dtype=np.float64)

    def describe(self) -> str:
        cfg = self.config
        kind = "mimic position" if not self._plain else "position"
        if cfg.use_delta:
            kind = ("delta-from-target " if cfg.use_target else "delta ") + kind
        return f"PD joint {kind}{' (normalized)' if cfg.normalize_action else ''}"


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDJointVelConfig(ControllerConfig):
    """Joint velocity control: ``force = kv (qd* - qd)``. Position-servo drives need
    ``stiffness=0`` here (the rules set it), so that the servo tracks velocity only.

    Attributes:
        lower, upper: target velocity bounds (rad/s or m/s).
    """

    writes: ClassVar[tuple[str, ...]] = ("velocity",)
    lower: PerJoint = -1.0
    upper: PerJoint = 1.0

    def __post_init__(self) -> None:
        super().__post_init__()
        check_bounds(self, "lower", "upper")

    @property
    def keeps_targets(self) -> bool:
        """A zero velocity lets a loaded joint give."""
        return False

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PDJointVelController(self, binding, context)


class PDJointVelController(Controller):
    config: PDJointVelConfig

    def __init__(self, config: PDJointVelConfig, binding: JointBinding, context: ControllerContext) -> None:
        super().__init__(config, binding, context)
        self.target_qvel: FloatArray = np.zeros((context.num_envs, binding.size))

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        name, n = type(self.config).__name__, self.binding.size
        return per_joint(name, "lower", self.config.lower, n), per_joint(name, "upper", self.config.upper, n)

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        self.target_qvel[env_ids] = 0.0

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        self.target_qvel = raw
        self.targets.velocity[:, self.binding.column_sel] = raw

    def single_apply(self, raw: FloatArray, qpos: FloatArray) -> Callable[[], None] | None:
        """One env: :meth:`apply` of the action entries ``raw`` (a ``(1, k)`` view of a
        buffer the caller rewrites before each call) as a call of no arguments (see
        :meth:`PDJointPosController.single_apply`): the same targets, copied into a new
        :attr:`target_qvel` array per call (never a view of ``raw``). ``None`` for a
        subclass or joints whose drive columns are not consecutive."""
        columns, buffer = self.binding.column_sel, self.targets.velocity
        if type(self) is not PDJointVelController or not isinstance(columns, slice) or buffer.shape[0] != 1:
            return None
        velocity = buffer[:, columns]  # the drives' buffer (never replaced)

        def apply_single() -> None:
            target = raw.copy()
            self.target_qvel = target
            velocity[...] = target

        return apply_single

    def observe(self) -> dict[str, FloatArray]:
        return {"target_qvel": self.target_qvel}

    def get_state(self) -> dict[str, FloatArray]:
        return {"target_qvel": self.target_qvel.copy()}

    def set_state(self, state: dict[str, FloatArray]) -> None:
        self.target_qvel = np.array(state["target_qvel"], dtype=np.float64)

    def describe(self) -> str:
        return f"PD joint velocity{' (normalized)' if self.config.normalize_action else ''}"


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDJointPosVelConfig(PDJointPosConfig):
    """Position and velocity targets: the action is ``[q_target (n), qd_target (n)]``.

    ``vel_lower`` / ``vel_upper`` bound the velocity half (rad/s or m/s). The drives
    need stiffness > 0 (a PD servo tracks both targets).
    """

    writes: ClassVar[tuple[str, ...]] = ("position", "velocity")
    vel_lower: PerJoint = -1.0
    vel_upper: PerJoint = 1.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.use_target:
            raise ConfigError(
                "PDJointPosVelConfig: use_target is not supported; use use_delta with measured positions."
            )
        if self.stiffness is not None and np.any(np.asarray(self.stiffness, dtype=np.float64) <= 0):
            raise ConfigError(f"PDJointPosVelConfig: expected stiffness > 0 on every joint, got {self.stiffness}.")
        check_bounds(self, "vel_lower", "vel_upper")

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PDJointPosVelController(self, binding, context)


class PDJointPosVelController(PDJointPosController):
    config: PDJointPosVelConfig

    def __init__(self, config: PDJointPosVelConfig, binding: JointBinding, context: ControllerContext) -> None:
        super().__init__(config, binding, context)
        self.target_qvel: FloatArray = np.zeros((context.num_envs, binding.size))

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        low, high = super().action_bounds()
        name, n = type(self.config).__name__, self.binding.size
        vlow = per_joint(name, "vel_lower", self.config.vel_lower, n)
        vhigh = per_joint(name, "vel_upper", self.config.vel_upper, n)
        return np.concatenate([low, vlow]), np.concatenate([high, vhigh])

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        super().reset(env_ids, sim)
        self.target_qvel[env_ids] = 0.0

    def hold_raw(self, sim: SimView) -> FloatArray:
        """Absolute modes: the measured positions (rad or m) and zero velocities,
        ``(num_envs, 2 n)``; delta modes: zero."""
        if self.config.use_delta:
            return super().hold_raw(sim)
        positions = self._fold_periodic(sim.qpos[:, self.binding.qpos_adr])
        held: FloatArray = np.concatenate([positions, np.zeros_like(positions)], axis=1)
        return held

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        n = self.binding.size
        if self.config.use_delta:
            targets = sim.qpos[:, self.binding.qpos_sel] + raw[:, :n]
        else:
            targets = self._nearest_to_measured(0.0 + raw[:, :n], sim)
        self.target_qpos = self._clip_to_limits(targets)
        self.target_qvel = raw[:, n:]
        self.targets.position[:, self._columns] = self.target_qpos
        self.targets.velocity[:, self._columns] = self.target_qvel

    @property
    def needs_substep(self) -> bool:
        return False

    def observe(self) -> dict[str, FloatArray]:
        return {"target_qpos": self.target_qpos, "target_qvel": self.target_qvel}

    def get_state(self) -> dict[str, FloatArray]:
        return {**super().get_state(), "target_qvel": self.target_qvel.copy()}

    def set_state(self, state: dict[str, FloatArray]) -> None:
        super().set_state(state)
        self.target_qvel = np.array(state["target_qvel"], dtype=np.float64)

    def describe(self) -> str:
        cfg = self.config
        kind = f"{'delta ' if cfg.use_delta else ''}position + velocity"
        return f"PD joint {kind}{' (normalized)' if cfg.normalize_action else ''}"


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class JointEffortConfig(ControllerConfig):
    """Joint efforts: the action is the torque (N*m) or force (N) each joint's drive
    applies on top of its (declared or overridden) PD terms; set ``stiffness=0`` and
    ``damping=0`` for pure torque control of servo drives.

    Attributes:
        lower, upper: effort bounds (N*m or N); ``None``: the drives' effort limits.
    """

    writes: ClassVar[tuple[str, ...]] = ("effort",)
    lower: PerJoint | None = None
    upper: PerJoint | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        check_bounds(self, "lower", "upper")

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return JointEffortController(self, binding, context)


class JointEffortController(Controller):
    config: JointEffortConfig

    def __init__(self, config: JointEffortConfig, binding: JointBinding, context: ControllerContext) -> None:
        limits = np.array([context.effort_limits.get(j, np.inf) for j in binding.joint_names], dtype=np.float64)
        self._limits = limits
        super().__init__(config, binding, context)
        self.target_effort: FloatArray = np.zeros((context.num_envs, binding.size))

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        name, n = type(self.config).__name__, self.binding.size
        high = self._limits if self.config.upper is None else per_joint(name, "upper", self.config.upper, n)
        low = -self._limits if self.config.lower is None else per_joint(name, "lower", self.config.lower, n)
        return low.copy(), high.copy()

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        self.target_effort[env_ids] = 0.0

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        self.target_effort = raw
        self.targets.effort[:, self.binding.column_sel] = raw

    def observe(self) -> dict[str, FloatArray]:
        return {"target_effort": self.target_effort}

    def get_state(self) -> dict[str, FloatArray]:
        return {"target_effort": self.target_effort.copy()}

    def set_state(self, state: dict[str, FloatArray]) -> None:
        self.target_effort = np.array(state["target_effort"], dtype=np.float64)

    def describe(self) -> str:
        return f"joint effort{' (normalized)' if self.config.normalize_action else ''}"
