"""A :class:`~robot_agents.real.bus.JointBus` on a simulated copy of a robot: the
bridge run and tested without hardware. Each :meth:`SimulatedBus.write` sets its drives'
targets and advances its physics one control period (where real motors would keep
moving in real time until the next command)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from robot_agents.actuators.drives import DriveOverride
from robot_agents.agent import Agent
from robot_agents.errors import ActionError, ConfigError, StateError, UnknownNameError
from robot_agents.registry import agent_class
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene

FloatArray = npt.NDArray[np.float64]


class SimulatedBus:
    """A :class:`JointBus` on a simulated copy of ``robot`` (its driven joints).

    Args:
        robot: registered uid or Agent subclass.
        keyframe: where the simulated robot starts (default: its first keyframe).
        sim_freq / control_freq: the copy's physics and command rates (Hz); each
            :meth:`write` advances ``1 / control_freq`` s.
    """

    def __init__(
        self,
        robot: str | type[Agent],
        keyframe: str | None = None,
        sim_freq: int | None = None,
        control_freq: int = DEFAULT_CONTROL_FREQ,
    ) -> None:
        cls = agent_class(robot, "SimulatedBus")
        # an absolute joint mode: no controller rewrites the targets between substeps
        mode = "pd_joint_pos" if "pd_joint_pos" in cls.modes() else None
        self.scene = Scene(cls, sim_freq=sim_freq, control_freq=control_freq, control_modes=mode)
        self.agent = self.scene.agents[0]
        checked = cls.check()
        if keyframe is not None and checked.keyframe_name(keyframe) is None:
            self.scene.close()
            raise UnknownNameError("SimulatedBus", "keyframe", keyframe, checked.keyframes, checked.keyframe_aliases)
        if cls.keyframe_names():
            self.scene.reset(keyframes=keyframe)
        # the drives take every target kind they are sent (position, velocity
        # feed-forward, effort), as hardware drives do
        drives = self.agent.drives
        self._closed = False
        self.set_gains(drives.declared_stiffness, drives.declared_damping, drives.declared_effort_limit)
        self._names = tuple(self.agent.drives.joint_names)

    @property
    def joint_names(self) -> Sequence[str]:
        return self._names

    def read(self) -> tuple[FloatArray, FloatArray]:
        if self._closed:
            raise StateError("SimulatedBus.read: this bus is closed.")
        drives = self.agent.drives
        return self.scene.world.qpos[0, drives.qpos_adr].copy(), self.scene.world.qvel[0, drives.dof_adr].copy()

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        if self._closed:
            raise StateError("SimulatedBus.write: this bus is closed.")
        n = len(self._names)
        arrays = [np.asarray(a, dtype=np.float64) for a in (position, velocity, effort)]
        if any(a.shape != (n,) or not np.all(np.isfinite(a)) for a in arrays):
            raise ActionError(f"SimulatedBus.write: expected finite targets of shape ({n},), got {arrays}.")
        drives = self.agent.drives
        targets = drives.targets
        targets.position[0], targets.velocity[0], targets.effort[0] = arrays
        drives.write(self.scene.world.ctrl)
        self.scene.step()

    def set_gains(self, stiffness: FloatArray, damping: FloatArray, effort_limit: FloatArray) -> None:
        if self._closed:
            raise StateError("SimulatedBus.set_gains: this bus is closed.")
        drives = self.agent.drives
        values = [np.asarray(a, dtype=np.float64) for a in (stiffness, damping, effort_limit)]
        n = len(drives.joint_names)
        # an effort limit may be inf (no limit); an infinite gain would make the physics NaN
        finite = (True, True, False)
        if any(
            v.shape != (n,) or np.any(np.isnan(v)) or np.any(v < 0) or (must and not np.all(np.isfinite(v)))
            for v, must in zip(values, finite, strict=True)
        ):
            raise ConfigError(
                f"SimulatedBus.set_gains: expected ({n},) arrays of values >= 0, stiffness and damping finite "
                f"(an effort limit may be inf), got {values}."
            )
        declared = (drives.declared_stiffness, drives.declared_damping, drives.declared_effort_limit)
        # as a mode's override: NaN where the declared value stands
        override = DriveOverride(*(np.where(v == d, np.nan, v) for v, d in zip(values, declared, strict=True)))
        drives.activate(override, uses_velocity=True, uses_effort=True)

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self.scene.close()
