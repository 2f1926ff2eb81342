"""The Gymnasium environment every task builds on.

Batch-first: observations, actions and states carry a leading ``num_envs`` axis.
Env-level signals follow Gymnasium's single-env contract when ``num_envs == 1``
(``reward`` a float, ``terminated`` / ``truncated`` bools, ``render()`` one
``H x W x 3`` frame) and are arrays of shape ``(num_envs,)`` (frames
``(num_envs, H, W, 3)``) otherwise.
"""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar, NoReturn

import gymnasium as gym
import mujoco
import numpy as np
import numpy.typing as npt
from gymnasium.utils import seeding

from robot_agents.agent import Agent
from robot_agents.envs import episode_checks
from robot_agents.envs.clearance import Clearance
from robot_agents.envs.markers import Marker, draw_markers
from robot_agents.envs.observations import SensorObservation, parse_obs_mode
from robot_agents.envs.single_step import StepResult, plain_single_step
from robot_agents.envs.state_obs import StateObservation
from robot_agents.envs.state_source import check_source, state_source
from robot_agents.errors import (
    ActionError,
    ConfigError,
    PhysicsError,
    StateError,
    UnknownNameError,
)
from robot_agents.model.scene import Prop
from robot_agents.sensors.camera import MAX_SIZE, CameraConfig, is_pixel_count
from robot_agents.sensors.framing import framed_camera, framing_camera, robot_bounds
from robot_agents.sensors.overrides import SensorOverrides
from robot_agents.sensors.renderer import make_renderer
from robot_agents.sensors.segmentation import SegmentationEntry
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, ENV_STATE_KEYS, SCENE_STATE_KEYS, RobotSpecifier, Scene
from robot_agents.validation import check_bool, check_open, check_real, check_state_keys, is_whole

FloatArray = npt.NDArray[np.float64]

#: Draws of a robot's reset noise per env before the noiseless keyframe is kept instead.
RESET_NOISE_DRAWS = 32
#: The keys ``reset(options=...)`` takes.
RESET_OPTIONS = ("env_ids", "keyframe")
#: How much deeper (m) than at its noiseless keyframe the noise may put a robot geom
#: into a fixed geom (floor, table, static props) or another robot geom.
RESET_PENETRATION_TOLERANCE = 1e-3


def task_keywords(cls: type[RobotEnv]) -> list[str]:
    """The keyword arguments task class ``cls`` accepts: those of its ``__init__`` and,
    while an ``__init__`` forwards ``**kwargs``, of its base classes' up to
    :class:`RobotEnv` (whose ``**unknown`` only reports misspellings)."""
    names: list[str] = []
    for klass in cls.__mro__:
        if "__init__" not in vars(klass):
            continue
        parameters = inspect.signature(vars(klass)["__init__"]).parameters.values()
        names += [
            p.name
            for p in parameters
            if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name != "self" and p.name not in names
        ]
        if klass is RobotEnv or not any(p.kind is p.VAR_KEYWORD for p in parameters):
            break
    return names


def check_render_size(size: Any, where: str) -> tuple[int, int]:
    """``render_size`` ``(width, height)`` as two whole numbers of pixels in ``[1,
    MAX_SIZE]`` (the rule camera sizes follow); raises :class:`ConfigError`."""
    valid = isinstance(size, (tuple, list, np.ndarray)) and len(size) == 2 and all(is_pixel_count(v) for v in size)
    if not valid:
        raise ConfigError(
            f"{where}: expected render_size to be (width, height), integer numbers of pixels in [1, {MAX_SIZE}], "
            f"got {size!r}."
        )
    return int(size[0]), int(size[1])


def check_max_episode_steps(steps: object, where: str) -> None:
    """:class:`ConfigError` (naming ``where``) unless ``steps`` is a whole number >= 1,
    ``-1`` (the task's default) or ``None`` (never truncate)."""
    if steps is not None and not is_whole(steps):
        raise ConfigError(f"{where}: expected max_episode_steps to be an int or None, got {steps!r}.")
    if steps is not None and steps != -1 and steps < 1:  # type: ignore[operator]
        raise ConfigError(f"{where}: expected max_episode_steps >= 1, got {steps!r}.")


