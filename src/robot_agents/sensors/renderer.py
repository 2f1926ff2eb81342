"""Offscreen rendering of declared cameras with ``mujoco.Renderer``.

One renderer (one OpenGL context) per image size is created on first use and reused.
For each camera the renderer:

- sets the clipping planes to the camera's ``near`` / ``far`` (MuJoCo has one pair per
  model, ``visual/map znear, zfar``; it is set around each render and restored),
- writes the exact projection of the camera's intrinsic matrix into the scene's
  frustum (MuJoCo's own principal-point convention differs between versions),
- switches shadows and reflections as the camera asks,
- renders RGB, depth and segmentation from the *current* ``MjData`` (nothing is
  integrated or recomputed, so rendering never changes the simulation),
- writes ``far`` into the depth pixels that see nothing: those that read what MuJoCo
  makes of the cleared depth buffer (:meth:`CameraRenderer.nothing_seen`). That value is
  not ``far`` itself: ``mujoco.Renderer`` converts the buffer with float32 projection
  coefficients, whose rounding puts the converted far plane up to ~1e-4 of ``far``
  off it (99.9934 m for near 0.01 m, far 100 m; 10.000006 m for far 10 m), and every
  depth seen is at most that value; depths beyond ``far`` (a surface past ``far`` inside
  MuJoCo's plane) read ``far``, so depth stays within ``[0, far]``.

Sensor cameras render without multisampling (MuJoCo ``offsamples = 0``): about twice
as fast in software rendering, and no pixel blends two surfaces. Their shadow map has
8 texels per image pixel (``shadowsize``, 512 to 4096; MuJoCo's default is 4096): the
same shadows at 128 x 128, at half the cost.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.gl_backend import current_choice, rendering_error
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.segmentation import SegmentationLookup

FloatArray = npt.NDArray[np.float64]
#: Shadow-map texels per image pixel of sensor cameras, and the bounds of its side.
SHADOW_TEXELS_PER_PIXEL = 8
SHADOW_SIZE_RANGE = (512, 4096)


def shadow_size_for(width: int, height: int) -> int:
    """Side (pixels) of a sensor camera's shadow map: 1024 for 128 x 128 images."""
    low, high = SHADOW_SIZE_RANGE
    return min(high, max(low, SHADOW_TEXELS_PER_PIXEL * max(width, height)))


def make_renderer(
    model: mujoco.MjModel, width: int, height: int, multisample: bool = True, shadow_size: int | None = None
) -> mujoco.Renderer:
    """A ``mujoco.Renderer``; a missing or broken OpenGL backend raises
    :class:`~robot_agents.errors.RenderError` naming the library to install.

    Its offscreen framebuffer is ``width`` x ``height`` pixels, whatever the model's
    ``visual/global offwidth, offheight`` (MuJoCo sizes every context by them: the
    largest camera of the scene, at least 1280 x 960). ``multisample=False`` turns
    anti-aliasing off and ``shadow_size`` sets the shadow map's side (pixels). MuJoCo
    reads all of these when the context is created; the model keeps its values."""
    choice = current_choice()
    if choice.headless_failed:
        raise rendering_error("make_renderer", choice)
    frame_buffer, quality = model.vis.global_, model.vis.quality
    saved = (int(frame_buffer.offwidth), int(frame_buffer.offheight), int(quality.offsamples), int(quality.shadowsize))
    frame_buffer.offwidth, frame_buffer.offheight = width, height
    if not multisample:
        quality.offsamples = 0
    if shadow_size is not None:
        quality.shadowsize = shadow_size
    try:
        return mujoco.Renderer(model, height=height, width=width)
    except (ImportError, RuntimeError, OSError, AttributeError, mujoco.FatalError) as err:
        raise rendering_error("make_renderer", choice, err) from err
    finally:
        frame_buffer.offwidth, frame_buffer.offheight, quality.offsamples, quality.shadowsize = saved


@contextmanager
def clipping_planes(model: mujoco.MjModel, near: float, far: float) -> Iterator[None]:
    """Temporarily set the model's clipping planes to ``near`` / ``far`` metres."""
    vis_map = model.vis.map
    extent = float(model.stat.extent)
    saved = (float(vis_map.znear), float(vis_map.zfar))
    vis_map.znear, vis_map.zfar = near / extent, far / extent
    try:
        yield
    finally:
        vis_map.znear, vis_map.zfar = saved


def set_frustum(scene: mujoco.MjvScene, intrinsic: FloatArray, width: int, height: int) -> None:
    """Write the frustum of OpenCV intrinsics ``K`` into the scene's cameras (after
    ``mjv_updateScene``): the image spans pixel edges ``[-0.5, W - 0.5]`` x ``[-0.5, H - 0.5]``."""
    fx, fy, cx, cy = intrinsic[0, 0], intrinsic[1, 1], intrinsic[0, 2], intrinsic[1, 2]
    for camera in scene.camera:  # both eyes; mono rendering averages them
        near = camera.frustum_near
        left, right = near * (-0.5 - cx) / fx, near * (width - 0.5 - cx) / fx
        camera.frustum_center = (left + right) / 2
        camera.frustum_width = (right - left) / 2
        camera.frustum_top = near * (cy + 0.5) / fy
        camera.frustum_bottom = -near * (height - 0.5 - cy) / fy


