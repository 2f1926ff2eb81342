"""Passive joints: no action, the actuator only adds optional viscous damping."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robot_agents.controllers.base import (
    Controller,
    ControllerConfig,
    ControllerContext,
    FloatArray,
    IntArray,
    JointBinding,
    PerJoint,
    SimView,
    per_joint,
)


@dataclass(frozen=True, kw_only=True)
class PassiveConfig(ControllerConfig):
    """Joints that move freely. ``damping``: viscous damping per joint (N*m*s/rad or N*s/m)."""

    damping: PerJoint = 0.0
    normalize_action: bool = False

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PassiveController(self, binding, context.num_envs)


class PassiveController(Controller):
    config: PassiveConfig

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        return np.zeros(0), np.zeros(0)

    def gains(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        n = self.binding.size
        kv = per_joint("PassiveConfig", "damping", self.config.damping, n)
        return np.zeros(n), np.zeros(n), -kv, np.full(n, 1e6)

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        sim.ctrl[np.ix_(env_ids, self.binding.ctrl_adr)] = 0.0

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        return None

    def describe(self) -> str:
        return "passive"
