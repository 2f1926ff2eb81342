"""A Scene: robots and props composed into one model, ``num_envs`` copies of it, and
the control-rate step (``sim_freq // control_freq`` physics substeps).

Usable on its own (no Gymnasium) and the core of every environment.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.agent.agent import CONTROL_STATE_KEYS, JOINT_STATE_KEYS
from robot_agents.agent.declaration import composition
from robot_agents.errors import ConfigError, StateError, UnknownNameError
from robot_agents.model.load_scope import one_read_per_file
from robot_agents.model.physics_twin import physics_twin
from robot_agents.model.scene import Prop, RobotMount, SceneOptions, compile_scene, compose_scene
from robot_agents.registry import agent_class
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.overrides import SensorOverrides, plan_cameras
from robot_agents.sensors.rig import CameraRig
from robot_agents.sensors.segmentation import segmentation_id_map
from robot_agents.sim.world import BatchedWorld
from robot_agents.validation import POSE_AXES, check_open, check_pose, check_state_keys, is_whole

#: Default physics rate (Hz): a 2 ms step keeps the stiff PD actuators and finger
#: contacts stable with the implicitfast integrator.
DEFAULT_SIM_FREQ = 500
#: Default control rate (Hz), as in ManiSkill: 25 substeps per action at 500 Hz.
DEFAULT_CONTROL_FREQ = 20
#: The keys of :meth:`Scene.get_state` (``set_state`` refuses others: a misspelt key
#: would leave that part of the state unrestored).
SCENE_STATE_KEYS = ("physics", "sleep", "sensors", "agents")
#: The keys :meth:`RobotEnv.get_state` adds to the scene's (named when given to
#: :meth:`Scene.set_state`).
ENV_STATE_KEYS = ("elapsed_steps", "episode", "rng", "render_camera", "source")

RobotSpecifier = str | type[Agent]


def default_sim_freq(classes: Sequence[type[Agent]]) -> int:
    """The physics rate a scene of these robots runs at unless told: the highest of
    their ``sim_freq`` (the smallest step any of them needs; :data:`DEFAULT_SIM_FREQ`
    for one that declares none)."""
    return max((int(cls.sim_freq or DEFAULT_SIM_FREQ) for cls in classes), default=DEFAULT_SIM_FREQ)


def contact_options(classes: Sequence[type[Agent]]) -> tuple[str, float]:
    """The friction cone and impratio a scene of these robots uses: the elliptic cone
    when any of them declares it, and the largest ``impratio`` declared (MuJoCo's
    pyramidal cone and 1 when none declares any)."""
    cone = "elliptic" if any(cls.friction_cone == "elliptic" for cls in classes) else "pyramidal"
    return cone, max((float(cls.impratio or 1.0) for cls in classes), default=1.0)


def solver_tolerance(classes: Sequence[type[Agent]]) -> float:
    """The constraint solver's tolerance a scene of these robots uses: the smallest any
    of them declares (:class:`SceneOptions`' default, MuJoCo's 1e-8, when none declares one)."""
    declared = (float(cls.solver_tolerance) for cls in classes if cls.solver_tolerance is not None)
    return min(declared, default=SceneOptions.tolerance)


def jacobian_option(classes: Sequence[type[Agent]]) -> str:
    """The constraint Jacobian a scene of these robots uses: sparse when any of them
    declares it, else dense when any declares that, else MuJoCo's choice (``"auto"``)."""
    asked = {cls.jacobian for cls in classes}
    return "sparse" if "sparse" in asked else "dense" if "dense" in asked else "auto"


