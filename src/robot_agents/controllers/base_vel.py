"""Mobile-base velocity control (ManiSkill's names): commands in the robot's own frame,
turned into velocity targets of the base's planar joints (x and y slides, a yaw hinge
about +z, in the frame the robot is mounted in).

- ``pd_base_vel`` (holonomic): action ``(vx, vy, wz)``: forward and lateral speed (m/s)
  and yaw rate (rad/s), in the robot's heading frame.
- ``pd_base_forward_vel`` (differential drive): action ``(v, wz)``: forward speed and
  yaw rate; the base cannot move sideways.

The robot-frame command goes to the mount frame turned by the heading at mid-step and
shortened to the chord of the arc it describes over the control step, so a base that
drives and turns at once ends the step on that arc. The base joints' drives track the
velocity targets (a velocity servo, or a PD servo with its stiffness relaxed by the
mode), so the base pushes and is pushed by the world.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from robot_agents.actuators.config import PerJoint, per_joint
from robot_agents.controllers.base import (
    Controller,
    ControllerConfig,
    ControllerContext,
    FloatArray,
    JointBinding,
    SimView,
    check_bounds,
)
from robot_agents.controllers.joint import PDJointVelController
from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDBaseVelConfig(ControllerConfig):
    """Velocity control of a planar base.

    Attributes:
        joint_names: the x slide, the y slide and the yaw hinge, in that order.
        holonomic: ``(vx, vy, wz)`` actions; ``False``: differential drive, ``(v, wz)``.
        lower, upper: action bounds per entry (m/s and rad/s).
    """

    writes: ClassVar[tuple[str, ...]] = ("velocity",)
    holonomic: bool = True
    lower: PerJoint = -1.0
    upper: PerJoint = 1.0
    stiffness: PerJoint | None = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if len(self.joint_names) != 3:
            raise ConfigError(
                f"{type(self).__name__}: expected the x slide, y slide and yaw hinge joints, got {self.joint_names}."
            )
        check_bounds(self, "lower", "upper", 3 if self.holonomic else 2, "action entry")

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PDBaseVelController(self, binding, context)


class PDBaseVelController(PDJointVelController):
    """Robot-frame base velocities to mount-frame joint velocity targets (the velocity
    controller's targets and state, with the base's action layout)."""

    config: PDBaseVelConfig  # type: ignore[assignment]

    def __init__(self, config: PDBaseVelConfig, binding: JointBinding, context: ControllerContext) -> None:
        super().__init__(config, binding, context)  # type: ignore[arg-type]
        self._yaw_adr = int(binding.qpos_adr[2])
        self._half_step = 0.5 * context.control_timestep  # s
        self._holonomic = config.holonomic
        self._velocity = self.targets.velocity  # the drives' buffer (never replaced)

    def _heading(self, yaw: FloatArray, turn: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``cos`` and ``sin`` of the heading at mid-step, ``yaw + wz dt / 2``, and the
        chord's share of the arc, ``sin(h) / h`` with ``h = wz dt / 2``, each
        ``(num_envs,)``: the mean of the robot-frame command turned by the heading over a
        step turning at ``wz`` is the command turned by the mid-step heading and
        shortened by that share, which puts the base at the end of the arc the command
        describes. (Turned by the heading at the step's start, as ManiSkill does, the
        base slid outward, up to 0.17 m/s sideways on Fetch at 1 m/s and 3.14 rad/s.)
        Without a turn, exactly ``yaw`` and a share of 1 (``yaw + 0.0`` would make a yaw
        of ``-0.0`` ``0.0``)."""
        half = turn * self._half_step
        still = half == 0.0
        heading = yaw + half
        share = np.ones(half.shape, half.dtype)  # (np.ones_like's result, without its Python wrapper)
        if still.any():
            np.copyto(heading, yaw, where=still)
        np.divide(np.sin(half), half, out=share, where=~still)
        return np.cos(heading), np.sin(heading), share

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        name = type(self.config).__name__
        n = 3 if self.config.holonomic else 2
        return per_joint(name, "lower", self.config.lower, n), per_joint(name, "upper", self.config.upper, n)

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        if raw.shape[0] == 1:
            self._apply_single(raw, sim)
            return
        turn = raw[:, -1]
        yaw = sim.qpos[:, self._yaw_adr]
        cos, sin, share = self._heading(yaw, turn)
        forward = raw[:, 0] * share
        lateral = raw[:, 1] * share if self._holonomic else 0.0
        target = np.empty((raw.shape[0], 3))
        target[:, 0] = cos * forward - sin * lateral
        target[:, 1] = sin * forward + cos * lateral
        target[:, 2] = turn
        self.target_qvel = target
        self._velocity[:, self.binding.column_sel] = target

    def _apply_single(self, raw: FloatArray, sim: SimView) -> None:
        """:meth:`apply` of one env (``raw`` ``(1, k)``) through :meth:`_single_target`."""
        target = np.array([self._single_target(raw[0].tolist(), float(sim.qpos[0, self._yaw_adr]))])
        self.target_qvel = target
        self._velocity[:, self.binding.column_sel] = target

    def _single_target(self, action: list[float], yaw: float) -> list[float]:
        """One env's mount-frame velocity targets ``[x, y, yaw]`` (m/s, m/s, rad/s) for its
        raw ``action`` (``k`` Python floats) at base yaw ``yaw`` (rad): :meth:`_heading`'s
        and :meth:`apply`'s products and sums on Python floats (IEEE operations, as
        NumPy's, in the same order; the sines and cosines through NumPy's own ``sin`` /
        ``cos``), without a dozen operations on one-element arrays."""
        turn = action[-1]
        half = turn * self._half_step
        if half == 0.0:  # no turn: the heading is the yaw, the share 1
            heading, share = yaw, 1.0
        else:
            heading, share = yaw + half, float(np.sin(half)) / half
        cos, sin = float(np.cos(heading)), float(np.sin(heading))
        forward = action[0] * share
        lateral = action[1] * share if self._holonomic else 0.0
        return [cos * forward - sin * lateral, sin * forward + cos * lateral, turn]

    def single_apply(self, raw: FloatArray, qpos: FloatArray) -> Callable[[], None] | None:
        """One env: :meth:`apply` of the action entries ``raw`` (a ``(1, k)`` view of a
        buffer the caller rewrites before each call) as a call of no arguments, reading
        the yaw from ``qpos``, a ``(1, nq)`` view that follows the simulation (see
        :meth:`PDJointPosController.single_apply
        <robot_agents.controllers.joint.PDJointPosController.single_apply>`): the same
        targets, bit for bit (:meth:`_single_target`), a new :attr:`target_qvel` array
        per call. ``None`` for a subclass or base joints whose drive columns are not
        consecutive."""
        columns = self.binding.column_sel
        if type(self) is not PDBaseVelController or not isinstance(columns, slice) or self._velocity.shape[0] != 1:
            return None
        row, qpos_row, yaw_adr = raw[0], qpos[0], self._yaw_adr
        velocity = self._velocity[:, columns]  # the drives' buffer (never replaced), (1, 3)
        velocity_row = velocity[0]
        single_target = self._single_target

        def apply_single() -> None:
            # the targets written into the drives' row by element, then copied out as the
            # new target array (the same float64 values as building it first)
            velocity_row[0], velocity_row[1], velocity_row[2] = single_target(row.tolist(), qpos_row.item(yaw_adr))
            self.target_qvel = velocity.copy()

        return apply_single

    def describe(self) -> str:
        kind = "holonomic (vx, vy, wz)" if self.config.holonomic else "differential (v, wz)"
        return f"base velocity, {kind}{' (normalized)' if self.config.normalize_action else ''}"


def base_modes(joints: tuple[str, str, str], holonomic: bool, max_speed: float, max_turn: float) -> PDBaseVelConfig:
    """The base part of every mode: ``pd_base_vel`` or ``pd_base_forward_vel`` bounds."""
    if not (math.isfinite(max_speed) and max_speed > 0 and math.isfinite(max_turn) and max_turn > 0):
        raise ConfigError(f"Base: expected finite max_speed and max_turn > 0, got {max_speed!r}, {max_turn!r}.")
    bounds = (max_speed, max_speed, max_turn) if holonomic else (max_speed, max_turn)
    return PDBaseVelConfig(joint_names=joints, holonomic=holonomic, lower=tuple(-b for b in bounds), upper=bounds)
