"""Small argument checks shared by the public entry points.

Each raises the library error it is given (``ConfigError`` unless told) with a message
that names where, what was expected and what was given. ``bool`` is never taken for a
number (``True`` is an ``int`` to Python), nor a number for a ``bool``.

Poses and quaternions have one rule (:func:`check_vector`, :func:`check_quat`,
:func:`check_pose`, :func:`check_quat_rows`): a sequence or 1-D array of real numbers
(no bools, no strings), all finite; a quaternion ``(w, x, y, z)`` of any length above
:data:`ZERO_QUAT` is accepted and divided by its norm ``math.sqrt(w*w + x*x + y*y + z*z)``
(summed in that order, the bits every declaration had before), a shorter one is refused
as zero.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, RobotAgentsError, StateError, close_names

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]

#: A quaternion whose norm is below this is refused as zero (no direction to normalize).
ZERO_QUAT = 1e-9

#: How far past a joint limit a written or declared position may lie (rounding).
LIMIT_MARGIN = 1e-9

#: The axes a pose lists (position in m, then its orientation quaternion).
POSE_AXES = "(x, y, z, qw, qx, qy, qz)"


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
    unit: str = "",
) -> float:
    """``value`` as a ``float`` if it is a finite real number (not a ``bool``) within
    ``[minimum, maximum]`` (either bound may be left open); ``unit`` (e.g. ``" (m)"``)
    follows the bounds in the message."""
    if (
        not is_real(value)
        or not np.isfinite(value)
        or (minimum is not None and value < minimum)
        or (maximum is not None and value > maximum)
    ):
        bounds = f" in [{minimum if minimum is not None else '-inf'}, {maximum if maximum is not None else 'inf'}]"
        raise error(f"{where}: expected {name} to be a finite number{bounds}{unit}, got {value!r}.")
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
    """``env_ids`` (``None``: all; one int, a sequence or a 1-D array) as distinct ints in
    ``[0, num_envs)``, ``int64`` ``(k,)`` with ``k >= 1``: an empty selection (``[]``,
    ``np.array([], int)``) is refused, as is an array of two or more dimensions."""
    if env_ids is None:
        return np.arange(num_envs)
    try:
        given = np.asarray(env_ids)
    except Exception:  # whatever the input's own __array__ raises
        raise error(f"{where}: expected env ids in [0, {num_envs}), got {env_ids!r}.") from None
    if given.ndim > 1:
        raise error(f"{where}: expected env ids as one int or a 1-D sequence, got an array of shape {given.shape}.")
    if given.size == 0:
        raise error(f"{where}: expected at least one env id in [0, {num_envs}), got an empty selection {env_ids!r}.")
    ids = given.reshape(-1)
    if ids.dtype == np.bool_:  # a mask, read as the ids 0 and 1 by a plain int check
        raise error(
            f"{where}: expected env ids (ints) in [0, {num_envs}), got bools {ids.tolist()}; for a mask, pass "
            f"np.flatnonzero(mask) (a vector env's reset takes options={{'reset_mask': mask}})."
        )
    if ids.dtype.kind not in "iu" or np.any(ids < 0) or np.any(ids >= num_envs):
        raise error(f"{where}: expected env ids in [0, {num_envs}), got {ids.tolist()}.")
    if len(np.unique(ids)) != len(ids):
        raise error(f"{where}: expected distinct env ids, got {ids.tolist()}.")
    return ids.astype(np.int64)


def is_real(value: Any) -> bool:
    """``value`` is a Python or NumPy real number, not a ``bool`` (nor a string)."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def check_vector(
    value: Any, size: int, what: str, where: str, error: type[RobotAgentsError] = ConfigError
) -> tuple[float, ...]:
    """``value`` as a tuple of ``size`` floats if it is a sequence or 1-D array (not a
    string) of ``size`` real numbers (not bools), all finite; else ``error`` naming
    ``where``, ``what`` the entries are (e.g. ``"(x, y, z) (m)"``) and what was given."""
    form = f"{where}: expected {size} finite numbers {what}, got {value!r}"
    if (
        isinstance(value, (str, bytes))
        or not isinstance(value, (Sequence, np.ndarray))
        or (isinstance(value, np.ndarray) and value.ndim != 1)
        or len(value) != size
        or not all(is_real(v) for v in value)
    ):
        raise error(f"{form}.")
    floats = tuple(float(v) for v in value)
    if not all(math.isfinite(v) for v in floats):
        raise error(f"{form} (NaN or inf).")
    return floats


def _normalized(quat: tuple[float, ...], axes: str, where: str, error: type[RobotAgentsError]) -> tuple[float, ...]:
    """``quat`` divided by its norm (summed in order), or ``error`` for a zero one."""
    norm = math.sqrt(sum(q * q for q in quat))
    if norm < ZERO_QUAT:
        raise error(
            f"{where}: expected a unit quaternion {axes}, got {quat} (zero). A non-zero quaternion of any "
            "length is accepted (normalized)."
        )
    return tuple(q / norm for q in quat)


