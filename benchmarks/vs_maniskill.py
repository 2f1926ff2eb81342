"""Side by side with the peer library: env steps/s of each robot both libraries have,
ours and ManiSkill 3's CPU simulation, same task (``Empty-v1``), control mode
(``pd_joint_delta_pos`` unless ``--modes`` names others), control frequency (20 Hz),
seeded random actions, one env, in one run with the two timed in alternating rounds.

    python benchmarks/vs_maniskill.py                       # panda so100 ...
    python benchmarks/vs_maniskill.py panda --rounds 5 --maniskill-python ~/.venvs/maniskill/bin/python
    python benchmarks/vs_maniskill.py xarm6_robotiq --modes pd_joint_delta_pos pd_ee_delta_pose

Robots whose ManiSkill assets are downloaded at run time (``xarm6_*``, ``widowxai``)
need them under ``$MS_ASSET_DIR/data/robots/`` (ManiSkill's layout); without a
rendering device SAPIEN cannot build URDF visuals, so strip the ``<visual>`` elements
from the copy you benchmark (visuals carry no mass; the physics is unchanged).

ManiSkill runs in a separate interpreter (``--maniskill-python``; default: this one if
it imports ``mani_skill``, else ``~/.venvs/maniskill/bin/python`` as made by
``setup_maniskill.sh``). Without one the script says so and exits 0. Not run in CI.
Each library runs at its own default physics step (ours: the robot's ``sim_freq``).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

import robot_agents as ra

#: Robots both libraries register under the same uid.
SHARED = ("panda", "so100", "koch-v1.1", "widowxai", "xarm6_nogripper", "xarm6_robotiq", "floating_panda_gripper")

PEER = """
import sys, time, numpy as np, gymnasium as gym, mani_skill.envs  # noqa
uid, steps, rounds, mode = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
env = gym.make("Empty-v1", robot_uids=uid, obs_mode="state", control_mode=mode,
               sim_backend="cpu", render_backend="none")
env.reset(seed=0)
acts = np.random.default_rng(0).uniform(-1, 1, (steps,) + env.action_space.shape).astype(np.float32)
for _ in range(rounds):
    t = time.perf_counter()
    for a in acts: env.step(a)
    print(steps / (time.perf_counter() - t), flush=True)
"""


def peer_python(given: str | None) -> str | None:
    if given:
        return given
    if importlib.util.find_spec("mani_skill") is not None:
        return sys.executable
    venv = Path.home() / ".venvs" / "maniskill" / "bin" / "python"
    return str(venv) if venv.exists() else None


def ours(uid: str, steps: int, mode: str) -> float:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode)
    env.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-1, 1, (steps, *env.action_space.shape)).astype(np.float32)
    start = time.perf_counter()
    for a in acts:
        env.step(a)
    rate = steps / (time.perf_counter() - start)
    env.close()
    return rate


def theirs(python: str, uid: str, steps: int, mode: str) -> float | str:
    """ManiSkill's rate, or why it did not run (the last line of its error)."""
    done = subprocess.run([python, "-c", PEER, uid, str(steps), "2", mode], capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines()
        return lines[-1][:120] if lines else f"exit {done.returncode}"
    rates = [float(line) for line in done.stdout.split()]
    return rates[-1]  # the second round: imports and first-step costs excluded


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("uids", nargs="*", default=list(SHARED))
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--maniskill-python", default=None)
    parser.add_argument("--modes", nargs="+", default=["pd_joint_delta_pos"])
    args = parser.parse_args(argv)
    python = peer_python(args.maniskill_python)
    if python is None:
        print("mani-skill is not installed (see /work/shared/peers/setup_maniskill.sh): nothing to compare.")
        return 0
    load = os.getloadavg()[0]
    print(f"load average {load:.2f}\n")
    print("| robot | mode | our sim_freq | ours (env steps/s) | ManiSkill CPU | ratio |")
    print("|---|---|---|---|---|---|")
    for uid in args.uids:
        for mode in args.modes:
            if mode not in ra.get_agent(uid).modes():
                print(f"| `{uid}` | `{mode}` | - | not a mode of this robot | - | - |")
                continue
            mine: list[float] = []
            peer: list[float] = []
            failure = ""
            for _ in range(args.rounds):
                mine.append(ours(uid, args.steps, mode))
                rate = theirs(python, uid, args.steps, mode)
                if isinstance(rate, str):
                    failure = rate
                    break
                peer.append(rate)
            freq = ra.get_agent(uid).sim_freq or 500
            row = f"| `{uid}` | `{mode}` | {freq} | {np.median(mine):.0f}"
            if not peer:
                print(f"{row} | did not run: {failure} | - |")
                continue
            ratio = float(np.median(mine)) / float(np.median(peer))
            print(f"{row} | {np.median(peer):.0f} | {ratio:.1f}x |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
