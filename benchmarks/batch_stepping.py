"""Ways to step many envs of one model on this machine's cores: is ours as fast as
MuJoCo's own threaded ``mujoco.rollout``?

All on the compiled Panda ``Empty-v1`` model, 25 substeps per control step, N copies
starting at the rest pose, constant ``ctrl``; physics only (no controller, no
observations), control steps/s of all N envs together:
- ``1 env loop``: one MjData, ``mj_step(model, data, 25)`` in a loop (the reference);
- ``python loop``: N MjData stepped one after another on one thread;
- ``BatchedWorld``: our ``BatchedWorld.step()`` (threads; MuJoCo releases the GIL);
- ``rollout``: ``mujoco.rollout.Rollout(nthread=T).rollout`` over the N states,
  25 steps each, one persistent pool (the state it returns is discarded).

Usage: ``python benchmarks/batch_stepping.py [--num-envs 64] [--rounds 10]``.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

import mujoco
import numpy as np
from mujoco import rollout

import robot_agents as ra


def rate(run: Callable[[], None], steps_per_call: int, rounds: int) -> float:
    run()
    start = time.perf_counter()
    for _ in range(rounds):
        run()
    return rounds * steps_per_call / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--num-envs", type=int, default=64)
    parser.add_argument("--rounds", type=int, default=10)
    args = parser.parse_args()
    n, threads = args.num_envs, os.cpu_count() or 1
    scene = ra.Scene("panda", num_envs=n)
    scene.reset()
    model, world, substeps = scene.model, scene.world, scene.substeps
    one = mujoco.MjData(model)
    datas = [mujoco.MjData(model) for _ in range(n)]
    start = world.get_state()[0]
    for data in [one, *datas]:
        mujoco.mj_setState(model, data, start, mujoco.mjtState.mjSTATE_INTEGRATION)
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    initial = np.empty((n, mujoco.mj_stateSize(model, full)))
    for i, data in enumerate(datas):
        mujoco.mj_getState(model, data, initial[i], full)
    controls = np.tile(world.ctrl[:1], (n, substeps, 1))
    pool = rollout.Rollout(nthread=threads)
    scratch = [mujoco.MjData(model) for _ in range(threads)]

    def python_loop() -> None:
        for data in datas:
            mujoco.mj_step(model, data, substeps)

    results = {
        "1 env loop": rate(lambda: mujoco.mj_step(model, one, substeps), 1, args.rounds * n),
        "python loop": rate(python_loop, n, args.rounds),
        "BatchedWorld": rate(world.step, n, args.rounds),
        "rollout": rate(lambda: pool.rollout(model, scratch, initial, controls), n, args.rounds),
    }
    pool.close()
    scene.close()
    print(f"{n} envs, {threads} threads, {substeps} substeps per control step; control steps/s of all envs")
    reference = results["1 env loop"]
    for name, value in results.items():
        print(f"{name:<13} {value:8.0f}  {value / reference:5.2f}x")


if __name__ == "__main__":
    main()
