"""How close to raw MuJoCo can any Python env step get? A lower bound for our overhead.

Times, in alternating blocks on the same compiled Panda model (25 substeps per step):
- ``raw const``: ``mj_step(model, data, 25)`` with constant ``ctrl``;
- ``minimal``: a hand-written loop doing the least a ``pd_joint_delta_pos`` env step
  must do — check the action, clip and scale it, add it to the measured arm joints,
  write ``ctrl``, step, and build the same 34-number observation — with no classes;
- ``env``: our ``env.step`` on the same actions (small, alternating sign);
- ``raw 25x1``: for reference, the naive raw loop that calls ``mj_step(model, data)``
  once per substep from Python (what we avoid by stepping with ``nstep``).

Usage: ``python benchmarks/python_floor.py [--rounds 40] [--block 50]``.
"""

from __future__ import annotations

import argparse
import math
import time

import mujoco
import numpy as np

import robot_agents as ra

STATE = mujoco.mjtState.mjSTATE_INTEGRATION


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--rounds", type=int, default=40)
    parser.add_argument("--block", type=int, default=50)
    args = parser.parse_args()
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_delta_pos", max_episode_steps=None)
    u = env.unwrapped
    env.reset(seed=0)
    model, agent = u.model, u.agent
    start = u.get_state()["physics"][0]
    const_data, minimal_data, single_data = mujoco.MjData(model), mujoco.MjData(model), mujoco.MjData(model)
    for data in (const_data, minimal_data, single_data):
        mujoco.mj_setState(model, data, start, STATE)
    rng = np.random.default_rng(0)
    actions = [((-1) ** i * 0.1 * rng.uniform(0, 1, (1, 8))).astype(np.float32) for i in range(64)]

    controller = agent.controller
    clip_low, clip_high = controller.action_low, controller.action_high
    scale = (
        np.concatenate([c.raw_high for c in controller.parts.values()])
        - np.concatenate([c.raw_low for c in controller.parts.values()])
    ) / 2
    offset = (
        np.concatenate([c.raw_high for c in controller.parts.values()])
        + np.concatenate([c.raw_low for c in controller.parts.values()])
    ) / 2
    q_low, q_high = agent.qpos_limits[:7, 0], agent.qpos_limits[:7, 1]
    ctrl = np.zeros((1, model.nu))
    tcp = agent.frames.end_effector(None, "python_floor").id  # the Panda's TCP is a body

    def minimal_step(action: np.ndarray) -> np.ndarray:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != (1, 8) or not math.isfinite(a.sum()):
            raise ValueError("bad action")
        raw = np.minimum(np.maximum(a, clip_low), clip_high) * scale + offset
        qpos = minimal_data.qpos.copy().reshape(1, -1)
        target = np.minimum(np.maximum(qpos[:, :7] + raw[:, :7], q_low), q_high)
        ctrl[:, :7] = target
        ctrl[:, 7:9] = raw[:, 7:8]
        minimal_data.ctrl[:] = ctrl[0]
        mujoco.mj_step(model, minimal_data, 25)
        qpos = minimal_data.qpos.copy().reshape(1, -1)
        qvel = minimal_data.qvel.copy().reshape(1, -1)
        pose = np.concatenate((minimal_data.xpos[tcp], minimal_data.xquat[tcp])).reshape(1, 7)
        return np.concatenate([qpos, qvel, target, ctrl[:, 7:9], pose], axis=1, dtype=np.float32)

    loops = {
        "raw const": lambda i: mujoco.mj_step(model, const_data, 25),
        "minimal": lambda i: minimal_step(actions[i % 64]),
        "env": lambda i: env.step(actions[i % 64]),
        "raw 25x1": lambda i: [mujoco.mj_step(model, single_data) for _ in range(25)],
    }
    totals = dict.fromkeys(loops, 0.0)
    for _ in range(args.rounds):
        for name, loop in loops.items():
            begin = time.perf_counter()
            for i in range(args.block):
                loop(i)
            totals[name] += time.perf_counter() - begin
    steps = args.rounds * args.block
    raw = steps / totals["raw const"]
    for name in loops:
        rate = steps / totals[name]
        print(f"{name:<10} {rate:7.0f} steps/s  {rate / raw:5.2f} of raw const  {1e6 / rate:6.1f} us/step")


if __name__ == "__main__":
    main()
