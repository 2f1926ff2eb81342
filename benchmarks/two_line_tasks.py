"""Two-line robots from model files in the table-top tasks, solved by the scripted
solvers of ``examples/scripted_pick.py`` (docs/using-a-model-file.md, "Two-line robots
in the tasks").

For each model file: the two-line robot (``uid`` and the path, nothing else) is
registered, and each task it has the parts for (``PickCube-v1`` and ``PushCube-v1``
need a gripper or a tool, ``ReachPose-v1`` an arm) runs ``--seeds`` envs (seeds 0 ..
N-1, one batch) with the generic scripted solver; printed: successes per task.

Usage: ``python benchmarks/two_line_tasks.py FILE [FILE ...] [--seeds 20]`` (the
``mani-skill`` wheel's arms: ``pip download --no-deps mani-skill==3.0.1`` and unzip
``mani_skill/assets/robots``).
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import robot_agents as ra
from robot_agents.errors import ConfigError

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import scripted_pick  # (the solvers live with the examples)

TASKS = ("PickCube-v1", "PushCube-v1", "ReachPose-v1")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("paths", type=Path, nargs="+", help="model files")
    parser.add_argument("--seeds", type=int, default=20)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print("| file | " + " | ".join(TASKS) + " |\n|---|" + "---|" * len(TASKS))
    for path in args.paths:
        uid = f"two_line_{path.stem}"
        ra.register_agent(type("TwoLine", (ra.Agent,), {"uid": uid, "urdf_path": path.resolve()}), override=True)
        cells = []
        for task in TASKS:
            try:
                successes, _ = scripted_pick.success_rate(task, uid, args.seeds)
                cells.append(f"{successes}/{args.seeds}")
            except ConfigError as error:  # the robot lacks the task's parts
                cells.append(f"- ({str(error).split(': ', 1)[-1][:60]})")
        print(f"| {path.name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
