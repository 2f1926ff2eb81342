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

Dense reward: ``1 - tanh(|tcp - cube|)`` (lengths in ``0.2 R``; it rises as the base
comes closer, from about 1e-4 at the start: Stretch, seed 0, 1.2-1.4 m), ``+ 1`` while
grasped, ``+ min(lift / 5 cm, 1)`` while grasped; 3 on success. ``normalized_dense``
divides by 3, ``sparse`` is 1 on success.
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
        return {"success": grasped & (lift >= LIFT_HEIGHT), "is_grasped": grasped, "lift": lift}

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        cube = self.body_pose("cube")[:, :3]
        tcp = self.agent.tcp_pose[:, :3]
        grasped = info["is_grasped"].astype(np.float64)
        reward = 1.0 - np.tanh(np.linalg.norm(tcp - cube, axis=1) / self.length_scale)
        reward += grasped * (1.0 + np.clip(info["lift"] / LIFT_HEIGHT, 0.0, 1.0))
        return self.reward(reward, info["success"])

    def _extra_obs(self) -> dict[str, FloatArray]:
        obs: dict[str, FloatArray] = {"is_grasped": self.agent.is_grasping("cube").astype(np.float64)}
        if self.privileged_obs:
            cube = self.body_pose("cube")
            obs.update(obj_pose=cube, tcp_to_obj_pos=cube[:, :3] - self.agent.tcp_pose[:, :3])
        return obs