def check_quat(
    value: Any, where: str, error: type[RobotAgentsError] = ConfigError
) -> tuple[float, float, float, float]:
    """``value`` (4 finite numbers ``(w, x, y, z)``, not all zero) as a unit quaternion,
    its sign kept; else ``error`` naming ``where``."""
    axes = "(w, x, y, z)"
    w, x, y, z = _normalized(check_vector(value, 4, f"{axes} (a quaternion)", where, error), axes, where, error)
    return (w, x, y, z)


def check_pose(value: Any, where: str, error: type[RobotAgentsError] = ConfigError) -> tuple[float, ...]:
    """``value`` (7 finite numbers ``(x, y, z, qw, qx, qy, qz)``: position in m and a
    non-zero quaternion) with its quaternion normalized as :func:`check_quat` does; else
    ``error`` naming ``where``."""
    pose = check_vector(value, 7, f"{POSE_AXES} (m, unit quaternion)", where, error)
    return (*pose[:3], *_normalized(pose[3:], "(qw, qx, qy, qz)", where, error))


def check_quat_rows(quats: FloatArray, what: str, where: str, error: type[RobotAgentsError] = StateError) -> FloatArray:
    """The norms ``(n,)`` of already finite quaternion rows ``quats`` ``(n, 4)`` (one per
    env); ``error`` naming ``where``, ``what`` holds them and the first env whose
    quaternion is zero (norm below :data:`ZERO_QUAT`)."""
    norms: FloatArray = np.linalg.norm(quats, axis=1)
    zero = norms < ZERO_QUAT
    if np.any(zero):
        env = int(np.flatnonzero(zero)[0])
        raise error(
            f"{where}: expected {what} with a unit quaternion, got {quats[env].tolist()} in env {env} (zero). "
            "A non-zero quaternion of any length is accepted."
        )
    return norms


def ball_angles(quats: FloatArray) -> FloatArray:
    """Rotation angles (rad, ``(n,)``) of unit quaternion rows ``(n, 4)`` ``(w, x, y, z)``:
    what a ball joint's range bounds (MuJoCo: the largest rotation from the reference)."""
    angles: FloatArray = 2.0 * np.arccos(np.clip(np.abs(quats[:, 0]), 0.0, 1.0))
    return angles


def outside_limits(
    values: npt.ArrayLike, low: npt.ArrayLike, high: npt.ArrayLike, margin: float = LIMIT_MARGIN
) -> npt.NDArray[np.bool_]:
    """Where ``values`` lie below ``low`` or above ``high`` by more than ``margin``
    (elementwise, broadcast): the one joint-limit rule; each caller's message names the
    joint, the value and its limits."""
    values, low, high = np.asarray(values), np.asarray(low), np.asarray(high)
    outside: npt.NDArray[np.bool_] = (values < low - margin) | (values > high + margin)
    return outside


def check_state_keys(given: Iterable[Any], accepted: Sequence[str], what: str, where: str, hint: str = "") -> None:
    """:class:`StateError` naming the keys of a state dict (``what``, e.g. ``"state"``)
    that are not in ``accepted``, with the closest accepted names: a misspelt key of a
    state would otherwise be ignored and that part of the state not restored."""
    unknown = sorted(str(key) for key in given if key not in accepted)
    if not unknown:
        return
    hints = "".join(
        f" {name!r}: did you mean {close[0]!r}?" for name in unknown if (close := close_names(name, accepted))
    )
    raise StateError(f"{where}: unknown {what} keys {unknown}; expected {', '.join(map(repr, accepted))}.{hints}{hint}")


def check_open(closed: bool, what: str, where: str) -> None:
    """:class:`StateError` naming ``where`` once ``what`` (e.g. ``"this env"``) is closed."""
    if closed:
        raise StateError(f"{where}: {what} is closed; make a new one.")


def check_per_joint(value: Any, where: str, minimum: float = 0.0) -> None:
    """Raise :class:`ConfigError` naming ``where`` (e.g. ``"PDActuator.stiffness"``)
    unless ``value`` is one real number or a non-empty sequence of them (a per-joint
    value; no bools, no strings), all finite and at least ``minimum``."""
    entries = (
        list(value) if isinstance(value, (Sequence, np.ndarray)) and not isinstance(value, (str, bytes)) else [value]
    )
    if not entries or not all(is_real(v) for v in entries):
        raise ConfigError(f"{where}: expected a number or a tuple of numbers, got {value!r}.")
    array = np.asarray(entries, dtype=np.float64).reshape(-1)
    if not np.all(np.isfinite(array)) or np.any(array < minimum):
        raise ConfigError(f"{where}: expected finite values >= {minimum:g}, got {value!r}.")
