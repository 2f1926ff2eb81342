"""What an env keeps per episode beyond the scene's state, checked as it comes in: the
seeds of a reset, and :meth:`RobotEnv.set_state`'s step counts, task arrays and random
streams (each check raises before anything is written, so a rejected call changes
nothing)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, StateError, close_names
from robot_agents.validation import check_array, is_real, is_whole


def check_seeds(seed: Any, num_envs: int, where: str) -> list[int | None]:
    """The seed of each env (``None``: keep its stream) from a reset's ``seed``: an int
    ``s >= 0`` seeds env ``i`` with ``s + i``; a list (or a 1-D integer array) gives one
    per env."""

    def valid(value: Any) -> bool:
        return bool(is_whole(value) and value >= 0)

    if seed is None:
        return [None] * num_envs
    if valid(seed):
        return [int(seed) + i for i in range(num_envs)]
    if isinstance(seed, np.ndarray) and seed.ndim == 1 and seed.dtype.kind in "iu":
        seed = seed.tolist()  # Gymnasium's SyncVectorEnv takes an integer array too
    if (
        isinstance(seed, Sequence)
        and not isinstance(seed, str)
        and len(seed) == num_envs
        and all(s is None or valid(s) for s in seed)
    ):
        return [None if s is None else int(s) for s in seed]
    raise ConfigError(
        f"{where}: expected seed to be an int >= 0, None, or a list of {num_envs} ints >= 0 or None "
        f"(one per env), got {seed!r}."
    )


def check_reset_options(given: Sequence[str], accepted: Sequence[str], where: str) -> None:
    """:class:`ConfigError` naming the reset options in ``given`` that are not in
    ``accepted`` (with close-name hints); nothing when all are known."""
    unknown = sorted(str(name) for name in given if name not in accepted)
    if not unknown:
        return
    hints = [f"{name!r}: did you mean {close[0]!r}?" for name in unknown if (close := close_names(name, accepted))]
    raise ConfigError(
        f"{where}: unknown options {unknown}; expected {', '.join(map(repr, accepted))}."
        + "".join(f" {hint}" for hint in hints)
    )


def check_elapsed_steps(value: Any, num_envs: int, where: str) -> npt.NDArray[np.int64]:
    """A state's ``elapsed_steps``: ``num_envs`` whole numbers >= 0."""
    try:
        raw = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raw = np.array([np.nan])
    if raw.shape != (num_envs,) or not np.all(np.isfinite(raw)) or np.any(raw < 0) or np.any(raw != np.round(raw)):
        raise StateError(f"{where}: expected elapsed_steps as {num_envs} whole numbers >= 0, got {value!r}.")
    return raw.astype(np.int64)


def check_arrays(state: Any, shapes: Mapping[str, tuple[int, ...]], where: str) -> dict[str, npt.NDArray[np.float64]]:
    """A state's ``episode`` dict: exactly the task's per-episode array names
    (``shapes``' keys), each finite and of its shape."""
    if not isinstance(state, Mapping) or sorted(state) != sorted(shapes):
        raise StateError(f"{where}: expected 'episode' to be a dict with keys {list(shapes)}, got {state!r:.80}.")
    return {name: check_array(state[name], shape, f"episode {name!r}", where) for name, shape in shapes.items()}


def _same_state(kept: Any, given: Any) -> bool:
    """``kept`` (what a bit generator holds) equals ``given`` (what it was set to),
    arrays (MT19937's key) compared by value and dtype kind."""
    if isinstance(kept, Mapping):
        return (
            isinstance(given, Mapping) and set(kept) == set(given) and all(_same_state(kept[k], given[k]) for k in kept)
        )
    if isinstance(kept, np.ndarray):
        given = np.asarray(given)
        return kept.shape == given.shape and kept.dtype.kind == given.dtype.kind and bool(np.all(kept == given))
    if isinstance(given, (bool, np.bool_)) or (isinstance(given, (float, np.floating)) and not isinstance(kept, float)):
        return False  # NumPy took True for 1 and 1.0 for 1: numbers of another kind than it keeps
    return bool(kept == given)


