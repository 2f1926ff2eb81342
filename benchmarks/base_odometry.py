"""Odometry of every registered base against the command: the table in
docs/mobile-manipulators.md ("Odometry").

    python benchmarks/base_odometry.py                 # every robot with a Base, both dynamics
    python benchmarks/base_odometry.py stretch --dynamics kinematic

From ``(0, 0)`` facing +x at 20 Hz, then 10 steps at zero (the tests' ``drive`` helper,
tests/test_mobile_kinematic.py): 1 m forward at 0.5 m/s (0.25 m/s for a base whose top
speed is lower), 90 deg in place in 3 s, and an arc, that speed and 1 rad/s for 1 s,
whose end is compared with ``(sin 1, 1 - cos 1) v / w`` and a heading of 1 rad
("across": the error across the arc's end heading, negative outward).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests.test_mobile_kinematic import drive, registered_bases

import robot_agents as ra


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robots", nargs="*", help="robot uids (default: every registered robot with a Base)")
    parser.add_argument("--dynamics", nargs="+", default=["dynamic", "kinematic"], choices=["dynamic", "kinematic"])
    args = parser.parse_args()
    print(
        "| robot | base | 1 m forward: along / sideways / heading | 90 deg in 3 s: heading / drift | "
        "arc: error (of its length) / across / heading |"
    )
    print("|---|---|---|---|---|")
    for uid in args.robots or registered_bases():
        max_speed = next(p for p in ra.get_agent(uid).check().parts if isinstance(p, ra.Base)).max_speed
        speed = 0.5 if max_speed >= 0.5 else 0.25
        for dynamics in args.dynamics:
            xy, yaw = drive(uid, dynamics, speed, 0.0, round(1.0 / speed / 0.05))
            turned_xy, turned = drive(uid, dynamics, 0.0, np.pi / 6, 60)
            arc_xy, arc_yaw = drive(uid, dynamics, speed, 1.0, 20)
            error = arc_xy - np.array([np.sin(1.0), 1.0 - np.cos(1.0)]) * speed
            across = -error[0] * np.sin(1.0) + error[1] * np.cos(1.0)
            size = float(np.linalg.norm(error))
            print(
                f"| `{uid}` | {dynamics} | {xy[0] - 1.0:.1e} m / {1e3 * xy[1]:.2f} mm / {yaw:.1e} rad | "
                f"{turned - np.pi / 2:.1e} rad / {np.linalg.norm(turned_xy):.0e} m | "
                f"{1e3 * size:.2f} mm ({100 * size / speed:.2f} %) / {1e3 * across:.2f} mm / {arc_yaw - 1.0:.1e} rad |",
                flush=True,
            )


if __name__ == "__main__":
    main()
