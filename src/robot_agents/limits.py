"""Sanity bounds the library enforces on simulated motion."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from robot_agents.errors import StateError

#: A joint speed (rad/s or m/s) no robot reaches: a state with a faster joint is refused,
#: and a step whose joint-velocity vector is longer counts as unstable even before
#: MuJoCo's own guard (1e10) resets the env.
MAX_SPEED = 1e4


def check_speeds(qvel: npt.NDArray[np.float64], where: str, what: str = "qvel") -> None:
    """Raise :class:`StateError` when a joint speed in ``qvel`` (any shape; rad/s or
    m/s) passes :data:`MAX_SPEED`: a state no robot reaches, refused when it would be
    written (a reset, a state restore)."""
    if qvel.size and float(np.max(np.abs(qvel))) > MAX_SPEED:
        raise StateError(
            f"{where}: expected joint speeds below {MAX_SPEED:g} (rad/s or m/s) in {what}, "
            f"got up to {float(np.max(np.abs(qvel))):.3g}."
        )