def generators(state: Any, num_envs: int, where: str) -> list[np.random.Generator | None]:
    """A state's ``rng`` list (``None`` or a bit generator's state per env) as new
    generators (the env's own are untouched until the state is written)."""
    if not isinstance(state, Sequence) or isinstance(state, str) or len(state) != num_envs:
        raise StateError(f"{where}: expected 'rng' to be a list of {num_envs} random states, got {state!r:.80}.")
    out: list[np.random.Generator | None] = []
    for env, entry in enumerate(state):
        if entry is None:
            out.append(None)
            continue
        try:
            # only a bit generator class is called: any other name of np.random (random,
            # seed) would draw from or re-seed NumPy's global stream before refusing
            kind = getattr(np.random, str(entry["bit_generator"]))
            if not (isinstance(kind, type) and issubclass(kind, np.random.BitGenerator)):
                raise TypeError(kind)
            bit_generator = kind()
            bit_generator.state = entry
            if not _same_state(bit_generator.state, entry):  # NumPy truncates a 1.5: not that state
                raise ValueError(entry)
        except Exception:  # a malformed state: whatever NumPy raises
            raise StateError(
                f"{where}: expected rng[{env}] to be None or a NumPy bit generator's state, got {entry!r:.80}."
            ) from None
        out.append(np.random.Generator(bit_generator))
    return out


def _camera(value: Any, what: str, where: str) -> npt.NDArray[np.float64]:
    """One framing camera ``(lookat x, y, z, distance, azimuth, elevation)`` (m, m, deg,
    deg), finite with a distance > 0 (``what`` names it)."""
    try:
        camera = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        camera = np.full(1, np.nan)
    if camera.shape != (6,) or not np.all(np.isfinite(camera)) or camera[3] <= 0:
        raise StateError(
            f"{where}: expected {what} to be None or 6 finite numbers (lookat x, y, z, distance > 0, "
            f"azimuth, elevation), got {value!r:.80}."
        )
    return camera


def render_cameras(value: Any, num_envs: int, where: str) -> list[npt.NDArray[np.float64] | None]:
    """A state's ``render_camera``: per env, ``None`` (framed at the next render) or the
    framing camera ``(lookat x, y, z, distance, azimuth, elevation)`` (m, m, deg, deg),
    finite with a distance > 0. The older forms, one entry for every env (``None`` or one
    camera: env 0's, which framed them all), give every env that entry."""
    if value is None:
        return [None] * num_envs
    per_env = (isinstance(value, (list, tuple)) and not all(is_real(entry) for entry in value)) or (
        isinstance(value, np.ndarray) and value.ndim == 2
    )
    expected = (
        f"{where}: expected render_camera to be a list of {num_envs} entries (one per env), each None or 6 finite "
        "numbers (lookat x, y, z, distance > 0, azimuth, elevation)"
    )
    if not per_env:  # one camera for every env
        try:
            camera = _camera(value, "render_camera", where)
        except StateError:
            raise StateError(f"{expected}, got {value!r:.80}.") from None
        return [camera.copy() for _ in range(num_envs)]
    if len(value) != num_envs:
        raise StateError(f"{expected}, got {len(value)} entries.")
    return [None if entry is None else _camera(entry, f"render_camera[{k}]", where) for k, entry in enumerate(value)]


def check_num_envs(state: Mapping[str, Any], num_envs: int, where: str) -> None:
    """:class:`StateError` when a state's ``physics`` rows say it was saved by an env of
    another ``num_envs`` (said first, not as the first array whose shape differs)."""
    rows = np.shape(state["physics"])[:1] if "physics" in state else ()
    if rows and rows[0] != num_envs and np.ndim(state["physics"]) == 2:
        raise StateError(
            f"{where}: the state is of {rows[0]} envs and this env has num_envs={num_envs}; a state restores into "
            "an env made with the same arguments (num_envs, robots, task)."
        )
