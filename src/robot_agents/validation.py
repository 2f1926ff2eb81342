"""Small argument checks shared by the public entry points.

Each raises the library error it is given (``ConfigError`` unless told) with a message
that names where, what was expected and what was given. ``bool`` is never taken for a
number (``True`` is an ``int`` to Python), nor a number for a ``bool``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, RobotAgentsError, StateError

IntArray = npt.NDArray[np.int64]


def is_whole(value: Any) -> bool:
    """``value`` is a Python or NumPy integer, not a ``bool``."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def check_bool(value: Any, name: str, where: str, error: type[RobotAgentsError] = ConfigError) -> bool:
    """``value`` if it is a ``bool`` (or NumPy bool), else ``error`` naming ``where``."""
    if not isinstance(value, (bool, np.bool_)):
        raise error(f"{where}: expected {name} to be a bool (True or False), got {value!r}.")
    return bool(value)


def check_whole(
    value: Any, name: str, where: str, minimum: int = 0, error: type[RobotAgentsError] = ConfigError, unit: str = ""
) -> int:
    """``value`` as an ``int`` if it is a whole number (not a ``bool``) >= ``minimum``."""
    if not is_whole(value) or value < minimum:
        raise error(f"{where}: expected {name} to be a whole number >= {minimum}{unit}, got {value!r}.")
    return int(value)


def check_real(
    value: Any,
    name: str,
    where: str,
    minimum: float | None = None,
    maximum: float | None = None,
    error: type[RobotAgentsError] = ConfigError,
) -> float:
    """``value`` as a ``float`` if it is a finite real number (not a ``bool``) within
    ``[minimum, maximum]`` (either bound may be left open)."""
    real = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    if (
        not real
        or not np.isfinite(value)
        or (minimum is not None and value < minimum)
        or (maximum is not None and value > maximum)
    ):
        bounds = f" in [{minimum if minimum is not None else '-inf'}, {maximum if maximum is not None else 'inf'}]"
        raise error(f"{where}: expected {name} to be a finite number{bounds}, got {value!r}.")
    return float(value)


def check_array(
    value: Any, shape: tuple[int, ...], what: str, where: str, error: type[RobotAgentsError] = StateError
) -> npt.NDArray[np.float64]:
    """``value`` as a float64 array (a copy) if it has ``shape`` and only finite values;
    else ``error`` naming ``where`` and ``what`` it should be."""
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        array = np.full(1, np.nan)
    if array.shape != shape or not np.all(np.isfinite(array)):
        raise error(f"{where}: expected {what} as finite numbers of shape {shape}, got {value!r:.80}.")
    return array


def check_env_ids(env_ids: Any, num_envs: int, where: str, error: type[RobotAgentsError] = StateError) -> IntArray:
    """``env_ids`` (``None``: all) as distinct ints in ``[0, num_envs)``, ``int64``."""
    if env_ids is None:
        return np.arange(num_envs)
    try:
        ids = np.asarray(env_ids).reshape(-1)
    except Exception:  # whatever the input's own __array__ raises
        raise error(f"{where}: expected env ids in [0, {num_envs}), got {env_ids!r}.") from None
    if ids.dtype.kind not in "iu" or np.any(ids < 0) or np.any(ids >= num_envs):
        raise error(f"{where}: expected env ids in [0, {num_envs}), got {ids.tolist()}.")
    if len(np.unique(ids)) != len(ids):
        raise error(f"{where}: expected distinct env ids, got {ids.tolist()}.")
    return ids.astype(np.int64)
