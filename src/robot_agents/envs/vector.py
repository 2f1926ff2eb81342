"""Gymnasium's vector API over one batched env (no subprocesses, no copies of the model).

``gymnasium.make_vec("robot_agents/PickCube-v1", num_envs=64, vectorization_mode=
"vector_entry_point", robot_uids="panda")`` returns a :class:`RobotVectorEnv`: a
``gymnasium.vector.VectorEnv`` whose ``num_envs`` sub-environments are the envs of one
:class:`~robot_agents.envs.RobotEnv` (one compiled model, ``num_envs`` MjData, stepped
on threads).

Autoreset follows Gymnasium 1.x; the mode is ``metadata["autoreset_mode"]`` and the
``autoreset_mode`` keyword picks it:

- ``NEXT_STEP`` (default, Gymnasium's default): the step that returns ``terminated`` or
  ``truncated`` for an env returns its last observation; the *next* ``step`` ignores that
  env's action, resets it and returns its first observation with reward 0 and
  ``terminated = truncated = False``.
- ``SAME_STEP``: the step that ends an episode resets the env at once and returns its
  first observation; the last one is in ``info["final_obs"]`` (an object array with one
  observation per env that ended, ``None`` elsewhere; mask ``info["_final_obs"]``) and
  that step's info in ``info["final_info"]`` (mask ``info["_final_info"]``).
- ``DISABLED``: no autoreset; reset envs yourself with ``reset(options={"reset_mask":
  mask})``.

Each env terminates (success or failure of the task) and truncates (``max_episode_steps``)
on its own. A reset of some envs (``options={"reset_mask": mask}`` or ``{"env_ids":
[...]}``, or an autoreset) leaves the others untouched. Seeding: ``reset(seed=s)`` seeds
env ``i`` with ``s + i`` and a list gives one seed per env, as Gymnasium's sync and async
vector envs do; each env draws from its own stream, so env ``i`` of a batch is bit for bit
a single env seeded ``s + i`` (a reset env is stepped with the others and then reset:
the reset restores its whole integration state, so the discarded step leaves no trace),
and :meth:`RobotVectorEnv.render` draws its frame as that single env would (each env's
camera frames that env's robots, at its first render after its reset).

``info`` holds one entry per env for every key (arrays with a leading ``num_envs`` axis)
and, as Gymnasium's sync and async vector envs give, a bool mask ``info["_<key>"]``
(``(num_envs,)``, all ``True``: every env reports every key); for an env reset in the
step, the task's metrics (``success``, ...) describe its new first state and
``elapsed_steps`` is 0.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
import numpy.typing as npt
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from robot_agents.envs.base_env import RESET_OPTIONS, RobotEnv
from robot_agents.envs.episode_checks import check_num_envs, check_reset_options
from robot_agents.errors import ConfigError, StateError, did_you_mean
from robot_agents.sim.scene import ENV_STATE_KEYS, SCENE_STATE_KEYS
from robot_agents.validation import check_state_keys

BoolArray = npt.NDArray[np.bool_]
#: The keys :meth:`RobotVectorEnv.reset` takes: Gymnasium's ``reset_mask`` and the env's own.
VECTOR_RESET_OPTIONS = ("reset_mask", *RESET_OPTIONS)


def single_space(space: gym.Space[Any]) -> gym.Space[Any]:
    """The space of one env from a batched space (leading ``num_envs`` axis dropped)."""
    if isinstance(space, gym.spaces.Dict):
        return gym.spaces.Dict({key: single_space(value) for key, value in space.spaces.items()})
    if isinstance(space, gym.spaces.Box):
        return gym.spaces.Box(space.low[0], space.high[0], shape=space.shape[1:], dtype=space.dtype)
    raise ConfigError(f"RobotVectorEnv: cannot split a {type(space).__name__} space per env.")


def _rows(tree: Any, ids: Any) -> Any:
    """Rows ``ids`` of every array in a (nested) dict of batched arrays."""
    if isinstance(tree, Mapping):
        return {key: _rows(value, ids) for key, value in tree.items()}
    return np.asarray(tree)[ids]


def _set_rows(tree: Any, ids: Any, values: Any) -> None:
    """Write ``values`` into rows ``ids`` of every array in ``tree`` (in place)."""
    if isinstance(tree, Mapping):
        for key, value in tree.items():
            _set_rows(value, ids, values[key])
        return
    tree[ids] = values


def _autoreset_mode(value: Any) -> AutoresetMode:
    """An ``AutoresetMode`` from itself, its name (any case) or its value."""
    if isinstance(value, AutoresetMode):
        return value
    if isinstance(value, str):
        for mode in AutoresetMode:
            if value.upper() == mode.name or value == mode.value:
                return mode
    names = [m.name for m in AutoresetMode]
    given = value.upper() if isinstance(value, str) else value
    raise ConfigError(
        f"RobotVectorEnv: expected autoreset_mode to be one of {names} (any case) or an AutoresetMode, got {value!r}."
        + did_you_mean(given, names)
    )


class RobotVectorEnv(VectorEnv):
    """Gymnasium's vector API over a batched :class:`RobotEnv` (see the module doc).

    Args:
        task: a registered task name (``"PickCube-v1"``) or a :class:`RobotEnv` subclass.
        num_envs: sub-environments (``>= 1``).
        autoreset_mode: ``AutoresetMode`` or its name (``"next_step"``, ``"same_step"``,
            ``"disabled"``); default ``NEXT_STEP``.
        **kwargs: the task's keywords (``robot_uids``, ``control_mode``, ``obs_mode``,
            ``max_episode_steps``, ...).

    Attributes:
        env: the batched env (``env.agent``, task attributes).

    State: :meth:`get_state` is ``env.get_state()`` plus ``"autoreset"``, the envs
    whose autoreset is pending (bool ``(num_envs,)``: they ended on the last step and
    the next one resets them); :meth:`set_state` restores both, so the continuation is
    bit-identical, and its action and observation spaces follow a restored control
    mode. ``env.get_state()`` / ``env.set_state()`` leave the pending autoresets out.
    The spaces follow the robots' control modes however they change (``env.set_state``,
    ``env.agent.set_control_mode``).
    """

    def __init__(
        self,
        task: str | type[RobotEnv],
        num_envs: int = 1,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        **kwargs: Any,
    ) -> None:
        mode = _autoreset_mode(autoreset_mode)
        if isinstance(task, str):
            from robot_agents.envs import make_env

            self.env: RobotEnv = make_env(task, num_envs=num_envs, **kwargs).unwrapped  # type: ignore[assignment]
        else:
            self.env = task(num_envs=num_envs, **kwargs)
        self.num_envs = self.env.num_envs
        self.metadata = {**self.env.metadata, "autoreset_mode": mode}
        self.render_mode = self.env.render_mode
        self.autoreset_mode = mode
        self._update_spaces()
        self._autoreset: BoolArray = np.zeros(self.num_envs, dtype=bool)
        #: All ``True`` ``(num_envs,)``: the info masks are copies of it (never handed out).
        self._every: BoolArray = np.ones(self.num_envs, dtype=bool)

    def _update_spaces(self) -> None:
        self._space_modes = [agent.control_mode for agent in self.env.agents]
        single_obs, single_act = single_space(self.env.observation_space), self.env.single_action_space
        self._spaces = {
            "single_observation_space": single_obs,
            "single_action_space": single_act,
            "observation_space": batch_space(single_obs, self.num_envs),
            "action_space": batch_space(single_act, self.num_envs),
        }

    def _space(self, name: str) -> gym.Space[Any]:
        """A space of the robots' current control modes, built again when a mode changed
        since it was built, however it changed (``envs.env.set_state``,
        ``envs.env.agent.set_control_mode``)."""
        if [agent.control_mode for agent in self.env.agents] != self._space_modes:
            self._update_spaces()
        return self._spaces[name]

    def _set_space(self, name: str, space: gym.Space[Any]) -> None:
        self._spaces[name] = space

    single_observation_space = property(
        lambda self: self._space("single_observation_space"),
        lambda self, space: self._set_space("single_observation_space", space),
        doc="One env's observation space (of the robots' current control modes).",
    )
    single_action_space = property(
        lambda self: self._space("single_action_space"),
        lambda self, space: self._set_space("single_action_space", space),
        doc="One env's action space (of the robots' current control modes).",
    )
    observation_space = property(
        lambda self: self._space("observation_space"),
        lambda self, space: self._set_space("observation_space", space),
        doc="The batched observation space.",
    )
    action_space = property(
        lambda self: self._space("action_space"),
        lambda self, space: self._set_space("action_space", space),
        doc="The batched action space.",
    )

    def set_control_mode(self, mode: str, robot: int = 0) -> None:
        """Switch a robot's control mode in every env; the action spaces follow."""
        self.env.set_control_mode(mode, robot)
        self._update_spaces()

    # -- state -----------------------------------------------------------------------------
    def get_state(self) -> dict[str, Any]:
        """Exact state for :meth:`set_state`: :meth:`RobotEnv.get_state` and the pending
        autoresets ``"autoreset"`` (bool ``(num_envs,)``)."""
        return {**self.env.get_state(), "autoreset": self._autoreset.copy()}

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state`; continuing with the same actions is bit-identical,
        an autoreset pending when it was saved included. The spaces follow the restored
        control modes. A state from ``env.get_state()`` (no ``"autoreset"``) restores
        the env and clears the pending autoresets. Everything is checked before anything
        is written."""
        where = "RobotVectorEnv.set_state"
        given = state if isinstance(state, Mapping) else {}
        check_state_keys(given, (*SCENE_STATE_KEYS, *ENV_STATE_KEYS, "autoreset"), "state", where)
        check_num_envs(given, self.num_envs, where)
        pending = np.zeros(self.num_envs, dtype=bool)
        if "autoreset" in given:
            flags = np.asarray(given["autoreset"])
            if flags.shape != (self.num_envs,) or flags.dtype != np.bool_:
                raise StateError(
                    f"{where}: expected 'autoreset' to be a bool array of shape ({self.num_envs},) (the envs whose "
                    f"autoreset is pending), got {flags.dtype} of shape {flags.shape}."
                )
            pending = flags.copy()
        modes = [agent.control_mode for agent in self.env.agents]
        rest = {key: value for key, value in given.items() if key != "autoreset"}
        self.env.set_state(rest if isinstance(state, Mapping) else state)  # not a dict: the env names what it takes
        self._autoreset = pending
        if [agent.control_mode for agent in self.env.agents] != modes:
            self._update_spaces()

    # -- reset -----------------------------------------------------------------------------
    def reset(
        self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        """Reset every env, or those of ``options["reset_mask"]`` (bool ``(num_envs,)``) /
        ``options["env_ids"]``; ``seed``: an int (env ``i`` gets ``seed + i``), one per env,
        or ``None``. An int also seeds the vector env's own ``np_random`` (its
        ``np_random_seed`` is that int, as ``gymnasium.vector.VectorEnv.reset`` does)."""
        self.env._check_open("RobotVectorEnv.reset")
        if options is not None and not isinstance(options, Mapping):
            raise ConfigError(
                "RobotVectorEnv.reset: expected options to be a dict (keys 'reset_mask', 'env_ids', 'keyframe'), "
                f"got {options!r}."
            )
        options = dict(options or {})
        check_reset_options(list(options), VECTOR_RESET_OPTIONS, "RobotVectorEnv.reset")
        if "reset_mask" in options:
            mask = np.asarray(options.pop("reset_mask"))
            if mask.shape != (self.num_envs,) or mask.dtype != np.bool_ or not mask.any():
                raise StateError(
                    f"RobotVectorEnv.reset: expected reset_mask to be a bool array of shape ({self.num_envs},) "
                    f"with at least one True, got {mask!r}."
                )
            if "env_ids" in options:
                raise StateError("RobotVectorEnv.reset: give reset_mask or env_ids, not both.")
            options["env_ids"] = np.flatnonzero(mask)
        obs, info = self.env.reset(seed=seed, options=options or None)
        if isinstance(seed, (int, np.integer)):  # checked by the env: np_random_seed is it, as Gymnasium's
            super().reset(seed=int(seed))
        ids = self.env.agent.state.env_ids(options.get("env_ids"), "RobotVectorEnv.reset")
        self._autoreset[ids] = False
        return obs, _with_masks(info, self._every)

    # -- step ------------------------------------------------------------------------------
    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        self.env._check_open("RobotVectorEnv.step")
        n = self.num_envs
        if self.autoreset_mode is AutoresetMode.NEXT_STEP and self._autoreset.any():
            # The envs that ended last step are reset after this step, and that reset
            # observes every env: the step's own observation (camera renders included)
            # would be thrown away, so it is not taken.
            obs, reward, terminated, truncated, info = self._step_unobserved(actions)
        else:
            obs, reward, terminated, truncated, info = self.env.step(actions)
        reward = np.asarray(reward, dtype=np.float64).reshape(n).copy()
        terminated = np.asarray(terminated, dtype=bool).reshape(n).copy()
        truncated = np.asarray(truncated, dtype=bool).reshape(n).copy()
        if self.autoreset_mode is AutoresetMode.NEXT_STEP:
            reset = self._autoreset.copy()
            if reset.any():  # these envs ended last step: their step is discarded
                reward[reset] = 0.0
                terminated[reset] = False
                truncated[reset] = False
                obs, info = self._reset_ended(reset, obs, info)
            self._autoreset = terminated | truncated
        elif self.autoreset_mode is AutoresetMode.SAME_STEP:
            ended = terminated | truncated
            if ended.any():
                ids = np.flatnonzero(ended)
                final_obs = np.full(n, None, dtype=object)
                for i in ids:
                    final_obs[i] = _rows(obs, i)
                final_info = {key: value for key, value in info.items()}
                final_info.update({f"_{key}": ended.copy() for key in info})
                obs, info = self._reset_ended(ended, obs, info)
                info.update(
                    final_obs=final_obs, _final_obs=ended.copy(), final_info=final_info, _final_info=ended.copy()
                )
        return obs, reward, terminated, truncated, _with_masks(info, self._every)

    def _step_unobserved(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        """``env.step(actions)`` with ``None`` for its observation (the bound observer
        is swapped out for the call, so the plain step pays nothing for this)."""
        observe = self.env._get_obs
        self.env._get_obs = _no_observation
        try:
            return self.env.step(actions)
        finally:
            self.env._get_obs = observe

    def _reset_ended(self, ended: BoolArray, obs: Any, info: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
        """Reset envs ``ended`` (their random streams go on); their rows of ``obs`` and
        ``info`` become those of their first state."""
        ids = np.flatnonzero(ended)
        new_obs, reset_info = self.env.reset(options={"env_ids": ids})
        fresh = {key: np.array(value, copy=True) for key, value in info.items()}
        metrics = self.env.evaluate()
        for key, value in metrics.items():
            if key in fresh and np.shape(fresh[key])[:1] == (self.num_envs,):
                fresh[key][ids] = np.asarray(value)[ids]
        fresh["elapsed_steps"] = reset_info["elapsed_steps"]
        if "physics_unstable" in fresh:
            fresh["physics_unstable"][ids] = False
        return new_obs, fresh

    # -- the rest --------------------------------------------------------------------------
    def render(self) -> Any:
        """One RGB frame per env, ``(num_envs, H, W, 3)`` (``render_mode="rgb_array"``),
        each that of a single env in that env's state (:meth:`RobotEnv.render`)."""
        self.env._check_open("RobotVectorEnv.render")
        frames = self.env.render()
        return None if frames is None else np.asarray(frames).reshape(self.num_envs, *np.shape(frames)[-3:])

    def close_extras(self, **kwargs: Any) -> None:
        self.env.close()

    def __repr__(self) -> str:
        return f"RobotVectorEnv({type(self.env).__name__}, num_envs={self.num_envs}, autoreset_mode={self.autoreset_mode.name})"


def _with_masks(info: dict[str, Any], every: BoolArray) -> dict[str, Any]:
    """``info`` with Gymnasium's vector-info mask ``"_<key>"`` (bool ``(num_envs,)``, all
    ``True``) beside every key that has none, as ``SyncVectorEnv`` gives them (a wrapper
    or user code reading ``info["_success"]`` works on either).

    Each mask is a new array, a copy of ``every`` (all ``True``, ``(num_envs,)``): as in
    Gymnasium's vector envs, whose ``_add_info`` writes masks in place and makes new ones
    every step, a caller may keep or change one without touching another key's, another
    step's or ``every``. Copying is what is saved (``np.ones`` per key cost ~1 us, a
    copy ~0.2 us); shared read-only masks would refuse such writes."""
    for key in [key for key in info if not key.startswith("_") and f"_{key}" not in info]:
        info[f"_{key}"] = every.copy()
    return info


def _no_observation() -> None:
    """Stands in for an env's observer in a step whose observation is not used."""
    return None


def vector_entry_point(task: str) -> Any:
    """The ``vector_entry_point`` Gymnasium registers for ``task``."""

    def make(num_envs: int = 1, **kwargs: Any) -> RobotVectorEnv:
        return RobotVectorEnv(task, num_envs=num_envs, **kwargs)

    make.__name__ = make.__qualname__ = f"make_{task.replace('-', '_')}_vector_env"
    return make


__all__ = ["RobotVectorEnv", "single_space", "vector_entry_point"]
