"""The table-top scene every manipulation task shares: the table, cubes and the task
camera placed by the robot's layout (:mod:`robot_agents.envs.tasks.layout`), and
:class:`TableTopEnv`, the env the tasks build on."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.envs.base_env import RobotEnv
from robot_agents.envs.tasks.layout import (
    CUBE_DENSITY,
    FloatArray,
    TableTopLayout,
    robot_class,
    table_top_layout,
    tool_arm,
)
from robot_agents.errors import ConfigError, did_you_mean
from robot_agents.kinematics.rotations import yaw_to_quat
from robot_agents.model.materials import FrictionMaterial
from robot_agents.model.scene import Prop
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sim.scene import RobotSpecifier

#: Draws of a prop's pose per env before a reset gives up: the robot blocks the region.
SPAWN_DRAWS = 100

IntArray = npt.NDArray[np.int64]


def cube_prop(name: str, layout: TableTopLayout, rgba: tuple[float, float, float, float]) -> Prop:
    """A free cube of ``CUBE_DENSITY`` on the table at the workspace centre (a reset
    places it)."""
    half_size = layout.cube_half_size
    return free_cube(name, half_size, rgba, pos=(0.0, 0.0, layout.table_height + half_size))


def free_cube(
    name: str,
    half_size: float,
    rgba: tuple[float, float, float, float],
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> Prop:
    """A free cube of ``CUBE_DENSITY`` (edge ``2 * half_size``, m) with the tasks' cube
    material, at ``pos`` (m)."""
    return Prop(
        name,
        "box",
        (half_size,) * 3,
        pos=pos,
        mass=CUBE_DENSITY * (2.0 * half_size) ** 3,
        rgba=rgba,
        friction=FrictionMaterial(sliding=1.0, torsional=0.005, rolling=0.0001),
    )


def table_prop(layout: TableTopLayout) -> Prop:
    """The table: a static box from the floor to the table top."""
    return Prop(
        "table",
        "box",
        layout.table_half_size,
        pos=layout.table_center,
        mass=None,
        rgba=(0.62, 0.5, 0.38, 1.0),
    )


def base_camera(layout: TableTopLayout) -> CameraConfig:
    """A 128 x 128, 90 deg task camera in front of the workspace looking back at the
    robot and the table (ManiSkill's PickCube camera, scaled by the reach)."""
    r, h = layout.reach, layout.table_height
    return CameraConfig.look_at(
        "base_camera",
        eye=(0.32 * r, 0.0, h + 0.63 * r),
        target=(-0.1 * r, 0.0, h + 0.1 * r),
        fovy=90.0,
        far=10.0 * r,
    )


class TableTopEnv(RobotEnv):
    """A robot on a table (see the module doc for the layout). One robot; its pose
    comes from :func:`table_top_layout` unless ``robot_poses`` is given.

    Task modules add their props (:meth:`_task_props`), randomize them in
    :meth:`_initialize_episode`, and report metrics, rewards and observations.

    Args:
        reward_mode: ``"normalized_dense"`` (default, in ``[0, 1]``), ``"dense"``
            (in ``[0, max_reward]``) or ``"sparse"`` (1.0 on success, else 0.0).
        **kwargs: see :class:`~robot_agents.envs.RobotEnv`.
    """

    reward_modes = ("normalized_dense", "dense", "sparse")
    #: The largest dense reward (what a success earns).
    max_reward: float = 1.0

    def __init__(
        self,
        robot_uids: RobotSpecifier | Sequence[RobotSpecifier] = "panda",
        num_envs: int = 1,
        reward_mode: str = "normalized_dense",
        **kwargs: Any,
    ) -> None:
        name = type(self).__name__
        if reward_mode not in self.reward_modes:
            raise ConfigError(
                f"{name}: expected reward_mode in {list(self.reward_modes)}, got {reward_mode!r}."
                + did_you_mean(reward_mode, self.reward_modes)
            )
        self.reward_mode = reward_mode
        cls = robot_class(robot_uids, name)
        self._check_robot(cls)
        self.layout = table_top_layout(cls)
        if kwargs.get("robot_poses") is None:
            kwargs["robot_poses"] = [self.layout.robot_pose]
        kwargs.setdefault("sleep", True)  # props at rest sleep (docs/tasks.md)
        self._task_ready = False
        super().__init__(robot_uids=cls, num_envs=num_envs, **kwargs)

    # -- hooks for the tasks --------------------------------------------------------------
    def _check_robot(self, cls: type[Agent]) -> None:
        """Raise :class:`ConfigError` when the robot lacks a part the task needs."""

    def _task_props(self) -> list[Prop]:
        return []

    def _setup_task(self) -> None:
        """After the scene is built (before the observation space is): the task's
        bodies and per-env state."""

    def _build_observation_space(self) -> Any:
        if not self._task_ready:
            arm = tool_arm(self.agent, type(self).__name__)
            joints = [self.agent.index.joint(j, type(self).__name__) for j in self.agent.part_joints[arm.name]]
            #: The arm's entries in the robot's ``qvel`` (the joints that carry the tool).
            self.arm_dofs = np.array([j.dof_start + k for j in joints for k in range(j.nv)], dtype=np.int64)
            #: Distances in rewards are measured in this unit: 0.2 R (0.19 m for the Panda).
            self.length_scale = 0.2 * self.layout.reach
            self._setup_task()
            self._task_ready = True
        return super()._build_observation_space()

    def arm_speed(self) -> FloatArray:
        """Per env, the fastest arm joint's speed (rad/s or m/s)."""
        speed: FloatArray = np.max(np.abs(self.agent.qvel[:, self.arm_dofs]), axis=1)
        return speed

    @property
    def privileged_obs(self) -> bool:
        """State observation modes see object poses; camera modes see only the goal."""
        return self._sensor_obs is None

    # -- scene --------------------------------------------------------------------------
    def _scene_props(self) -> Sequence[Prop]:
        return [table_prop(self.layout), *self._task_props()]

    def _scene_cameras(self) -> Sequence[CameraConfig]:
        return (base_camera(self.layout),)

    def _render_bounds(self, env: int = 0) -> tuple[FloatArray, FloatArray]:
        layout = self.layout
        # a robot on a pedestal: the arm over its table, not the pedestal under them
        lower, upper = self._robots_extent(env, above=layout.table_height if layout.pedestal else -np.inf)
        s = layout.spawn_half_size * 2.0
        box = np.array([[-s, -s, layout.table_height], [s, s, layout.table_height + s]])
        return np.minimum(lower, box[0]), np.maximum(upper, box[1])

    # -- helpers ------------------------------------------------------------------------
    def free_body(self, name: str) -> tuple[int, IntArray, IntArray]:
        """A free prop's body id and the model addresses of its joint's qpos (7) and qvel (6)."""
        model = self.model
        body = model.body(name)
        joint = int(body.jntadr[0])
        qpos = np.arange(7, dtype=np.int64) + int(model.jnt_qposadr[joint])
        qvel = np.arange(6, dtype=np.int64) + int(model.jnt_dofadr[joint])
        return int(body.id), qpos, qvel

    def place_body(self, name: str, poses: npt.ArrayLike, env_ids: npt.ArrayLike | None = None) -> None:
        """Put free prop ``name`` at world ``poses`` ``(k, 7)`` at rest in ``env_ids``
        (default: every env)."""
        ids = np.arange(self.num_envs) if env_ids is None else np.asarray(env_ids, dtype=np.int64).reshape(-1)
        rows = np.asarray(poses, dtype=np.float64).reshape(len(ids), 7)
        _, qpos_adr, qvel_adr = self.free_body(name)
        self.scene.world.write_joint_state(ids, qpos_adr, rows, qvel_adr, np.zeros((len(ids), 6)))

    def draw_clear_pose(
        self, name: str, env: int, draw: Callable[[np.random.Generator], npt.ArrayLike], region: str = ""
    ) -> FloatArray:
        """A world pose ``(7,)`` of free prop ``name`` in env ``env``, from ``draw(rng)``
        on the env's stream, drawn again while the prop there would overlap a robot at
        its pose in the env now (a contact with a robot geom at a distance below 0);
        after :data:`SPAWN_DRAWS` draws, :class:`ConfigError` (``region`` says where the
        prop is drawn). Nothing is written: the task places the pose (:meth:`place_body`)."""
        body, qpos_adr, _ = self.free_body(name)
        clearance = self.clearance
        clearance.load(self.scene.world.physics_sources([env])[0])
        rng = self.env_rng(env)
        for _ in range(SPAWN_DRAWS):
            pose = np.asarray(draw(rng), dtype=np.float64).reshape(7)
            if clearance.body_clear_of_robots(body, qpos_adr, pose):
                return pose
        where = f" {region}" if region else ""
        raise ConfigError(
            f"{type(self).__name__}.reset: {SPAWN_DRAWS} poses of {name!r} drawn{where} in env {env} all overlap "
            f"the robot at its reset pose; expected a spawn region the robot leaves free (check robot_poses "
            f"and the reset keyframe)."
        )

    def draw_cube_pose(self, env: int, name: str = "cube") -> FloatArray:
        """A resting pose ``(7,)`` of cube ``name`` in env ``env``: its centre uniform over
        the spawn square (``spawn_half_size`` about the workspace centre), turned uniformly
        about z, drawn again while it would overlap the robot (:meth:`draw_clear_pose`)."""
        s, z = self.layout.spawn_half_size, self.layout.table_height + self.layout.cube_half_size

        def draw(rng: np.random.Generator) -> FloatArray:
            return np.concatenate([rng.uniform(-s, s, 2), [z], random_yaw_quats(rng, 1)[0]])

        return self.draw_clear_pose(name, env, draw, f"within {s:.4f} m of the workspace centre")

    def body_pose(self, name: str) -> FloatArray:
        """World pose ``(num_envs, 7)`` of a scene body."""
        return self.scene.body_pose(name)

    def reward(self, dense: FloatArray, success: npt.NDArray[np.bool_]) -> FloatArray:
        """The reward of the env's ``reward_mode`` from the dense reward and success."""
        if self.reward_mode == "sparse":
            return success.astype(np.float64)
        dense = np.where(success, self.max_reward, dense)
        if self.reward_mode == "dense":
            return dense
        return dense / self.max_reward


def random_yaw_quats(rng: np.random.Generator, count: int) -> FloatArray:
    """``count`` rotations about z, uniform over a quarter turn (a cube's symmetry)."""
    return yaw_to_quat(rng.uniform(-math.pi / 4, math.pi / 4, count))
