"""Which cameras a scene gets: the robots' declarations and the task's, under their
observation keys, with the user's ``sensor_configs`` overrides applied.

``sensor_configs`` maps a camera key to a dict of :class:`CameraConfig` fields to
replace (``{"hand_camera": {"width": 256, "height": 256}}``), or to ``None`` to drop the
camera. A key or a field that matches nothing raises, listing what exists. Everything
is checked before any model is built.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.rig import MountedCamera

SensorOverrides = Mapping[str, Mapping[str, Any] | None]


def plan_cameras(
    robot_cameras: Sequence[tuple[str, Sequence[CameraConfig]]],
    scene_cameras: Sequence[CameraConfig],
    overrides: SensorOverrides | None,
) -> list[MountedCamera]:
    """The scene's cameras, robots' first (in robot order), then the task's.

    Args:
        robot_cameras: ``(robot id, declared cameras)`` per robot.
        scene_cameras: the task's cameras (mounted on ``"world"`` or a scene body).
        overrides: the env's ``sensor_configs``.
    """
    single = len(robot_cameras) == 1
    planned: dict[str, MountedCamera] = {}

    def add(camera: MountedCamera, source: str) -> None:
        if camera.key in planned:
            raise ConfigError(
                f"Scene cameras: two cameras have the key {camera.key!r} ({source} and an earlier one); rename one."
            )
        planned[camera.key] = camera

    for robot_id, configs in robot_cameras:
        for config in configs:
            if not isinstance(config, CameraConfig):
                raise ConfigError(f"Scene cameras: expected CameraConfig entries for {robot_id}, got {config!r}.")
            key = config.uid if single else f"{robot_id}/{config.uid}"
            add(MountedCamera(key, config, f"{robot_id}/{config.uid}", robot_id), f"robot {robot_id}")
    for config in scene_cameras:
        if not isinstance(config, CameraConfig):
            raise ConfigError(f"Scene cameras: expected CameraConfig entries for the task, got {config!r}.")
        add(MountedCamera(config.uid, config, config.uid, None), "the task")
    if overrides is None:
        return list(planned.values())
    if not isinstance(overrides, Mapping):
        raise ConfigError(
            f"sensor_configs: expected a dict of camera key -> dict of fields (or None to drop), got {overrides!r}."
        )
    declared = list(planned)
    for key, change in overrides.items():
        if key not in declared:
            raise UnknownNameError("sensor_configs", "camera", str(key), declared)
        camera = planned[key]
        if change is None:
            del planned[key]
        else:
            config = camera.config.with_overrides(change, f"sensor_configs[{key!r}]")
            planned[key] = MountedCamera(camera.key, config, camera.name, camera.robot)
    return list(planned.values())
