"""What the floating grippers' 6-DoF mounts share (``floating_panda_gripper``,
``floating_robotiq_2f_85_gripper``): three slides then three hinges named
``root_{x,y,z}_axis_joint`` / ``root_{x,y,z}_rot_joint`` (ManiSkill's names), and their
arm part. Each robot declares the mount's drives (kp 1000, kv 100 as ManiSkill's) with
its own effort limit: the mount is a fixture, not a motor, and what suits it depends on
the gripper it carries (see each robot's module).
"""

from __future__ import annotations

from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.parts.declaration import Arm, EndEffector

#: The mount's six joints (a pattern over the joint names).
MOUNT_JOINTS = "root_.*_joint"


def mount_arm(tcp: str) -> Arm:
    """The mount as the robot's ``arm`` part, with its end effector ``tcp`` (a site or
    body of the gripper) and both end-effector pose modes; absolute positions bounded
    by the slides' +-1 m range."""
    return Arm(
        name="arm",
        joints=MOUNT_JOINTS,
        end_effectors=(EndEffector(tcp, name="tcp"),),
        task_space=TaskSpace(
            position_bounds=WorkspaceBox(lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0)),
            modes=("pd_ee_delta_pose", "pd_ee_pose"),
        ),
    )


__all__ = ["MOUNT_JOINTS", "mount_arm"]
