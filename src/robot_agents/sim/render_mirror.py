"""What renderers draw when the simulated model leaves out visual-only geoms: one
``MjData`` of the render model per env, filled with that env's simulated state when a
picture is asked for (:mod:`robot_agents.model.physics_twin`).

The simulated model is the authority for what both models have: before each picture,
its body poses, the pose, size, colour and material of its geoms, its cameras, lights
and materials (:data:`SHARED_FIELDS`) and its headlight (:data:`HEADLIGHT_FIELDS`) are
copied into the render model, so a change made to ``env.model`` (moving a static
body, randomizing a geom's colour or size, a light, the headlight or a camera's field
of view) shows as it did with one model. The visual-only geoms exist only in the
render model: change them there."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import mujoco

from robot_agents.model.physics_twin import shared_geoms
from robot_agents.sim.allocation import allocate_datas

#: Fields of elements both models have in the same order (cameras, lights, materials),
#: copied whole from the simulated model before each picture (those this MuJoCo has).
SHARED_FIELDS = tuple(
    name
    for name in (
        "cam_pos",
        "cam_quat",
        "cam_fovy",
        "light_type",
        "light_pos",
        "light_dir",
        "light_active",
        "light_diffuse",
        "light_ambient",
        "light_specular",
        "light_castshadow",
        "light_attenuation",
        "light_cutoff",
        "light_exponent",
        "light_bulbradius",
        "light_intensity",
        "light_range",
        "mat_rgba",
        "mat_emission",
        "mat_specular",
        "mat_shininess",
        "mat_reflectance",
        "mat_metallic",
        "mat_roughness",
        "mat_texid",
        "mat_texrepeat",
        "mat_texuniform",
    )
    if hasattr(mujoco.MjModel, name)
)

#: Colours of MuJoCo's headlight (``model.vis.headlight``, the light that moves with the
#: viewing camera), copied with its on/off switch ``active``.
HEADLIGHT_FIELDS = ("ambient", "diffuse", "specular")


class RenderMirror:
    """The render model's ``MjData`` of ``num_envs`` envs (made on first use).

    Args:
        render_model: the whole scene, as drawn.
        simulated_model: the simulated twin: ``render_model`` less some geoms (the same
            bodies, joints, actuators, cameras, materials and mocap bodies, so their
            state copies across unchanged).
        num_envs: number of envs.
    """

    def __init__(self, render_model: mujoco.MjModel, simulated_model: mujoco.MjModel, num_envs: int) -> None:
        self.model = render_model
        self.simulated_model = simulated_model
        self.num_envs = num_envs
        #: The render model's id of each simulated geom.
        self.geoms = shared_geoms(render_model, simulated_model)
        self._datas: list[mujoco.MjData] | None = None

    def sync_model(self) -> None:
        """Copy what the simulated model decides into the render model (see the module doc)."""
        drawn, simulated, geoms = self.model, self.simulated_model, self.geoms
        drawn.body_pos[:] = simulated.body_pos
        drawn.body_quat[:] = simulated.body_quat
        for name in ("geom_pos", "geom_quat", "geom_size", "geom_rgba", "geom_matid"):
            getattr(drawn, name)[geoms] = getattr(simulated, name)
        for name in SHARED_FIELDS:
            getattr(drawn, name)[:] = getattr(simulated, name)
        drawn_light, light = drawn.vis.headlight, simulated.vis.headlight
        for name in HEADLIGHT_FIELDS:
            getattr(drawn_light, name)[:] = getattr(light, name)
        drawn_light.active = light.active

    def fill(self, simulated: Sequence[mujoco.MjData], env_ids: Iterable[int]) -> list[mujoco.MjData]:
        """The render ``MjData`` of ``env_ids`` holding the state of ``simulated[env]``
        (time, joint and actuator state, controls, mocap poses), after
        :meth:`sync_model`; ``mj_forward`` derives the poses, contacts and sensors drawn
        from it."""
        if self._datas is None:
            self._datas = allocate_datas(self.model, self.num_envs)  # a clean error when memory runs out
        self.sync_model()
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
