"""How long the real-robot bridge takes to turn an action into joint targets.

``RealRobot.step`` reads the bus, writes the measured joints into the controllers'
model (``mj_forward``), runs the mode's controllers (end-effector modes solve their IK)
and writes the targets. Here the bus is a stub that returns a fixed measured state and
drops the targets, so the time is the bridge's own: what a control loop on hardware
pays per command before the motors' own latency. Per robot and mode, the median over
``--rounds`` rounds of ``--block`` steps of small random actions (CPU time of this
process), in microseconds.

Usage: ``python benchmarks/bridge_latency.py [--robots UID ...] [--rounds 20] [--block 50]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

import robot_agents as ra
from robot_agents.real import RealRobot, SimulatedBus

FloatArray = npt.NDArray[np.float64]

#: Modes timed per robot, those it has.
MODES = ("pd_joint_delta_pos", "pd_joint_target_delta_pos", "pd_ee_delta_pos", "pd_ee_delta_pose")


class StubBus:
    """A bus that measures the simulated robot's start pose once and drops what it is sent."""

    def __init__(self, uid: str) -> None:
        twin = SimulatedBus(uid)
        self.joint_names = tuple(twin.joint_names)
        self._qpos, self._qvel = twin.read()
        twin.close()

    def read(self) -> tuple[FloatArray, FloatArray]:
        return self._qpos, self._qvel

    def write(self, position: FloatArray, velocity: FloatArray, effort: FloatArray) -> None:
        pass

    def set_gains(self, stiffness: FloatArray, damping: FloatArray, effort_limit: FloatArray) -> None:
        pass

    def close(self) -> None:
        pass


def latency(uid: str, mode: str, rounds: int, block: int) -> float:
    """Median microseconds per ``RealRobot.step`` of ``uid`` in ``mode``."""
    robot = RealRobot(uid, StubBus(uid), control_mode=mode)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-0.1, 0.1, (block, *robot.action_space.shape))
    for action in actions:  # warm up
        robot.step(action)
    times = []
    for _ in range(rounds):
        begin = time.process_time()
        for action in actions:
            robot.step(action)
        times.append((time.process_time() - begin) / block)
    robot.close()
    return float(np.median(times) * 1e6)


def bridged_robots() -> list[str]:
    """Registered robots the bridge drives (fixed root, no mobile base)."""
    out = []
    for uid in ra.list_agents():
        try:
            RealRobot(uid, StubBus(uid)).close()
        except ra.ConfigError:
            continue
        out.append(uid)
    return out


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", nargs="*", help="uids (default: every robot the bridge drives)")
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--block", type=int, default=50)
    args = parser.parse_args(argv)
    uids = args.robots or bridged_robots()
    print("| robot | mode | µs per step |\n|---|---|---|")
    for uid in uids:
        modes = ra.get_agent(uid).modes()
        for mode in (m for m in MODES if m in modes):
            print(f"| `{uid}` | `{mode}` | {latency(uid, mode, args.rounds, args.block):.0f} |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
