"""Observation modes with cameras, and their Gymnasium spaces (ManiSkill's layout).

Every visual mode returns the ``state_dict`` observation (``agent``, ``extra``) plus
``sensor_param`` (per camera ``intrinsic_cv`` ``(N, 3, 3)``, ``extrinsic_cv``
``(N, 3, 4)``, ``cam2world_gl`` ``(N, 4, 4)``, float32) and either

- ``sensor_data``: per camera the mode's textures: ``rgb`` ``(N, H, W, 3)`` uint8,
  ``depth`` ``(N, H, W, 1)`` float32 metres, ``segmentation`` ``(N, H, W, 1)`` int16
  segmentation ids (body ids; see :mod:`robot_agents.sensors.segmentation`); or
- ``pointcloud`` (mode ``pointcloud``): ``xyzw`` ``(N, P, 4)`` float32, ``rgb``
  ``(N, P, 3)`` uint8, ``segmentation`` ``(N, P, 1)`` int16, fused from all cameras.

Modes: ``sensor_data`` (rgb + depth + segmentation), ``rgb``, ``depth``, ``rgbd``,
``segmentation``, ``pointcloud``, or any ``+``-joined set of ``rgb``, ``depth``,
``segmentation`` (e.g. ``"rgb+segmentation"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np

from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.sensors.pointcloud import fuse, pixel_rays
from robot_agents.sensors.rig import TEXTURES, CameraRig
from robot_agents.sensors.segmentation import BACKGROUND_ID, SEGMENTATION_DTYPE, max_segmentation_id

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

STATE_MODES = ("state", "state_dict")
VISUAL_MODES: dict[str, tuple[str, ...]] = {
    "sensor_data": TEXTURES,
    "rgb": ("rgb",),
    "depth": ("depth",),
    "rgbd": ("rgb", "depth"),
    "segmentation": ("segmentation",),
    "pointcloud": TEXTURES,
}
OBS_MODES = (*STATE_MODES, *VISUAL_MODES)
_FLOAT_MAX = float(np.finfo(np.float32).max)


@dataclass(frozen=True)
class ObsMode:
    """A parsed observation mode: which textures are rendered, and whether they are
    fused into a point cloud."""

    name: str
    textures: tuple[str, ...] = ()
    pointcloud: bool = False

    @property
    def visual(self) -> bool:
        return bool(self.textures)


def parse_obs_mode(mode: Any, where: str) -> ObsMode:
    """Check ``mode``; unknown names raise :class:`UnknownNameError` with suggestions."""
    if not isinstance(mode, str):
        raise ConfigError(f"{where}: expected obs_mode to be a string, got {mode!r}.")
    if mode in STATE_MODES:
        return ObsMode(mode)
    if mode in VISUAL_MODES:
        return ObsMode(mode, VISUAL_MODES[mode], pointcloud=mode == "pointcloud")
    parts = mode.split("+")
    if len(parts) > 1 and all(p in TEXTURES for p in parts) and len(set(parts)) == len(parts):
        return ObsMode(mode, tuple(t for t in TEXTURES if t in parts))
    raise UnknownNameError(where, "obs_mode", mode, (*OBS_MODES, "rgb+segmentation", "depth+segmentation"))


class SensorObservation:
    """Builds the camera part of the observation, and its space, for one env.

    Args:
        rig: the scene's cameras; at least one is needed.
        mode: a visual :class:`ObsMode`.
        where: the env's name, for errors.
    """

    def __init__(self, rig: CameraRig, mode: ObsMode, where: str) -> None:
        if not rig.cameras:
            raise ConfigError(
                f"{where}: obs_mode {mode.name!r} needs at least one camera, but the robots and the task declare "
                "none (or sensor_configs dropped them all)."
            )
        self.rig = rig
        self.mode = mode
        self.where = where
        rig.prepare()  # a missing OpenGL backend fails here, before any episode
        self._max_id = max_segmentation_id(rig.model)
        self._rays = {}
        if mode.pointcloud:
            self._rays = {
                key: pixel_rays(rig.intrinsic(key), c.config.width, c.config.height) for key, c in rig.cameras.items()
            }

    def observe(self, world: SimBackend) -> dict[str, Any]:
        """``sensor_param`` and ``sensor_data`` (or ``pointcloud``) of every env."""
        params = self.rig.params(world)
        images = self.rig.capture(world, self.mode.textures)
        out: dict[str, Any] = {
            "sensor_param": {k: {n: v.astype(np.float32) for n, v in p.items()} for k, p in params.items()}
        }
        if self.mode.pointcloud:
            poses = {key: p["cam2world_gl"] for key, p in params.items()}
            far = {key: c.config.far for key, c in self.rig.cameras.items()}
            out["pointcloud"] = fuse(images, self._rays, poses, far)
        else:
            out["sensor_data"] = images
        return out

    def spaces(self, num_envs: int) -> dict[str, gym.spaces.Dict]:
        """Spaces of :meth:`observe`'s entries. Gymnasium's ``Box`` holds bounds of the
        observation's shape (twice its bytes, plus two booleans an element); when memory
        runs out a :class:`ConfigError` names the envs and the image sizes."""

        def box(shape: tuple[int, ...], low: float, high: float, dtype: Any) -> gym.spaces.Box:
            try:
                return gym.spaces.Box(low, high, shape=(num_envs, *shape), dtype=dtype)
            except MemoryError:
                size = num_envs * math.prod(shape) * (2 * np.dtype(dtype).itemsize + 2) / 2**30
                cameras = ", ".join(f"{k!r} {c.config.width} x {c.config.height}" for k, c in self.rig.cameras.items())
                raise ConfigError(
                    f"{self.where}: the observation space of obs_mode {self.mode.name!r} could not be allocated: "
                    f"an entry of shape {(num_envs, *shape)} needs about {size:.1f} GiB for its bounds. Use fewer "
                    f"envs or smaller images (sensor_configs width / height); cameras: {cameras}."
                ) from None

        params: dict[str, gym.Space[Any]] = {
            key: gym.spaces.Dict(
                {
                    "extrinsic_cv": box((3, 4), -_FLOAT_MAX, _FLOAT_MAX, np.float32),
                    "cam2world_gl": box((4, 4), -_FLOAT_MAX, _FLOAT_MAX, np.float32),
                    "intrinsic_cv": box((3, 3), -_FLOAT_MAX, _FLOAT_MAX, np.float32),
                }
            )
            for key in self.rig.cameras
        }
        spaces = {"sensor_param": gym.spaces.Dict(params)}
        if self.mode.pointcloud:
            points = sum(c.config.width * c.config.height for c in self.rig.cameras.values())
            spaces["pointcloud"] = gym.spaces.Dict(
                {
                    "xyzw": box((points, 4), -_FLOAT_MAX, _FLOAT_MAX, np.float32),
                    "rgb": box((points, 3), 0, 255, np.uint8),
                    "segmentation": box((points, 1), BACKGROUND_ID, self._max_id, SEGMENTATION_DTYPE),
                }
            )
            return spaces
        data: dict[str, gym.Space[Any]] = {}
        for key, camera in self.rig.cameras.items():
            h, w = camera.config.height, camera.config.width
            textures = {
                "rgb": box((h, w, 3), 0, 255, np.uint8),
                "depth": box((h, w, 1), 0.0, camera.config.far, np.float32),
                "segmentation": box((h, w, 1), BACKGROUND_ID, self._max_id, SEGMENTATION_DTYPE),
            }
            data[key] = gym.spaces.Dict({t: textures[t] for t in self.mode.textures})
        spaces["sensor_data"] = gym.spaces.Dict(data)
        return spaces
