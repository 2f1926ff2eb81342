"""Passive joints: no action and no target; the drive is relaxed (zero stiffness) and
adds only optional viscous damping."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from robot_agents.actuators.config import PerJoint
from robot_agents.controllers.base import (
    Controller,
    ControllerConfig,
    ControllerContext,
    FloatArray,
    IntArray,
    JointBinding,
    SimView,
)
from robot_agents.keywords import checked_keywords


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PassiveConfig(ControllerConfig):
    """Joints that move freely. ``damping``: viscous damping per joint (N*m*s/rad or
    N*s/m) the drive applies while the mode is active."""

    writes: ClassVar[tuple[str, ...]] = ()
    stiffness: PerJoint | None = 0.0
    damping: PerJoint | None = 0.0
    normalize_action: bool = False

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        return PassiveController(self, binding, context)


class PassiveController(Controller):
    config: PassiveConfig

    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        return np.zeros(0), np.zeros(0)

    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        return None

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        return None

    def describe(self) -> str:
        return "passive"
