"""What renderers draw when the simulated model leaves out visual-only geoms: one
``MjData`` of the render model per env, filled with that env's simulated state when a
picture is asked for (:mod:`robot_agents.model.physics_twin`)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import mujoco


class RenderMirror:
    """The render model's ``MjData`` of ``num_envs`` envs (made on first use).

    Args:
        render_model: the whole scene, as drawn; it has the simulated model's bodies,
            joints, actuators and mocap bodies, so their state copies across unchanged.
        num_envs: number of envs.
    """

    def __init__(self, render_model: mujoco.MjModel, num_envs: int) -> None:
        self.model = render_model
        self.num_envs = num_envs
        self._datas: list[mujoco.MjData] | None = None

    def fill(self, simulated: Sequence[mujoco.MjData], env_ids: Iterable[int]) -> list[mujoco.MjData]:
        """The render ``MjData`` of ``env_ids`` holding the state of ``simulated[env]``
        (time, joint and actuator state, controls, mocap poses); ``mj_forward`` derives
        the poses, contacts and sensors drawn from it."""
        if self._datas is None:
            self._datas = [mujoco.MjData(self.model) for _ in range(self.num_envs)]
        out = []
        for env in env_ids:
            source, target = simulated[env], self._datas[env]
            target.time = source.time
            target.qpos[:] = source.qpos
            target.qvel[:] = source.qvel
            target.act[:] = source.act
            target.ctrl[:] = source.ctrl
            target.mocap_pos[:] = source.mocap_pos
            target.mocap_quat[:] = source.mocap_quat
            mujoco.mj_forward(self.model, target)
            out.append(target)
        return out
