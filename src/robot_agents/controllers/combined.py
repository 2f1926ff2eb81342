"""One flat action split by slices over per-part controllers (arm, gripper, base, ...)."""

from __future__ import annotations

from collections.abc import Mapping

import mujoco
import numpy as np

from robot_agents.controllers.base import Controller, FloatArray, IntArray


class CombinedController:
    """The controllers of one control mode, in action order.

    ``parts`` maps a part name (``"arm"``, ``"gripper"``, ...) to its controller; the
    flat action is their actions concatenated in that order.
    """

    def __init__(self, mode: str, parts: Mapping[str, Controller]) -> None:
        self.mode = mode
        self.parts = dict(parts)
        self.slices: dict[str, slice] = {}
        start = 0
        for name, controller in self.parts.items():
            self.slices[name] = slice(start, start + controller.action_dim)
            start += controller.action_dim
        self.action_dim = start
        self.action_low = np.concatenate([c.action_low for c in self.parts.values()]) if self.parts else np.zeros(0)
        self.action_high = np.concatenate([c.action_high for c in self.parts.values()]) if self.parts else np.zeros(0)
        self._substep_parts = [c for c in self.parts.values() if c.needs_substep]

    @property
    def needs_substep(self) -> bool:
        return bool(self._substep_parts)

    def activate(self, model: mujoco.MjModel, qpos: FloatArray, qvel: FloatArray, ctrl: FloatArray) -> None:
        """Apply this mode's gains and start holding the measured pose in every env."""
        all_envs = np.arange(qpos.shape[0])
        for controller in self.parts.values():
            controller.apply_gains(model)
            controller.reset(all_envs, qpos, qvel, ctrl)

    def reset(self, env_ids: IntArray, qpos: FloatArray, qvel: FloatArray, ctrl: FloatArray) -> None:
        for controller in self.parts.values():
            controller.reset(env_ids, qpos, qvel, ctrl)

    def set_action(self, action: FloatArray, qpos: FloatArray, qvel: FloatArray, ctrl: FloatArray) -> None:
        """``action``: validated, shape ``(num_envs, action_dim)``."""
        for name, controller in self.parts.items():
            controller.set_action(action[:, self.slices[name]], qpos, qvel, ctrl)

    def before_substep(self, substep: int, substeps: int, ctrl: FloatArray) -> None:
        for controller in self._substep_parts:
            controller.before_substep(substep, substeps, ctrl)

    def get_state(self) -> dict[str, dict[str, FloatArray]]:
        return {name: c.get_state() for name, c in self.parts.items()}

    def set_state(self, state: Mapping[str, Mapping[str, FloatArray]]) -> None:
        for name, controller in self.parts.items():
            controller.set_state(dict(state.get(name, {})))
