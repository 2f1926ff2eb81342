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
#: The slides' travel either side of the mount's home (m; ``range="-1 1"`` in
#: floating_mount.xml).
SLIDE_TRAVEL = 1.0


def reachable_box(tool_offset: float) -> WorkspaceBox:
    """The box of every tool position the mount reaches, in its command frame (the root
    body at home, m): the slides move the hinges' common point anywhere in the cube of
    +-:data:`SLIDE_TRAVEL`, and the three hinges (each -pi..pi, together every
    orientation) turn the tool point on a sphere of radius ``tool_offset`` (m, the tool
    point's distance from that point) about it; so the reachable set is the cube grown
    by that sphere, and its box is +-(travel + offset) on every axis, each face reached
    (the cube's corner with the tool turned along the axis)."""
    half = SLIDE_TRAVEL + tool_offset
    return WorkspaceBox(lower=(-half, -half, -half), upper=(half, half, half))


def mount_arm(tcp: str, tool_offset: float) -> Arm:
    """The mount as the robot's ``arm`` part, with its end effector ``tcp`` (a site or
    body of the gripper) and both end-effector pose modes; absolute positions bounded
    by :func:`reachable_box` of ``tool_offset``, the tcp's distance (m) from the root
    body's origin, where the hinges' axes meet (tests/test_floating_mount.py checks it
    against the compiled model)."""
    return Arm(
        name="arm",
        joints=MOUNT_JOINTS,
        end_effectors=(EndEffector(tcp, name="tcp"),),
        task_space=TaskSpace(
            position_bounds=reachable_box(tool_offset),
            modes=("pd_ee_delta_pose", "pd_ee_pose"),
        ),
    )


__all__ = ["MOUNT_JOINTS", "SLIDE_TRAVEL", "mount_arm", "reachable_box"]
