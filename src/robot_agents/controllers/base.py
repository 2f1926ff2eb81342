"""What every controller shares: joint bindings, action bounds and [-1, 1]
normalization, and the joint targets it produces.

A *config* is a frozen dataclass that a robot declares; :meth:`ControllerConfig.build`
turns it into a small stateful *controller* bound to joints of a compiled model. A
controller never writes MuJoCo controls: it writes joint targets (position, velocity,
effort) into the robot's :class:`~robot_agents.actuators.drives.JointTargets`, and the
drive stage turns them into ``ctrl`` for the robot's declared actuators. A config may
override the drives' gains while its mode is active (``stiffness``, ``damping``,
``effort_limit``); ``None`` keeps what the robot declares.
"""

from __future__ import annotations

import abc
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar, Protocol

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.config import PerJoint
from robot_agents.actuators.drives import JointTargets
from robot_agents.clipping import clip_ufunc as clip_ufunc  # (re-exported: the controllers' clip)
from robot_agents.clipping import one_pass_clip_exact as one_pass_clip_exact
from robot_agents.errors import ActionError, ConfigError
from robot_agents.indexing import index_selector
from robot_agents.kinematics.forward import FrameRef, Kinematics, resolve_frame
from robot_agents.validation import check_per_joint

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


class SimView(Protocol):
    """What a controller reads: the batched state of every env, ``qpos``
    ``(num_envs, nq)`` and ``qvel`` ``(num_envs, nv)`` (read-only)."""

    @property
    def qpos(self) -> FloatArray: ...

    @property
    def qvel(self) -> FloatArray: ...


@dataclass(frozen=True)
class JointBinding:
    """Indices of a controller's joints in the compiled model (resolved once at load).

    Attributes:
        joint_names: full (prefixed) joint names, shape ``(n,)``.
        qpos_adr: index of each joint in ``qpos``, shape ``(n,)``.
        dof_adr: index of each joint in ``qvel``, shape ``(n,)``.
        columns: each joint's column in the robot's joint targets (its drive), ``(n,)``.
        qpos_range: joint limits, shape ``(n, 2)``; ``(-inf, inf)`` for unlimited joints.
        periodic: ``(n,)`` booleans, true for an unlimited hinge (a continuous joint,
            whose angle is periodic: ``q`` and ``q + 2 pi`` are the same pose); empty
            (the default): none is.
    """

    joint_names: tuple[str, ...]
    qpos_adr: IntArray
    dof_adr: IntArray
    columns: IntArray
    qpos_range: FloatArray
    periodic: npt.NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool))
    #: ``qpos_adr`` / ``dof_adr`` / ``columns`` as slices where they are contiguous
    #: (indexing with a slice is a view and several times faster than with an array).
    qpos_sel: slice | IntArray = field(init=False, repr=False)
    dof_sel: slice | IntArray = field(init=False, repr=False)
    column_sel: slice | IntArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        periodic = np.asarray(self.periodic, dtype=bool).reshape(-1)
        object.__setattr__(self, "periodic", periodic if periodic.size else np.zeros(len(self.joint_names), dtype=bool))
        object.__setattr__(self, "qpos_sel", index_selector(self.qpos_adr))
        object.__setattr__(self, "dof_sel", index_selector(self.dof_adr))
        object.__setattr__(self, "column_sel", index_selector(self.columns))

    @property
    def size(self) -> int:
        return len(self.joint_names)


def scale_directions(action: FloatArray, entries: Sequence[slice]) -> FloatArray:
    """``action`` ``(num_envs, A)`` with each group of ``entries`` (a direction, e.g. a
    quaternion) whose largest magnitude exceeds 1 divided by it, so that a later clip to
    ``[-1, 1]`` leaves its direction; a new array when any is scaled."""
    for group in entries:
        largest = np.abs(action[:, group]).max(axis=1)
        if np.any(largest > 1.0):
            action = np.array(action, dtype=np.float64)
            action[:, group] /= np.maximum(largest, 1.0)[:, None]
    return action


