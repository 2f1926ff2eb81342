"""``PickCube-v1`` env steps/s through Gymnasium's vector API, next to ManiSkill 3's CPU PickCube.

In one run on one machine:

- ``ours x1`` / ``ours x64``: ``gymnasium.make_vec("robot_agents/PickCube-v1", num_envs=N,
  vectorization_mode="vector_entry_point", robot_uids="panda", obs_mode="state",
  control_mode="pd_joint_delta_pos")`` (one batched MuJoCo world; 64 envs stepped on
  threads), uniformly random actions from a fixed seed, autoreset on (Gymnasium's default
  ``NEXT_STEP``); env steps/s of all envs together;
- ``ManiSkill x1`` (where a Python with ``mani-skill`` is given, ``--maniskill-python``,
  default ``~/.venvs/maniskill/bin/python``): ManiSkill's ``PickCube-v1`` with the same
  robot, observation and control mode on its CPU backend (``sim_backend="cpu"``,
  ``render_backend="none"``: one env per process), random actions from the same seed,
  reset when an episode ends. Its scene builders ask for a render device even with
  ``render_backend="none"``; the peer replaces SAPIEN's render material and texture
  classes by inert stand-ins first (visual only; physics unchanged). It runs in a subprocess of that Python (this project never
  imports ManiSkill) that steps a block when asked, so the three loops are timed in
  alternating blocks and machine noise hits them alike.

Both sides use 50-step episodes (ManiSkill's PickCube default; ours is 100, set to 50
here) so resets weigh the same. The load average (``os.getloadavg``) is printed before
and after: the figures only compare within a run on a shared machine.

Usage: ``python benchmarks/task_throughput.py [--rounds 10] [--maniskill-python PATH]``
(``--maniskill-python ''`` skips the peer).
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np

import robot_agents as ra

CONTROL_MODE = "pd_joint_delta_pos"
EPISODE_STEPS = 50
SEED = 0

#: The peer side, run by ManiSkill's own Python: reads a step count per line, steps that
#: many random actions (resetting at episode ends) and answers the seconds it took.
PEER = f"""
import sys, time, numpy as np, gymnasium as gym, mani_skill, mani_skill.envs, sapien.render
class Inert:  # stands in for render materials and textures: no render device here (no effect on physics)
    def __init__(self, *args, **kwargs):
        pass
for module in (sapien.render, sapien.pysapien.render):
    module.RenderMaterial = module.RenderTexture2D = Inert
env = gym.make("PickCube-v1", robot_uids="panda", obs_mode="state", control_mode="{CONTROL_MODE}",
               sim_backend="cpu", render_backend="none", max_episode_steps={EPISODE_STEPS})
env.reset(seed={SEED})
actions = np.random.default_rng({SEED}).uniform(-1, 1, (256,) + env.action_space.shape).astype(np.float32)
count = 0
def run(n):
    global count
    for _ in range(n):
        _, _, terminated, truncated, _ = env.step(actions[count % len(actions)])
        count += 1
        if bool(terminated) or bool(truncated):
            env.reset()
print("ready", mani_skill.__version__, flush=True)
for line in sys.stdin:
    if line.strip() == "quit":
        break
    start = time.perf_counter()
    run(int(line))
    print(time.perf_counter() - start, flush=True)
"""


class Ours:
    """Our vector env stepping random actions in blocks."""

    def __init__(self, num_envs: int, sleep: bool = True) -> None:
        self.env = gym.make_vec(
            "robot_agents/PickCube-v1",
            num_envs=num_envs,
            vectorization_mode="vector_entry_point",
            robot_uids="panda",
            obs_mode="state",
            control_mode=CONTROL_MODE,
            max_episode_steps=EPISODE_STEPS,
            sleep=sleep,
        )
        self.env.reset(seed=SEED)
        shape = (256, *self.env.action_space.shape)
        self.actions = np.random.default_rng(SEED).uniform(-1, 1, shape).astype(np.float32)
        self.count = 0
        self.num_envs = num_envs

    def block(self, steps: int) -> float:
        """Seconds for ``steps`` vector steps."""
        start = time.perf_counter()
        for _ in range(steps):
            self.env.step(self.actions[self.count % len(self.actions)])
            self.count += 1
        return time.perf_counter() - start


class Peer:
    """ManiSkill's PickCube in a subprocess of its own Python."""

    def __init__(self, python: str) -> None:
        self.proc = subprocess.Popen(
            [python, "-c", PEER], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
        )
        assert self.proc.stdout is not None
        ready = self.proc.stdout.readline().split()
        if not ready or ready[0] != "ready":
            raise RuntimeError(f"the ManiSkill side did not start ({python}); run it by hand to see why")
        self.version = ready[1]

    def block(self, steps: int) -> float:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(f"{steps}\n")
        self.proc.stdin.flush()
        return float(self.proc.stdout.readline())

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write("quit\n")
        self.proc.stdin.flush()
        self.proc.wait(timeout=30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--block", type=int, default=100, help="env steps per block of a single env")
    parser.add_argument("--batch-block", type=int, default=10, help="vector steps per block at 64 envs")
    parser.add_argument("--maniskill-python", default=str(Path.home() / ".venvs/maniskill/bin/python"))
    parser.add_argument(
        "--no-sleep-too",
        action="store_true",
        help="also time ours with MuJoCo's island sleeping off (the tasks turn it on)",
    )
    args = parser.parse_args()

    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())} ({os.cpu_count()} CPUs)")
    print(f"Python {platform.python_version()}, MuJoCo {mujoco.__version__}, robot_agents {ra.__version__}")
    loops: dict[str, tuple[object, int, int]] = {
        "ours x1": (Ours(1), args.block, 1),
        "ours x64": (Ours(64), args.batch_block, 64),
    }
    if args.no_sleep_too:
        loops["ours x1, sleep off"] = (Ours(1, sleep=False), args.block, 1)
        loops["ours x64, sleep off"] = (Ours(64, sleep=False), args.batch_block, 64)
    peer = None
    if args.maniskill_python and Path(args.maniskill_python).exists():
        peer = Peer(args.maniskill_python)
        print(f"ManiSkill {peer.version} ({args.maniskill_python})")
        loops["ManiSkill x1 (CPU)"] = (peer, args.block, 1)
    else:
        print(f"ManiSkill: no Python at {args.maniskill_python!r}; skipped")

    totals = dict.fromkeys(loops, 0.0)
    for loop, steps, _ in loops.values():  # warm-up
        loop.block(steps)  # type: ignore[attr-defined]
    for _ in range(args.rounds):
        for name, (loop, steps, _) in loops.items():
            totals[name] += loop.block(steps)  # type: ignore[attr-defined]
    if peer is not None:
        peer.close()

    rates = {name: args.rounds * steps * envs / totals[name] for name, (_, steps, envs) in loops.items()}
    print(f"\nPickCube-v1, Panda, state obs, {CONTROL_MODE}, random actions (seed {SEED}), {args.rounds} rounds")
    print("| loop | env steps/s | vs ours x1 |\n|---|---|---|")
    for name, rate in rates.items():
        print(f"| {name} | {rate:.0f} | {rate / rates['ours x1']:.2f}x |")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
