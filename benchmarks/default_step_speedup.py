"""What a robot's declared physics step buys: env steps/s at 500 Hz against the robot's
own ``sim_freq`` (docs/timestep.md, "What the new defaults buy").

``Empty-v1``, ``pd_joint_delta_pos``, one env, zero actions, the two envs timed in
alternating blocks of 100 steps after a warm-up block (``--rounds``, default 8), wall
clock (``step_throughput.interleaved``).

    python benchmarks/default_step_speedup.py floating_panda_gripper so100 stretch

Not run in CI.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable, Sequence

import numpy as np

import robot_agents as ra
from step_throughput import interleaved


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

    def stepping(env: ra.RobotEnv) -> Callable[[int], None]:
        def loop(count: int) -> None:
            for _ in range(count):
                env.step(zero)

        return loop

    at_500, at_default = interleaved([stepping(env) for env in envs], rounds, block)
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
