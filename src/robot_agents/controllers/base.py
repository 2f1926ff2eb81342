"""What every controller shares: joint bindings, gains written into MuJoCo actuators,
action bounds and [-1, 1] normalization.

A *config* is a frozen dataclass that a robot declares; :meth:`ControllerConfig.build`
turns it into a small stateful *controller* bound to joints of a compiled model.
PD control runs inside MuJoCo: every controlled joint has one ``general`` actuator
with an affine bias, ``force = gain * ctrl + b1 * qpos + b2 * qvel`` (clamped to the
force limit), and a controller writes ``gain``/``bias`` when its mode is activated
and the target into ``ctrl`` on each action.
"""

from __future__ import annotations

import abc
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.indexing import index_selector
from robot_agents.kinematics.forward import FrameRef, Kinematics, resolve_frame

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
#: A scalar applied to every joint, or one value per joint.
PerJoint = float | tuple[float, ...]


class SimView(Protocol):
    """What a controller reads and writes: the batched state of every env.

    ``qpos`` ``(num_envs, nq)`` and ``qvel`` ``(num_envs, nv)`` are read-only;
    controllers write their commands into ``ctrl`` ``(num_envs, nu)``.
    """

    @property
    def qpos(self) -> FloatArray: ...

    @property
    def qvel(self) -> FloatArray: ...

    @property
    def ctrl(self) -> FloatArray: ...


@dataclass(frozen=True)
class JointBinding:
    """Indices of a controller's joints in the compiled model (resolved once at load).

    Attributes:
        joint_names: full (prefixed) joint names, shape ``(n,)``.
        qpos_adr: index of each joint in ``qpos``, shape ``(n,)``.
        dof_adr: index of each joint in ``qvel``, shape ``(n,)``.
        actuator_ids: the actuator driving each joint, shape ``(n,)``.
        ctrl_adr: index of each actuator's control in ``ctrl``, shape ``(n,)``.
        qpos_range: joint limits, shape ``(n, 2)``; ``(-inf, inf)`` for unlimited joints.
    """

    joint_names: tuple[str, ...]
    qpos_adr: IntArray
    dof_adr: IntArray
    actuator_ids: IntArray
    ctrl_adr: IntArray
    qpos_range: FloatArray
    #: ``qpos_adr`` / ``dof_adr`` / ``ctrl_adr`` as slices where they are contiguous
    #: (indexing with a slice is a view and several times faster than with an array).
    qpos_sel: slice | IntArray = field(init=False, repr=False)
    dof_sel: slice | IntArray = field(init=False, repr=False)
    ctrl_sel: slice | IntArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "qpos_sel", index_selector(self.qpos_adr))
        object.__setattr__(self, "dof_sel", index_selector(self.dof_adr))
        object.__setattr__(self, "ctrl_sel", index_selector(self.ctrl_adr))

    @property
    def size(self) -> int:
        return len(self.joint_names)


def per_joint(owner: str, field: str, value: PerJoint, n: int) -> FloatArray:
    """Broadcast a scalar or per-joint tuple to a float64 array of shape ``(n,)``."""
    array = np.asarray(value, dtype=np.float64).reshape(-1)
    if array.size == 1:
        return np.full(n, float(array[0]))
    if array.size != n:
        raise ConfigError(
            f"{owner}.{field}: expected 1 or {n} values (one per joint), got {array.size}: {array.tolist()}."
        )
    return array


@dataclass(frozen=True)
class ControllerContext:
    """What a controller may need beyond its joints, given by the robot that builds it.

    Attributes:
        num_envs: number of envs (the leading axis of every array).
        model: the compiled scene.
        control_timestep: seconds per control step (one action).
        kinematics: side-effect-free kinematics of the scene (shared by the robot's controllers).
        root_frame: the robot's root body (the frame of root-relative commands).
        tool_frame: the robot's tool centre point, if it declares one.
        prefix: the robot's name prefix in the scene.
        owner: the robot's class name, for messages.
    """

    num_envs: int
    model: mujoco.MjModel
    control_timestep: float
    kinematics: Kinematics
    root_frame: FrameRef
    tool_frame: FrameRef | None
    prefix: str = ""
    owner: str = ""

    def resolve_frame(self, name: str, where: str) -> FrameRef:
        """The robot's body or site ``name`` (unprefixed); unknown names raise with suggestions."""
        return resolve_frame(self.model, name, self.prefix, where)