class Scene:
    """One or more robots, props and a floor, simulated in ``num_envs`` copies.

    Args:
        robots: a robot uid or Agent class, or a sequence of them (several robots).
        num_envs: independent copies, stepped together.
        sim_freq / control_freq: physics and control rates in Hz; ``sim_freq`` must be
            a multiple of ``control_freq``. ``None``: the robots' own default step (the
            highest ``sim_freq`` they declare, see :func:`default_sim_freq`).
        props: primitive objects to add.
        robot_poses: world pose ``(x, y, z, qw, qx, qy, qz)`` of each robot's root;
            defaults place robots 1 m apart along y.
        control_modes: one mode name for every robot, or one per robot; ``None`` uses
            each robot's default.
        num_threads: threads for stepping ``num_envs > 1``.
        cameras: the task's cameras (mounted on ``"world"`` or a scene body).
        sensor_configs: camera overrides by camera key: a dict of
            :class:`~robot_agents.sensors.CameraConfig` fields, or ``None`` to drop it.
        render_only_visuals: simulate :attr:`model`, the scene without the geoms that
            only show (no contacts, no mass; :mod:`robot_agents.model.physics_twin`), and
            draw :attr:`render_model`, the whole scene (the same motion, bit for bit, and
            a physics step 8-22 % faster on most built-in robots). ``False``: one model
            for both.
        sleep: MuJoCo's island sleeping (``mjENBL_SLEEP``): trees that stay still (a
            prop at rest; a robot's actuated tree never sleeps) stop being simulated
            until something touches them. Faster with resting props, a different (still
            deterministic) trajectory; state round trips stay exact (the sleep counters
            are saved). Off by default.

    The robots' and the task's cameras are in :attr:`cameras` (a
    :class:`~robot_agents.sensors.CameraRig`); nothing is rendered unless asked.
    """

    def __init__(
        self,
        robots: RobotSpecifier | Sequence[RobotSpecifier],
        num_envs: int = 1,
        sim_freq: int | None = None,
        control_freq: int = DEFAULT_CONTROL_FREQ,
        props: Sequence[Prop] = (),
        robot_poses: Sequence[Sequence[float]] | None = None,
        control_modes: str | Sequence[str | None] | None = None,
        num_threads: int | None = None,
        floor: bool = True,
        cameras: Sequence[CameraConfig] = (),
        sensor_configs: SensorOverrides | None = None,
        render_only_visuals: bool = True,
        sleep: bool = False,
    ) -> None:
        for flag_name, flag in (("floor", floor), ("render_only_visuals", render_only_visuals), ("sleep", sleep)):
            if not isinstance(flag, bool):
                raise ConfigError(f"Scene: expected {flag_name} to be a bool, got {flag!r}.")
        if isinstance(props, Prop):
            raise ConfigError(
                f"Scene: expected props to be a sequence of Prop, got a single Prop {props.name!r}: put it in a list."
            )
        if not isinstance(props, Sequence) or isinstance(props, str) or not all(isinstance(p, Prop) for p in props):
            raise ConfigError(f"Scene: expected props to be a sequence of robot_agents.Prop, got {props!r:.80}.")
        if isinstance(robots, (str, type)):
            specifiers: list[Any] = [robots]
        elif isinstance(robots, Sequence):
            specifiers = list(robots)
        else:
            raise ConfigError(f"Scene: expected a robot uid, an Agent subclass, or a sequence of them, got {robots!r}.")
        if not specifiers:
            raise ConfigError("Scene: expected at least one robot, got none.")
        with one_read_per_file():  # each model file parsed once for the checks and builds below
            classes = [agent_class(r, "Scene") for r in specifiers]
            if sim_freq is None:
                sim_freq = default_sim_freq(classes)
            for name, value in (("sim_freq", sim_freq), ("control_freq", control_freq)):
                if not is_whole(value) or value <= 0:
                    raise ConfigError(f"Scene: expected {name} to be a positive integer (Hz), got {value!r}.")
            if sim_freq % control_freq:
                raise ConfigError(
                    f"Scene: expected sim_freq to be a multiple of control_freq, got sim_freq={sim_freq}, control_freq={control_freq}."
                )
            poses = self._poses(robot_poses, [cls.check().mount_pose for cls in classes])
            modes = self._modes(control_modes, len(classes))
            self.sim_freq, self.control_freq = int(sim_freq), int(control_freq)
            self.props = tuple(props)
            #: Each robot's world pose ``(x, y, z, qw, qx, qy, qz)`` (m, unit quaternion), in
            #: the order of :attr:`robot_ids`.
            self.robot_poses = tuple(tuple(float(v) for v in pose) for pose in poses)
            #: Whether MuJoCo's island sleeping is on (the ``sleep`` argument).
            self.sleep = sleep
            self.robot_ids = [f"{cls.uid or cls.__name__}-{i}" for i, cls in enumerate(classes)]
            planned = plan_cameras(
                [(rid, composition(cls).cameras) for rid, cls in zip(self.robot_ids, classes, strict=True)],
                cameras,
                sensor_configs,
            )
            mounts = [
                RobotMount(
                    prefix=f"{rid}/",
                    spec=cls.build_spec(cameras=[c.config for c in planned if c.robot == rid]),
                    pos=tuple(p[:3]),  # type: ignore[arg-type]
                    quat=tuple(p[3:]),  # type: ignore[arg-type]
                )
                for rid, cls, p in zip(self.robot_ids, classes, poses, strict=True)
            ]
        cone, impratio = contact_options(classes)
        options = SceneOptions(
            timestep=1.0 / sim_freq,
            floor=floor,
            cone=cone,
            impratio=impratio,
            jacobian=jacobian_option(classes),
            tolerance=solver_tolerance(classes),
        )
        self.spec = compose_scene(mounts, self.props, options, [c.config for c in planned if c.robot is None])
        #: The model renderers draw: the whole scene as composed.
        self.render_model = compile_scene(self.spec)
        #: The simulated model: ``render_model`` without the visual-only geoms that
        #: change nothing the physics computes, when there are any and
        #: ``render_only_visuals`` (:mod:`robot_agents.model.physics_twin`).
        twin = physics_twin(self.spec, self.render_model) if render_only_visuals else None
        self.model = twin if twin is not None else self.render_model
        if sleep:
            self.model.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
        self.world = BatchedWorld(
            self.model, num_envs, sim_freq // control_freq, num_threads, render_model=self.render_model
        )
        self.agents: list[Agent] = [
            cls(self.world, prefix=f"{rid}/", control_mode=mode, mount_pose=pose)
            for rid, cls, mode, pose in zip(self.robot_ids, classes, modes, poses, strict=True)
        ]
        self._initial_state = self.world.get_state()[0].copy()
        #: The scene's one robot (None with several): the common case of :meth:`step`.
        self._one_agent = self.agents[0] if len(self.agents) == 1 else None
        # One robot whose before / after-step hooks never have work (Agent's own hooks, no
        # planar base: nothing moves it kinematically or turns wheels between steps).
        one = self._one_agent
        self._hookless_single = (
            one is not None
            and one.mobile.planar is None
            and type(one).before_step is Agent.before_step
            and type(one).after_step is Agent.after_step
            and type(one).writes_after_step is Agent.writes_after_step
        )
        prefixes = {rid: f"{rid}/" for rid in self.robot_ids}
        self.cameras = CameraRig(self.render_model, planned, segmentation_id_map(self.render_model, prefixes))

    @staticmethod
    def _poses(poses: Sequence[Sequence[float]] | None, mounts: Sequence[Sequence[float]]) -> list[tuple[float, ...]]:
        """Each robot's world pose: given, or its class's ``mount_pose`` (several robots
        are set 1 m apart along y)."""
        n = len(mounts)
        if poses is None:
            return [(m[0], m[1] + (i - (n - 1) / 2) * 1.0, *m[2:]) for i, m in enumerate(mounts)]
        if isinstance(poses, (str, bytes)) or not isinstance(poses, (Sequence, np.ndarray)) or len(poses) != n:
            raise ConfigError(
                f"Scene.robot_poses: expected {n} poses of 7 finite numbers {POSE_AXES} (one per robot), got {poses!r}."
            )
        return [check_pose(pose, f"Scene.robot_poses[{k}]") for k, pose in enumerate(poses)]

    @staticmethod
    def _modes(modes: str | Sequence[str | None] | None, n: int) -> list[str | None]:
        if modes is None or isinstance(modes, str):
            return [modes] * n
        if not isinstance(modes, Sequence) or not all(m is None or isinstance(m, str) for m in modes):
            raise ConfigError(
                f"Scene.control_modes: expected a mode name, None, or one per robot ({n}), got {modes!r}."
            )
        result = list(modes)
        if len(result) != n:
            raise ConfigError(f"Scene.control_modes: expected one mode per robot ({n}), got {len(result)}: {result}.")
        return result

    # ------------------------------------------------------------------ properties
    @property
    def num_envs(self) -> int:
        """How many copies of the scene are simulated side by side (the leading axis of
        every per-env array)."""
        return self.world.num_envs

    @property
    def substeps(self) -> int:
        """Physics steps per control step: ``sim_freq / control_freq``."""
        return self.world.substeps

    @property
    def timestep(self) -> float:
        """Physics step in seconds."""
        return float(self.model.opt.timestep)

    @property
    def control_timestep(self) -> float:
        """Seconds per control step."""
        return self.timestep * self.substeps

    def body_pose(self, name: str) -> npt.NDArray[np.float64]:
        """World pose of a scene body, shape ``(num_envs, 7)``: position, quaternion (w, x, y, z)."""
        body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, name) if isinstance(name, str) else -1
        if body < 0:
            raise UnknownNameError(
                "Scene.body_pose", "body", str(name), [self.model.body(b).name for b in range(self.model.nbody)]
            )
        return self.world.body_poses([body])[:, 0]

    # ------------------------------------------------------------------ stepping
    def step(self) -> None:
        """One control step: every robot's substep hooks, then the physics substeps."""
        if self.world.closed:
            self._check_open("Scene.step")
        # The poses after the physics are left to the first robot that writes joint state
        # in every env after it (wheels, a kinematic base): nothing reads them before, and
        # its write recomputes them from the same qpos.
        agent = self._one_agent
        if agent is not None and not agent.needs_substep:  # the common case, without lists
            if self._hookless_single:  # one fixed-base robot
                self.world.step()
                return
            agent.before_step()
            self.world.step(sync_poses=not agent.writes_after_step)
            agent.after_step()
            return
        agents = self.agents
        for agent in agents:
            agent.before_step()
        sync = not any(a.writes_after_step for a in agents)
        hooked = [a for a in agents if a.needs_substep]
        if not hooked:
            self.world.step(sync_poses=sync)
        else:

            def before_substep(i: int, n: int) -> None:
                for agent in hooked:
                    agent.before_substep(i, n)

            self.world.step(before_substep, sync_poses=sync)
        for agent in self.agents:
            agent.after_step()

    def reset(
        self,
        env_ids: npt.ArrayLike | None = None,
        keyframes: str | Sequence[str | None] | Mapping[str, str | None] | None = None,
        qpos: Sequence[npt.ArrayLike | None] | None = None,
    ) -> None:
        """Reset the envs ``env_ids`` (a sequence of env indices; all by default): props and
        time to their initial state, each robot to a keyframe (``keyframes``: one name for
        every robot, one per robot or a dict by robot id, ``None`` for its first) or to the
        given ``qpos`` (one entry per robot, each ``(nq,)`` for every env or
        ``(len(env_ids), nq)``, rad / m;
        ``None`` entries take the keyframe). Every robot's input is checked before any env
        is rewound."""
        where = "Scene.reset"
        self._check_open(where)
        if isinstance(env_ids, str):  # scene.reset("rest"): the first argument is env_ids
            raise StateError(
                f"{where}: expected env ids (a sequence of ints or None) as the first argument, got {env_ids!r}; "
                f"a keyframe goes by keyword: reset(keyframes={env_ids!r})."
            )
        ids = self.agents[0].state.env_ids(env_ids, where)
        frames = self.check_keyframes(keyframes, where)
        n = len(self.agents)
        if qpos is None:
            positions: list[Any] = [None] * n
        elif isinstance(qpos, (Sequence, np.ndarray)) and not isinstance(qpos, str) and len(qpos) == n:
            positions = list(qpos)
        else:
            given = f"{len(qpos)}" if isinstance(qpos, (Sequence, np.ndarray)) else repr(qpos)
            raise StateError(f"{where}: expected a sequence of one qpos (or None) per robot ({n}), got {given}.")
        # every robot's input is checked before any env is rewound
        writes = [
            agent.prepare_reset(frame, position, None, ids, f"{where} ({type(agent).__name__})")
            for agent, frame, position in zip(self.agents, frames, positions, strict=True)
        ]
        self.world.reset_envs(ids, self._initial_state)  # also clears MuJoCo's warning counters
        for agent, write in zip(self.agents, writes, strict=True):
            agent.apply_reset(write)

    def check_keyframes(self, keyframes: Any, where: str) -> list[str | None]:
        """One keyframe name (or ``None``: the default) per robot, checked: from one name
        for every robot, one per robot, or a dict by robot id (as actions are keyed; a
        robot it leaves out takes its default)."""
        if isinstance(keyframes, Mapping):
            for key in keyframes:
                if key not in self.robot_ids:
                    raise UnknownNameError(
                        f"{where} (keyframes keyed by robot id)", "robot id", str(key), self.robot_ids
                    )
            keyframes = [keyframes.get(rid) for rid in self.robot_ids]
        if keyframes is None or isinstance(keyframes, str):
            frames: list[Any] = [keyframes] * len(self.agents)
        elif isinstance(keyframes, Sequence) and len(keyframes) == len(self.agents):
            frames = list(keyframes)
        else:
            raise StateError(
                f"{where}: expected a keyframe name, None, one per robot ({len(self.agents)}) or a dict by robot id "
                f"({', '.join(self.robot_ids)}), got {keyframes!r}."
            )
        for agent, frame in zip(self.agents, frames, strict=True):
            checked = agent.check()
            if frame is not None and (not isinstance(frame, str) or checked.keyframe_name(frame) is None):
                raise UnknownNameError(
                    f"{where} ({type(agent).__name__})",
                    "keyframe",
                    str(frame),
                    checked.keyframes,
                    checked.keyframe_aliases,
                )
        return frames

    # ------------------------------------------------------------------ state
    def get_state(self) -> dict[str, Any]:
        """Everything for a bit-identical continuation: physics state ``(num_envs, n)``
        (MuJoCo's integration state), the island-sleep state ``(num_envs, sleep_size)``
        (``sleep``), the sensor readings ``(num_envs, nsensordata)`` (``sensors``: what
        the last step measured; an older state without these restores the rest) plus
        each robot's control state (:meth:`Agent.get_control_state`: control mode,
        controller state, drive targets, a planar base's dynamics)."""
        self._check_open("Scene.get_state")
        return {
            "physics": self.world.get_state(),
            "sleep": self.world.get_sleep_state(),
            "sensors": self.world.get_sensor_state(),
            "agents": [a.get_control_state() for a in self.agents],
        }

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state`. The state is checked before anything is written."""
        self._check_open("Scene.set_state")
        if not isinstance(state, Mapping) or "physics" not in state or "agents" not in state:
            raise StateError("Scene.set_state: expected a dict with keys 'physics' and 'agents' from get_state().")
        env_keys = [key for key in ENV_STATE_KEYS if key in state]
        check_state_keys(
            state,
            SCENE_STATE_KEYS,
            "state",
            "Scene.set_state",
            f" {env_keys} belong to an env's state: restore it with RobotEnv.set_state." if env_keys else "",
        )
        physics = self.world.check_state(state["physics"], "Scene.set_state")
        sleep = self.world.check_sleep_state(state["sleep"], "Scene.set_state") if "sleep" in state else None
        sensors = self.world.check_sensor_state(state["sensors"], "Scene.set_state") if "sensors" in state else None
        agent_states = state["agents"]
        if not isinstance(agent_states, Sequence) or isinstance(agent_states, str):
            raise StateError(
                f"Scene.set_state: expected 'agents' to be a list of {len(self.agents)} agent states "
                f"(dicts with keys 'control_mode' and 'controller'), got {type(agent_states).__name__}."
            )
        if len(agent_states) != len(self.agents):
            raise StateError(f"Scene.set_state: expected {len(self.agents)} agent states, got {len(agent_states)}.")
        drive_targets = []
        for k, (agent, agent_state) in enumerate(zip(self.agents, agent_states, strict=True)):
            if (
                not isinstance(agent_state, Mapping)
                or "control_mode" not in agent_state
                or "controller" not in agent_state
            ):
                raise StateError(
                    f"Scene.set_state: expected agents[{k}] ({self.robot_ids[k]}) to be a dict with keys "
                    f"'control_mode' and 'controller', got {agent_state!r:.80}."
                )
            joint_keys = [key for key in JOINT_STATE_KEYS if key in agent_state]
            check_state_keys(
                agent_state,
                CONTROL_STATE_KEYS,
                f"agents[{k}] ({self.robot_ids[k]}) state",
                "Scene.set_state",
                f" {joint_keys} belong to Agent.get_state(): the scene restores joints from 'physics'; "
                "restore a robot's own state with Agent.set_state."
                if joint_keys
                else "",
            )
            drive_targets.append(agent.check_control_state(agent_state, f"Scene.set_state (agents[{k}])"))
        for agent, agent_state, targets in zip(self.agents, agent_states, drive_targets, strict=True):
            agent.restore_control_state(agent_state, targets)
        self.world.set_state(physics, sleep, sensors)

    def _check_open(self, where: str) -> None:
        check_open(self.world.closed, "this scene", where)

    def close(self) -> None:
        """Release the renderers and threads; the scene (and its robots) refuse further use."""
        self.cameras.close()
        self.world.close()
