"""The seam between robots and the simulation: what a backend must provide.

Agents, controllers, sensors and environments read and write simulation state only
through this interface; :class:`~robot_agents.sim.world.BatchedWorld` (threaded CPU
MuJoCo) is its first implementation, a GPU backend or a real-robot driver are others.
Every array carries a leading ``num_envs`` axis.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol

import mujoco
import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


class SimBackend(Protocol):
    """Batched simulation state of ``num_envs`` copies of one compiled model."""

    #: The simulated model.
    model: mujoco.MjModel
    #: The model renderers draw: ``model``, or the same scene with visual-only geoms
    #: the simulated model leaves out.
    render_model: mujoco.MjModel
    num_envs: int
    substeps: int
    #: Controls of every env, ``(num_envs, nu)``, written by the drive stage.
    ctrl: FloatArray
    #: Set by :meth:`close`: the robots bound to a closed backend refuse resets, state
    #: restores, actions and mode switches.
    closed: bool

    @property
    def qpos(self) -> FloatArray:
        """Joint positions ``(num_envs, nq)``, read-only."""

    @property
    def qvel(self) -> FloatArray:
        """Joint velocities ``(num_envs, nv)``, read-only."""

    @property
    def qacc_warmstart(self) -> FloatArray:
        """The constraint solver's warm start ``(num_envs, nv)`` (rad/s^2, m/s^2): the
        accelerations the next step's solver starts from, read-only."""

    @property
    def time(self) -> FloatArray:
        """Simulated time (s), ``(num_envs,)``."""

    def step(self, before_substep: Callable[[int, int], None] | None = None, sync_poses: bool = True) -> None:
        """Advance every env by ``substeps`` physics steps (``sync_poses=False``: the
        caller writes joint state in every env next, which recomputes the poses)."""

    def forward(self) -> None:
        """Recompute derived quantities of every env."""

    def body_poses(self, body_ids: int | npt.ArrayLike) -> FloatArray:
        """World poses ``(num_envs, k, 7)`` of bodies."""

    def site_poses(self, site_ids: npt.ArrayLike) -> FloatArray:
        """World poses ``(num_envs, k, 7)`` of sites."""

    def sensor_values(self, adr: npt.ArrayLike) -> FloatArray:
        """Sensor readings ``(num_envs, k)``."""

    def contact_forces(self, sources: Sequence[Sequence[int]], target: int) -> FloatArray:
        """Force ``(num_envs, len(sources), 3)`` each body group exerts on ``target`` (N)."""

    def camera_poses(self, camera_id: int) -> FloatArray:
        """Camera poses ``(num_envs, 4, 4)``."""

    def physics_sources(self, env_ids: Sequence[int] | None = None) -> list[mujoco.MjData]:
        """Each env's simulated MjData, of :attr:`model` (read-only)."""

    def render_sources(self, env_ids: Sequence[int] | None = None) -> list[mujoco.MjData]:
        """What a ``mujoco.Renderer`` of :attr:`render_model` draws for each env (read-only)."""

    def write_joint_state(
        self,
        env_ids: npt.ArrayLike,
        qpos_adr: npt.ArrayLike,
        qpos: FloatArray,
        dof_adr: npt.ArrayLike,
        qvel: FloatArray,
        forward: bool = True,
        warmstart: FloatArray | None = None,
    ) -> None:
        """Set joint positions and velocities of some envs. ``forward``: recompute every
        derived quantity (contacts, sensors, ...); ``False``: body and camera poses only,
        for a write after a step that only moves bodies (the next step recomputes the
        rest from the joint state). ``warmstart`` ``(n, len(dof_adr))``: the solver's warm
        start of those dofs (the others' kept, a saved state restored); ``None``: every
        dof's cleared (a new configuration)."""

    def write_joint_row(
        self,
        qpos_adr: npt.NDArray[np.int64],
        qpos: FloatArray,
        dof_adr: npt.NDArray[np.int64],
        qvel: FloatArray,
        forward: bool = True,
    ) -> None:
        """One env only: :meth:`write_joint_state` of env 0 with addresses resolved once
        (int64 arrays) and one row each of ``qpos`` and ``qvel``, the warm start cleared
        (the per-step writes of wheels, kinematic bases and held legs); raises
        :class:`~robot_agents.errors.StateError` with several envs or rows that are not
        one value per address (nothing written)."""

    def reset_envs(self, env_ids: npt.ArrayLike, state: FloatArray) -> None:
        """Reset envs to one integration state."""

    def sync_ctrl(self, env_ids: npt.ArrayLike | None = None) -> None:
        """Apply the ``ctrl`` buffer now."""

    def get_state(self) -> FloatArray:
        """Exact integration state ``(num_envs, state_size)``."""

    def check_state(self, state: npt.ArrayLike, where: str = ...) -> FloatArray:
        """Validate a state without applying it."""

    def set_state(self, state: npt.ArrayLike) -> None:
        """Restore :meth:`get_state` exactly."""

    def invalidate(self) -> None:
        """Forget cached reads."""

    def instability_counts(self) -> npt.NDArray[np.int64]:
        """How often each env blew up (MuJoCo reset it) since its last reset."""

    def close(self) -> None:
        """Release threads and buffers; sets :attr:`closed`."""
