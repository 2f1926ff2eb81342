"""What a legged robot's contact options cost and buy: for each friction-cone setting,
how far the standing robot's base creeps (m) between 1 s and 5 s of holding its default
keyframe in its default mode, and how many control steps per second it runs after its
legs have folded under small random deltas in ``pd_joint_delta_pos`` (the mode
``benchmarks/vs_maniskill.py`` compares; deltas from the measured pose let loaded legs
give), lying on the floor in a heap of contacts.

Usage: ``python benchmarks/legged_contacts.py [UID ...] [--steps 200]`` (default
``anymal_c``, whose declared contacts are Menagerie's elliptic cone with impratio 100).
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np

import robot_agents as ra
from robot_agents.checks import hold_action

#: Variants: name -> class attributes overriding the robot's.
VARIANTS: dict[str, dict[str, Any]] = {
    "as declared": {},
    "pyramidal, impratio 1 (MuJoCo's default)": {"friction_cone": "pyramidal", "impratio": 1.0},
    "elliptic, impratio 10": {"friction_cone": "elliptic", "impratio": 10.0},
}


def creep(cls: type[ra.Agent]) -> float:
    """The base's movement (m) from 1 s to 5 s of holding the default keyframe."""
    scene = ra.Scene(cls)
    scene.reset()
    agent = scene.agents[0]
    hold = hold_action(agent)
    positions = []
    for _ in range(5 * scene.control_freq):
        agent.set_action(hold)
        scene.step()
        positions.append(agent.base_pose[0, :3].copy())
    scene.close()
    return float(np.linalg.norm(positions[-1] - positions[scene.control_freq - 1]))


def folded_rate(cls: type[ra.Agent], steps: int) -> float:
    """Control steps per second (CPU time) of ``steps`` small random deltas in
    ``pd_joint_delta_pos`` from the default keyframe."""
    scene = ra.Scene(cls, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-0.05, 0.05, agent.controller.action_dim) for _ in range(steps)]
    begin = time.process_time()
    for action in actions:
        agent.set_action(action)
        scene.step()
    elapsed = time.process_time() - begin
    scene.close()
    return steps / elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=["anymal_c"])
    parser.add_argument("--steps", type=int, default=200)
    args = parser.parse_args()
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| robot | contacts | creep 1-5 s standing (mm) | folded: control steps/s |\n|---|---|---|---|")
    for uid in args.uids:
        base = ra.get_agent(uid)
        for name, attributes in VARIANTS.items():
            cls = type(base.__name__, (base,), {"uid": "", **attributes})
            print(f"| `{uid}` | {name} | {1000 * creep(cls):.2f} | {folded_rate(cls, args.steps):.0f} |", flush=True)


if __name__ == "__main__":
    main()
