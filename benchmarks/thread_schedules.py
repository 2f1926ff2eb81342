"""Where does ``BatchedWorld``'s threaded step lose to ``mujoco.rollout`` on many cores?
Ways of handing the per-env ``mj_step`` calls to threads, timed against each other.

All on the compiled Panda ``Empty-v1`` model at rest, 25 substeps per control step,
N envs, one thread per core; physics only (no controller, no observations); control
steps/s of all N envs together, each loop timed in alternating blocks after a warm-up:

- ``current``: ``BatchedWorld.step()`` as shipped: one contiguous chunk of envs per
  thread, handed out through a ``ThreadPoolExecutor`` (the calling thread steps the first);
- ``dynamic 1`` / ``dynamic 2``: the same pool, but each thread takes the next 1 or 2
  envs from a shared counter until none are left (balances uneven threads);
- ``barrier dynamic`` / ``barrier static``: long-lived threads woken by a
  ``threading.Barrier`` instead of the executor, taking envs from a shared counter or
  one contiguous chunk each;
- ``no pose sync``: ``current`` without the ``mj_kinematics`` + ``mj_camlight`` after each
  env's step (two fewer calls, so two fewer GIL hand-overs per env; the library needs
  them, see ``BatchedWorld._step_all``: this row only measures their cost);
- ``rollout``: ``mujoco.rollout.Rollout(nthread=T).rollout`` over the same N states
  (one C call per chunk of envs, no GIL; it steps scratch ``MjData`` and keeps no
  per-env data, which is why the library does not use it, see docs/benchmarks.md).

Every variant ends in the same ``qpos`` / ``qvel`` as ``current`` (checked; the rollout
is not compared). Usage: ``python benchmarks/thread_schedules.py [--num-envs 16 64 256]
[--rounds 8]``.
"""

from __future__ import annotations

import argparse
import functools
import itertools
import os
import threading
from collections.abc import Callable

import mujoco
import numpy as np
from mujoco import rollout

import robot_agents as ra
from render_throughput import interleaved  # a script beside this one: one way to time loops
from robot_agents.sim.world import BatchedWorld


def dynamic(world: BatchedWorld, size: int) -> Callable[[int], None]:
    """``_step_all`` with envs taken ``size`` at a time from a shared counter."""
    n, pool = world.num_envs, world._pool

    def step_all(nstep: int) -> None:
        counter = itertools.count(0, size)  # next() is atomic under the GIL

        def work() -> None:
            for first in counter:
                if first >= n:
                    return
                world._step_chunk(range(first, min(first + size, n)), nstep)

        futures = [pool.submit(work) for _ in range(world.num_threads - 1)] if pool else []
        work()
        for future in futures:
            future.result()

    return step_all


class BarrierThreads:
    """``_step_all`` on long-lived threads that meet at two barriers per step."""

    def __init__(self, world: BatchedWorld, size: int) -> None:
        self.world, self.size, self.nstep, self.stopping = world, size, 0, False
        self.counter = itertools.count()
        self.start = threading.Barrier(world.num_threads)
        self.end = threading.Barrier(world.num_threads)
        self.threads = [threading.Thread(target=self.serve, daemon=True) for _ in range(world.num_threads - 1)]
        for thread in self.threads:
            thread.start()

    def work(self) -> None:
        n, size = self.world.num_envs, self.size
        for first in self.counter:
            if first >= n:
                return
            self.world._step_chunk(range(first, min(first + size, n)), self.nstep)

    def serve(self) -> None:
        while True:
            self.start.wait()
            if self.stopping:
                return
            self.work()
            self.end.wait()

    def __call__(self, nstep: int) -> None:
        self.nstep, self.counter = nstep, itertools.count(0, self.size)
        self.start.wait()
        self.work()
        self.end.wait()

    def close(self) -> None:
        self.stopping = True
        self.start.wait()
        for thread in self.threads:
            thread.join()


def repeated(call: Callable[[], object]) -> Callable[[int], None]:
    """A loop of ``count`` calls of ``call``, as :func:`render_throughput.interleaved` times them."""

    def loop(count: int) -> None:
        for _ in range(count):
            call()

    return loop


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--num-envs", type=int, nargs="+", default=[16, 64, 256])
    parser.add_argument("--rounds", type=int, default=8)
    args = parser.parse_args()
    threads = os.cpu_count() or 1
    print(f"mujoco {mujoco.__version__}, {threads} cores, load average {os.getloadavg()[0]:.1f}")
    names = ["current", "dynamic 1", "dynamic 2", "barrier dynamic", "barrier static", "no pose sync"]
    print("\n| envs | " + " | ".join([*names, "rollout"]) + " |")
    print("|---" * (len(names) + 2) + "|")
    for n in args.num_envs:
        scenes = {name: ra.Scene("panda", num_envs=n) for name in names}
        for scene in scenes.values():
            scene.reset()
        worlds = {name: scene.world for name, scene in scenes.items()}
        barriers = [
            BarrierThreads(worlds["barrier dynamic"], 1),
            BarrierThreads(worlds["barrier static"], -(-n // worlds["barrier static"].num_threads)),
        ]
        worlds["dynamic 1"]._step_all = dynamic(worlds["dynamic 1"], 1)  # type: ignore[method-assign]
        worlds["dynamic 2"]._step_all = dynamic(worlds["dynamic 2"], 2)  # type: ignore[method-assign]
        worlds["barrier dynamic"]._step_all = barriers[0]  # type: ignore[method-assign]
        worlds["barrier static"]._step_all = barriers[1]  # type: ignore[method-assign]
        worlds["no pose sync"]._sync_after_step = False
        reference = worlds["current"]
        model, substeps = reference.model, reference.substeps
        full = mujoco.mjtState.mjSTATE_FULLPHYSICS
        initial = np.empty((n, mujoco.mj_stateSize(model, full)))
        for i, data in enumerate(reference.datas):
            mujoco.mj_getState(model, data, initial[i], full)
        controls = np.tile(reference.ctrl[:1], (n, substeps, 1))
        pool = rollout.Rollout(nthread=threads)
        scratch = [mujoco.MjData(model) for _ in range(threads)]
        loops: dict[str, Callable[[], object]] = {name: world.step for name, world in worlds.items()}
        loops["rollout"] = functools.partial(pool.rollout, model, scratch, initial, controls)
        block = max(2, 2048 // n)
        calls = dict(
            zip(loops, interleaved([repeated(loop) for loop in loops.values()], args.rounds, block), strict=True)
        )
        cells = []
        for name, per_second in calls.items():
            same = name == "rollout" or all(
                np.array_equal(a.qpos, b.qpos) and np.array_equal(a.qvel, b.qvel)
                for a, b in zip(reference.datas, worlds[name].datas, strict=True)
            )
            cells.append(f"{per_second * n:.0f} ({per_second / calls['current']:.2f}x){'' if same else ' DIFFERS'}")
        print(f"| {n} | " + " | ".join(cells) + " |", flush=True)
        for barrier in barriers:
            barrier.close()
        pool.close()
        for scene in scenes.values():
            scene.close()
    print(f"\nload average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