class RobotEnv(gym.Env[Any, Any]):
    """A task with one or more robots in a :class:`~robot_agents.sim.Scene`.

    Args:
        robot_uids: a robot uid, a model file path, ``module:Class`` (as the command
            line reads them: :func:`~robot_agents.robot_source.resolve_robot`) or an
            Agent class, or a tuple of them for several robots.
        num_envs: parallel copies (``>= 1``).
        control_mode: a mode name for every robot, or one per robot; default: each
            robot's default mode.
        obs_mode: ``"state"`` (flat float32 array ``(num_envs, D)``), ``"state_dict"``, or
            a camera mode: ``"sensor_data"``, ``"rgb"``, ``"depth"``, ``"rgbd"``,
            ``"segmentation"``, ``"pointcloud"`` (see ``docs/sensors.md``).
        sim_freq / control_freq: physics / control rates in Hz; ``sim_freq=None``: the
            robots' declared default step (``AgentDefinition.sim_freq``), else 500 Hz.
        render_mode: ``None`` or ``"rgb_array"`` (offscreen scene camera).
        render_size: ``(width, height)`` of rendered frames in pixels, each in ``[1,
            8192]`` (the offscreen framebuffer is enlarged to hold them).
        max_episode_steps: episodes are truncated after this many steps (``None``: never;
            ``-1``: the task's default, :attr:`default_max_episode_steps`).
        robot_init_qpos_noise: std-dev (rad / m) of Gaussian noise added to the reset
            keyframe, drawn from the env's seeded RNG; drawn again (up to
            :data:`RESET_NOISE_DRAWS` times, then the keyframe) while it puts a robot
            geom more than 1 mm deeper into the fixed scene (floor, table) or a robot
            than the keyframe does.
        num_threads: stepping threads for ``num_envs > 1``.
        robot_poses: world pose ``(x, y, z, qw, qx, qy, qz)`` of each robot's mount (m;
            a quaternion, normalized), one per robot; default: each robot's ``mount_pose``.
        raise_on_instability: raise :class:`PhysicsError` when MuJoCo resets an env
            during a step; otherwise ``info["physics_unstable"]`` reports it per env.
        sensor_configs: camera overrides by camera key, e.g.
            ``{"hand_camera": {"width": 256, "height": 256}}``, or ``{"base_camera": None}``
            to drop a camera; unknown keys and fields raise.
        base_dynamics: ``"dynamic"`` or ``"kinematic"`` for every robot with a ``Base``
            part (overrides ``Base.dynamics``; see docs/mobile-manipulators.md);
            ``None``: as declared.
        render_only_visuals: simulate the scene without its visual-only geoms (the
            same motion, a faster physics step) and draw them in renders
            (:attr:`model` is what is simulated, :attr:`render_model` what is drawn);
            ``False``: one model for both.
        sleep: MuJoCo's island sleeping for props at rest (a robot never sleeps):
            faster scenes with resting props, a different deterministic trajectory;
            :meth:`get_state` saves the sleep counters. Off by default.

    Randomness: every env has its own random stream, :meth:`env_rng`; ``reset(seed=s)``
    seeds env ``i`` with ``s + i`` (Gymnasium's rule for vector envs), so env ``i`` of a
    batch draws exactly what a single env reset with seed ``s + i`` draws. The reset
    noise of the robots and a task's randomization come from these streams.

    Subclasses override :meth:`_scene_props`, :meth:`_scene_cameras`,
    :meth:`_initialize_episode`, :meth:`compute_reward`, :meth:`evaluate`,
    :meth:`_extra_obs` and :meth:`_render_bounds`.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": DEFAULT_CONTROL_FREQ}
    default_max_episode_steps: ClassVar[int | None] = 200
    #: Names of the task's per-episode arrays (``(num_envs, ...)``, drawn at reset: a
    #: goal), saved and restored by :meth:`get_state` / :meth:`set_state`.
    episode_state: ClassVar[tuple[str, ...]] = ()

    def __init__(
        self,
        robot_uids: RobotSpecifier | Sequence[RobotSpecifier] = "panda",
        num_envs: int = 1,
        control_mode: str | Sequence[str | None] | None = None,
        obs_mode: str = "state",
        sim_freq: int | None = None,
        control_freq: int = DEFAULT_CONTROL_FREQ,
        render_mode: str | None = None,
        render_size: tuple[int, int] = (480, 360),
        max_episode_steps: int | None = -1,
        robot_init_qpos_noise: float = 0.02,
        num_threads: int | None = None,
        sensor_configs: SensorOverrides | None = None,
        robot_poses: Sequence[Sequence[float]] | None = None,
        raise_on_instability: bool = False,
        base_dynamics: str | None = None,
        render_only_visuals: bool = True,
        sleep: bool = False,
        **unknown: Any,
    ) -> None:
        if unknown:  # a misspelt keyword (gymnasium.make passes every keyword here)
            given = sorted(unknown)[0]
            raise UnknownNameError(type(self).__name__, "keyword argument", given, task_keywords(type(self)))
        if not inspect.signature(self._render_bounds).parameters:  # written for the one camera of env 0
            raise ConfigError(
                f"{type(self).__name__}._render_bounds: expected a method taking the env whose render camera it "
                "frames (def _render_bounds(self, env: int = 0), e.g. returning self._robots_extent(env)), got one "
                "without parameters."
            )
        mode = parse_obs_mode(obs_mode, type(self).__name__)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise UnknownNameError(type(self).__name__, "render_mode", str(render_mode), self.metadata["render_modes"])
        size = check_render_size(render_size, type(self).__name__)
        noise = check_real(robot_init_qpos_noise, "robot_init_qpos_noise", type(self).__name__, 0.0, unit=" (rad or m)")
        # checked before the scene is built (models compiled, renderers made)
        self.set_max_episode_steps(max_episode_steps)
        self.raise_on_instability = check_bool(raise_on_instability, "raise_on_instability", type(self).__name__)
        self.scene = Scene(
            robot_uids,
            num_envs=num_envs,
            sim_freq=sim_freq,
            control_freq=control_freq,
            props=self._scene_props(),
            control_modes=control_mode,
            num_threads=num_threads,
            cameras=self._scene_cameras(),
            sensor_configs=sensor_configs,
            robot_poses=robot_poses,
            render_only_visuals=render_only_visuals,
            sleep=sleep,
        )
        if base_dynamics is not None:
            self._override_base_dynamics(base_dynamics)
        self.num_envs = self.scene.num_envs
        self.sim_freq, self.control_freq = self.scene.sim_freq, self.scene.control_freq
        self.obs_mode = obs_mode
        self._sensor_obs = SensorObservation(self.scene.cameras, mode, type(self).__name__) if mode.visual else None
        self.render_mode = render_mode
        self.render_size = size
        self.robot_init_qpos_noise = noise
        self._clearance: Clearance | None = None
        self.metadata = {**self.metadata, "render_fps": self.control_freq}
        self.elapsed_steps = np.zeros(self.num_envs, dtype=np.int64)
        self._env_rngs: list[np.random.Generator | None] = [None] * self.num_envs
        self._closed = False
        self._renderer: mujoco.Renderer | None = None
        #: Per env, :meth:`render`'s framing camera (``None``: framed at the next render).
        self._render_cameras: list[mujoco.MjvCamera | None] = [None] * self.num_envs
        self._single = self.num_envs == 1
        self._plain_task = (
            type(self).evaluate is RobotEnv.evaluate and type(self).compute_reward is RobotEnv.compute_reward
        )
        self._agent0 = self.scene.agents[0]
        self._one_robot = len(self.scene.agents) == 1
        extra_obs = self._extra_obs if type(self)._extra_obs is not RobotEnv._extra_obs else None
        self._observation = StateObservation(
            self.scene, obs_mode == "state", self._sensor_obs, extra_obs, type(self).__name__
        )
        #: The observation of every env (:meth:`StateObservation.observe`, bound once).
        self._get_obs: Callable[[], Any] = self._observation.observe
        #: The planned one-env step (:mod:`robot_agents.envs.single_step`), ``None`` where it has none.
        self._planned_step: Callable[[Any], StepResult | None] | None = plain_single_step(self)
        self._update_spaces()

    # ------------------------------------------------------------------ task hooks
    def _scene_props(self) -> Sequence[Prop]:
        """Props of the task's scene."""
        return ()

    def _scene_cameras(self) -> Sequence[CameraConfig]:
        """The task's cameras, mounted on ``"world"`` or a scene body."""
        return ()

    def compute_reward(self, info: Mapping[str, Any]) -> FloatArray:
        """Reward per env, shape ``(num_envs,)``."""
        return np.zeros(self.num_envs)

    def evaluate(self) -> dict[str, Any]:
        """Task metrics per env; a ``"success"`` or ``"fail"`` bool array ends an episode."""
        return {}

    def _extra_obs(self) -> dict[str, FloatArray]:
        """Task observations beyond proprioception (each ``(num_envs, ...)``)."""
        return {}

    def _initialize_episode(self, env_ids: npt.NDArray[np.int64]) -> None:
        """Randomize the task in ``env_ids`` at a reset, after the robots were reset
        (draw from :meth:`env_rng` of each env, one env after the other)."""

    def _render_markers(self, env: int) -> Sequence[Marker]:
        """What :meth:`render` draws into env ``env``'s frame besides the scene (a task's
        goal; :mod:`robot_agents.envs.markers`): never seen by the cameras."""
        return ()

    def _render_bounds(self, env: int = 0) -> tuple[FloatArray, FloatArray]:
        """World box ``(lower, upper)`` (m) the render camera of env ``env`` frames: the
        robots' extent in that env (read nothing of another env: each env's frame is
        that of a single env in its state)."""
        return self._robots_extent(env)

    def _robots_extent(self, env: int = 0, above: float = -np.inf) -> tuple[FloatArray, FloatArray]:
        """World box ``(lower, upper)`` around the robots' geoms in env ``env`` centred at
        least ``above`` (m, world z) high (:func:`~robot_agents.sensors.framing.robot_bounds`)."""
        return robot_bounds(self.scene.world, [f"{rid}/" for rid in self.scene.robot_ids], env=env, above=above)

    def env_rng(self, env: int) -> np.random.Generator:
        """The random stream of env ``env``, a whole number in ``[0, num_envs)`` (seeded by
        :meth:`reset`; unseeded: from fresh entropy on first use)."""
        if not is_whole(env) or not 0 <= env < self.num_envs:  # (-1 gave the last env's stream)
            raise StateError(
                f"{type(self).__name__}.env_rng: expected an env index in [0, {self.num_envs}), got {env!r}."
            )
        rng = self._env_rngs[env]
        if rng is None:
            rng, _ = seeding.np_random(None)
            self._env_rngs[env] = rng
        return rng

    # ------------------------------------------------------------------ access
    @property
    def agents(self) -> list[Agent]:
        """The robots, in the order of ``robot_uids`` (see :attr:`agent`)."""
        return self.scene.agents

    @property
    def agent(self) -> Agent:
        """The robot (the first one when the scene has several; see :attr:`agents`)."""
        return self.scene.agents[0]

    @property
    def model(self) -> mujoco.MjModel:
        """The simulated scene, shared by every env (without the visual-only geoms, see
        :attr:`render_model`)."""
        return self.scene.model

    @property
    def render_model(self) -> mujoco.MjModel:
        """The model renderers draw: :attr:`model` plus the visual-only geoms the
        simulation leaves out (``render_only_visuals``; :class:`~robot_agents.sim.scene.Scene`)."""
        return self.scene.render_model

    @property
    def data(self) -> mujoco.MjData:
        """The MjData of env 0 (the CPU backend's, for inspection)."""
        return self.scene.world.physics_sources([0])[0]

    @property
    def segmentation_id_map(self) -> dict[int, SegmentationEntry]:
        """Segmentation id -> the robot link or scene object it stands for (``-1``:
        background)."""
        return dict(self.scene.cameras.segmentation_id_map)

    @property
    def single_action_space(self) -> gym.Space[Any]:
        """One env's action space: the robot's (a ``Box`` of the active mode's action
        size), or a ``Dict`` of them by robot id for several robots; ``action_space`` is
        it batched over ``num_envs``."""
        if len(self.agents) == 1:
            return self.agent.single_action_space
        return gym.spaces.Dict(
            {rid: a.single_action_space for rid, a in zip(self.scene.robot_ids, self.agents, strict=True)}
        )

    def _build_action_space(self) -> gym.Space[Any]:
        if len(self.agents) == 1:
            return self.agent.action_space
        return gym.spaces.Dict({rid: a.action_space for rid, a in zip(self.scene.robot_ids, self.agents, strict=True)})

    def set_control_mode(self, mode: str, robot: int = 0) -> None:
        """Switch a robot's control mode (its gains are applied again) and update the
        action and observation spaces (the controller's targets are observed)."""
        where = f"{type(self).__name__}.set_control_mode"
        self._check_open(where)
        if not (is_whole(robot) and 0 <= robot < len(self.agents)):
            raise ConfigError(f"{where}: expected robot to be an index in [0, {len(self.agents)}), got {robot!r}.")
        self.agents[robot].set_control_mode(mode)
        self._update_spaces()

    def _update_spaces(self) -> None:
        """Build :attr:`action_space` and :attr:`observation_space` again for the robots'
        current control modes (the controller's targets are observed, so both differ per
        mode)."""
        self._space_modes = [agent.control_mode for agent in self.scene.agents]
        self.action_space = self._build_action_space()
        self.observation_space = self._build_observation_space()

    def _follow_control_modes(self) -> None:
        """Build the spaces again when a robot's control mode changed since they were
        built, however it changed (:meth:`Agent.set_control_mode`, :meth:`Agent.set_state`,
        :meth:`Scene.set_state`, not only this env's methods)."""
        if [agent.control_mode for agent in self.scene.agents] != self._space_modes:
            self._update_spaces()

    @property
    def action_space(self) -> gym.Space[Any]:
        """The action space of the robots' current control modes (a ``Dict`` by robot id
        for several robots)."""
        self._follow_control_modes()
        return self._action_space

    @action_space.setter
    def action_space(self, space: gym.Space[Any]) -> None:
        self._action_space = space

    @property
    def observation_space(self) -> gym.Space[Any]:
        """The observation space of the robots' current control modes (the controllers'
        targets are observed)."""
        self._follow_control_modes()
        return self._observation_space

    @observation_space.setter
    def observation_space(self, space: gym.Space[Any]) -> None:
        self._observation_space = space

    # ------------------------------------------------------------------ observations
    def _build_observation_space(self) -> gym.Space[Any]:
        """The observation space (built again when a control mode changes; a task may
        prepare what its :meth:`_extra_obs` reads first)."""
        return self._observation.space()

    # ------------------------------------------------------------------ gym API
    def reset(
        self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        """Reset every env (or ``options["env_ids"]``) to each robot's keyframe
        (``options["keyframe"]``: a name, one per robot or a dict by robot id; default the
        first) plus seeded noise, then the task's randomization.

        ``seed``: ``None`` continues each env's random stream; an int ``s`` re-seeds env
        ``i`` (of those reset) with ``s + i``; a list of ``num_envs`` ints or ``None``
        gives each env its own seed (``None``: not re-seeded)."""
        where = f"{type(self).__name__}.reset"
        self._check_open(where)
        # Everything is checked before the RNG is re-seeded or any env is touched.
        seeds = episode_checks.check_seeds(seed, self.num_envs, where)
        if options is not None and not isinstance(options, Mapping):
            raise ConfigError(f"{where}: expected options to be a dict (keys 'env_ids', 'keyframe'), got {options!r}.")
        options = dict(options or {})
        env_ids = options.pop("env_ids", None)
        keyframe = options.pop("keyframe", None)
        episode_checks.check_reset_options(list(options), RESET_OPTIONS, where)
        ids = self.agent.state.env_ids(env_ids, where)
        self.scene.check_keyframes(keyframe, where)
        if isinstance(seed, (int, np.integer)):
            super().reset(seed=int(seed))
        for env in ids:
            if seeds[env] is not None:
                self._env_rngs[env] = seeding.np_random(seeds[env])[0]
        self.scene.reset(env_ids=ids, keyframes=keyframe)
        if self.robot_init_qpos_noise > 0:
            self._perturb_robots(ids)
        self._initialize_episode(ids)
        self.elapsed_steps[ids] = 0
        for env in ids:  # framed again at the next render, from the new episode
            self._render_cameras[env] = None
        return self._get_obs(), {"elapsed_steps": self.elapsed_steps.copy()}

    def _perturb_robots(self, ids: npt.NDArray[np.int64]) -> None:
        """Add each env's reset noise to the robots' keyframe pose (every robot's draw,
        one robot after the other, from the env's stream); drawn again while it puts a
        robot geom more than :data:`RESET_PENETRATION_TOLERANCE` deeper into a fixed
        geom or another robot geom than the noiseless keyframe does (up to
        :data:`RESET_NOISE_DRAWS` draws, then the keyframe itself). Joint velocities stay
        the keyframe's."""
        clearance = self.clearance
        std = self.robot_init_qpos_noise
        rows = [np.empty((len(ids), agent.qpos_adr.size)) for agent in self.agents]
        for k, (env, source) in enumerate(zip(ids, self.scene.world.physics_sources(ids.tolist()), strict=True)):
            one, rng = ids[k : k + 1], self.env_rng(int(env))
            clearance.load(source)
            keyframe = clearance.data.qpos.copy()
            allowed = clearance.keyframe_depths()
            draws = [keyframe[agent.qpos_adr] for agent in self.agents]  # the fallback: the keyframe
            for _ in range(RESET_NOISE_DRAWS):
                candidate = [agent.perturbed_qpos(one, std, rng)[0] for agent in self.agents]
                qpos = keyframe.copy()
                for agent, row in zip(self.agents, candidate, strict=True):
                    qpos[agent.qpos_adr] = row
                if clearance.robots_clear(qpos, allowed, RESET_PENETRATION_TOLERANCE):
                    draws = candidate
                    break
            for agent_rows, row in zip(rows, draws, strict=True):
                agent_rows[k] = row
        for agent, agent_rows in zip(self.agents, rows, strict=True):
            agent.reset(qpos=agent_rows, qvel=agent.qvel[ids], env_ids=ids)  # the keyframe's velocities kept

    @property
    def clearance(self) -> Clearance:
        """The collision checks resets make (:class:`~robot_agents.envs.clearance.Clearance`)."""
        if self._clearance is None:
            self._clearance = Clearance(self.model, self.agents)
        return self._clearance

    def _override_base_dynamics(self, dynamics: str) -> None:
        """``base_dynamics=``: every robot with a planar ``Base`` runs ``"dynamic"`` or
        ``"kinematic"`` (its ``refuse_collisions`` setting is kept)."""
        mobile = [a for a in self.scene.agents if a.mobile.kind == "planar"]
        if not mobile:
            raise ConfigError(
                f"{type(self).__name__}: base_dynamics={dynamics!r} needs a robot with a Base part; "
                f"got {[type(a).__name__ for a in self.scene.agents]}."
            )
        for agent in mobile:
            agent.set_base_dynamics(dynamics)

    def step(self, action: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        """Apply ``action`` (``(num_envs, A)`` or ``(A,)``; a dict by robot id for several
        robots), advance one control step, and return Gymnasium's five values."""
        if self._closed:
            self._check_open(f"{type(self).__name__}.step")
        planned = self._planned_step
        if planned is not None:  # one env, one robot, joint-position parts, a float action
            result = planned(action)
            if result is not None:
                return result
        if self._one_robot:
            self._agent0.set_action(action)
        else:
            self._set_multi_action(action)
        self.scene.step()
        elapsed, unstable = self.elapsed_steps, self.scene.world.last_step_unstable
        if self._single:
            count = elapsed.item(0) + 1  # a Python int, written back by element: cheaper than the array add
            elapsed[0] = count
            if self.raise_on_instability and unstable[0]:
                self._raise_unstable(unstable)
            if self._plain_task:  # the one-env Empty-style step: no task hooks, zero reward
                info: dict[str, Any] = {"elapsed_steps": elapsed.copy(), "physics_unstable": unstable.copy()}
                if self._one_robot:
                    reported = self._agent0.step_info()
                    if reported:
                        info.update(reported)
                else:
                    self._add_controller_info(info)
                limit = self.max_episode_steps
                return self._get_obs(), 0.0, False, limit is not None and bool(count >= limit), info
        else:
            elapsed += 1
            if self.raise_on_instability and unstable.any():
                self._raise_unstable(unstable)
        if self._plain_task:  # no task hooks: no metrics, zero reward, never terminates
            info = {"elapsed_steps": elapsed.copy(), "physics_unstable": unstable.copy()}
            self._add_controller_info(info)
            reward: FloatArray = np.zeros(self.num_envs)
            terminated: npt.NDArray[np.bool_] = np.zeros(self.num_envs, dtype=bool)
        else:
            info = self.evaluate()
            reward = self.compute_reward(info)
            terminated = self._terminated(info)
            info["elapsed_steps"] = self.elapsed_steps.copy()
            info["physics_unstable"] = unstable.copy()
            self._add_controller_info(info)
        truncated: npt.NDArray[np.bool_]
        if self.max_episode_steps is None:
            truncated = np.zeros(self.num_envs, dtype=bool)
        else:
            truncated = self.elapsed_steps >= self.max_episode_steps
        obs = self._get_obs()
        if self._single:
            return obs, float(reward[0]), bool(terminated[0]), bool(truncated[0]), info
        return obs, reward, terminated, truncated, info

    def _raise_unstable(self, unstable: npt.NDArray[np.bool_]) -> NoReturn:
        """:class:`PhysicsError` naming the envs that ``unstable`` ``(num_envs,)`` flags."""
        raise PhysicsError(
            f"{type(self).__name__}.step: the simulation became unstable in env(s) {np.flatnonzero(unstable).tolist()} "
            "and MuJoCo reset them; lower the gains, add armature to light joints, or use a smaller time step "
            "(sim_freq)."
        )

    def _add_controller_info(self, info: dict[str, Any]) -> None:
        """What the robots report about the last action, per env (``(num_envs,)``
        arrays even for one env; :meth:`Agent.step_info`), e.g. ``ik_success``,
        ``ik_position_error`` (m) and ``ik_rotation_error`` (rad) in end-effector modes,
        ``base_move_refused`` for mobile bases; keyed ``"<robot id>/<key>"`` when the
        scene has several robots."""
        if self._one_robot:
            info.update(self._agent0.step_info())
            return
        for rid, agent in zip(self.scene.robot_ids, self.agents, strict=True):
            info.update({f"{rid}/{key}": value for key, value in agent.step_info().items()})

    def _terminated(self, info: Mapping[str, Any]) -> npt.NDArray[np.bool_]:
        """``success | fail`` per env (all false when the task reports neither)."""
        success, fail = info.get("success"), info.get("fail")
        if success is None and fail is None:
            return np.zeros(self.num_envs, dtype=bool)
        terminated = np.zeros(self.num_envs, dtype=bool)
        for flags in (success, fail):
            if flags is not None:
                terminated |= np.asarray(flags, dtype=bool)
        return terminated

    def _set_multi_action(self, action: Any) -> None:
        ids = self.scene.robot_ids
        if not isinstance(action, Mapping) or set(action) != set(ids):
            where = f"{type(self).__name__}.step"
            if not isinstance(action, Mapping):
                raise ConfigError(f"{where}: expected a dict of actions keyed by {ids}, got {type(action).__name__}.")
            unknown = [key for key in action if key not in ids]
            if unknown:
                raise UnknownNameError(f"{where} (actions keyed by robot id)", "robot id", str(unknown[0]), ids)
            missing = [rid for rid in ids if rid not in action]
            raise ConfigError(f"{where}: expected a dict of actions keyed by {ids}, got no action for {missing}.")
        checked = []
        for rid, agent in zip(ids, self.agents, strict=True):
            try:
                checked.append(agent.validate_action(action[rid]))
            except (ActionError, ConfigError, StateError) as err:  # robots may share a class: say whose it was
                raise type(err)(f"{type(self).__name__}.step, action[{rid!r}]: {err}") from None
        for agent, act in zip(self.agents, checked, strict=True):
            agent.set_action(act)

    def get_state(self) -> dict[str, Any]:
        """Exact state for :meth:`set_state`: the scene's (physics, sensors, controllers,
        drive targets), the episode step counts, the task's per-episode arrays
        (:attr:`episode_state`: its goals), each env's random stream (the draws of
        its next resets), :meth:`render`'s framing camera of each env, and ``"source"``:
        what made the state (task, robots, scene; :mod:`robot_agents.envs.state_source`),
        which :meth:`set_state` checks."""
        self._check_open(f"{type(self).__name__}.get_state")
        return {
            **self.scene.get_state(),
            "elapsed_steps": self.elapsed_steps.copy(),
            "episode": {name: np.array(getattr(self, name), dtype=np.float64) for name in self.episode_state},
            "rng": [None if rng is None else rng.bit_generator.state for rng in self._env_rngs],
            "render_camera": [_camera_state(camera) for camera in self._render_cameras],
            "source": state_source(type(self), self.scene),
        }

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state`; continuing with the same actions is bit-identical,
        through later resets too (an older state without the task's arrays or the random
        streams restores the rest). A restored control mode brings its action and
        observation spaces back (as :meth:`set_control_mode` does). Everything is checked
        before anything is written.

        A state saved by another task, other robots or another scene (its ``"source"``,
        :mod:`robot_agents.envs.state_source`) is refused with :class:`StateError` naming
        the first field that differs, this env's value and the state's. A state without
        ``"source"`` (saved before states recorded it) is restored unchecked, with a
        ``UserWarning``."""
        where = f"{type(self).__name__}.set_state"
        self._check_open(where)
        given = state if isinstance(state, Mapping) else {}
        check_state_keys(
            given,
            SCENE_STATE_KEYS + ENV_STATE_KEYS,
            "state",
            where,
            " 'autoreset' belongs to RobotVectorEnv.get_state(): restore it with RobotVectorEnv.set_state."
            if "autoreset" in given
            else "",
        )
        episode_checks.check_num_envs(given, self.num_envs, where)
        if "source" in given:
            check_source(given["source"], state_source(type(self), self.scene), where)
        steps = (
            episode_checks.check_elapsed_steps(given["elapsed_steps"], self.num_envs, where)
            if "elapsed_steps" in given
            else None
        )
        shapes = {name: np.shape(getattr(self, name)) for name in self.episode_state}
        episode = episode_checks.check_arrays(given["episode"], shapes, where) if "episode" in given else None
        rngs = episode_checks.generators(given["rng"], self.num_envs, where) if "rng" in given else None
        cameras = (
            episode_checks.render_cameras(given["render_camera"], self.num_envs, where)
            if "render_camera" in given
            else None
        )
        modes = [agent.control_mode for agent in self.agents]
        # the scene's part (a state that is no dict: the scene names what it takes)
        self.scene.set_state(
            {key: given[key] for key in SCENE_STATE_KEYS if key in given} if isinstance(state, Mapping) else state
        )
        if "source" not in given:  # said once the state was taken, not for one refused anyway
            warnings.warn(
                f"{where}: the state has no 'source' (it was saved before states recorded what made them): "
                "restored without checking that it comes from this task, these robots and this scene.",
                UserWarning,
                stacklevel=2,
            )
        if [agent.control_mode for agent in self.agents] != modes:
            self._update_spaces()
        if steps is not None:
            self.elapsed_steps = steps
        if episode is not None:
            for name, array in episode.items():
                getattr(self, name)[...] = array
        if rngs is not None:
            self._env_rngs = rngs
        if cameras is not None:  # the frames render() draws follow the state, not this env's past
            self._render_cameras = [None if camera is None else framed_camera(camera) for camera in cameras]

    def render(self) -> Any:
        """An RGB frame (uint8 ``H x W x 3``) per env (one for ``num_envs == 1``), each seen
        by a camera of its own that frames the robots from their extent in that env
        (:meth:`_render_bounds`) at its first render after a reset: env ``i``'s frame is
        that of a single env in env ``i``'s state. :meth:`get_state` saves the cameras,
        so a restored state renders as it did where it was saved."""
        self._check_open(f"{type(self).__name__}.render")
        if self.render_mode is None:
            # a note, as the library's others (gymnasium's convention: no frame, no error)
            warnings.warn(
                f"{type(self).__name__}.render: no frame, render_mode is None; pass render_mode='rgb_array' to make_env.",
                RuntimeWarning,
                stacklevel=2,
            )
            return None
        if self._renderer is None:
            width, height = self.render_size
            self._renderer = make_renderer(self.scene.render_model, width, height)
        cameras = self._render_cameras
        for env, camera in enumerate(cameras):
            if camera is None:  # framed once per reset, from the robots' extent (and the task's)
                lower, upper = self._render_bounds(env)
                width, height = self.render_size
                cameras[env] = framing_camera(
                    lower, upper, fovy=float(self.scene.render_model.vis.global_.fovy), aspect=width / height
                )
        frames = []
        for env, data in enumerate(self.scene.world.render_sources()):
            # Twice, as the sensor cameras do: MuJoCo lays the floor out around the camera
            # of the *previous* update, so one update made a frame depend on what was
            # drawn before (a renderer's first frame, a re-framed camera after a reset).
            self._renderer.update_scene(data, camera=cameras[env])
            self._renderer.update_scene(data, camera=cameras[env])
            draw_markers(self._renderer.scene, self._render_markers(env))
            frames.append(self._renderer.render().copy())
        return frames[0] if self._single else np.stack(frames)

    def set_max_episode_steps(self, steps: int | None) -> None:
        """Truncate episodes after ``steps`` steps (``None``: never; ``-1``: the task's default)."""
        check_max_episode_steps(steps, type(self).__name__)
        self.max_episode_steps = self.default_max_episode_steps if steps == -1 else steps

    def _check_open(self, where: str) -> None:
        check_open(self._closed, "this env", where)

    def __reduce__(self) -> Any:
        """Refused, with the way that works: an env holds MuJoCo's compiled model and
        renderers, which cannot be pickled or deep-copied."""
        raise StateError(
            f"{type(self).__name__}: an env cannot be pickled or copied (it holds MuJoCo's model and renderers); "
            "save env.unwrapped.get_state() (plain arrays, picklable) and set_state() it on an env made with the "
            "same arguments."
        )

    def close(self) -> None:
        """Free the renderers and the simulation; a later call other than ``close`` is a
        :class:`~robot_agents.errors.StateError`."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        self.scene.close()
        self._closed = True


def _camera_state(camera: mujoco.MjvCamera | None) -> FloatArray | None:
    """A framing camera as ``(lookat x, y, z, distance, azimuth, elevation)`` (m, m,
    deg, deg), ``None`` before it was framed (after a reset, until the next render)."""
    if camera is None:
        return None
    return np.array([*camera.lookat, camera.distance, camera.azimuth, camera.elevation], dtype=np.float64)
