"""Your arm's model file with a built-in gripper on its flange, in a few lines.

``six_joint_arm.urdf`` stands for a file you have: six joints, no actuators, no effort
limits. The robot below mounts the built-in Robotiq 2F-85 piece on its flange and
states the arm's servos (``DerivedActuators``: the gains are still derived from the
model's inertia, with the stated torque and rotor inertia in them; the gripper brings
its own drive). Everything else is inferred as for the file alone: the arm part (its
six joints, its end effector the gripper's ``tcp``, its task space measured: the
end-effector control modes) beside the gripper part the piece declares. Without the
``actuators`` line the arm's drives are derived with no limits stated. It then runs the
table-top tasks with the scripted solvers of ``scripted_pick.py`` and prints the
successes::

    python examples/compose_arm_gripper.py --seeds 20
    python examples/compose_arm_gripper.py --seeds 1 --video pick.gif   # one PickCube episode

(The servo figures are an example's, not a datasheet's: state your motors'.)
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import robot_agents as ra
from robot_agents.robots.robotiq.robotiq import Robotiq2F85

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import scripted_pick  # noqa: E402  (the solvers live beside this example)


class SixJointArm2F85(ra.Agent):
    """The six-joint arm of ``six_joint_arm.urdf`` with a Robotiq 2F-85 on its flange."""

    uid = "six_joint_arm_2f85"
    urdf_path = HERE / "six_joint_arm.urdf"
    # the arm's servos: 50 N*m, 0.02 kg*m^2 of reflected rotor inertia each (the file has neither)
    actuators = (ra.DerivedActuators(effort_limit=50.0, armature=0.02),)
    attachments = (ra.Attachment(Robotiq2F85, at="flange_roll_link", prefix="gripper_", pos=(0.0, 0.0, 0.06)),)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="envs (seeds 0 .. N-1) per task")
    parser.add_argument("--video", help="record one PickCube-v1 episode (seed 0) to this .gif / .mp4")
    args = parser.parse_args(argv)
    ra.register_agent(SixJointArm2F85, override=True)
    if args.video:
        succeeded = scripted_pick.record_episode("PickCube-v1", SixJointArm2F85.uid, 0, args.video)
        print(f"PickCube-v1 seed 0: {'success' if succeeded else 'no success'}; {args.video}")
        return 0
    modes = [m for m in SixJointArm2F85.check().modes if m.startswith("pd_ee")]
    print(f"{SixJointArm2F85.uid}: end-effector modes {', '.join(modes)}")
    for task in scripted_pick.TASKS:
        successes, seconds = scripted_pick.success_rate(task, SixJointArm2F85.uid, args.seeds)
        print(f"{task}: {successes}/{args.seeds} ({seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
