"""``ReachPose-v1``: move the end effector to a goal pose.

Any robot with an end effector; the scene is laid out from the robot's definition
(:mod:`.table_top`, without a cube). The goal is a pose the tool reaches at a
configuration of the arm drawn near its default keyframe, so it is reachable by
construction: position, and orientation when the arm has at least 6 joints (a
5-joint arm cannot choose its tool's orientation freely; its goals are positions).

Randomization (each env from its own stream): the arm's joints at the default
keyframe plus uniform offsets (hinges up to 0.6 rad, slides up to ``0.25 R``),
clipped to their limits; drawn again (up to 100 times, then the keyframe's own tool
pose) while the arm would touch itself or the table there, the tool would be lower
than ``0.05 R`` above the table top, or the goal position would lie within two success
thresholds of the tool at the reset (it would start met).

Success: the tool within ``0.02 R`` of the goal position (1.9 cm for the Panda, 1 cm
for the SO-100) and, with orientation, within 0.1 rad of its orientation.

Dense reward (lengths in units of ``0.2 R``): ``1 - tanh(position error)`` plus,
with orientation, ``1 - tanh(2 * rotation error / rad)``; on success the largest
reward (3 with orientation, 2 without). ``normalized_dense`` is the dense reward
divided by it, ``sparse`` is 1 on success.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.agent.index import JointKind
from robot_agents.envs.markers import Marker, goal_sphere, pose_axes
from robot_agents.envs.tasks.layout import FloatArray, tool_arm
from robot_agents.envs.tasks.table_top import TableTopEnv
from robot_agents.errors import ConfigError
from robot_agents.kinematics.rotations import quat_to_rotvec, relative_pose, rotation_error
from robot_agents.parts.declaration import Arm

#: Largest offset of a hinge (rad) and of a slide (share of the reach) from the keyframe.
HINGE_OFFSET = 0.6
SLIDE_OFFSET = 0.25
#: Draws before falling back to the keyframe's tool pose.
MAX_DRAWS = 100
#: Success thresholds: position (share of the reach) and orientation (rad).
POSITION_THRESHOLD = 0.02
ROTATION_THRESHOLD = 0.1
#: Joints an arm needs for goals with an orientation.
ORIENTATION_DOF = 6
#: A goal is drawn again while its position lies within this many position thresholds
#: of the tool at the reset (it would start met, or nearly).
START_CLEARANCE = 2.0


class ReachPoseEnv(TableTopEnv):
    """Bring the tool to the goal pose (see the module doc)."""

    default_max_episode_steps = 100
    episode_state = ("goal_pose",)

    def _check_robot(self, cls: type[Agent]) -> None:
        if not any(isinstance(p, Arm) and p.end_effectors for p in cls.check().parts):
            raise ConfigError(f"ReachPose-v1: {cls.__name__} declares no end effector (an Arm part's end_effectors).")

    def _setup_task(self) -> None:
        agent = self.agent
        #: Goal tool pose per env (world): position (m), quaternion (w, x, y, z).
        self.goal_pose: FloatArray = agent.tcp_pose
        #: Whether goals include the tool's orientation (arms of 6 or more joints).
        self.with_orientation = self.layout.dof >= ORIENTATION_DOF
        self.max_reward = 3.0 if self.with_orientation else 2.0
        self.position_threshold = POSITION_THRESHOLD * self.layout.reach
        arm = tool_arm(agent, type(self).__name__)
        self._arm_joints = [agent.index.joint(j, "ReachPoseEnv") for j in agent.part_joints[arm.name]]
        self._scratch = mujoco.MjData(self.model)
        robot_bodies = {b for b in range(self.model.nbody) if self.model.body(b).name.startswith(agent.prefix)}
        table = self.model.body("table").id
        self._watched = robot_bodies | {table}
        self._robot_bodies = robot_bodies

    def _draw_goal(self, rng: np.random.Generator, rest: FloatArray, env: int) -> FloatArray:
        """One reachable goal pose of env ``env`` (see the module doc)."""
        agent, layout = self.agent, self.layout
        base = np.array(self.scene.world.qpos[env], dtype=np.float64)
        tool = agent.frames.end_effector(None, "ReachPoseEnv")
        start = agent.kinematics.pose(base, tool)[0, :3]  # the tool at the reset (m, world)
        base[agent.qpos_adr] = rest
        for _ in range(MAX_DRAWS):
            qpos = base.copy()
            for joint in self._arm_joints:
                if joint.kind is JointKind.HINGE:
                    offset = rng.uniform(-HINGE_OFFSET, HINGE_OFFSET)
                elif joint.kind is JointKind.SLIDE:
                    offset = rng.uniform(-SLIDE_OFFSET, SLIDE_OFFSET) * layout.reach
                else:
                    continue
                value = qpos[joint.qpos_adr] + offset
                if joint.limited:
                    value = min(max(value, joint.range[0]), joint.range[1])
                qpos[joint.qpos_adr] = value
            pose: FloatArray = agent.kinematics.pose(qpos, tool)[0]
            if (
                pose[2] >= layout.table_height + 0.05 * layout.reach
                and np.linalg.norm(pose[:3] - start) > START_CLEARANCE * self.position_threshold
                and not self._collides(qpos)
            ):
                return pose
        fallback: FloatArray = agent.kinematics.pose(base, tool)[0]
        return fallback

    def _collides(self, qpos: FloatArray) -> bool:
        """Whether the robot touches itself or the table at scene configuration ``qpos``."""
        model, data = self.model, self._scratch
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        for i in range(data.ncon):
            contact = data.contact[i]
            if contact.dist > -1e-3:
                continue
            bodies = {int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])}
            if bodies & self._robot_bodies and bodies <= self._watched:
                return True
        return False

    def _initialize_episode(self, env_ids: npt.NDArray[np.int64]) -> None:
        rest = self.agent.keyframe_qpos(self.agent.keyframe_names()[0])
        for env in env_ids:
            self.goal_pose[env] = self._draw_goal(self.env_rng(int(env)), rest, int(env))

    def _render_markers(self, env: int) -> Sequence[Marker]:
        """The goal region around the goal position and, for orientation goals, the
        goal's axes (x red, y green, z blue; four thresholds long)."""
        goal = self.goal_pose[env]
        markers = [goal_sphere(goal[:3], self.position_threshold)]
        if self.with_orientation:
            markers += pose_axes(goal, 4.0 * self.position_threshold, self.position_threshold / 8.0)
        return markers

    # -- metrics, reward, observations ---------------------------------------------------
    def errors(self) -> tuple[FloatArray, FloatArray]:
        """Per env: the tool's distance to the goal (m) and its rotation error (rad)."""
        tcp = self.agent.tcp_pose
        position = np.linalg.norm(self.goal_pose[:, :3] - tcp[:, :3], axis=1)
        rotation = np.linalg.norm(rotation_error(self.goal_pose[:, 3:], tcp[:, 3:]), axis=1)
        return position, rotation

    def evaluate(self) -> dict[str, Any]:
        position, rotation = self.errors()
        success = position <= self.position_threshold
        if self.with_orientation:
            success &= rotation <= ROTATION_THRESHOLD
        return {"success": success, "position_error": position, "rotation_error": rotation}

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        reward = 1.0 - np.tanh(info["position_error"] / self.length_scale)
        if self.with_orientation:
            reward += 1.0 - np.tanh(2.0 * info["rotation_error"])
        return self.reward(reward, info["success"])

    def _extra_obs(self) -> dict[str, FloatArray]:
        tcp = self.agent.tcp_pose
        obs = {"goal_pose": self.goal_pose.copy(), "tcp_to_goal_pos": self.goal_pose[:, :3] - tcp[:, :3]}
        if self.with_orientation:  # the turn from the tool to the goal, in the tool's axes
            obs["goal_rotvec_in_tcp"] = quat_to_rotvec(relative_pose(self.goal_pose, tcp)[:, 3:])
        return obs
