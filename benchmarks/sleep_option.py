"""What MuJoCo 4.0's island sleeping (``sleep=True``, ``mjENBL_SLEEP``) saves.

A task env (``PickCube-v1`` by default) steps the same seeded actions with the option
off and on: the first half small random moves, the second half zero actions (the arm
and the cube at rest); process CPU time per step, ``--rounds`` alternating runs. It
also reports whether the two trajectories are equal, and whether ``get_state`` /
``set_state`` round-trip exactly with sleeping on (a sleeping state restored in a fresh
env: MuJoCo's integration state does not carry the sleep state; the library's
``get_state`` adds it under ``"sleep"``).

    python benchmarks/sleep_option.py [--task PickCube-v1] [--robot panda] [--rounds 3]

Not run in CI.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence

import numpy as np

import robot_agents as ra


def run(task: str, robot: str, sleep: bool, steps: int = 200) -> tuple[float, np.ndarray]:
    """(CPU µs per step, final physics state)."""
    env = ra.make_env(
        task, robot_uids=robot, control_mode="pd_joint_delta_pos", max_episode_steps=None, sleep=sleep
    ).unwrapped
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    dim = env.action_space.shape[-1]
    actions = [rng.uniform(-0.1, 0.1, dim).astype(np.float32) for _ in range(steps // 2)]
    actions += [np.zeros(dim, dtype=np.float32)] * (steps - steps // 2)
    start = time.process_time()
    for action in actions:
        env.step(action)
    per_step = (time.process_time() - start) / steps * 1e6
    state = env.get_state()["physics"][0].copy()
    env.close()
    return per_step, state


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--task", default="PickCube-v1")
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    print("| run | off (µs/step) | on (µs/step) | same final state |\n|---|---|---|---|")
    for i in range(args.rounds):
        off, state_off = run(args.task, args.robot, False)
        on, state_on = run(args.task, args.robot, True)
        print(f"| {i + 1} | {off:.0f} | {on:.0f} | {np.array_equal(state_off, state_on)} |", flush=True)
    print(f"\nget_state / set_state round trip exact with sleeping on: {round_trip(args.task, args.robot)}")
    return 0


def round_trip(task: str, robot: str) -> bool:
    """Save the state after 150 still steps (the cube asleep), step 50 more; restore it
    in a second env and step the same 50: equal final states?"""
    finals = []
    saved = None
    for _ in range(2):
        env = ra.make_env(
            task, robot_uids=robot, control_mode="pd_joint_delta_pos", max_episode_steps=None, sleep=True
        ).unwrapped
        env.reset(seed=0)
        zero = np.zeros(env.action_space.shape[-1], dtype=np.float32)
        if saved is None:
            for _ in range(150):
                env.step(zero)
            saved = env.get_state()
        else:
            env.set_state(saved)
        for _ in range(50):
            env.step(zero)
        finals.append(env.get_state()["physics"].copy())
        env.close()
    return bool(np.array_equal(finals[0], finals[1]))


if __name__ == "__main__":
    raise SystemExit(main())
