"""What the simplified Unitree variants buy: MuJoCo's physics time per control step of
``unitree_go2_simplified_locomotion`` and ``unitree_h1_simplified`` against the full
``unitree_go2`` and ``unitree_h1``, in three motions (20 Hz control, one env; both
robots of a pair at the full robot's declared ``sim_freq``, so that the ratio is the
collision model's alone: the simplified Go2 declares a coarser step of its own, 320 Hz
against 400):

- ``standing``: the default keyframe's hold (only the feet touch anything: the two
  robots' trajectories are the same bit for bit);
- ``moving legs``: standing while small target deltas of alternating sign (+-0.1 of the
  bound, seeded) move the legs in ``pd_joint_target_delta_pos``;
- ``random``: uniform random absolute targets over the joint ranges in ``pd_joint_pos``:
  the robot folds up and thrashes on the floor, its links touching the floor and each
  other.

Per robot and motion the scene steps the actions once, recording each control step's
``ctrl``; then a bare loop on a plain ``MjData`` of the scene's (stepped) model replays
them from the same start (``data.ctrl[:] = u``; ``mj_step(model, data, substeps)``),
checked to end in the scene's exact state. The full and simplified replays run in
alternating blocks of ``--block`` control steps, ``--rounds`` times; the table gives the
median microseconds per control step of each (this process's CPU time: a shared
machine's waits for a core are not the step's cost) and their ratio.

Usage: ``python benchmarks/simplified_collisions.py [--steps 200] [--rounds 15] [--block 20]``
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.checks import hold_action

PAIRS = (("unitree_go2", "unitree_go2_simplified_locomotion"), ("unitree_h1", "unitree_h1_simplified"))


def standing(agent: ra.Agent, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """The default keyframe's hold, repeated."""
    return [hold_action(agent)] * count


def moving_legs(agent: ra.Agent, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Small target deltas of alternating sign (a tenth of the bound)."""
    space = agent.single_action_space
    return [(-1) ** i * 0.1 * space.high * rng.uniform(0, 1, space.shape) for i in range(count)]


def random_targets(agent: ra.Agent, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Uniform random absolute targets over the joint ranges."""
    space = agent.single_action_space
    return [rng.uniform(space.low, space.high) for _ in range(count)]


#: Motion name -> (control mode, action maker).
MOTIONS: dict[str, tuple[str, Callable[[ra.Agent, int, np.random.Generator], list[np.ndarray]]]] = {
    "standing": ("pd_joint_pos", standing),
    "moving legs": ("pd_joint_target_delta_pos", moving_legs),
    "random": ("pd_joint_pos", random_targets),
}


class Replay:
    """One robot's recorded motion, replayed on a plain ``MjData``."""

    def __init__(
        self, uid: str, mode: str, make: Callable[..., list[np.ndarray]], steps: int, sim_freq: int | None = None
    ) -> None:
        scene = ra.Scene(uid, control_modes=mode, sim_freq=sim_freq)
        agent = scene.agents[0]
        scene.reset()
        self.model = scene.model
        self.substeps = scene.substeps
        self.start = mujoco.MjData(self.model)
        world = scene.world.datas[0]
        mujoco.mj_copyData(self.start, self.model, world)
        self.ctrls = []
        self.contacts = 0
        for action in make(agent, steps, np.random.default_rng(0)):
            agent.set_action(action)
            scene.step()
            self.ctrls.append(world.ctrl.copy())
            self.contacts += world.ncon
        self.end = np.concatenate([world.qpos, world.qvel])
        self.ngeom = self.model.ngeom
        self.colliding = int(np.count_nonzero(self.model.geom_contype | self.model.geom_conaffinity))
        scene.close()
        data = self.reset()
        self.run(data, 0, len(self.ctrls))
        if not np.array_equal(np.concatenate([data.qpos, data.qvel]), self.end):
            raise RuntimeError(f"{uid} ({mode}): the replay does not end in the scene's state")

    def reset(self) -> mujoco.MjData:
        data = mujoco.MjData(self.model)
        mujoco.mj_copyData(data, self.model, self.start)
        return data

    def run(self, data: mujoco.MjData, begin: int, end: int) -> float:
        """Replay control steps ``begin:end``; CPU seconds."""
        model, n = self.model, self.substeps
        ctrls = self.ctrls[begin:end]
        t0 = time.process_time()
        for u in ctrls:
            data.ctrl[:] = u
            mujoco.mj_step(model, data, n)
        return time.process_time() - t0


def compare(full: Replay, simplified: Replay, rounds: int, block: int) -> tuple[float, float]:
    """Median microseconds per control step of each, alternating blocks."""
    steps = len(full.ctrls)
    per_round: dict[str, list[float]] = {"full": [], "simplified": []}
    for r in range(rounds):
        totals = {"full": 0.0, "simplified": 0.0}
        data = {"full": full.reset(), "simplified": simplified.reset()}
        order = ("full", "simplified") if r % 2 == 0 else ("simplified", "full")
        for begin in range(0, steps, block):
            for name in order:
                replay = full if name == "full" else simplified
                totals[name] += replay.run(data[name], begin, min(begin + block, steps))
        for name, total in totals.items():
            per_round[name].append(total / steps * 1e6)
    return statistics.median(per_round["full"]), statistics.median(per_round["simplified"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200, help="control steps per motion")
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--block", type=int, default=20, help="control steps per timed block")
    args = parser.parse_args()
    print(
        "| robot | motion | sim_freq (Hz) | colliding geoms, full / simplified | contacts per control step, full / "
        "simplified | physics per control step, full (us) | simplified (us) | simplified / full |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for full_uid, simplified_uid in PAIRS:
        for motion, (mode, make) in MOTIONS.items():
            full = Replay(full_uid, mode, make, args.steps)
            simplified = Replay(simplified_uid, mode, make, args.steps, sim_freq=full.substeps * 20)
            a, b = compare(full, simplified, args.rounds, args.block)
            freq = full.substeps * 20
            print(
                f"| `{simplified_uid}` | {motion} (`{mode}`) | {freq} | {full.colliding} / {simplified.colliding} | "
                f"{full.contacts / args.steps:.1f} / {simplified.contacts / args.steps:.1f} | {a:.0f} | {b:.0f} | "
                f"{b / a:.3f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
