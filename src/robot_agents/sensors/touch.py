"""Touch sensors: :class:`TouchSensorConfig` and reading them.

A touch sensor is MuJoCo's ``touch`` sensor on a site: it reports the sum of the
normal forces (N) of the contacts that involve the site's body and whose contact point
lies inside the site's volume. A robot declares them in ``Agent.touch_sensors``, either
on an existing site of its model or as a new site (a box, by default) on a link; make
the site slightly larger than the pad it covers, since contact points lie midway
through the penetration.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, ModelError, did_you_mean
from robot_agents.keywords import checked_keywords
from robot_agents.sensors.validation import float_tuple, unit_quat_tuple

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]

#: Site shapes MuJoCo's touch sensor accepts, with the number of size values each takes.
SITE_SHAPES = {"box": 3, "sphere": 1, "capsule": 2, "cylinder": 2, "ellipsoid": 3}


@checked_keywords
@dataclass(frozen=True)
class TouchSensorConfig:
    """A touch sensor on a robot.

    Attributes:
        uid: sensor name (also the name of the site it creates).
        link: body to put a new site on; or
        site: an existing site of the model, which senses over its own shape and pose
            (``shape``, ``size``, ``pos``, ``quat`` left at their defaults; others raise).
            Exactly one of ``link`` / ``site``.
        shape: ``"box"``, ``"sphere"``, ``"capsule"``, ``"cylinder"`` or ``"ellipsoid"``.
        size: MuJoCo site size (m): box half extents (3), sphere radius (1), capsule /
            cylinder radius and half length (2), ellipsoid radii (3).
        pos, quat: the new site's pose in the link frame (m; ``w, x, y, z``).
    """

    uid: str
    link: str | None = None
    site: str | None = None
    shape: str = "box"
    size: tuple[float, ...] = (0.01, 0.01, 0.01)
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.uid, str) or not self.uid or "/" in self.uid:
            raise ConfigError(f"TouchSensorConfig: expected uid to be a non-empty name without '/', got {self.uid!r}.")
        where = f"TouchSensorConfig {self.uid!r}"
        if (self.link is None) == (self.site is None):
            raise ConfigError(
                f"{where}: expected exactly one of link (a new site) or site (an existing one), "
                f"got link={self.link!r}, site={self.site!r}."
            )
        for name in ("link", "site"):
            value = getattr(self, name)
            if value is not None and (not isinstance(value, str) or not value):
                raise ConfigError(f"{where}: expected {name} to be a non-empty name, got {value!r}.")
        if self.site is not None:
            given = [
                f"{name}={getattr(self, name)!r}"
                for name, default in _NEW_SITE_DEFAULTS.items()
                if not _same(getattr(self, name), default)
            ]
            if given:
                raise ConfigError(
                    f"{where}: site={self.site!r} senses over that site's own shape and pose; expected no "
                    f"shape, size, pos or quat (they shape a new site on a link), got {', '.join(given)}."
                )
        if not isinstance(self.shape, str) or self.shape not in SITE_SHAPES:
            raise ConfigError(
                f"{where}: expected shape in {sorted(SITE_SHAPES)}, got {self.shape!r}."
                + did_you_mean(self.shape, SITE_SHAPES)
            )
        size = float_tuple(self.size, SITE_SHAPES[self.shape], f"size of a {self.shape} (m)", where)
        if min(size) <= 0:
            raise ConfigError(f"{where}: expected positive sizes (m), got {self.size!r}.")
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "pos", float_tuple(self.pos, 3, "pos (m)", where))
        object.__setattr__(self, "quat", unit_quat_tuple(self.quat, where))


#: The fields that shape a new site, with their defaults.
_NEW_SITE_DEFAULTS: dict[str, object] = {
    "shape": "box",
    "size": (0.01, 0.01, 0.01),
    "pos": (0.0, 0.0, 0.0),
    "quat": (1.0, 0.0, 0.0, 0.0),
}


def _same(value: object, default: object) -> bool:
    """``value`` equals ``default`` (a tuple compared element-wise, as any sequence)."""
    if isinstance(default, tuple):
        try:
            return bool(np.array_equal(np.asarray(value, dtype=np.float64), np.asarray(default)))
        except (TypeError, ValueError):
            return False
    return value == default


class TouchReader:
    """Reads a robot's touch sensors from every env.

    Args:
        model: the compiled scene.
        prefix: the robot's name prefix in the scene.
        sensors: the robot's declarations, in order.
    """

    def __init__(self, model: mujoco.MjModel, prefix: str, sensors: Sequence[TouchSensorConfig]) -> None:
        self.names: tuple[str, ...] = tuple(s.uid for s in sensors)
        addresses = []
        for config in sensors:
            sensor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, prefix + config.uid)
            if sensor < 0:
                raise ModelError(f"TouchReader: touch sensor {prefix + config.uid!r} is not in the compiled model.")
            addresses.append(int(model.sensor_adr[sensor]))
        self._adr = np.array(addresses, dtype=np.int64)

    def read(self, world: SimBackend) -> FloatArray:
        """Normal force (N) of each sensor, shape ``(num_envs, len(names))``."""
        return world.sensor_values(self._adr)
