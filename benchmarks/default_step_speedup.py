"""What a robot's declared physics step buys: env steps/s at 500 Hz against the robot's
own ``sim_freq`` (docs/timestep.md, "What the new defaults buy").

``Empty-v1``, ``pd_joint_delta_pos``, one env, zero actions, the two envs timed in
alternating blocks of 100 steps (``--rounds``, default 8), wall clock.

    python benchmarks/default_step_speedup.py floating_panda_gripper so100 stretch

Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Sequence

import numpy as np

import robot_agents as ra


def speedup(uid: str, rounds: int, block: int = 100) -> str:
    """One table row: env steps/s at 500 Hz, at the default, and their ratio."""
    envs = []
    for freq in (500, None):
        env = ra.make_env(
            "Empty-v1", robot_uids=uid, control_mode="pd_joint_delta_pos", max_episode_steps=None, sim_freq=freq
        ).unwrapped
        env.reset(seed=0)
        envs.append(env)
    zero = np.zeros(envs[0].action_space.shape[-1], dtype=np.float32)
    seconds = [0.0, 0.0]
    for _ in range(rounds):
        for i, env in enumerate(envs):
            start = time.perf_counter()
            for _ in range(block):
                env.step(zero)
            seconds[i] += time.perf_counter() - start
    at_500, at_default = rounds * block / seconds[0], rounds * block / seconds[1]
    default = envs[1].sim_freq
    for env in envs:
        env.close()
    return f"| `{uid}` ({default} Hz) | {at_500:.0f} | {at_default:.0f} | {at_default / at_500:.2f}x |"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=ra.list_agents())
    parser.add_argument("--rounds", type=int, default=8)
    args = parser.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f}\n")
    print("| robot | 500 Hz | default | speed-up |\n|---|---|---|---|")
    for uid in args.uids:
        print(speedup(uid, args.rounds), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
