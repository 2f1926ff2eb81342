"""What made an env's state: the fingerprint :meth:`RobotEnv.get_state` saves as
``"source"`` and :meth:`RobotEnv.set_state` checks before anything is written.

A state's arrays are read against the env that restores them: the physics rows are
MuJoCo's integration state of the compiled scene (which robots, in which order, where
they stand, which props, their shapes, sizes and initial poses, static or free), at
the scene's time step (``sim_freq``) and substeps (``control_freq``), with island
sleeping on or off; the task's per-episode arrays are the task's; there is one random
stream and one render camera per env. Another task, robot or scene whose arrays
happen to have the same shapes would take such a state and go on from something that
never happened. :data:`SOURCE_FIELDS` is what decides that meaning:

- ``task``: the task class's qualified name (``"PickCubeEnv"``; not its module, so a
  task class defined in a script, ``__main__`` there, is the same task imported from it
  elsewhere);
- ``robots``: the scene's robot ids (``"<uid>-<k>"``, in order);
- ``num_envs``, ``sim_freq`` / ``control_freq`` (Hz), ``sleep``;
- ``robot_poses``: each robot's world pose ``(x, y, z, qw, qx, qy, qz)``;
- ``props``: each prop's ``name``, ``shape``, ``size`` (m), ``pos`` (m), ``quat`` and
  ``mass`` (kg, ``None``: static).

Not in it, since the state restores them or they do not change what it means: the
control modes and a base's dynamics (restored from the state), the observation and
render settings, camera overrides, reset noise, episode limits, reward modes, props'
colours and friction, and changes made to ``env.model`` after the env was built.

The fingerprint is plain data (str, int, float, bool, None, lists and dicts of them),
the same in every process: it pickles and compares without the env that made it.
Numbers are compared to :data:`SOURCE_RTOL`, relative (absolute near zero), so a layout computed on
another CPU (whose vectorized NumPy may round a last bit otherwise) still matches.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from robot_agents.errors import StateError
from robot_agents.model.scene import Prop
from robot_agents.validation import check_state_keys

if TYPE_CHECKING:
    from robot_agents.sim.scene import Scene

#: The fields of a state's ``"source"`` (see the module doc).
SOURCE_FIELDS = ("task", "robots", "num_envs", "sim_freq", "control_freq", "sleep", "robot_poses", "props")
#: Tolerance of the numbers compared (poses, sizes, masses): relative, and absolute near zero.
SOURCE_RTOL = 1e-9


def _prop_source(prop: Prop) -> dict[str, Any]:
    """A prop's part of the fingerprint (plain numbers)."""
    return {
        "name": prop.name,
        "shape": prop.shape,
        "size": [float(v) for v in prop.size],
        "pos": [float(v) for v in prop.pos],
        "quat": [float(v) for v in prop.quat],
        "mass": None if prop.mass is None else float(prop.mass),
    }


def state_source(task: type, scene: Scene) -> dict[str, Any]:
    """The fingerprint of the states an env of class ``task`` on ``scene`` saves (a new
    dict of plain data at every call)."""
    return {
        "task": task.__qualname__,
        "robots": list(scene.robot_ids),
        "num_envs": int(scene.num_envs),
        "sim_freq": int(scene.sim_freq),
        "control_freq": int(scene.control_freq),
        "sleep": bool(scene.sleep),
        "robot_poses": [list(pose) for pose in scene.robot_poses],
        "props": [_prop_source(prop) for prop in scene.props],
    }


def _is_sequence(value: Any) -> bool:
    return (isinstance(value, Sequence) and not isinstance(value, (str, bytes))) or (
        isinstance(value, np.ndarray) and value.ndim >= 1
    )


def _same(expected: Any, given: Any) -> bool:
    """One plain value of the fingerprint equals ``expected`` (numbers to :data:`SOURCE_RTOL`)."""
    if expected is None or isinstance(expected, str):
        return bool(given is None) if expected is None else isinstance(given, str) and given == expected
    if isinstance(expected, bool):
        return isinstance(given, (bool, np.bool_)) and bool(given) == expected
    if isinstance(given, (bool, np.bool_)) or not isinstance(given, (int, float, np.integer, np.floating)):
        return False
    if isinstance(expected, int):
        return float(given) == expected
    return math.isclose(float(given), expected, rel_tol=SOURCE_RTOL, abs_tol=SOURCE_RTOL)


def first_difference(expected: Any, given: Any, path: str) -> tuple[str, Any, Any] | None:
    """``(path, expected entry, given entry)`` of the first entry where ``given`` is not
    ``expected`` (``path`` like ``"props[1]['size']"``), ``None`` when they match."""
    if isinstance(expected, Mapping):
        if not isinstance(given, Mapping) or sorted(map(str, given)) != sorted(expected):
            return path, expected, given
        for key, value in expected.items():
            found = first_difference(value, given[key], f"{path}[{key!r}]")
            if found is not None:
                return found
        return None
    if isinstance(expected, list):
        if not _is_sequence(given) or len(given) != len(expected):
            return path, expected, given
        for k, value in enumerate(expected):
            found = first_difference(value, given[k], f"{path}[{k}]")
            if found is not None:
                return found
        return None
    return None if _same(expected, given) else (path, expected, given)


def check_source(given: Any, expected: Mapping[str, Any], where: str) -> None:
    """:class:`StateError` unless a state's ``"source"`` is ``expected`` (this env's):
    the first field that differs is named with this env's value and the state's."""
    if not isinstance(given, Mapping):
        raise StateError(
            f"{where}: expected 'source' to be a dict with keys {list(SOURCE_FIELDS)} (what made the state, "
            f"as get_state() saves it), got {given!r:.80}."
        )
    check_state_keys(given, SOURCE_FIELDS, "source", where)
    missing = [field for field in SOURCE_FIELDS if field not in given]
    if missing:
        raise StateError(f"{where}: expected 'source' to have keys {list(SOURCE_FIELDS)}, got none for {missing}.")
    for field in SOURCE_FIELDS:
        found = first_difference(expected[field], given[field], field)
        if found is None:
            continue
        path, mine, theirs = found
        raise StateError(
            f"{where}: the state was saved by another env: expected its source {path} to be {mine!r:.200} "
            f"(this env's), got {theirs!r:.200}. A state restores into an env made with the same task, robots "
            f"and scene arguments ({', '.join(SOURCE_FIELDS)})."
        )
