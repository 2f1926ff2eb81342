"""A bound robot's control modes: building each mode's controllers (with their drive
overrides), switching modes, and checking and applying actions."""

from __future__ import annotations

import contextvars
import math
from collections.abc import Callable, Mapping
from typing import Any

import gymnasium as gym
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.drives import DriveOverride, Drives, override_for
from robot_agents.agent.coupling import coupled_range
from robot_agents.agent.declaration import SINGLE_PART, ModeConfig
from robot_agents.agent.index import JointKind, RobotIndex
from robot_agents.controllers.base import ControllerConfig, ControllerContext, JointBinding
from robot_agents.controllers.combined import CombinedController, ControlledSim
from robot_agents.errors import ActionError, UnknownNameError

FloatArray = npt.NDArray[np.float64]


#: ``ndarray.sum`` without its Python wrapper (used for a finiteness test only).
_sum = np.add.reduce


def _quiet_runner() -> Callable[..., Any]:
    """``run(f, *args)``: ``f(*args)`` with NumPy's floating-point warnings off, for the
    finiteness test's sum (huge finite actions overflow it, then pass the exact check).

    NumPy >= 2 keeps its error state in a context variable: the call runs in a context
    of its own (one per caller: a context is entered by one thread at a time), which
    costs a few tens of ns. Older NumPy keeps it per thread: ``np.errstate`` per call."""
    before = np.geterr()
    context = contextvars.copy_context()
    context.run(np.seterr, all="ignore")
    if np.geterr() == before:
        return context.run
    np.seterr(**before)  # NumPy < 2: the thread's state changed; put it back

    def run(function: Callable[..., Any], *args: Any) -> Any:
        with np.errstate(all="ignore"):
            return function(*args)

    return run


