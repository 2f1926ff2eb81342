"""``MobilePickCube-v1``: drive a mobile manipulator to a table and pick a cube up.

Any robot with a ``Base`` part, an end effector and a Gripper (or Hand) part with
fingers. The table and the cube are PickCube's, laid out by the table-top rule for
mobile robots (:mod:`.table_top`): the robot's *stance* (``layout.robot_pose``) is where
it stands to work at the table, on the floor, facing it. Episodes start away from it.

Randomization (each env from its own stream, :meth:`RobotEnv.env_rng`): the cube as in
PickCube (centre uniformly within ``0.1 R`` of the workspace centre, turned uniformly
about z, drawn again while it would touch the robot standing at its stance); the base
``1.0 .. 1.5 m`` from the stance, in a direction up to 45 deg either side of straight
away from the table, turned up to 45 deg either way from the stance's heading (the arm
at its default keyframe).

Success: the cube grasped (``agent.is_grasping``) with its centre at least 5 cm above
where it rested on the table.

Dense reward: reaching, ``0.5 * (1 - tanh(far / R))`` (``far``: how much farther the
base's ground point lies from the cube, horizontally, than ``work_distance``, the
stance's distance to the workspace centre plus ``0.3 R``; it rises while the base drives
closer and is 0.5 once the base is that near) ``+ 0.5 * (1 - tanh(|tcp - cube| / 0.2
R))`` (PickCube's term: it rises as the tool closes in); ``+ 1`` while grasped, ``+
min(lift / 5 cm, 1)`` while grasped; 3 on success. ``dense`` lies in ``[0, 3]``,
``normalized_dense`` divides by 3, ``sparse`` is 1 on success. (Before 2026-11-29 the
reaching term was the tool's alone: 1e-6 to 1e-4 of the normalized reward at the
start, the tool 1.1-1.9 m from the cube, with next to no gain from driving.)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.envs.tasks.layout import FloatArray
from robot_agents.envs.tasks.pick_cube import needs_gripper
from robot_agents.envs.tasks.table_top import TableTopEnv, cube_prop
from robot_agents.errors import ConfigError
from robot_agents.kinematics.rotations import z_rotation_angle
from robot_agents.model.scene import Prop
from robot_agents.parts.declaration import Base

#: How far from its stance the base starts (m).
START_DISTANCE = (1.0, 1.5)
#: The start lies this far either side of straight away from the table (rad)...
START_BEARING = math.pi / 4
#: ... and the base is turned up to this far either way from the stance's heading (rad).
START_TURN = math.pi / 4
#: How high above its resting height the cube must be for a success (m).
LIFT_HEIGHT = 0.05
#: The reaching reward's share for the base coming within working distance of the cube;
#: the rest is the tool's (PickCube's term).
BASE_REACH_SHARE = 0.5
#: The base works within the stance's distance to the workspace centre plus this share
#: of the reach from the cube (horizontally): the spawn square's half-diagonal (0.14 R)
#: and room to stand back from the table.
WORK_MARGIN = 0.3


def reaching_reward(
    base_to_cube: FloatArray,
    work_distance: float,
    reach: float,
    tcp_to_cube: FloatArray,
    length_scale: float,
) -> FloatArray:
    """MobilePickCube's reaching term, in ``[0, 1]`` per env: ``BASE_REACH_SHARE`` for
    the base's horizontal distance to the cube beyond ``work_distance`` (``1 - tanh`` of
    it in units of ``reach``: full once within), the rest for the tool's distance to the
    cube (``1 - tanh`` of it in units of ``length_scale``). Distances in m."""
    far = np.maximum(base_to_cube - work_distance, 0.0) / reach
    base_term = 1.0 - np.tanh(far)
    tool_term = 1.0 - np.tanh(tcp_to_cube / length_scale)
    term: FloatArray = BASE_REACH_SHARE * base_term + (1.0 - BASE_REACH_SHARE) * tool_term
    return term


class MobilePickCubeEnv(TableTopEnv):
    """Drive to the table and lift the cube 5 cm (see the module doc)."""

    default_max_episode_steps = 500
    max_reward = 3.0

    def _check_robot(self, cls: type[Agent]) -> None:
        needs_gripper(cls, "MobilePickCube-v1")
        if not any(isinstance(p, Base) for p in cls.check().parts):
            raise ConfigError(f"MobilePickCube-v1: {cls.__name__} declares no Base part; the task drives to the table.")

    def _task_props(self) -> list[Prop]:
        return [cube_prop("cube", self.layout, (0.85, 0.15, 0.12, 1.0))]

    def _setup_task(self) -> None:
        pose = self.layout.robot_pose
        #: Where the base stands to work at the table: ground point (x, y) and yaw.
        self.stance_xy = np.array(pose[:2])
        self.stance_yaw = z_rotation_angle(pose[3:])
        #: The base works within this horizontal distance of the cube (m): the stance's
        #: distance to the workspace centre plus ``WORK_MARGIN * R`` (the reaching reward).
        self.work_distance = float(np.linalg.norm(self.layout.center[:2] - self.stance_xy)) + WORK_MARGIN * (
            self.layout.reach
        )
        #: Resting height of the cube's centre (m).
        self.cube_rest_z = self.layout.table_height + self.layout.cube_half_size

    def _initialize_episode(self, env_ids: npt.NDArray[np.int64]) -> None:
        cubes, starts, yaws = np.empty((len(env_ids), 7)), np.empty((len(env_ids), 2)), np.empty(len(env_ids))
        for row, env in enumerate(env_ids):
            rng = self.env_rng(int(env))
            cubes[row] = self.draw_cube_pose(int(env))  # clear of the robot at its stance
            distance = rng.uniform(*START_DISTANCE)
            bearing = math.pi + rng.uniform(-START_BEARING, START_BEARING)  # the table lies along +x
            starts[row] = self.stance_xy + distance * np.array([math.cos(bearing), math.sin(bearing)])
            yaws[row] = self.stance_yaw + rng.uniform(-START_TURN, START_TURN)
        self.place_body("cube", cubes, env_ids)
        self.agent.set_base_pose(starts, yaws, env_ids)

    # -- metrics, reward, observations ---------------------------------------------------
    def evaluate(self) -> dict[str, Any]:
        lift = self.body_pose("cube")[:, 2] - self.cube_rest_z
        grasped = self.agent.is_grasping("cube")
        base = np.linalg.norm(self.body_pose("cube")[:, :2] - self.agent.base_pos[:, :2], axis=1)
        return {
            "success": grasped & (lift >= LIFT_HEIGHT),
            "is_grasped": grasped,
            "lift": lift,
            "base_to_obj_dist": base,
        }

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        cube = self.body_pose("cube")[:, :3]
        tcp = self.agent.tcp_pose[:, :3]
        grasped = info["is_grasped"].astype(np.float64)
        reward = reaching_reward(
            info["base_to_obj_dist"],
            self.work_distance,
            self.layout.reach,
            np.linalg.norm(tcp - cube, axis=1),
            self.length_scale,
        )
        reward += grasped * (1.0 + np.clip(info["lift"] / LIFT_HEIGHT, 0.0, 1.0))
        return self.reward(reward, info["success"])

    def _extra_obs(self) -> dict[str, FloatArray]:
        obs: dict[str, FloatArray] = {"is_grasped": self.agent.is_grasping("cube").astype(np.float64)}
        if self.privileged_obs:
            cube = self.body_pose("cube")
            obs.update(obj_pose=cube, tcp_to_obj_pos=cube[:, :3] - self.agent.tcp_pose[:, :3])
        return obs
