"""Gymnasium environments. ``make_env("Empty-v1", robot_uids="panda")`` or
``gymnasium.make("robot_agents/Empty-v1", robot_uids="panda")``; the vector API:
``gymnasium.make_vec("robot_agents/PickCube-v1", num_envs=64,
vectorization_mode="vector_entry_point", robot_uids="panda")``."""

from __future__ import annotations

import importlib
from typing import Any, cast

import gymnasium as gym

from robot_agents.envs.base_env import RobotEnv, check_max_episode_steps, task_keywords
from robot_agents.envs.empty import EmptyEnv
from robot_agents.envs.vector import RobotVectorEnv, vector_entry_point
from robot_agents.errors import UnknownNameError
from robot_agents.validation import check_bool

NAMESPACE = "robot_agents"
#: Task name -> entry point, registered with Gymnasium as ``robot_agents/<name>``.
TASKS = {
    "Empty-v1": "robot_agents.envs.empty:EmptyEnv",
    "ReachPose-v1": "robot_agents.envs.tasks.reach_pose:ReachPoseEnv",
    "PickCube-v1": "robot_agents.envs.tasks.pick_cube:PickCubeEnv",
    "PushCube-v1": "robot_agents.envs.tasks.push_cube:PushCubeEnv",
    "MobilePickCube-v1": "robot_agents.envs.tasks.mobile_pick_cube:MobilePickCubeEnv",
}

#: Keywords of ``gymnasium.make`` itself that :func:`make_env` passes on.
GYM_MAKE_KEYWORDS = ("disable_env_checker",)


def register_envs() -> None:
    """Register the tasks with Gymnasium (idempotent): ``gymnasium.make`` gives the
    batched env, ``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`` a
    :class:`RobotVectorEnv` over it."""
    for name, entry_point in TASKS.items():
        env_id = f"{NAMESPACE}/{name}"
        if env_id not in gym.registry:
            gym.register(
                id=env_id,
                entry_point=entry_point,
                vector_entry_point=vector_entry_point(name),
                disable_env_checker=True,
                order_enforce=False,
            )


def task_class(name: str) -> type[RobotEnv]:
    """The class of registered task ``name`` (a key of :data:`TASKS`)."""
    module, attribute = TASKS[name].split(":")
    return cast("type[RobotEnv]", getattr(importlib.import_module(module), attribute))


def make_env(env_id: str, **kwargs: Any) -> gym.Env[Any, Any]:
    """Make a robot_agents task, e.g. ``make_env("Empty-v1", robot_uids="panda")``.

    Keyword arguments go to the task (see :class:`RobotEnv` and the task's own); one
    it does not take, or a ``render_mode`` it does not offer, raises
    :class:`UnknownNameError` before anything is built. ``max_episode_steps`` is
    the task's own limit (truncation per env, ``(num_envs,)``, at any batch size), not
    Gymnasium's ``TimeLimit`` wrapper (which ``gymnasium.make(..., max_episode_steps=N)``
    adds: one ``truncated`` for the whole batch, the task's limit unchanged).
    ``disable_env_checker`` (a bool) goes to ``gymnasium.make`` itself.
    """
    register_envs()
    if not isinstance(env_id, str):
        raise UnknownNameError("make_env", "env id", str(env_id), TASKS)
    name = env_id.split("/", 1)[1] if env_id.startswith(NAMESPACE + "/") else env_id
    if name not in TASKS:
        raise UnknownNameError("make_env", "env id", env_id, TASKS)
    task = task_class(name)
    where = f"make_env({env_id!r})"
    accepted = task_keywords(task)
    for key in sorted(kwargs):
        if key not in accepted and key not in GYM_MAKE_KEYWORDS:
            raise UnknownNameError(where, "keyword argument", key, [*accepted, *GYM_MAKE_KEYWORDS])
    render_mode = kwargs.get("render_mode")
    modes = task.metadata["render_modes"]
    if render_mode is not None and render_mode not in modes:  # gymnasium would wrap "human" around "rgb_array"
        raise UnknownNameError(where, "render_mode", str(render_mode), modes)
    if "disable_env_checker" in kwargs:  # (gymnasium takes any value, as its truth)
        check_bool(kwargs["disable_env_checker"], "disable_env_checker", where)
    steps = kwargs.pop("max_episode_steps", -1)
    check_max_episode_steps(steps, task.__name__)  # before the build
    env = gym.make(f"{NAMESPACE}/{name}", **kwargs)
    if steps != -1:
        env.unwrapped.set_max_episode_steps(steps)  # type: ignore[attr-defined]
    return env


register_envs()

__all__ = ["NAMESPACE", "TASKS", "EmptyEnv", "RobotEnv", "RobotVectorEnv", "make_env", "register_envs"]
