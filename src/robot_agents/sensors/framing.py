"""A viewing camera that frames the robots: a hand, a humanoid and a mobile base each
fill the picture, whatever their size (the env's ``render()`` and the demo use it)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]


def robot_bounds(
    world: SimBackend, prefixes: Sequence[str], env: int = 0, above: float = -np.inf
) -> tuple[FloatArray, FloatArray]:
    """Axis-aligned box ``(lower, upper)`` (m, world frame) around the geoms of the
    robots whose names start with ``prefixes``, in env ``env`` (bounding spheres), of
    those whose centre is at least ``above`` (m, world z) high."""
    model = world.render_model
    data = world.render_sources([env])[0]
    lower, upper = np.full(3, np.inf), np.full(3, -np.inf)
    for geom in range(model.ngeom):
        body = model.body(int(model.geom_bodyid[geom])).name
        if not body.startswith(tuple(prefixes)) or int(model.geom_type[geom]) == int(mujoco.mjtGeom.mjGEOM_PLANE):
            continue
        if data.geom_xpos[geom, 2] < above:
            continue
        radius = float(model.geom_rbound[geom])
        lower = np.minimum(lower, data.geom_xpos[geom] - radius)
        upper = np.maximum(upper, data.geom_xpos[geom] + radius)
    if not np.all(np.isfinite(lower)):
        lower, upper = np.zeros(3), np.zeros(3)
    return lower, upper


def framing_camera(
    lower: FloatArray,
    upper: FloatArray,
    fovy: float = 45.0,
    margin: float = 1.0,
    azimuth: float = 140.0,
    elevation: float = -22.0,
    min_distance: float = 0.3,
    aspect: float = 1.0,
) -> mujoco.MjvCamera:
    """A free camera looking at the box's centre from ``azimuth`` / ``elevation`` (deg),
    far enough that the box's bounding sphere, times ``margin``, fits the vertical field
    of view ``fovy`` (deg) and the horizontal one of an image ``aspect`` (width / height)
    times as wide as tall (the narrower of the two for a portrait image)."""
    center = (lower + upper) / 2
    radius = float(np.linalg.norm(upper - lower)) / 2
    half_fov = math.atan(math.tan(math.radians(fovy) / 2) * min(1.0, aspect))
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.lookat[:] = center
    camera.distance = max(min_distance, margin * radius / math.sin(half_fov))
    camera.azimuth, camera.elevation = azimuth, elevation
    return camera


def framed_camera(values: FloatArray) -> mujoco.MjvCamera:
    """The free camera ``(lookat x, y, z, distance, azimuth, elevation)`` describes (the
    numbers :meth:`RobotEnv.get_state` saves of :func:`framing_camera`'s camera)."""
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.lookat[:] = values[:3]
    camera.distance, camera.azimuth, camera.elevation = float(values[3]), float(values[4]), float(values[5])
    return camera
