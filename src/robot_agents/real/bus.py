"""What the bridge needs of a real robot's joints: the :class:`JointBus` protocol."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


@runtime_checkable
class JointBus(Protocol):
    """A real robot's joint interface, as the bridge uses it.

    ``joint_names``: the joints it reads and commands (the robot definition's joint
    names, without a scene prefix), in the order of every array below. Units: rad and
    rad/s for hinges, m and m/s for slides, N*m / N for efforts.
    """

    @property
    def joint_names(self) -> Sequence[str]: ...

    def read(self) -> tuple[FloatArray, FloatArray]:
        """Measured positions and velocities, each ``(n,)``."""
        ...

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        """Targets ``(n,)`` each: position, velocity (0 where the mode sets none) and
        feed-forward effort (0 where the mode sets none)."""
        ...

    def set_gains(self, stiffness: FloatArray, damping: FloatArray, effort_limit: FloatArray) -> None:
        """The drives' settings for the active mode, ``(n,)`` each: stiffness (N*m/rad or
        N/m; 0 for a velocity drive), damping (N*m*s/rad or N*s/m) and effort limit
        (N*m or N): the definition's declared drives with the mode's overrides."""
        ...

    def close(self) -> None: ...