@dataclass(frozen=True)
class ControllerContext:
    """What a controller may need beyond its joints, given by the robot that builds it.

    Attributes:
        num_envs: number of envs (the leading axis of every array).
        model: the compiled scene.
        control_timestep: seconds per control step (one action).
        kinematics: side-effect-free kinematics of the scene (shared by the robot's controllers).
        root_frame: the robot's root body (the frame of root-relative commands).
        targets: the robot's joint targets, which controllers write.
        end_effectors: the robot's end effectors by name: ``(tool frame, command frame)``;
            the first is the default.
        effort_limits: each driven joint's effort limit (N*m or N; ``inf`` if none).
        prefix: the robot's name prefix in the scene.
        owner: the robot's class name, for messages.
    """

    num_envs: int
    model: mujoco.MjModel
    control_timestep: float
    kinematics: Kinematics
    root_frame: FrameRef
    targets: JointTargets
    end_effectors: dict[str, tuple[FrameRef, FrameRef]] = field(default_factory=dict)
    effort_limits: dict[str, float] = field(default_factory=dict)
    prefix: str = ""
    owner: str = ""

    def resolve_frame(self, name: str, where: str) -> FrameRef:
        """The robot's body or site ``name`` (unprefixed); unknown names raise with suggestions."""
        return resolve_frame(self.model, name, self.prefix, where)


