"""What a joint-state write after a step costs to sync: MuJoCo's full ``mj_forward``
against poses only (``mj_kinematics`` + ``mj_camlight``), per robot model, and one
control step's physics beside them for scale (``timeit``, best of 5).

The world syncs wheels and held legs with poses only (``write_joint_state(...,
forward=False)``); other writes (resets, a kinematic base before its collision check)
keep the full ``mj_forward``.

    python benchmarks/pose_sync_cost.py fetch stretch google_robot spot

Not run in CI.
"""

from __future__ import annotations

import argparse
import timeit
from collections.abc import Sequence

import mujoco

import robot_agents as ra


def costs(uid: str) -> str:
    env = ra.make_env("Empty-v1", robot_uids=uid, max_episode_steps=None).unwrapped
    env.reset(seed=0)
    model, data, substeps = env.model, env.scene.world.datas[0], env.scene.world.substeps

    def best(call: object, number: int) -> float:
        return min(timeit.repeat(call, number=number, repeat=5)) / number * 1e6  # type: ignore[arg-type]

    forward = best(lambda: mujoco.mj_forward(model, data), 2000)
    poses = best(lambda: (mujoco.mj_kinematics(model, data), mujoco.mj_camlight(model, data)), 2000)
    step = best(lambda: mujoco.mj_step(model, data, substeps), 200)
    env.close()
    return f"| `{uid}` | {forward:.1f} | {poses:.1f} | {step:.0f} |"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=["fetch", "stretch", "google_robot", "spot"])
    args = parser.parse_args(argv)
    print("| robot | mj_forward (µs) | poses only (µs) | one control step's physics (µs) |\n|---|---|---|---|")
    for uid in args.uids:
        print(costs(uid), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
