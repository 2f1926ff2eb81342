"""``PushCube-v1``: push a cube across the table into a goal region.

Any robot with an end effector (a gripper is not needed); the scene is laid out from
the robot's definition (:mod:`.table_top`). ManiSkill's PushCube, with every length
scaled by the robot's reach ``R`` (the cube by its gripper, if it has one).

Randomization (each env from its own stream): the cube's centre uniformly within
``0.1 R`` of the workspace centre on the table, turned uniformly about z, drawn again
while it would touch the robot (:meth:`TableTopEnv.draw_cube_pose`); the goal
region, a disc of radius ``0.1 R`` on the table, centred ``[0.15 R, 0.25 R]`` ahead of
the cube (away from the robot, world +x) and up to ``0.05 R`` to either side.

Success: the cube's centre within the goal disc (distance in x, y) while it rests on
the table (its centre less than an eighth of its edge above its resting height).

Dense reward (ManiSkill's, lengths in units of ``0.2 R``): ``1 - tanh(|tcp - push
point|)``, the push point being behind the cube (half an edge and an eighth more, on
the far side from the goal); ``+ (1 - tanh(|cube - goal|))`` (in x, y) once the tool
is within a quarter edge of the push point; 3 on success. ``dense`` lies in
``[0, 3]``, ``normalized_dense`` is it divided by 3, ``sparse`` is 1 on success.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.envs.markers import Marker, goal_disc
from robot_agents.envs.tasks.layout import FloatArray
from robot_agents.envs.tasks.table_top import TableTopEnv, cube_prop
from robot_agents.errors import ConfigError
from robot_agents.model.scene import Prop
from robot_agents.parts.declaration import Arm

#: Radius of the goal disc, as a share of the reach.
GOAL_RADIUS = 0.1
#: The goal's distance ahead of the cube, and to either side, as shares of the reach.
GOAL_AHEAD = (0.15, 0.25)
GOAL_ASIDE = 0.05


class PushCubeEnv(TableTopEnv):
    """Push the cube into the goal disc (see the module doc)."""

    default_max_episode_steps = 100
    episode_state = ("goal_pos",)
    max_reward = 3.0

    def _check_robot(self, cls: type[Agent]) -> None:
        if not any(isinstance(p, Arm) and p.end_effectors for p in cls.check().parts):
            raise ConfigError(f"PushCube-v1: {cls.__name__} declares no end effector (an Arm part's end_effectors).")

    def _task_props(self) -> list[Prop]:
        return [cube_prop("cube", self.layout, (0.15, 0.35, 0.85, 1.0))]

    def _setup_task(self) -> None:
        #: Centre of the goal disc per env (m, world; on the table top).
        self.goal_pos: FloatArray = np.tile(self.layout.center, (self.num_envs, 1))
        self.goal_radius = GOAL_RADIUS * self.layout.reach

    def _initialize_episode(self, env_ids: npt.NDArray[np.int64]) -> None:
        layout = self.layout
        h, r = layout.table_height, layout.reach
        poses = np.empty((len(env_ids), 7))
        for row, env in enumerate(env_ids):
            rng = self.env_rng(int(env))
            poses[row] = self.draw_cube_pose(int(env))
            cube = poses[row, :3]
            offset = np.array([rng.uniform(*GOAL_AHEAD) * r, rng.uniform(-GOAL_ASIDE, GOAL_ASIDE) * r, 0.0])
            self.goal_pos[env] = np.array([cube[0], cube[1], h]) + offset
        self.place_body("cube", poses, env_ids)

    def push_point(self) -> FloatArray:
        """Where the tool should be to push the cube towards the goal ``(num_envs, 3)``."""
        half = self.layout.cube_half_size
        cube = self.body_pose("cube")[:, :3]
        direction = self.goal_pos[:, :2] - cube[:, :2]
        direction /= np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-9)
        point: FloatArray = cube.copy()
        point[:, :2] -= direction * (half + 0.25 * half)
        return point

    def _render_markers(self, env: int) -> Sequence[Marker]:
        """The goal disc, lying on the table top (1 mm above it, so the table does not hide it)."""
        return (goal_disc(self.goal_pos[env] + np.array([0.0, 0.0, 0.001]), self.goal_radius),)

    def evaluate(self) -> dict[str, Any]:
        cube = self.body_pose("cube")[:, :3]
        half = self.layout.cube_half_size
        distance = np.linalg.norm(self.goal_pos[:, :2] - cube[:, :2], axis=1)
        on_table = cube[:, 2] < self.layout.table_height + half + 0.25 * half
        return {"success": (distance < self.goal_radius) & on_table, "obj_to_goal_dist": distance}

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        tcp = self.agent.tcp_pose[:, :3]
        to_push = np.linalg.norm(self.push_point() - tcp, axis=1)
        reward = 1.0 - np.tanh(to_push / self.length_scale)
        reached = to_push < 0.5 * self.layout.cube_half_size
        reward += (1.0 - np.tanh(info["obj_to_goal_dist"] / self.length_scale)) * reached
        return self.reward(reward, info["success"])

    def _extra_obs(self) -> dict[str, FloatArray]:
        obs: dict[str, FloatArray] = {"goal_pos": self.goal_pos.copy()}
        if self.privileged_obs:
            cube = self.body_pose("cube")
            obs.update(obj_pose=cube, tcp_to_obj_pos=cube[:, :3] - self.agent.tcp_pose[:, :3])
        return obs
