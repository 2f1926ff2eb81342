"""``PickCube-v1``: pick a cube up from the table and hold it at a goal in the air.

Any robot with an end effector and a Gripper (or Hand) part with fingers; the scene
is laid out from the robot's definition (:mod:`.table_top`). ManiSkill's PickCube,
with every length scaled by the robot's reach ``R`` and the cube by its gripper.

Randomization (each env from its own stream, :meth:`RobotEnv.env_rng`): the cube's
centre uniformly within ``0.1 R`` of the workspace centre on the table, turned
uniformly about z, drawn again while it would touch the robot
(:meth:`TableTopEnv.draw_cube_pose`); the goal's x, y uniform within ``0.1 R``, its
height above the resting cube's centre uniform in ``[0, 0.2 R]`` (``GOAL_HEIGHT``),
drawn again while it lies within twice the success threshold of the cube (at most 100
times, then :class:`ConfigError`: a goal region the threshold fills).

Success: the cube's centre within ``1.25`` half-edges of the goal (2.5 cm for the
Panda's 4 cm cube) and the arm still (every arm joint slower than 0.2 rad/s or m/s).

Dense reward (ManiSkill's, lengths in units of ``0.2 R``): ``1 - tanh(|tcp - cube|)``
for reaching, ``+ 1`` while grasped, ``+ (1 - tanh(|cube - goal|))`` while grasped,
``+ (1 - tanh(5 s/rad * |arm qvel|))`` once the cube is at the goal (ManiSkill's
factor: joint speeds are not lengths); 5 on success. ``dense``
lies in ``[0, 5]``, ``normalized_dense`` is it divided by 5, ``sparse`` is 1 on
success and 0 otherwise.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.envs.markers import Marker, goal_sphere
from robot_agents.envs.tasks.layout import FloatArray
from robot_agents.envs.tasks.table_top import SPAWN_DRAWS, TableTopEnv, cube_prop
from robot_agents.errors import ConfigError
from robot_agents.model.scene import Prop
from robot_agents.parts.declaration import Arm, Gripper

#: The goal's height range above the resting cube, as a share of the reach.
GOAL_HEIGHT = 0.2
#: Success threshold in half-edges of the cube.
GOAL_THRESHOLD = 1.25
#: Joint speed below which the arm counts as still (rad/s or m/s).
STATIC_SPEED = 0.2
#: The static reward's factor on the arm's joint speed (s/rad): ManiSkill's
#: ``1 - tanh(5 * |qvel|)``, kept as it is since a speed is not a length.
STATIC_REWARD_GAIN = 5.0


def needs_gripper(cls: type[Agent], task: str) -> None:
    """Raise unless ``cls`` has an end effector and a gripper with two fingers."""
    parts = cls.check().parts
    if not any(isinstance(p, Arm) and p.end_effectors for p in parts):
        raise ConfigError(f"{task}: {cls.__name__} declares no end effector (an Arm part's end_effectors).")
    if not any(isinstance(p, Gripper) and len(p.finger_links) >= 2 for p in parts):
        raise ConfigError(f"{task}: {cls.__name__} declares no Gripper or Hand part with fingers; {task} grasps.")


class PickCubeEnv(TableTopEnv):
    """Pick the cube and hold it still at the goal (see the module doc)."""

    default_max_episode_steps = 100
    episode_state = ("goal_pos",)
    max_reward = 5.0

    def _check_robot(self, cls: type[Agent]) -> None:
        needs_gripper(cls, "PickCube-v1")

    def _task_props(self) -> list[Prop]:
        return [cube_prop("cube", self.layout, (0.85, 0.15, 0.12, 1.0))]

    def _setup_task(self) -> None:
        half = self.layout.cube_half_size
        #: Goal position of the cube's centre per env (m, world).
        self.goal_pos: FloatArray = np.tile(self.layout.center + np.array([0.0, 0.0, half]), (self.num_envs, 1))
        self.goal_threshold = GOAL_THRESHOLD * half

    def _initialize_episode(self, env_ids: npt.NDArray[np.int64]) -> None:
        layout = self.layout
        s, half, h = layout.spawn_half_size, layout.cube_half_size, layout.table_height
        poses = np.empty((len(env_ids), 7))
        for row, env in enumerate(env_ids):
            rng = self.env_rng(int(env))
            poses[row] = self.draw_cube_pose(int(env))
            cube = poses[row, :3]
            for _ in range(SPAWN_DRAWS):
                goal = np.array([*rng.uniform(-s, s, 2), h + half + rng.uniform(0.0, GOAL_HEIGHT * layout.reach)])
                if np.linalg.norm(goal - cube) > 2.0 * self.goal_threshold:
                    break
            else:
                raise ConfigError(
                    f"{type(self).__name__}.reset: {SPAWN_DRAWS} goals drawn in env {env} all lie within "
                    f"{2.0 * self.goal_threshold:.4f} m (twice the success threshold) of the cube at {cube.round(4)}; "
                    f"expected a goal region (within {s:.4f} m of the workspace centre, up to "
                    f"{GOAL_HEIGHT * layout.reach:.4f} m above the resting cube) larger than the threshold."
                )
            self.goal_pos[env] = goal
        self.place_body("cube", poses, env_ids)

    def _render_markers(self, env: int) -> Sequence[Marker]:
        """The goal region: where the cube's centre must be for a success."""
        return (goal_sphere(self.goal_pos[env], self.goal_threshold),)

    # -- metrics, reward, observations ---------------------------------------------------
    def evaluate(self) -> dict[str, Any]:
        cube = self.body_pose("cube")[:, :3]
        distance = np.linalg.norm(self.goal_pos - cube, axis=1)
        placed = distance <= self.goal_threshold
        static = self.arm_speed() <= STATIC_SPEED
        return {
            "success": placed & static,
            "is_obj_placed": placed,
            "is_robot_static": static,
            "is_grasped": self.agent.is_grasping("cube"),
            "obj_to_goal_dist": distance,
        }

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        cube = self.body_pose("cube")[:, :3]
        tcp = self.agent.tcp_pose[:, :3]
        grasped = info["is_grasped"].astype(np.float64)
        reward = 1.0 - np.tanh(np.linalg.norm(tcp - cube, axis=1) / self.length_scale)
        reward += grasped
        reward += (1.0 - np.tanh(info["obj_to_goal_dist"] / self.length_scale)) * grasped
        speed = np.linalg.norm(self.agent.qvel[:, self.arm_dofs], axis=1)
        reward += (1.0 - np.tanh(STATIC_REWARD_GAIN * speed)) * info["is_obj_placed"]
        return self.reward(reward, info["success"])

    def _extra_obs(self) -> dict[str, FloatArray]:
        obs: dict[str, FloatArray] = {
            "goal_pos": self.goal_pos.copy(),
            "is_grasped": self.agent.is_grasping("cube").astype(np.float64),
        }
        if self.privileged_obs:
            cube = self.body_pose("cube")
            tcp = self.agent.tcp_pose[:, :3]
            obs.update(
                obj_pose=cube,
                tcp_to_obj_pos=cube[:, :3] - tcp,
                obj_to_goal_pos=self.goal_pos - cube[:, :3],
            )
        return obs
