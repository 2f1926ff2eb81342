"""How the scripted PushCube solver's pushes press on the cube, per seed: the figures
of "Stretch's stalled pushes" in docs/tasks.md.

    python benchmarks/push_forces.py stretch --seeds 20 --no-rise   # the solver before the rise
    python benchmarks/push_forces.py stretch --seeds 20             # as it is

Runs ``examples/scripted_pick.py``'s ``solve_push`` on one batch of envs (seeds
``0 .. N-1``) and sums, at every control step, the contact forces between the robot and
the cube (``Arm.force_on``: the robot's force on the cube, world axes). Per seed (the
misses, or every seed with ``--all``): whether it succeeded, the steps the robot touched
the cube, the mean downward and horizontal parts of its force over those steps (N), how
far the cube moved along its line to the goal and how far it ended from the goal (cm).
``--no-rise`` sets the
rule's rise to 0: the solver as it was before the rule. Not run in CI (its smallest
setting is, in tests/test_benchmark_scripts.py).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))

import scripted_pick as solver  # the example (examples/ is not a package)

import robot_agents as ra


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robot", help="a registered uid the PushCube task takes")
    parser.add_argument("--seeds", type=int, default=20, help="envs of one batch, seeds 0 .. N-1")
    parser.add_argument("--no-rise", action="store_true", help="the solver without its rise (RISE = 0)")
    parser.add_argument("--all", action="store_true", help="a row for every seed, not only the misses")
    args = parser.parse_args()
    if args.no_rise:
        solver.RISE = 0.0
    n = args.seeds
    env = ra.make_env("PushCube-v1", robot_uids=args.robot, num_envs=n).unwrapped
    touch, down, horizontal = np.zeros(n, int), np.zeros(n), np.zeros(n)
    force_on = solver.Arm.force_on

    def recorded_force_on(self: solver.Arm, body: str) -> np.ndarray:
        """The solver's own per-step call (once a control step while it pushes), recorded."""
        force = force_on(self, body)
        touching = np.any(force != 0.0, axis=1)
        touch[touching] += 1
        down[touching] += -force[touching, 2]
        horizontal[touching] += np.linalg.norm(force[touching, :2], axis=1)
        return force

    solver.Arm.force_on = recorded_force_on  # type: ignore[method-assign]
    env.reset(seed=0)
    start, goal = env.body_pose("cube")[:, :3].copy(), env.goal_pos.copy()
    success = solver.solve_push(env, 0)
    end = env.body_pose("cube")[:, :3]
    line = goal[:, :2] - start[:, :2]
    line /= np.linalg.norm(line, axis=1, keepdims=True)
    moved = np.einsum("ij,ij->i", end[:, :2] - start[:, :2], line)
    left = np.linalg.norm(goal[:, :2] - end[:, :2], axis=1)
    print(
        f"{args.robot}, PushCube-v1, seeds 0-{n - 1}{' (no rise)' if args.no_rise else ''}: "
        f"{int(success.sum())}/{n}; goal radius {100.0 * float(np.min(env.goal_radius)):.2f} cm"
    )
    print(
        "| seed | success | steps touching | mean force down (N) | mean force along the table (N) | cube moved (cm) | left to the goal (cm) |"
    )
    print("|---|---|---|---|---|---|---|")
    for i in range(n):
        if success[i] and not args.all:
            continue
        steps = max(int(touch[i]), 1)
        print(
            f"| {i} | {bool(success[i])} | {touch[i]} | {down[i] / steps:.1f} | {horizontal[i] / steps:.1f} | "
            f"{100.0 * moved[i]:.1f} | {100.0 * left[i]:.1f} |"
        )
    env.close()


if __name__ == "__main__":
    main()
