"""Markers: shapes a task draws into :meth:`RobotEnv.render`'s frames and nowhere else.

A goal is a number to a policy; to a person watching an episode it should be visible.
A task returns, per env, the markers to draw (:meth:`RobotEnv._render_markers`): the
goal region of ``PickCube-v1``, the goal disc of ``PushCube-v1``, the goal position and
axes of ``ReachPose-v1``. They are added to MuJoCo's visual scene after it is built
from the simulation state, so they are not part of the model: no contacts, no mass, no
state, and the robots' and the task's cameras (the observations) never see them
(ManiSkill likewise hides its goal markers from its sensor cameras).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import RenderError, did_you_mean
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.model.scene import PRIMITIVE_SHAPES

FloatArray = npt.NDArray[np.float64]

#: The colour of goals (translucent green, as ManiSkill draws them).
GOAL_RGBA = (0.1, 0.8, 0.2, 0.45)


@dataclass(frozen=True)
class Marker:
    """One shape drawn in the render frames.

    Attributes:
        shape: ``"sphere"`` (size: radius), ``"cylinder"`` / ``"capsule"`` (radius, half
            length along the local z), ``"box"`` (half extents); metres.
        size: MuJoCo's geom size for the shape (m).
        pos: centre, world frame (m).
        quat: orientation ``(w, x, y, z)``, world frame.
        rgba: colour, alpha below 1 for a translucent shape.
    """

    shape: str
    size: tuple[float, ...]
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    rgba: tuple[float, float, float, float] = GOAL_RGBA

    def __post_init__(self) -> None:
        if self.shape not in PRIMITIVE_SHAPES:
            raise RenderError(
                f"Marker: expected shape in {sorted(PRIMITIVE_SHAPES)}, got {self.shape!r}."
                + did_you_mean(self.shape, PRIMITIVE_SHAPES)
            )
        values = [*self.size, *self.pos, *self.quat, *self.rgba]
        if not 1 <= len(self.size) <= 3 or not np.all(np.isfinite(values)) or min(self.size) <= 0:
            raise RenderError(
                f"Marker ({self.shape}): expected 1-3 positive sizes and finite pose and colour, "
                f"got size {self.size}, pos {self.pos}, quat {self.quat}, rgba {self.rgba}."
            )


def _point(values: npt.ArrayLike) -> tuple[float, float, float]:
    x, y, z = (float(v) for v in np.asarray(values, dtype=np.float64).reshape(3))
    return x, y, z


def goal_sphere(pos: npt.ArrayLike, radius: float) -> Marker:
    """A goal region: a translucent sphere of ``radius`` (m) at ``pos`` (m, world)."""
    return Marker("sphere", (float(radius),), _point(pos))


def goal_disc(pos: npt.ArrayLike, radius: float, thickness: float = 0.002) -> Marker:
    """A goal area on a surface: a flat cylinder of ``radius`` (m) centred at ``pos``
    (m, world), ``thickness`` (m) tall, lying in the world's x-y plane."""
    return Marker("cylinder", (float(radius), thickness / 2.0), _point(pos))


def pose_axes(pose: npt.ArrayLike, length: float, radius: float) -> list[Marker]:
    """A pose's axes: three capsules ``length`` (m) long from its origin along its x
    (red), y (green) and z (blue) axes; ``pose`` is ``(x, y, z, qw, qx, qy, qz)``."""
    values = np.asarray(pose, dtype=np.float64).reshape(7)
    origin, rotation = values[:3], quat_to_matrix(values[3:])
    # a capsule's axis is its local z: turn z onto each axis
    turns = {
        0: (np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0),  # +90 deg about y: z -> x
        1: (np.sqrt(0.5), -np.sqrt(0.5), 0.0, 0.0),  # -90 deg about x: z -> y
        2: (1.0, 0.0, 0.0, 0.0),
    }
    colours = ((0.9, 0.1, 0.1, 0.9), (0.1, 0.8, 0.1, 0.9), (0.1, 0.2, 0.9, 0.9))
    markers = []
    for axis in range(3):
        centre = origin + rotation[:, axis] * (length / 2.0)
        quat = np.empty(4)
        mujoco.mju_mulQuat(quat, values[3:], np.array(turns[axis]))
        markers.append(
            Marker(
                "capsule",
                (radius, length / 2.0),
                _point(centre),
                (float(quat[0]), float(quat[1]), float(quat[2]), float(quat[3])),
                colours[axis],
            )
        )
    return markers


def draw_markers(scene: mujoco.MjvScene, markers: Sequence[Marker]) -> None:
    """Add ``markers`` to a visual scene built by ``mujoco.Renderer.update_scene`` (before
    ``render``). Raises :class:`RenderError` when the scene has no room left for them
    (``Renderer(max_geom=...)``); nothing is added then."""
    if scene.ngeom + len(markers) > scene.maxgeom:
        raise RenderError(
            f"draw_markers: the visual scene holds {scene.maxgeom} geoms and has {scene.ngeom}; "
            f"{len(markers)} markers do not fit (a renderer with a larger max_geom would)."
        )
    matrix = np.empty(9)
    for marker in markers:
        size = np.zeros(3)
        size[: len(marker.size)] = marker.size
        mujoco.mju_quat2Mat(matrix, np.asarray(marker.quat, dtype=np.float64))
        geom = scene.geoms[scene.ngeom]
        mujoco.mjv_initGeom(
            geom,
            PRIMITIVE_SHAPES[marker.shape],
            size,
            np.asarray(marker.pos, dtype=np.float64),
            matrix,
            np.asarray(marker.rgba, dtype=np.float32),
        )
        geom.category = mujoco.mjtCatBit.mjCAT_DECOR
        scene.ngeom += 1
