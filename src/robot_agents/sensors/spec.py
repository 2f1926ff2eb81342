"""Write sensor declarations into an MjSpec: cameras on their mount bodies, touch
sensors as a site plus MuJoCo ``touch`` sensor. Names are checked; an unknown mount,
link or site lists what is available."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco

from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.sensors.camera import WORLD, CameraConfig
from robot_agents.sensors.touch import TouchSensorConfig

_SITE_TYPES = {
    "box": mujoco.mjtGeom.mjGEOM_BOX,
    "sphere": mujoco.mjtGeom.mjGEOM_SPHERE,
    "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE,
    "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
    "ellipsoid": mujoco.mjtGeom.mjGEOM_ELLIPSOID,
}
#: Site group of touch sites: hidden in the default render options (groups 0-2).
TOUCH_SITE_GROUP = 4


def _body_names(spec: mujoco.MjSpec) -> list[str]:
    return [b.name for b in spec.worldbody.find_all(mujoco.mjtObj.mjOBJ_BODY)]


def add_camera(spec: mujoco.MjSpec, config: CameraConfig, name: str, where: str, allow_world: bool) -> None:
    """Add ``config`` as MuJoCo camera ``name`` on its mount body (it moves with it).

    The model camera carries the vertical field of view and the resolution; the exact
    projection (principal point, ``fx != fy``) and the clipping planes are applied by
    robot_agents' renderer.
    """
    if config.mount == WORLD and allow_world:
        body = spec.worldbody
    else:
        body = spec.body(config.mount) if config.mount != WORLD else None
        if body is None:
            available = ([WORLD] if allow_world else []) + _body_names(spec)
            raise UnknownNameError(f"{where}[{config.uid!r}].mount", "body", config.mount, available)
    if spec.camera(name) is not None:
        raise ConfigError(f"{where}[{config.uid!r}]: the model already has a camera named {name!r}.")
    camera = body.add_camera(name=name, pos=list(config.pos), quat=list(config.quat), fovy=config.vertical_fov())
    camera.resolution = [config.width, config.height]


def add_cameras(spec: mujoco.MjSpec, cameras: Sequence[CameraConfig], where: str) -> None:
    """A robot's cameras, on its own links (a robot camera cannot be fixed in the world)."""
    for config in cameras:
        add_camera(spec, config, config.uid, where, allow_world=False)


def add_touch_sensors(spec: mujoco.MjSpec, sensors: Sequence[TouchSensorConfig], where: str) -> None:
    """One MuJoCo ``touch`` sensor per declaration, on a new or an existing site."""
    for config in sensors:
        label = f"{where}[{config.uid!r}]"
        if config.site is not None:
            if spec.site(config.site) is None:
                sites = [s.name for s in spec.sites if s.name]
                raise UnknownNameError(f"{label}.site", "site", config.site, sites)
            site_name = config.site
        else:
            body = spec.body(str(config.link))
            if body is None or body == spec.worldbody:  # a robot's touch site rides on one of its links
                raise UnknownNameError(f"{label}.link", "body", str(config.link), _body_names(spec))
            if spec.site(config.uid) is not None:
                raise ConfigError(f"{label}: the model already has a site named {config.uid!r}; rename the sensor.")
            body.add_site(
                name=config.uid,
                type=_SITE_TYPES[config.shape],
                size=list(config.size) + [0.0] * (3 - len(config.size)),
                pos=list(config.pos),
                quat=list(config.quat),
                group=TOUCH_SITE_GROUP,
                rgba=[0.1, 0.8, 0.2, 0.4],
            )
            site_name = config.uid
        if spec.sensor(config.uid) is not None:
            raise ConfigError(f"{label}: the model already has a sensor named {config.uid!r}.")
        spec.add_sensor(
            name=config.uid, type=mujoco.mjtSensor.mjSENS_TOUCH, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site_name
        )
