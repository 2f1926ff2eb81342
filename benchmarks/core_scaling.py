"""How the batched path scales with cores: env steps/s of all envs together against the
number of stepping threads, and whether the result depends on the thread count.

For each robot (``--robots``) and env count (``--num-envs``), ``make_env("Empty-v1",
robot_uids=..., num_envs=N, num_threads=T, obs_mode="state",
control_mode="pd_joint_delta_pos")`` is stepped with the same seeded random actions for
every thread count T in ``--threads`` (default 1, 2, 4, ... up to this machine's cores):

- ``steps/s``: env steps/s of all N envs together (``N`` per ``env.step``);
- ``speedup``: over T = 1 (the same N envs stepped on the calling thread alone);
- ``per thread``: speedup / T, how much of each added core is used;
- ``same``: whether the final physics state of every env (``get_state()["physics"]``:
  time, qpos, qvel, act, ...) is bit-identical to T = 1's
  (the documented promise: each env's result does not depend on the thread count).

The loops of one (robot, N) are timed in alternating blocks after a warm-up block, so
machine noise hits all thread counts alike. The load average is printed before and after.

Usage: ``python benchmarks/core_scaling.py [--robots panda unitree_h1] [--num-envs 16 64]
[--threads 1 2 4 8 16] [--rounds 5] [--block 20]``.
"""

from __future__ import annotations

import argparse
import os
import platform
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from render_throughput import interleaved, stepper  # a script beside this one: one way to time loops


def make(robot: str, num_envs: int, threads: int) -> Any:
    env = ra.make_env(
        "Empty-v1",
        robot_uids=robot,
        num_envs=num_envs,
        num_threads=threads,
        obs_mode="state",
        control_mode="pd_joint_delta_pos",
        max_episode_steps=None,
    )
    env.reset(seed=0)
    return env


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    cores = os.cpu_count() or 1
    default_threads = sorted({min(2**i, cores) for i in range(cores.bit_length() + 1)})
    parser.add_argument("--robots", nargs="+", default=["panda", "unitree_h1", "allegro_hand_right"])
    parser.add_argument("--num-envs", type=int, nargs="+", default=[16, 64, 256])
    parser.add_argument("--threads", type=int, nargs="+", default=default_threads)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--block", type=int, default=20, help="env steps per timed block")
    args = parser.parse_args()
    print(
        f"robot_agents {ra.__version__}, mujoco {mujoco.__version__}, python {platform.python_version()}, "
        f"{cores} cores, load average {os.getloadavg()[0]:.1f}"
    )
    print("\n| robot | envs | threads | env steps/s | speedup | per thread | same |")
    print("|---|---|---|---|---|---|---|")
    for robot in args.robots:
        for num_envs in args.num_envs:
            threads = [t for t in args.threads if t <= num_envs]
            envs = [make(robot, num_envs, t) for t in threads]
            rng = np.random.default_rng(0)
            shape = envs[0].action_space.shape
            actions = [rng.uniform(-1, 1, shape).astype(np.float32) for _ in range(args.block)]
            steps = interleaved([stepper(env, actions) for env in envs], args.rounds, args.block)
            states = [env.unwrapped.get_state()["physics"] for env in envs]
            for i, t in enumerate(threads):
                rate = steps[i] * num_envs
                speedup = steps[i] / steps[0]
                same = np.array_equal(states[0], states[i])
                print(
                    f"| `{robot}` | {num_envs} | {t} | {rate:.0f} | {speedup:.2f}x | {speedup / t:.2f} | {'yes' if same else 'NO'} |",
                    flush=True,
                )
            for env in envs:
                env.close()
    print(f"\nload average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
