"""Two-line robots from model files in the table-top tasks, solved by the scripted
solvers of ``examples/scripted_pick.py`` (docs/using-a-model-file.md, "Two-line robots
in the tasks").

For each model file: the two-line robot (``uid`` and the path, nothing else) is
registered, and each task it has the parts for (``PickCube-v1`` and ``PushCube-v1``
need a gripper or a tool, ``ReachPose-v1`` an arm) runs ``--seeds`` envs (seeds 0 ..
N-1, one batch) with the generic scripted solver; printed: successes per task.

``--servos`` adds a third line for the files whose servos the library knows: their
URDFs write ``effort="0"`` (or nothing), so the two-line robot's drives have no effort
limit and its jaw presses with whatever a 25 Hz spring on its light jaw gives
(``robot_agents.actuators.gains.GRIP_BANDWIDTH_HZ``; the arm's joints 10 Hz ones); the third
line states the datasheet facts of :mod:`robot_agents.robots.servo_arms.servos` with
``ra.DerivedActuators`` (gains still derived): :data:`SERVOS`.

``--gripper robotiq_2f85 --at LINK`` (or ``franka_hand``; the command line's options,
:data:`robot_agents.robots.catalog.BUILTIN_PIECES`) makes it three lines: a built-in
gripper piece mounted on each file's link ``LINK`` (its z axis pointing out of
the flange, as ROS-Industrial's ``tool0`` and UFactory's ``link_eef``), the arm's parts
and drives inferred from the file (docs/using-a-model-file.md, "Your arm's file with a
built-in gripper").

Usage: ``python benchmarks/two_line_tasks.py FILE [FILE ...] [--seeds 20] [--servos]
[--gripper NAME --at LINK]`` (the ``mani-skill`` wheel's arms: ``pip download --no-deps
mani-skill==3.0.1`` and unzip ``mani_skill/assets/robots``; arm-only files: the
``example-robot-data`` wheel's ``ur_description`` and ``xarm_description``, and the
``robosuite`` wheel's ``robosuite/models/assets/robots/<arm>/robot.xml``, arms driven by
torque motors, with ``--at right_hand``; ``--root-body vx300s_left`` picks one arm of
gym_aloha's two-arm ALOHA file).
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import robot_agents as ra
from robot_agents.errors import ConfigError
from robot_agents.robot_source import OUT_AXES, robot_from_file
from robot_agents.robots.catalog import BUILTIN_PIECES
from robot_agents.robots.servo_arms.servos import STS3215, XL330_M288, XL430_W250, Servo

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import scripted_pick  # (the solvers live with the examples)

TASKS = ("PickCube-v1", "PushCube-v1", "ReachPose-v1")


def stated(joints: str | None, servo: Servo) -> ra.DerivedActuators:
    """Derived drives on ``joints`` (``None``: every joint) with ``servo``'s stall torque,
    no-load speed, reflected inertia and friction."""
    return ra.DerivedActuators(
        joints=joints,
        effort_limit=servo.stall_torque,
        velocity_limit=servo.no_load_speed,
        armature=servo.armature,
        friction=servo.friction,
    )


#: File name -> the servos stated for it with ``--servos`` (the built-in ``so100`` and
#: ``koch-v1.1`` modules cite the servo models: six STS3215 on the SO-100; XL430-W250 on
#: the Koch's first two joints, XL330-M288 on the other four and the jaw).
SERVOS: dict[str, tuple[ra.DerivedActuators, ...]] = {
    "so100.urdf": (stated(None, STS3215),),
    "follower_arm_v1.1.urdf": (stated("joint_[12]", XL430_W250), stated("joint_[3-6]", XL330_M288)),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("paths", type=Path, nargs="+", help="model files")
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--servos", action="store_true", help="state the servos of the files in SERVOS")
    parser.add_argument("--gripper", choices=sorted(BUILTIN_PIECES), help="mount this built-in gripper (needs --at)")
    parser.add_argument("--at", help="the link of each file the gripper is mounted on")
    parser.add_argument(
        "--at-axis", default="z", choices=list(OUT_AXES), help="the axis of --at the gripper points along"
    )
    parser.add_argument("--root-body", help="each file's top-level body that is the robot, where there are several")
    args = parser.parse_args()
    if (args.gripper is None) != (args.at is None):
        parser.error("--gripper and --at go together")
    warnings.simplefilter("ignore")
    print("| file | " + " | ".join(TASKS) + " |\n|---|" + "---|" * len(TASKS))
    for path in args.paths:
        uid = f"two_line_{path.stem}"
        attrs: dict[str, object] = {"uid": uid}
        servos = SERVOS.get(path.name) if args.servos else None
        if servos is not None:
            attrs["actuators"] = servos
        # the file's robot as the command line makes it (--gripper / --at: the piece mounted)
        ra.register_agent(
            type(
                "TwoLine",
                (
                    robot_from_file(
                        path.resolve(), gripper=args.gripper, at=args.at, root_body=args.root_body, at_axis=args.at_axis
                    ),
                ),
                attrs,
            ),
            override=True,
        )
        cells = []
        for task in TASKS:
            try:
                successes, _ = scripted_pick.success_rate(task, uid, args.seeds)
                cells.append(f"{successes}/{args.seeds}")
            except ConfigError as error:  # the robot lacks the task's parts
                cells.append(f"- ({str(error).split(': ', 1)[-1][:60]})")
        # files of one name (robosuite's robots/<arm>/robot.xml) told apart by their folder
        shared = sum(p.name == path.name for p in args.paths) > 1
        name = f"{path.parent.name}/{path.name}" if shared else path.name
        label = f"{name} + servos" if servos is not None else name
        label += f" + {args.gripper}" if args.gripper is not None else ""
        label += f" (along {args.at_axis})" if args.at_axis != "z" else ""
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
