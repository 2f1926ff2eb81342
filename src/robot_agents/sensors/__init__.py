"""Sensors that travel with the robot: cameras (robot-mounted and task cameras) and
touch sensors. See ``docs/sensors.md``.

- :mod:`.camera`: :class:`CameraConfig` (declaration, overrides, intrinsics).
- :mod:`.touch`: :class:`TouchSensorConfig` and :class:`TouchReader`.
- :mod:`.spec`: declarations -> MjSpec cameras, sites and touch sensors.
- :mod:`.overrides`: a scene's cameras with the env's ``sensor_configs`` applied.
- :mod:`.rig`: :class:`CameraRig`, the scene's cameras rendered per env.
- :mod:`.renderer`: ``mujoco.Renderer`` per image size, exact intrinsics, near/far.
- :mod:`.camera_params`: intrinsic / extrinsic matrices and camera poses.
- :mod:`.segmentation`: per-pixel body ids (and flex / skin ids) and their names.
- :mod:`.pointcloud`: depth to world-frame points, fused over cameras.
"""

from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.rig import CameraRig, MountedCamera
from robot_agents.sensors.segmentation import BACKGROUND_ID, SegmentationEntry
from robot_agents.sensors.touch import TouchReader, TouchSensorConfig

__all__ = [
    "BACKGROUND_ID",
    "CameraConfig",
    "CameraRig",
    "MountedCamera",
    "SegmentationEntry",
    "TouchReader",
    "TouchSensorConfig",
]