@dataclass(frozen=True, kw_only=True)
class ControllerConfig(abc.ABC):
    """Base of all controller configs.

    Attributes:
        joint_names: the joints this controller drives, in action order (unprefixed).
        normalize_action: take actions in ``[-1, 1]`` and map them linearly onto
            ``[lower, upper]``; otherwise take raw values. Both are clipped.
    """

    joint_names: tuple[str, ...]
    normalize_action: bool = True

    def __post_init__(self) -> None:
        if isinstance(self.joint_names, str) or not isinstance(self.joint_names, Sequence):
            raise ConfigError(
                f"{type(self).__name__}.joint_names: expected a tuple of joint names, got {self.joint_names!r}."
            )
        object.__setattr__(self, "joint_names", tuple(self.joint_names))
        if len(set(self.joint_names)) != len(self.joint_names):
            raise ConfigError(f"{type(self).__name__}.joint_names: a joint is listed twice in {self.joint_names}.")

    @abc.abstractmethod
    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        """Make the controller for these joints of a compiled model."""


class Controller(abc.ABC):
    """A controller bound to a compiled model; all arrays carry a leading ``num_envs`` axis."""

    def __init__(self, config: ControllerConfig, binding: JointBinding, num_envs: int) -> None:
        self.config = config
        self.binding = binding
        self.num_envs = num_envs
        low, high = self.action_bounds()
        if low.shape != high.shape or np.any(low > high):
            raise ConfigError(
                f"{type(config).__name__}({', '.join(config.joint_names)}): expected lower <= upper bounds, "
                f"got lower={low.tolist()}, upper={high.tolist()}."
            )
        self.raw_low, self.raw_high = low, high
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
        if self.config.normalize_action:
            unit = np.clip(action, -1.0, 1.0)
            return self.raw_low + (unit + 1.0) * 0.5 * (self.raw_high - self.raw_low)
        return np.clip(action, self.raw_low, self.raw_high)

    # -- lifecycle --------------------------------------------------------------------
    @abc.abstractmethod
    def gains(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Actuator parameters per joint, each shape ``(n,)``: gain on ctrl, bias on qpos,
        bias on qvel, force limit (N or N*m)."""

    def apply_gains(self, model: mujoco.MjModel) -> None:
        """Write this controller's gains and force limits into the model's actuators."""
        gain, bias_q, bias_v, force = self.gains()
        ids = self.binding.actuator_ids
        model.actuator_gainprm[ids, 0] = gain
        model.actuator_biasprm[ids, 0] = 0.0
        model.actuator_biasprm[ids, 1] = bias_q
        model.actuator_biasprm[ids, 2] = bias_v
        model.actuator_forcelimited[ids] = 1
        model.actuator_forcerange[ids, 0] = -force
        model.actuator_forcerange[ids, 1] = force

    @abc.abstractmethod
    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        """Re-initialise targets of ``env_ids`` from the measured state and write the
        resulting hold command into ``sim.ctrl``."""

    def set_action(self, action: FloatArray, sim: SimView) -> None:
        """Turn a validated action ``(num_envs, action_dim)`` into targets written into ``ctrl``."""
        self.apply(self.to_raw(action), sim)

    @abc.abstractmethod
    def apply(self, raw: FloatArray, sim: SimView) -> None:
        """Like :meth:`set_action` for an action already clipped and de-normalized (:meth:`to_raw`)."""

    @property
    def checks_actions(self) -> bool:
        """True when :meth:`check_raw_action` can reject an action within the bounds."""
        return False

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
        """Update ``ctrl`` before physics substep ``substep`` of ``substeps`` (default: nothing)."""
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