class ControlModes:
    """The control modes of one bound robot; one of them is active.

    Args:
        owner: the robot's class name (messages).
        modes: the mode table (name -> config or ``{part: config}``).
        index, drives, context: the robot's names, drives and controller context.
        sim: the simulation the controllers read and the drives write.
    """

    def __init__(
        self,
        owner: str,
        modes: Mapping[str, ModeConfig],
        index: RobotIndex,
        drives: Drives,
        context: ControllerContext,
        sim: ControlledSim,
    ) -> None:
        self.owner = owner
        self.modes = dict(modes)
        self.index = index
        self.drives = drives
        self.context = context
        self.sim = sim
        self.num_envs = context.num_envs
        self._built: dict[str, CombinedController] = {}
        self.active: CombinedController
        self.mode = ""
        self._quiet = _quiet_runner()

    def parts_of(self, mode: str) -> dict[str, ControllerConfig]:
        entry = self.modes[mode]
        return {SINGLE_PART: entry} if isinstance(entry, ControllerConfig) else dict(entry)

    def controller_for(self, mode: Any, where: str = "") -> CombinedController:
        """The controller of ``mode`` (built on first use, not activated)."""
        if not isinstance(mode, str) or mode not in self.modes:
            raise UnknownNameError(where or self.owner, "control mode", str(mode), self.modes)
        built = self._built.get(mode)
        if built is None:
            built = self._built[mode] = self._build(mode)
        return built

    def _build(self, mode: str) -> CombinedController:
        override = DriveOverride.none(self.drives.size)
        where = f"{self.owner}.control_modes[{mode!r}]"
        bound = []
        for part, config in self.parts_of(mode).items():
            binding = self._binding(config, f"{where}[{part!r}]")
            override_for(self.drives, binding.columns, config.stiffness, config.damping, config.effort_limit, override)
            bound.append((part, config, binding))
        controllers = {}
        for part, config, binding in bound:
            self.drives.check_targets(binding.columns, config.target_kinds(), override, f"{where}[{part!r}]")
            controllers[part] = config.build(binding, self.context)
        return CombinedController(mode, controllers, self.drives, override)

    def _binding(self, config: ControllerConfig, where: str) -> JointBinding:
        index = self.index
        joints = [index.joint(name, f"{where} {type(config).__name__}") for name in config.joint_names]
        # an unlimited hinge or slide tied by a joint equality to a limited joint (a mimic)
        # takes the range the other's limits give it, and stays periodic (a hinge) only
        # while a whole turn of it is a whole turn of what it is tied to
        coupled = [
            coupled_range(self.context.model, j.id)
            if j.kind in (JointKind.HINGE, JointKind.SLIDE) and not j.limited
            else (j.range if j.limited else (-math.inf, math.inf), False)
            for j in joints
        ]
        ranges = np.array([c[0] for c in coupled], dtype=np.float64).reshape(-1, 2)
        return JointBinding(
            joint_names=config.joint_names,
            qpos_adr=np.array([j.qpos_adr for j in joints], dtype=np.int64),
            dof_adr=np.array([j.dof_adr for j in joints], dtype=np.int64),
            columns=self.drives.columns(config.joint_names, where),
            qpos_range=ranges,
            periodic=np.array([c[1] for c in coupled], dtype=bool),
        )

    def activate(self, mode: Any, where: str) -> None:
        """Make ``mode`` active: its drive settings (every time) and a hold of the measured pose."""
        controller = self.controller_for(mode, where)
        controller.activate(self.sim)
        self.active = controller
        self.mode = mode

    # -- actions --------------------------------------------------------------------------
    @property
    def single_action_space(self) -> gym.spaces.Box:
        c = self.active
        return gym.spaces.Box(c.action_low.astype(np.float32), c.action_high.astype(np.float32), dtype=np.float32)

    @property
    def action_space(self) -> gym.spaces.Box:
        c = self.active
        low = np.tile(c.action_low.astype(np.float32), (self.num_envs, 1))
        high = np.tile(c.action_high.astype(np.float32), (self.num_envs, 1))
        return gym.spaces.Box(low, high, dtype=np.float32)

    def validate_action(self, action: Any) -> FloatArray:
        """``action`` as float64 ``(num_envs, action_dim)``; ``(action_dim,)`` applies to
        every env. Raises :class:`ActionError` for other shapes, dtypes, NaN / inf."""
        return np.asarray(self.checked_action(action), dtype=np.float64)

    def checked_action(self, action: Any) -> npt.NDArray[Any]:
        """:meth:`validate_action` without the conversion to float64: the checked array in
        its own numeric dtype, ``(num_envs, action_dim)`` (possibly a read-only
        broadcast). The controllers' first operation (clipping against float64 bounds)
        converts it exactly, so the step skips one array copy."""
        active = self.active
        dim = active.action_dim
        if action.__class__ is np.ndarray:  # the common case: no conversion to try
            array = action
        else:
            try:
                array = np.asarray(action)
            except Exception as err:  # whatever the input's own __array__ raises
                raise ActionError(
                    f"{self._where()}: expected a numeric array of shape ({self.num_envs}, {dim}), "
                    f"got {type(action).__name__}: {err}."
                ) from None
        if array.dtype.kind not in "fiu":
            if array.dtype == object:
                raise ActionError(
                    f"{self._where()}: expected a numeric array of shape ({self.num_envs}, {dim}), "
                    f"got {type(action).__name__}: {action!r:.60}."
                )
            raise ActionError(f"{self._where()}: expected a float (or integer) array, got dtype {array.dtype}.")
        if array.dtype.itemsize > 8:  # long double: rounded to float64 first, as validate_action does
            array = np.asarray(array, dtype=np.float64)
        shape = array.shape
        if shape != (self.num_envs, dim):
            if shape != (dim,):
                parts = ", ".join(f"{p}: {s.stop - s.start}" for p, s in active.slices.items())
                raise ActionError(
                    f"{self._where()}: expected shape ({self.num_envs}, {dim}) or ({dim},) [{parts}], got {shape}."
                )
            # one env: a (1, dim) view (cheaper than broadcast_to); nothing writes into it
            array = array[None] if self.num_envs == 1 else np.broadcast_to(array, (self.num_envs, dim))
        # Fast path: a finite sum means every entry is finite (an overflowing sum of huge
        # finite values falls through to the exact check; the sum runs without NumPy's
        # overflow / invalid-value warnings). One env: Python's sum of the entries as
        # Python floats (exact conversions; it overflows to inf without a warning), which
        # is cheaper on one row than NumPy's reduction; integers are always finite.
        if self.num_envs == 1:
            finite = array.dtype.kind != "f" or math.isfinite(sum(array.ravel().tolist()))
        else:
            finite = math.isfinite(self._quiet(_sum, array, None))
        if not finite and not np.isfinite(array).all():
            bad = np.argwhere(~np.isfinite(array))[:3].tolist()
            raise ActionError(f"{self._where()}: expected finite values, got NaN or inf at (env, index) {bad}.")
        problem = active.check_action(array)
        if problem is not None:
            raise ActionError(f"{self._where()}: {problem}")
        return array

    def _where(self) -> str:
        return f"{self.owner}.set_action (mode {self.mode!r})"
