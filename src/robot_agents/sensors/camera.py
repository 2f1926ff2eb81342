"""Camera declarations: :class:`CameraConfig`.

A camera is a pinhole camera fixed to a *mount*: a robot link (declared by the robot,
``Agent.cameras``) or the world / a scene body (declared by a task). It moves with its
mount. Its pose is given in the mount's frame in **MuJoCo's camera convention**: x to
the right of the image, y up, looking along -z (the OpenGL convention).

Projection: a vertical field of view ``fovy`` (degrees, square pixels, principal point
at the image centre), or a full OpenCV intrinsic matrix ``intrinsic`` (pixels;
``fx``, ``fy``, ``cx``, ``cy``, no skew). Pixel centres are at integer coordinates
(OpenCV), so the centre of a ``W`` x ``H`` image is ``((W - 1) / 2, (H - 1) / 2)``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.keywords import checked_keywords
from robot_agents.kinematics.rotations import look_at_quat
from robot_agents.sensors.validation import float_tuple, unit_quat_tuple
from robot_agents.validation import is_real, is_whole

FloatArray = npt.NDArray[np.float64]
Matrix3 = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]

#: Field of view (degrees) when neither ``fovy`` nor ``intrinsic`` is given.
DEFAULT_FOVY = 90.0
#: Largest image side (pixels) accepted; MuJoCo's offscreen buffer is sized to fit.
MAX_SIZE = 8192


def is_pixel_count(value: object) -> bool:
    """``value`` is an image side MuJoCo can render: a whole number (not a bool) of
    pixels in ``[1, MAX_SIZE]``."""
    return is_whole(value) and 1 <= value <= MAX_SIZE  # type: ignore[operator]


#: The mount name of cameras fixed in the world frame.
WORLD = "world"


@checked_keywords
@dataclass(frozen=True)
class CameraConfig:
    """A camera fixed to a robot link, a scene body or the world.

    Attributes:
        uid: the camera's name; observation key ``obs["sensor_data"][uid]`` (robots in
            a scene with several robots: ``"<robot id>/<uid>"``). No ``/``.
        mount: body it is fixed to: a link name of the declaring robot (robot cameras),
            or ``"world"`` / a scene body name (task cameras).
        pos: position in the mount's frame (m).
        quat: orientation ``(w, x, y, z)`` in the mount's frame; the camera looks along
            its -z axis with y up (normalized on construction). See :meth:`look_at`.
        width, height: image size in pixels.
        fovy: vertical field of view in degrees (MuJoCo's ``fovy``); default 90 when
            ``intrinsic`` is not given. Giving both is an error.
        intrinsic: 3x3 OpenCV intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``
            in pixels; the principal point must lie inside the image.
        near, far: clipping planes (m) along the optical axis; depth is measured
            between them and pixels that see nothing read ``far``.
        shadows, reflections: MuJoCo's shadow and reflection passes for RGB images
            (realistic, but ~5-10x slower in software rendering).
    """

    uid: str
    mount: str = WORLD
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    width: int = 128
    height: int = 128
    fovy: float | None = None
    intrinsic: Matrix3 | None = None
    near: float = 0.01
    far: float = 10.0
    shadows: bool = False
    reflections: bool = False

    def __post_init__(self) -> None:
        uid = self.uid
        if not isinstance(uid, str) or not uid or "/" in uid:
            raise ConfigError(f"CameraConfig: expected uid to be a non-empty name without '/', got {uid!r}.")
        where = f"CameraConfig {uid!r}"
        if not isinstance(self.mount, str) or not self.mount:
            raise ConfigError(f"{where}: expected mount to be a body name or 'world', got {self.mount!r}.")
        object.__setattr__(self, "pos", float_tuple(self.pos, 3, "pos (m)", where))
        object.__setattr__(self, "quat", unit_quat_tuple(self.quat, where))
        for name in ("width", "height"):
            value = getattr(self, name)
            if not is_pixel_count(value):
                raise ConfigError(
                    f"{where}: expected {name} to be an integer number of pixels in [1, {MAX_SIZE}], got {value!r}."
                )
            object.__setattr__(self, name, int(value))
        self._check_projection(where)
        near, far = self.near, self.far
        if not (_finite(near) and _finite(far) and 0 < near < far):
            raise ConfigError(f"{where}: expected clipping planes 0 < near < far (m), got near={near!r}, far={far!r}.")
        object.__setattr__(self, "near", float(near))
        object.__setattr__(self, "far", float(far))
        for name in ("shadows", "reflections"):
            if not isinstance(getattr(self, name), bool):
                raise ConfigError(f"{where}: expected {name} to be True or False, got {getattr(self, name)!r}.")

    def _check_projection(self, where: str) -> None:
        if self.intrinsic is not None and self.fovy is not None:
            raise ConfigError(
                f"{where}: expected either fovy or intrinsic, got both (fovy={self.fovy!r}, intrinsic={self.intrinsic!r})."
            )
        if self.intrinsic is None:
            fovy = DEFAULT_FOVY if self.fovy is None else self.fovy
            if not (_finite(fovy) and 0 < fovy < 180):
                raise ConfigError(f"{where}: expected fovy in (0, 180) degrees, got {self.fovy!r}.")
            object.__setattr__(self, "fovy", float(fovy))
            return
        values = float_tuple(self.intrinsic, 9, "intrinsic (a 3x3 matrix)", where)
        fx, skew, cx, zero1, fy, cy, zero2, zero3, one = values
        if (zero1, zero2, zero3, one) != (0.0, 0.0, 0.0, 1.0) or skew != 0.0:
            raise ConfigError(
                f"{where}: expected intrinsic [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew), got {self.intrinsic!r}."
            )
        if not (fx > 0 and fy > 0):
            raise ConfigError(f"{where}: expected focal lengths fx, fy > 0 pixels, got fx={fx}, fy={fy}.")
        if not (-0.5 <= cx <= self.width - 0.5 and -0.5 <= cy <= self.height - 0.5):
            raise ConfigError(
                f"{where}: expected the principal point (cx, cy) inside the {self.width} x {self.height} image, "
                f"got ({cx}, {cy}); when changing width/height, give a matching intrinsic."
            )
        object.__setattr__(self, "intrinsic", ((fx, 0.0, cx), (0.0, fy, cy), (0.0, 0.0, 1.0)))

    # ------------------------------------------------------------------ builders
    @classmethod
    def look_at(
        cls,
        uid: str,
        eye: Sequence[float],
        target: Sequence[float],
        up: Sequence[float] = (0.0, 0.0, 1.0),
        **fields: Any,
    ) -> CameraConfig:
        """A camera at ``eye`` looking at ``target``, ``up`` pointing up in the image
        (points and directions in the mount's frame; other fields as keywords)."""
        given = sorted(set(fields) & {"pos", "quat"})
        if given:
            raise ConfigError(
                f"CameraConfig.look_at {uid!r}: the pose comes from eye, target and up; expected no {' or '.join(given)}, "
                f"got {', '.join(f'{name}={fields[name]!r}' for name in given)}."
            )
        return cls(uid=uid, pos=tuple(eye), quat=look_at_quat(eye, target, up, f"CameraConfig {uid!r}"), **fields)  # type: ignore[arg-type]

    def with_overrides(self, overrides: Mapping[str, Any], where: str) -> CameraConfig:
        """A copy with some fields replaced (validated). Giving ``fovy`` drops the
        intrinsic matrix and giving ``intrinsic`` drops ``fovy``, unless both are given."""
        if not isinstance(overrides, Mapping):
            raise ConfigError(
                f"{where}: expected a dict of camera fields or None (drop the camera), got {overrides!r}."
            )
        names = [f.name for f in dataclasses.fields(self) if f.name != "uid"]
        for key in overrides:
            if key not in names:
                raise UnknownNameError(where, "camera field", str(key), names)
        changes = dict(overrides)
        if "fovy" in changes and "intrinsic" not in changes:
            changes["intrinsic"] = None
        if "intrinsic" in changes and "fovy" not in changes:
            changes["fovy"] = None
        try:
            return dataclasses.replace(self, **changes)
        except ConfigError as err:  # a bad value: name the override that gave it
            raise ConfigError(f"{where}: {err}") from None

    def resized(self, width: int, height: int) -> CameraConfig:
        """The same view at another image size (an intrinsic matrix is scaled with it)."""
        for name, value in (("width", width), ("height", height)):
            if not is_pixel_count(value):
                raise ConfigError(
                    f"CameraConfig {self.uid!r}.resized: expected {name} to be an integer number of pixels in "
                    f"[1, {MAX_SIZE}], got {value!r}."
                )
        if self.intrinsic is None:
            return dataclasses.replace(self, width=width, height=height)
        sx, sy = width / self.width, height / self.height
        (fx, _, cx), (_, fy, cy), _ = self.intrinsic
        matrix = ((fx * sx, 0.0, (cx + 0.5) * sx - 0.5), (0.0, fy * sy, (cy + 0.5) * sy - 0.5), (0.0, 0.0, 1.0))
        return dataclasses.replace(self, width=width, height=height, intrinsic=matrix)

    # ------------------------------------------------------------------ derived
    def intrinsic_matrix(self) -> FloatArray:
        """The OpenCV intrinsic matrix ``K`` (3x3, pixels)."""
        if self.intrinsic is not None:
            return np.array(self.intrinsic, dtype=np.float64)
        focal = (self.height / 2) / math.tan(math.radians(self.fovy or DEFAULT_FOVY) / 2)
        return np.array([[focal, 0.0, (self.width - 1) / 2], [0.0, focal, (self.height - 1) / 2], [0.0, 0.0, 1.0]])

    def vertical_fov(self) -> float:
        """Vertical field of view in degrees (from ``fy`` for an intrinsic matrix)."""
        if self.intrinsic is None:
            return float(self.fovy or DEFAULT_FOVY)
        return math.degrees(2 * math.atan(self.height / (2 * self.intrinsic[1][1])))


def _finite(value: Any) -> bool:
    return is_real(value) and math.isfinite(value)
