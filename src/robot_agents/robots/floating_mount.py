"""What the floating grippers' 6-DoF mounts share (``floating_panda_gripper``,
``floating_robotiq_2f_85_gripper``): three slides then three hinges named
``root_{x,y,z}_axis_joint`` / ``root_{x,y,z}_rot_joint`` (ManiSkill's names), and their
arm part. Each robot declares the mount's drives (kp 1000, kv 100 as ManiSkill's) with
its own effort limit: the mount is a fixture, not a motor, and what suits it depends on
the gripper it carries (see each robot's module).
"""

from __future__ import annotations

from pathlib import Path

from robot_agents.controllers.task_space import FloatingMountTaskSpace
from robot_agents.parts.declaration import Arm, EndEffector

#: The mount file with ManiSkill's joint names and the armature that keeps its kp 1000
#: hinges out of torque-limit cycles above 166 Hz: the Robotiq 2F-85's, which the
#: floating hands (Ability, Inspire) mount too.
MANISKILL_MOUNT_MJCF = Path(__file__).parent / "robotiq" / "assets" / "floating_mount.xml"
#: The mount's six joints (a pattern over the joint names).
MOUNT_JOINTS = "root_.*_joint"
#: The slides' travel either side of the mount's home in the built-in mounts' files (m;
#: ``range="-1 1"`` in floating_mount.xml); the task space reads it from the model.
SLIDE_TRAVEL = 1.0


def mount_arm(tcp: str) -> Arm:
    """The mount as the robot's ``arm`` part, with its end effector ``tcp`` (a site or
    body of the gripper) and both end-effector pose modes; absolute positions bounded
    by the box of every tool position the mount reaches, computed on the compiled model
    when the robot is built (:class:`~robot_agents.controllers.task_space.FloatingMountTaskSpace`:
    the slides' travel grown by the tcp's distance from the point where the hinges'
    axes meet; +-1.1034 m with the Franka Hand, +-1.1553 m with the 2F-85)."""
    return Arm(
        name="arm",
        joints=MOUNT_JOINTS,
        end_effectors=(EndEffector(tcp, name="tcp"),),
        task_space=FloatingMountTaskSpace(modes=("pd_ee_delta_pose", "pd_ee_pose")),
    )


__all__ = ["MANISKILL_MOUNT_MJCF", "MOUNT_JOINTS", "SLIDE_TRAVEL", "mount_arm"]
