"""Checks of sensor declarations' numeric fields (``ConfigError`` naming where)."""

from __future__ import annotations

from typing import Any

import numpy as np

from robot_agents.errors import ConfigError
from robot_agents.validation import check_quat


def float_tuple(value: Any, size: int, what: str, where: str) -> tuple[float, ...]:
    """``value`` as a tuple of ``size`` finite floats, or a ConfigError naming ``where``."""
    try:
        array = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: expected {what} as {size} numbers, got {value!r}.") from None
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ConfigError(f"{where}: expected {what} as {size} finite numbers, got {value!r}.")
    return tuple(float(v) for v in array)


def unit_quat_tuple(value: Any, where: str) -> tuple[float, float, float, float]:
    """``value`` (4 finite numbers, not all zero) as a unit quaternion ``(w, x, y, z)``
    with its sign kept, or a ConfigError naming ``where``'s ``quat``
    (:func:`~robot_agents.validation.check_quat`)."""
    return check_quat(value, f"{where}.quat")
