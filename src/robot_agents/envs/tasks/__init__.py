"""Manipulation tasks written once against the agent interface: ``ReachPose-v1``,
``PickCube-v1``, ``PushCube-v1`` and (mobile manipulators) ``MobilePickCube-v1`` on a
table-top scene laid out from the robot's own definition (:mod:`.table_top`). See
``docs/tasks.md``."""

from __future__ import annotations

from robot_agents.envs.tasks.layout import TableTopLayout, table_top_layout
from robot_agents.envs.tasks.mobile_pick_cube import MobilePickCubeEnv
from robot_agents.envs.tasks.pick_cube import PickCubeEnv
from robot_agents.envs.tasks.push_cube import PushCubeEnv
from robot_agents.envs.tasks.reach_pose import ReachPoseEnv
from robot_agents.envs.tasks.table_top import TableTopEnv

__all__ = [
    "MobilePickCubeEnv",
    "PickCubeEnv",
    "PushCubeEnv",
    "ReachPoseEnv",
    "TableTopEnv",
    "TableTopLayout",
    "table_top_layout",
]
