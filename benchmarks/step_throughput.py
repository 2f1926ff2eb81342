"""Env step throughput of the Panda in every joint mode, against raw MuJoCo.

For each mode, in one run on one machine:
- ``raw``: ``mujoco.mj_step(model, data, nstep=substeps)`` in a Python loop on the same
  compiled model, constant ``ctrl``: control steps/s of bare physics;
- ``env``: ``env.step(action)`` of ``make_env("Empty-v1", robot_uids="panda", ...)``
  at ``num_envs=1`` (validation, controller, the same substeps, observation), with
  small random actions, in env steps/s; ``ratio`` = env / raw. Env and raw run in
  alternating blocks so that machine noise hits both alike;
- ``env xN``: env steps/s of all ``N`` envs together (``num_envs=N`` on all cores)
  and its ratio to the single-env raw physics rate.

Usage: ``python benchmarks/step_throughput.py [--rounds 20] [--block 50] [--num-envs 64]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from collections.abc import Callable

import mujoco
import numpy as np

import robot_agents as ra

JOINT_MODES = (
    "pd_joint_pos",
    "pd_joint_delta_pos",
    "pd_joint_target_delta_pos",
    "pd_joint_vel",
    "pd_joint_pos_vel",
    "pd_joint_delta_pos_vel",
)


def small_actions(env: ra.RobotEnv, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Small actions of alternating sign (absolute position modes: about the current
    pose): the arm keeps moving near its rest pose in every mode, so env and raw
    physics simulate the same situation (no drift into joint limits or the floor)."""
    space = env.agent.action_space
    mid, half = (space.low + space.high) / 2, (space.high - space.low) / 2
    actions = [
        (mid + (-1) ** i * 0.1 * half * rng.uniform(0, 1, space.shape)).astype(np.float32) for i in range(count)
    ]
    controller = env.agent.controller
    for part, config in ((p, c.config) for p, c in controller.parts.items()):
        if isinstance(config, ra.PDJointPosConfig) and not config.use_delta and not config.normalize_action:
            sl = controller.slices[part]
            n = len(config.joint_names)
            hold = env.agent.qpos[:, [env.agent.joint_names.index(j) for j in config.joint_names]]
            for action in actions:
                action[:, sl.start : sl.start + n] = hold + 0.05 * rng.uniform(-1, 1, hold.shape)
    if env.num_envs > 1:  # different motions per env
        for action in actions:
            rng.shuffle(action, axis=0)
    return actions


def make(mode: str, num_envs: int) -> ra.RobotEnv:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode=mode, num_envs=num_envs, max_episode_steps=None)
    env.reset(seed=0)
    return env.unwrapped  # type: ignore[return-value]


def stepper(env: ra.RobotEnv, actions: list[np.ndarray]) -> Callable[[int], None]:
    counter = [0]

    def run(n: int) -> None:
        for _ in range(n):
            env.step(actions[counter[0] % len(actions)])
            counter[0] += 1

    return run


def interleaved(a: Callable[[int], None], b: Callable[[int], None], rounds: int, block: int) -> tuple[float, float]:
    """Calls/s of ``a`` and ``b``, timed in alternating blocks after a warm-up."""
    a(block)
    b(block)
    time_a = time_b = 0.0
    for _ in range(rounds):
        start = time.perf_counter()
        a(block)
        time_a += time.perf_counter() - start
        start = time.perf_counter()
        b(block)
        time_b += time.perf_counter() - start
    return rounds * block / time_a, rounds * block / time_b


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--block", type=int, default=50, help="control steps per timed block")
    parser.add_argument("--num-envs", type=int, default=64)
    args = parser.parse_args()
    probe = make("pd_joint_pos", 1)
    scene = probe.scene
    print(f"robot_agents {ra.__version__}, mujoco {mujoco.__version__}, python {platform.python_version()}, {os.cpu_count()} cores")
    print(f"panda, Empty-v1, sim_freq {scene.sim_freq} Hz, control_freq {scene.control_freq} Hz, {scene.substeps} substeps/step\n")
    probe.close()
    n = args.num_envs
    header = f"{'mode':<26} {'raw steps/s':>11} {'env steps/s':>11} {'ratio':>6} {f'env x{n} steps/s':>17} {'vs raw':>7}"
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(0)
    for mode in JOINT_MODES:
        env = make(mode, 1)
        model = env.model
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, env.get_state()["physics"][0], mujoco.mjtState.mjSTATE_INTEGRATION)
        substeps = env.scene.substeps

        def raw(count: int, model: mujoco.MjModel = model, data: mujoco.MjData = data, substeps: int = substeps) -> None:
            for _ in range(count):
                mujoco.mj_step(model, data, substeps)

        env_rate, raw_rate = interleaved(stepper(env, small_actions(env, 64, rng)), raw, args.rounds, args.block)
        env.close()
        batched = make(mode, n)
        batch_rate, raw_rate_2 = interleaved(
            stepper(batched, small_actions(batched, 16, rng)), raw, max(2, args.rounds // 2), max(2, args.block // 5)
        )
        batched.close()
        raw_mean = (raw_rate + raw_rate_2) / 2
        print(
            f"{mode:<26} {raw_rate:>11.0f} {env_rate:>11.0f} {env_rate / raw_rate:>6.2f} "
            f"{batch_rate * n:>17.0f} {batch_rate * n / raw_mean:>6.2f}x",
            flush=True,
        )


if __name__ == "__main__":
    main()
