"""The cameras of a compiled scene and what they see, per env.

:class:`CameraRig` knows every camera in the scene (robot-mounted and task cameras)
under its observation key, renders the requested textures of all envs and gives the
camera parameters. Arrays have a leading ``num_envs`` axis and are new on every call.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import UnknownNameError
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.camera_params import camera_params
from robot_agents.sensors.renderer import CameraRenderer
from robot_agents.sensors.segmentation import SEGMENTATION_DTYPE, SegmentationEntry
from robot_agents.validation import check_env_ids, check_open

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]
#: The image kinds a camera renders.
TEXTURES = ("rgb", "depth", "segmentation")


@dataclass(frozen=True)
class MountedCamera:
    """A camera of the compiled scene.

    Attributes:
        key: observation key (the camera uid; ``"<robot id>/<uid>"`` for robot cameras
            when the scene has several robots).
        config: its declaration (after the env's overrides).
        name: the MuJoCo camera name in the scene (robot cameras carry the robot prefix).
        robot: the robot id of a robot-mounted camera, ``None`` for a task camera.
    """

    key: str
    config: CameraConfig
    name: str
    robot: str | None = None


class CameraRig:
    """Renders the scene's cameras.

    Args:
        model: the compiled scene.
        cameras: the cameras, in observation order.
        segmentation_map: segmentation id -> what it is (see :mod:`.segmentation`).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        cameras: Sequence[MountedCamera],
        segmentation_map: Mapping[int, SegmentationEntry] | None = None,
    ) -> None:
        self.model = model
        self.cameras: dict[str, MountedCamera] = {c.key: c for c in cameras}
        self._ids: dict[str, int] = {}
        for camera in cameras:
            camera_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera.name)
            if camera_id < 0:
                names = [model.camera(i).name for i in range(model.ncam)]
                raise UnknownNameError("CameraRig", "camera", camera.name, names)
            self._ids[camera.key] = int(camera_id)
        self._intrinsics = {c.key: c.config.intrinsic_matrix() for c in cameras}
        self.segmentation_id_map: dict[int, SegmentationEntry] = dict(segmentation_map or {})
        self._renderer: CameraRenderer | None = None

    @property
    def keys(self) -> list[str]:
        """Observation keys of the cameras, in order."""
        return list(self.cameras)

    def camera_id(self, key: str) -> int:
        """MuJoCo camera id of camera ``key``."""
        if not isinstance(key, str) or key not in self._ids:
            raise UnknownNameError("CameraRig", "camera", str(key), self._ids)
        return self._ids[key]

    def intrinsic(self, key: str) -> FloatArray:
        """OpenCV intrinsic matrix (3x3, pixels) of camera ``key`` (a copy)."""
        self.camera_id(key)
        intrinsic: FloatArray = self._intrinsics[key].copy()
        return intrinsic

    def params(self, world: SimBackend) -> dict[str, dict[str, FloatArray]]:
        """Per camera: ``intrinsic_cv`` ``(N, 3, 3)``, ``extrinsic_cv`` ``(N, 3, 4)``,
        ``cam2world_gl`` ``(N, 4, 4)`` (float64); see :mod:`.camera_params`. A closed
        ``world`` raises :class:`~robot_agents.errors.StateError`."""
        check_open(world.closed, "this scene", "CameraRig.params")
        return {key: camera_params(world, self._ids[key], self._intrinsics[key]) for key in self.cameras}

    def prepare(self) -> None:
        """Create the OpenGL contexts now (one per image size), so that a missing
        backend raises :class:`~robot_agents.errors.RenderError` here, not mid-episode."""
        if self._renderer is None:
            self._renderer = CameraRenderer(self.model)
        for camera in self.cameras.values():
            self._renderer.prepare(camera.config.width, camera.config.height)

    def capture(
        self, world: SimBackend, textures: Iterable[str] = ("rgb",), env_ids: Sequence[int] | None = None
    ) -> dict[str, dict[str, npt.NDArray[np.generic]]]:
        """Per camera, the requested textures of every env:

        - ``rgb``: ``(N, H, W, 3)`` uint8;
        - ``depth``: ``(N, H, W, 1)`` float32, metres along the optical axis, ``far``
          where nothing is seen;
        - ``segmentation``: ``(N, H, W, 1)`` int16 segmentation ids: body ids, ``-1`` background (see :mod:`.segmentation`).

        ``textures``: names from :data:`TEXTURES`, or one name (``"depth"``).
        ``env_ids``: the envs to render (``None``: all), distinct ids in ``[0, num_envs)``.
        A closed ``world`` raises :class:`~robot_agents.errors.StateError` (its OpenGL
        contexts were freed by ``Scene.close``; they are not made again).
        """
        check_open(world.closed, "this scene", "CameraRig.capture")
        try:
            wanted = (textures,) if isinstance(textures, str) else tuple(textures)
        except TypeError:
            raise UnknownNameError("CameraRig.capture", "texture", repr(textures), TEXTURES) from None
        for texture in wanted:
            if not isinstance(texture, str) or texture not in TEXTURES:
                raise UnknownNameError("CameraRig.capture", "texture", str(texture), TEXTURES)
        ids = None if env_ids is None else check_env_ids(env_ids, world.num_envs, "CameraRig.capture").tolist()
        if self._renderer is None:
            self._renderer = CameraRenderer(self.model)
        renderer = self._renderer
        datas = world.render_sources(ids)
        n = len(datas)
        out: dict[str, dict[str, npt.NDArray[np.generic]]] = {}
        for key, camera in self.cameras.items():
            h, w = camera.config.height, camera.config.width
            rgb = np.empty((n, h, w, 3), dtype=np.uint8) if "rgb" in wanted else None
            depth = np.empty((n, h, w, 1), dtype=np.float32) if "depth" in wanted else None
            seg = np.empty((n, h, w, 1), dtype=SEGMENTATION_DTYPE) if "segmentation" in wanted else None
            for env, data in enumerate(datas):
                renderer.render(
                    data,
                    self._ids[key],
                    camera.config,
                    self._intrinsics[key],
                    rgb=None if rgb is None else rgb[env],
                    depth=None if depth is None else depth[env, :, :, 0],
                    segmentation=None if seg is None else seg[env, :, :, 0],
                )
            images: dict[str, npt.NDArray[np.generic]] = {}
            for name, array in (("rgb", rgb), ("depth", depth), ("segmentation", seg)):
                if array is not None:
                    images[name] = array
            out[key] = images
        return out

    def close(self) -> None:
        """Free the OpenGL contexts (the rig renders again on the next capture)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
