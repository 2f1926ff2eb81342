"""MuJoCo compiler settings a robot declares for its model file.

Files from the wild need compiler flags MuJoCo does not set by default: inertias that
violate the triangle inequality (``balanceinertia``), massless dummy links of a mobile
base (``boundmass`` / ``boundinertia``), MJCF files whose angles are in degrees, meshes
in another folder, ``package://`` URIs, flat meshes. :class:`CompilerSettings` exposes
them; the library also fixes the common compile failures by itself, with a one-line note
that says which setting to declare (see :func:`robot_agents.agent.declaration.check`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import mujoco

from robot_agents.errors import ConfigError, did_you_mean
from robot_agents.keywords import checked_keywords
from robot_agents.validation import is_real

#: Folders searched for ``package://<pkg>/...`` meshes, besides the model's own (os.pathsep-separated).
PACKAGE_PATH_VARIABLE = "ROBOT_AGENTS_PACKAGE_PATH"


@checked_keywords
@dataclass(frozen=True)
class CompilerSettings:
    """How MuJoCo compiles a robot's model file (``None`` keeps the file's own setting).

    Attributes:
        angle: ``"radian"`` or ``"degree"``: the unit of the file's joint ranges and
            euler angles (MJCF's default is degree; a URDF is always radian).
        balanceinertia: make inertias that violate the triangle inequality valid.
        inertiafromgeom: compute body inertias from their geoms (``True``), never
            (``False``), or where a body has none (``None``: MuJoCo's "auto").
        boundmass, boundinertia: lower bounds of every body's mass (kg) and inertia
            (kg*m^2), for massless links (0: none).
        meshdir: folder of the file's meshes, relative to the file.
        package_paths: folders searched for ``package://<pkg>/...`` URIs, after the
            model's own folder and its parents (also: the ``ROBOT_AGENTS_PACKAGE_PATH``
            environment variable).
        shell_meshes: meshes whose volume MuJoCo takes from their surface (``inertia=
            "shell"``): a flat or open mesh it refuses as "mesh volume is too small".
    """

    angle: str | None = None
    balanceinertia: bool | None = None
    inertiafromgeom: bool | None = None
    boundmass: float = 0.0
    boundinertia: float = 0.0
    meshdir: str | None = None
    package_paths: tuple[str | Path, ...] = ()
    shell_meshes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.angle not in (None, "radian", "degree"):
            raise ConfigError(
                f"CompilerSettings.angle: expected 'radian', 'degree' or None, got {self.angle!r}."
                + did_you_mean(self.angle, ("radian", "degree"))
            )
        for name in ("boundmass", "boundinertia"):
            value = getattr(self, name)
            if not (is_real(value) and math.isfinite(value) and value >= 0):
                raise ConfigError(f"CompilerSettings.{name}: expected a finite number >= 0, got {value!r}.")
        object.__setattr__(self, "package_paths", tuple(self.package_paths))
        if isinstance(self.shell_meshes, str) or not all(isinstance(m, str) and m for m in self.shell_meshes):
            raise ConfigError(
                f"CompilerSettings.shell_meshes: expected a tuple of mesh names, got {self.shell_meshes!r}."
            )
        object.__setattr__(self, "shell_meshes", tuple(self.shell_meshes))

    def search_paths(self) -> list[Path]:
        """Declared package folders, then those of ``ROBOT_AGENTS_PACKAGE_PATH``."""
        extra = [p for p in os.environ.get(PACKAGE_PATH_VARIABLE, "").split(os.pathsep) if p]
        return [Path(p).expanduser() for p in (*self.package_paths, *extra)]

    def apply(self, spec: mujoco.MjSpec) -> None:
        """Write the declared settings into ``spec`` (after parsing, before compiling)."""
        compiler = spec.compiler
        if self.angle is not None:
            compiler.degree = self.angle == "degree"
        if self.balanceinertia is not None:
            compiler.balanceinertia = self.balanceinertia
        if self.inertiafromgeom is not None:
            compiler.inertiafromgeom = 1 if self.inertiafromgeom else 0
        if self.boundmass:
            compiler.boundmass = self.boundmass
        if self.boundinertia:
            compiler.boundinertia = self.boundinertia
        for name in self.shell_meshes:
            mesh = spec.mesh(name)
            if mesh is None:
                meshes = sorted(m.name for m in spec.meshes)
                raise ConfigError(f"CompilerSettings.shell_meshes: no mesh {name!r} in the model; meshes: {meshes}.")
            mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL


def range_limited(flag: mujoco.mjtLimited, bounds: Sequence[float], autolimits: bool) -> bool:
    """Whether MuJoCo's compiler limits a range (a joint's ``range``, an actuator's
    ``ctrlrange`` or ``forcerange``): ``limited="true"``, or ``"auto"`` (the attribute left
    out) with the compiler's ``autolimits`` on and a range given, as MuJoCo Menagerie's
    files write it."""
    if flag == mujoco.mjtLimited.mjLIMITED_AUTO:
        return autolimits and (float(bounds[0]) != 0.0 or float(bounds[1]) != 0.0)
    return bool(flag == mujoco.mjtLimited.mjLIMITED_TRUE)
