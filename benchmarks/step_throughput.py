"""Env step throughput of the Panda in every joint mode, against raw MuJoCo.

For each mode, in one run on one machine:
- ``env``: ``env.step(action)`` of ``make_env("Empty-v1", robot_uids="panda", ...)``
  (validation, controller, ``substeps`` physics steps, observation), in env steps/s;
- ``raw``: ``mujoco.mj_step(model, data, nstep=substeps)`` in a Python loop on the
  same compiled model with constant ``ctrl``, in control steps/s;
- ``ratio`` = env / raw at ``num_envs=1``;
- at ``num_envs=64`` the env-steps/s of all envs together and its ratio to the
  single-env raw rate (what threads buy on this machine).

Usage: ``python benchmarks/step_throughput.py [--seconds 2] [--num-envs 64] [--threads N]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

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


def timed(fn, seconds: float, batch: int = 20) -> float:  # type: ignore[no-untyped-def]
    """Calls of ``fn`` per second, run for about ``seconds`` (after a warm-up)."""
    for _ in range(batch):
        fn()
    calls, start = 0, time.perf_counter()
    while True:
        for _ in range(batch):
            fn()
        calls += batch
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return calls / elapsed


def env_rate(mode: str, num_envs: int, seconds: float, threads: int | None) -> tuple[float, ra.Agent]:
    env = ra.make_env(
        "Empty-v1",
        robot_uids="panda",
        control_mode=mode,
        num_envs=num_envs,
        num_threads=threads,
        max_episode_steps=None,
    )
    env.reset(seed=0)
    space = env.unwrapped.agent.action_space
    rng = np.random.default_rng(0)
    # Small actions keep the arm in a typical operating regime (no joint-limit slamming).
    low, high = space.low, space.high
    mid, half = (low + high) / 2, (high - low) / 2
    actions = [(mid + 0.1 * half * rng.uniform(-1, 1, space.shape)).astype(np.float32) for _ in range(64)]
    if mode in ("pd_joint_pos", "pd_joint_pos_vel"):
        hold = env.unwrapped.agent.qpos[:, :7]
        for a in actions:
            a[:, :7] = hold + 0.05 * rng.uniform(-1, 1, hold.shape)
    counter = [0]

    def step() -> None:
        env.step(actions[counter[0] % 64])
        counter[0] += 1

    rate = timed(step, seconds)
    agent = env.unwrapped.agent
    env.close()
    return rate * num_envs, agent


def raw_rate(mode: str, seconds: float) -> float:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode=mode)
    env.reset(seed=0)
    model = env.unwrapped.model
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, env.unwrapped.get_state()["physics"][0], mujoco.mjtState.mjSTATE_INTEGRATION)
    substeps = env.unwrapped.scene.substeps
    rate = timed(lambda: mujoco.mj_step(model, data, substeps), seconds)
    env.close()
    return rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="timing window per measurement")
    parser.add_argument("--num-envs", type=int, default=64)
    parser.add_argument("--threads", type=int, default=None, help="stepping threads (default: all cores)")
    args = parser.parse_args()
    probe = ra.make_env("Empty-v1", robot_uids="panda")
    scene = probe.unwrapped.scene
    print(
        f"robot_agents {ra.__version__}, mujoco {mujoco.__version__}, {platform.processor() or platform.machine()}, {os.cpu_count()} cores"
    )
    print(
        f"panda, Empty-v1, sim_freq {scene.sim_freq} Hz, control_freq {scene.control_freq} Hz, {scene.substeps} substeps/step\n"
    )
    probe.close()
    header = f"{'mode':<26} {'raw steps/s':>11} {'env steps/s':>11} {'ratio':>6} {f'env x{args.num_envs} steps/s':>18} {'vs raw':>7}"
    print(header)
    print("-" * len(header))
    for mode in JOINT_MODES:
        raw = raw_rate(mode, args.seconds)
        single, _ = env_rate(mode, 1, args.seconds, args.threads)
        batched, _ = env_rate(mode, args.num_envs, args.seconds, args.threads)
        print(
            f"{mode:<26} {raw:>11.0f} {single:>11.0f} {single / raw:>6.2f} {batched:>18.0f} {batched / raw:>6.2f}x",
            flush=True,
        )


if __name__ == "__main__":
    main()