def sensor_scene_option() -> mujoco.MjvOption:
    """What sensor cameras draw: the visual geoms (groups 0-2), not collision geoms
    (group 3), sites (MuJoCo's default options draw sites of groups 0-2, the group of
    a model file's sites unless set), tendons or rangefinder rays (drawn by default)."""
    option = mujoco.MjvOption()
    option.sitegroup[:] = 0
    option.flags[mujoco.mjtVisFlag.mjVIS_TENDON] = False
    option.flags[mujoco.mjtVisFlag.mjVIS_RANGEFINDER] = False
    return option


class CameraRenderer:
    """Renders declared cameras of one compiled model (one renderer per image size)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.option = sensor_scene_option()
        self._renderers: dict[tuple[int, int], mujoco.Renderer] = {}
        self._lookup = SegmentationLookup(model)
        #: What the depth render reads where nothing is seen, per (near, far) (m).
        self._nothing_seen: dict[tuple[float, float], float] = {}

    def prepare(self, width: int, height: int) -> None:
        """Create the renderer for ``width`` x ``height`` images now."""
        self._renderer(width, height)

    def _renderer(self, width: int, height: int) -> mujoco.Renderer:
        key = (width, height)
        renderer = self._renderers.get(key)
        if renderer is None:
            renderer = self._renderers[key] = make_renderer(
                self.model, width, height, multisample=False, shadow_size=shadow_size_for(width, height)
            )
        return renderer

    def render(
        self,
        data: mujoco.MjData,
        camera_id: int,
        config: CameraConfig,
        intrinsic: FloatArray,
        rgb: npt.NDArray[np.uint8] | None = None,
        depth: npt.NDArray[np.float32] | None = None,
        segmentation: npt.NDArray[np.int16] | None = None,
    ) -> None:
        """Render one camera of one env into the given arrays: ``rgb`` ``(H, W, 3)``
        uint8, ``depth`` ``(H, W)`` float32 metres along the optical axis,
        ``segmentation`` ``(H, W)`` int16 segmentation ids (see :mod:`.segmentation`)."""
        width, height = config.width, config.height
        renderer = self._renderer(width, height)
        with clipping_planes(self.model, config.near, config.far):
            self._update(renderer, data, camera_id, config, intrinsic)
            if rgb is not None:
                renderer.disable_depth_rendering()
                renderer.disable_segmentation_rendering()
                renderer.render(out=rgb)
            if depth is not None:
                renderer.enable_depth_rendering()
                renderer.render(out=depth)
                empty = self.nothing_seen(renderer, config.near, config.far)
                renderer.disable_depth_rendering()
                depth[depth >= empty] = config.far
                np.minimum(depth, config.far, out=depth)  # a surface beyond far that MuJoCo still shows
            if segmentation is not None:
                renderer.enable_segmentation_rendering()
                raw = renderer.render()  # (H, W, 2): object id, type; MuJoCo 3.3 takes no (H, W, 2) `out`
                renderer.disable_segmentation_rendering()
                self._lookup.body_ids(raw, segmentation)

    def nothing_seen(self, renderer: mujoco.Renderer, near: float, far: float) -> float:
        """The depth (m) ``renderer`` reads from a cleared depth buffer with the clipping
        planes ``near`` / ``far`` (set by the caller, the scene loaded, depth rendering on):
        measured once per pair by rendering the scene with nothing in it (its geoms,
        flexes and skins hidden for that render, then restored). Seen surfaces read less."""
        key = (near, far)
        value = self._nothing_seen.get(key)
        if value is None:
            scene = renderer.scene
            counts = (scene.ngeom, scene.nflex, scene.nskin)
            scene.ngeom = scene.nflex = scene.nskin = 0
            try:
                value = float(np.min(renderer.render()))
            finally:
                scene.ngeom, scene.nflex, scene.nskin = counts
            self._nothing_seen[key] = value
        return value

    def _update(
        self,
        renderer: mujoco.Renderer,
        data: mujoco.MjData,
        camera_id: int,
        config: CameraConfig,
        intrinsic: FloatArray,
    ) -> None:
        """Load the scene as seen by the camera: geometry, exact frustum, light passes."""
        # Twice: MuJoCo lays out infinite planes (the floor) around the scene's camera
        # as it was *before* the update, so a first update after another camera moved
        # the floor's tessellation and its depth by ~1e-6 relative. The second makes
        # every image a function of the state and the camera only (an update is ~5 us).
        renderer.update_scene(data, camera=camera_id, scene_option=self.option)
        renderer.update_scene(data, camera=camera_id, scene_option=self.option)
        set_frustum(renderer.scene, intrinsic, config.width, config.height)
        flags = renderer.scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = config.shadows
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = config.reflections

    def close(self) -> None:
        for renderer in self._renderers.values():
            renderer.close()
        self._renderers.clear()