def check_bounds(config: object, low_name: str, high_name: str, count: int | None = None, unit: str = "joint") -> None:
    """A config's action bounds ``low_name`` / ``high_name`` (each ``None``, one number,
    or one per joint of ``config.joint_names``; ``count``: one per ``unit`` of that many
    instead, e.g. 3 per axis): not NaN (infinite where unbounded), of the right size,
    and, both given, ``low <= high`` for every entry; :class:`ConfigError` naming the
    config otherwise. Checked when the config is made, not when its mode is first used.
    (Before 2026-11-29 a bound was not looked at when the one before it was ``None``.)"""
    where = f"{type(config).__name__}({', '.join(config.joint_names)})"  # type: ignore[attr-defined]
    n = len(config.joint_names) if count is None else count  # type: ignore[attr-defined]
    arrays = []
    for name in (low_name, high_name):
        value = getattr(config, name)
        if value is None:
            continue
        try:
            array = np.asarray(value, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise ConfigError(f"{where}.{name}: expected a number or one per {unit}, got {value!r}.") from None
        if array.size not in (1, n) or np.any(np.isnan(array)):
            raise ConfigError(f"{where}.{name}: expected a number or {n} (one per {unit}), got {value!r}.")
        arrays.append(array)
    if len(arrays) < 2:
        return
    low, high = np.broadcast_arrays(*arrays)
    if np.any(low > high):
        raise ConfigError(
            f"{where}: expected {low_name} <= {high_name} for every {unit}, got {low_name}="
            f"{getattr(config, low_name)!r}, {high_name}={getattr(config, high_name)!r}."
        )


@dataclass(frozen=True, kw_only=True)
class ControllerConfig(abc.ABC):
    """Base of all controller configs.

    Attributes:
        joint_names: the joints this controller drives, in action order (unprefixed).
        normalize_action: take actions in ``[-1, 1]`` and map them linearly onto
            ``[lower, upper]``; otherwise take raw values. Both are clipped.
        reverse_normalization: map ``-1`` onto ``upper`` and ``+1`` onto ``lower``
            instead (raw actions keep ``lower <= upper``); grippers use it so that ``-1``
            closes whichever way their joints close.
        stiffness, damping, effort_limit: drive settings this mode imposes on its
            joints while it is active (N*m/rad, N*m*s/rad, N*m; per joint or one for
            all); ``None`` keeps the robot's declared actuators'.
    """

    #: The target kinds the controller writes: ``"position"``, ``"velocity"``, ``"effort"``.
    writes: ClassVar[tuple[str, ...]] = ("position",)

    joint_names: tuple[str, ...]
    normalize_action: bool = True
    reverse_normalization: bool = False
    stiffness: PerJoint | None = None
    damping: PerJoint | None = None
    effort_limit: PerJoint | None = None

    def __post_init__(self) -> None:
        for name in ("stiffness", "damping", "effort_limit"):
            value = getattr(self, name)
            if value is not None:
                check_per_joint(value, f"{type(self).__name__}.{name}")
        if isinstance(self.joint_names, str) or not isinstance(self.joint_names, Sequence):
            raise ConfigError(
                f"{type(self).__name__}.joint_names: expected a tuple of joint names, got {self.joint_names!r}."
            )
        object.__setattr__(self, "joint_names", tuple(self.joint_names))
        if len(set(self.joint_names)) != len(self.joint_names):
            raise ConfigError(f"{type(self).__name__}.joint_names: a joint is listed twice in {self.joint_names}.")

    def target_kinds(self) -> tuple[str, ...]:
        """The target kinds the controller writes (see :attr:`writes`)."""
        return self.writes

    @property
    def keeps_targets(self) -> bool:
        """Whether the mode's hold action keeps the joint targets where they were taken
        (absolute and target-delta joint modes, end-effector modes, a base's velocity),
        rather than following the measured pose or a zero velocity, which lets a joint
        under a load it carries (a leg under the body) give without end."""
        return True

    @abc.abstractmethod
    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        """Make the controller for these joints of a compiled model."""


class Controller(abc.ABC):
    """A controller bound to a compiled model; all arrays carry a leading ``num_envs`` axis.

    It writes its joints' columns of ``targets`` (position, velocity, effort)."""

    def __init__(self, config: ControllerConfig, binding: JointBinding, context: ControllerContext) -> None:
        self.config = config
        self.binding = binding
        self.num_envs = context.num_envs
        self.targets = context.targets
        low, high = self.action_bounds()
        if low.shape != high.shape or np.any(low > high):
            raise ConfigError(
                f"{type(config).__name__}({', '.join(config.joint_names)}): expected lower <= upper bounds, "
                f"got lower={low.tolist()}, upper={high.tolist()}."
            )
        self.raw_low, self.raw_high = low, high
        #: The raw values a normalized action of -1 and +1 map onto.
        self.unit_low, self.unit_high = (high, low) if config.reverse_normalization else (low, high)
        if config.normalize_action and not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
            raise ConfigError(
                f"{type(config).__name__}({', '.join(config.joint_names)}): normalized actions need finite bounds, "
                f"got lower={low.tolist()}, upper={high.tolist()}."
            )

    # -- action interface -------------------------------------------------------------
    @abc.abstractmethod
    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        """Raw (un-normalized) action bounds, each of shape ``(action_dim,)``."""

    @property
    def action_dim(self) -> int:
        return int(self.raw_low.shape[0])

    @property
    def action_low(self) -> FloatArray:
        """Lower bound of the action this controller takes (``-1`` when normalized)."""
        return -np.ones(self.action_dim) if self.config.normalize_action else self.raw_low.copy()

    @property
    def action_high(self) -> FloatArray:
        return np.ones(self.action_dim) if self.config.normalize_action else self.raw_high.copy()

    def to_raw(self, action: FloatArray) -> FloatArray:
        """Clip an action of shape ``(num_envs, action_dim)`` and undo normalization."""
        entries = self.direction_entries
        if entries is not None:
            action = scale_directions(action, (entries,))
        if self.config.normalize_action:
            unit = np.clip(action, -1.0, 1.0)
            return self.unit_low + (unit + 1.0) * 0.5 * (self.unit_high - self.unit_low)
        return np.clip(action, self.raw_low, self.raw_high)

    def from_raw(self, raw: FloatArray) -> FloatArray:
        """The action (normalized if this controller's is) that commands ``raw``, clipped
        to the bounds; the inverse of :meth:`to_raw`. Shape ``(..., action_dim)``.

        Raises:
            ActionError: ``raw`` is not a finite array whose last axis is ``action_dim``.
        """
        try:
            values = np.asarray(raw, dtype=np.float64)
        except (TypeError, ValueError):
            values = np.full(1, np.nan)
        if values.ndim == 0 or values.shape[-1] != self.action_dim or not np.all(np.isfinite(values)):
            raise ActionError(
                f"{type(self).__name__}({', '.join(self.config.joint_names)}).from_raw: expected finite raw "
                f"commands of shape (..., {self.action_dim}), got {np.shape(raw)}"
                + (" with values not finite." if values.ndim and values.shape[-1] == self.action_dim else ".")
            )
        clipped = np.clip(values, self.raw_low, self.raw_high)
        if not self.config.normalize_action:
            return clipped
        span = self.unit_high - self.unit_low
        with np.errstate(invalid="ignore", divide="ignore"):
            unit = np.where(span != 0, 2.0 * (clipped - self.unit_low) / np.where(span != 0, span, 1.0) - 1.0, 0.0)
        return unit

    # -- lifecycle --------------------------------------------------------------------
    @abc.abstractmethod
    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        """Re-initialise the controller's state of ``env_ids`` from the measured state
        (the drive stage has set targets that hold the measured pose)."""

    def set_action(self, action: FloatArray, sim: SimView) -> None:
        """Turn a validated action ``(num_envs, action_dim)`` into joint targets."""
        self.apply(self.to_raw(action), sim)

    @abc.abstractmethod
    def apply(self, raw: FloatArray, sim: SimView) -> None:
        """Like :meth:`set_action` for an action already clipped and de-normalized
        (:meth:`to_raw`): ``raw`` ``(num_envs, action_dim)`` in the controller's physical
        units (rad, m, rad/s, m/s, N*m, N, or a pose's m and rad)."""

    def hold_raw(self, sim: SimView) -> FloatArray:
        """The raw action (physical units, not normalized) that asks this controller's
        joints to stay where they are, a new array ``(num_envs, action_dim)``: zero
        (delta, velocity, effort) unless a controller of absolute targets overrides it
        with the measured pose or its current target."""
        return np.zeros((self.num_envs, self.action_dim))

    @property
    def checks_actions(self) -> bool:
        """True when :meth:`check_raw_action` can reject an action within the bounds."""
        return False

    @property
    def direction_entries(self) -> slice | None:
        """Entries of the action that are one direction (a quaternion, normalized by the
        controller), or ``None``: beyond the bounds they are scaled down together, by their
        largest magnitude, instead of clipped one by one (which would turn the direction).
        Bounded to ``[-1, 1]`` (in normalized units too)."""
        return None

    def check_raw_action(self, raw: FloatArray) -> str | None:
        """Why a clipped, de-normalized action ``(num_envs, action_dim)`` cannot be applied,
        or ``None`` when it can (e.g. a zero quaternion). Checked before anything is
        written, for controllers whose :attr:`checks_actions` is true."""
        return None

    def step_info(self) -> dict[str, npt.NDArray[np.generic]]:
        """Per-env outcome of the last action for the env's ``info`` (copies, each with a
        leading ``num_envs`` axis), e.g. whether IK reached its target."""
        return {}

    @property
    def needs_substep(self) -> bool:
        """True when :meth:`before_substep` must run before every physics substep."""
        return False

    def before_substep(self, substep: int, substeps: int, sim: SimView) -> None:
        """Update targets before physics substep ``substep`` of ``substeps`` (default: nothing)."""
        return None

    def observe(self) -> dict[str, FloatArray]:
        """Controller quantities for observations, each with a leading ``num_envs`` axis.

        The arrays may be the controller's own buffers: copy before keeping them."""
        return {}

    def get_state(self) -> dict[str, FloatArray]:
        """The controller's internal state (copies), each array with a leading ``num_envs`` axis."""
        return {}

    def set_state(self, state: dict[str, FloatArray]) -> None:
        """Restore what :meth:`get_state` returned (default: nothing to restore)."""
        return None

    def describe(self) -> str:
        """One-line human description for CLIs and docs."""
        return type(self.config).__name__
