"""Allocating the ``MjData`` of many envs, with a clean error when memory runs out."""

from __future__ import annotations

import mujoco

from robot_agents.errors import ConfigError


def allocate_datas(model: mujoco.MjModel, num_envs: int) -> list[mujoco.MjData]:
    """``num_envs`` MjData of ``model``; MuJoCo's (or Python's) allocation failure
    becomes a :class:`ConfigError` naming ``num_envs`` and the memory each env takes."""
    datas: list[mujoco.MjData] = []
    try:
        for _ in range(num_envs):
            datas.append(mujoco.MjData(model))
    except (mujoco.FatalError, MemoryError) as err:
        made = len(datas)
        # each env: the model's arena (contacts, constraints, scratch) plus MjData's own buffer
        per_env = int(model.narena) + (int(datas[0].nbuffer) if datas else 0)
        datas.clear()  # give the memory back before raising
        raise ConfigError(
            f"BatchedWorld: could not allocate the simulation state of num_envs={num_envs} envs "
            f"(about {per_env / 2**20:.1f} MiB each, {num_envs * per_env / 2**30:.1f} GiB in all; "
            f"{made} were allocated when memory ran out: {err}). Use fewer envs "
            "(or a smaller arena: MJCF <size memory=...>)."
        ) from None
    return datas
