"""The mobile pick example (``examples/mobile_pick.py``) over many seeds, per robot: the
table in docs/mobile-manipulators.md.

    python benchmarks/mobile_pick_seeds.py                       # every mobile manipulator, seeds 0-49
    python benchmarks/mobile_pick_seeds.py stretch --seeds 10

Each episode makes its env, drives the base to the table, picks the cube and lifts it
(one env, the robot's default physics step); per robot the table gives the successes,
the ranges of the base's path and of the lift, the largest distance between where the
base stopped and its picking pose, the mean control steps (driving / all, and the most)
and the mean wall time per episode. Not run in CI.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))

from mobile_pick import mobile_manipulators, pick  # the example (examples/ is not a package)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robots", nargs="*", help="robot uids (default: every mobile manipulator)")
    parser.add_argument("--seeds", type=int, default=50, help="seeds 0 .. N-1")
    args = parser.parse_args()
    print(
        "| robot | success | base path (m) | cube lifted (cm) | base stop error (mm, max) | "
        "steps: drive / all (mean) | time per episode |"
    )
    print("|---|---|---|---|---|---|---|")
    for uid in args.robots or mobile_manipulators():
        results = [pick(uid, seed) for seed in range(args.seeds)]
        driven = [r.driven for r in results]
        lifted = [100.0 * r.lifted for r in results]
        print(
            f"| `{uid}` | {sum(r.success for r in results)}/{len(results)} | {min(driven):.2f}-{max(driven):.2f} | "
            f"{min(lifted):.1f}-{max(lifted):.1f} | {1000.0 * max(r.base_error for r in results):.1f} | "
            f"{statistics.mean(r.drive_steps for r in results):.0f} / {statistics.mean(r.steps for r in results):.0f} "
            f"(max {max(r.steps for r in results)}) | {statistics.mean(r.seconds for r in results):.2f} s |",
            flush=True,
        )


if __name__ == "__main__":
    main()
