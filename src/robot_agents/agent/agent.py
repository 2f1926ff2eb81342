"""The Agent base class: a declarative robot definition plus its lifecycle.

A robot is a subclass that declares, as class attributes, its model file, how to load
it, its drives, parts, mounted pieces, keyframes, control modes and sensors; see
``docs/defining-a-robot.md``. An *instance* is the robot loaded into a simulation
backend (:class:`~robot_agents.sim.backend.SimBackend`): every array it returns has a
leading ``num_envs`` axis and is a copy. What the instance does is split by concept:
names to addresses (:mod:`.index`), frames (:mod:`.frames`), control modes
(:mod:`.control`), joint state (:mod:`.joint_state`); the declaration is composed and
checked in :mod:`.declaration`; Habitat's mobile-manipulator names come from the base
class in :mod:`.habitat_api`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.drives import Drives, DriveTargetState
from robot_agents.agent import declaration
from robot_agents.agent.control import ControlModes
from robot_agents.agent.definition import AgentDefinition
from robot_agents.agent.frames import RobotFrames
from robot_agents.agent.grippers import GripperParts
from robot_agents.agent.habitat_api import MobileManipulatorAPI
from robot_agents.agent.index import RobotIndex
from robot_agents.agent.joint_state import JointState, JointWrite
from robot_agents.agent.legs import STANDING_TILT, LegParts
from robot_agents.agent.mobile import MobileBase
from robot_agents.controllers.base import ControllerContext
from robot_agents.controllers.base_vel import PDBaseVelController
from robot_agents.controllers.combined import CombinedController
from robot_agents.errors import ConfigError, StateError, UnknownNameError
from robot_agents.kinematics.forward import FrameRef, Kinematics
from robot_agents.parts.declaration import Arm, Base, Gripper, Legs, Part
from robot_agents.sensors.touch import TouchReader
from robot_agents.validation import check_state_keys, is_real

if TYPE_CHECKING:
    from robot_agents.keyframe import ResolvedKeyframe
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

#: The keys of :meth:`Agent.get_control_state` (``base``: a planar base's dynamics).
CONTROL_STATE_KEYS = ("control_mode", "controller", "drives", "base")
#: The joint keys :meth:`Agent.get_state` adds to them.
JOINT_STATE_KEYS = ("qpos", "qvel", "base_pose", "base_velocity", "warmstart")


class Agent(MobileManipulatorAPI, AgentDefinition):
    """Base class of every robot: subclass it, set the class attributes (see
    :class:`~robot_agents.agent.definition.AgentDefinition`), register it. An instance is
    the robot bound to a simulation backend."""

    # ------------------------------------------------------------------ binding
    def __init__(
        self,
        world: SimBackend,
        prefix: str = "",
        control_mode: str | None = None,
        mount_pose: npt.ArrayLike = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0),
    ) -> None:
        """Bind to the robot attached with ``prefix`` in ``world`` and activate a control
        mode. ``mount_pose`` ``(x, y, z, qw, qx, qy, qz)`` is where the scene attached
        it; a free robot's keyframe base poses are taken relative to it."""
        name = type(self).__name__
        checked = self.check()
        self.world = world
        self.prefix = prefix
        self.num_envs = world.num_envs
        model = world.model
        self.index = RobotIndex(model, prefix, name)
        self.drives = Drives(model, checked.drives, prefix, self.num_envs, name)
        self.part_joints = checked.part_joints
        self.parts_by_name: dict[str, Part] = {p.name: p for p in checked.parts}
        end_effectors = [ee for part in checked.parts if isinstance(part, Arm) for ee in part.end_effectors]
        self.frames = RobotFrames(model, self.index, end_effectors, name)
        self.state = JointState(world, self.index, np.asarray(mount_pose, dtype=np.float64).reshape(7), name)
        self.touch_reader = TouchReader(model, prefix, declaration.composition(type(self)).touch_sensors)
        context = ControllerContext(
            num_envs=self.num_envs,
            model=model,
            control_timestep=float(model.opt.timestep) * world.substeps,
            kinematics=self.frames.kinematics,
            root_frame=self.frames.root_frame,
            targets=self.drives.targets,
            end_effectors=self.frames.end_effectors,
            effort_limits=dict(zip(self.drives.joint_names, self.drives.declared_effort_limit.tolist(), strict=True)),
            prefix=prefix,
            owner=name,
        )
        self.control = ControlModes(name, checked.modes, self.index, self.drives, context, world)
        self.grippers = GripperParts(world, self.index, checked.parts, checked.part_joints, name)
        self.legs = LegParts(world, self.index, checked.parts, checked.part_joints, type(self).fix_root_link, name)
        # Held legs (Habitat's leg base): pinned at their drives' reset targets while a
        # kinematic base moves the body.
        held = [j for p in checked.parts if isinstance(p, Legs) and p.held for j in checked.part_joints[p.name]]
        base = next((p for p in checked.parts if isinstance(p, Base)), None)
        self.mobile = MobileBase(
            world, self.index, self.state, checked.part_joints[base.name] if base else None, name, base, held
        )
        self._manipulator = None  # the Habitat-named view, built on first use
        held_info = [self.index.joint(j, name) for j in held]
        self._held_qpos = np.array([j.qpos_adr for j in held_info], dtype=np.int64)
        self._held_dof = np.array([j.dof_adr for j in held_info], dtype=np.int64)
        self._held_start = np.array([j.qpos_start for j in held_info], dtype=np.int64)
        self._held_columns = self.drives.columns(held, name) if held else np.zeros(0, dtype=np.int64)
        self._every_env = np.arange(self.num_envs)
        self._holds_legs = len(self._held_qpos) > 0  # (read after every step)
        self._held_qvel = np.zeros((self.num_envs, len(held)))  # written, never changed
        # one env: the held legs' state written as rows (BatchedWorld.write_joint_row)
        self._held_rows = self._holds_legs and self.num_envs == 1
        self._held_qvel_row = self._held_qvel[0]
        # one env: the drives' position targets (rad, m; the buffer is never replaced), ``(n,)``
        self._held_position_row = self.drives.targets.position[0]
        # (active mode, its last base velocity part or None), for after_step
        self._base_controller: tuple[CombinedController | None, PDBaseVelController | None] = (None, None)
        self._opt = self.index.model.opt  # reads the live time step (the attribute makes a new wrapper)
        self.set_control_mode(control_mode if control_mode is not None else self.default_mode())

    # ------------------------------------------------------------------ names and sizes
    @property
    def joint_names(self) -> tuple[str, ...]:
        """Every joint except a floating root's, in model order."""
        return self.index.joint_names

    @property
    def dof(self) -> int:
        """Velocity degrees of freedom of the joints (a free root excluded): ``qvel`` width."""
        return self.index.nv

    @property
    def nq(self) -> int:
        """Width of ``qpos`` (a ball joint counts 4)."""
        return self.index.nq

    @property
    def qpos_adr(self) -> npt.NDArray[np.int64]:
        """Where the robot's joint positions lie in the scene's ``qpos``, shape ``(nq,)``
        (a free root's 7 excluded): ``data.qpos[agent.qpos_adr]`` is the robot's ``qpos``."""
        return self.index.qpos_adr

    @property
    def dof_adr(self) -> npt.NDArray[np.int64]:
        """Where the robot's joint velocities lie in the scene's ``qvel``, shape ``(dof,)``
        (a free root's 6 excluded)."""
        return self.index.dof_adr

    @property
    def qpos_limits(self) -> FloatArray:
        """``(nq, 2)`` joint limits (``(-inf, inf)`` where unlimited or a quaternion entry)."""
        return self.index.qpos_limits

    @property
    def root_body_id(self) -> int:
        """The scene model's id of the robot's root body (its free joint's body on a
        floating robot; :attr:`root_frame`'s body)."""
        return self.index.root_body_id

    @property
    def kinematics(self) -> Kinematics:
        """Side-effect-free kinematics of the scene (a private scratch MjData)."""
        return self.frames.kinematics

    @property
    def root_frame(self) -> FrameRef:
        """The frame of root-relative commands (see :class:`.frames.RobotFrames`)."""
        return self.frames.root_frame

    # ------------------------------------------------------------------ state reads
    @property
    def qpos(self) -> FloatArray:
        """Joint positions, shape ``(num_envs, nq)`` (rad / m / quaternions), a copy."""
        return self.state.qpos

    @property
    def qvel(self) -> FloatArray:
        """Joint velocities, shape ``(num_envs, dof)`` (rad/s / m/s), a copy."""
        return self.state.qvel

    @property
    def base_pose(self) -> FloatArray:
        """Root body pose in the world, shape ``(num_envs, 7)``: ``x, y, z, qw, qx, qy, qz``."""
        return self.world.body_poses(self.index.root_body_id)[:, 0]

    def tcp_pose_of(self, end_effector: str | None = None) -> FloatArray:
        """World pose ``(num_envs, 7)`` of an end effector (default: the first declared)."""
        frame = self.frames.end_effector(end_effector, f"{type(self).__name__}.tcp_pose")
        return self.frames.measured_pose(frame, self.world)

    @property
    def tcp_pose(self) -> FloatArray:
        """World pose ``(num_envs, 7)`` of the first end effector: position (m), quaternion (w, x, y, z)."""
        return self.tcp_pose_of(None)

    @property
    def has_end_effector(self) -> bool:
        """The robot has at least one end effector (an ``Arm`` part's, declared or derived):
        :attr:`tcp_pose` and the ``pd_ee_*`` modes need one."""
        return bool(self.frames.end_effectors)

    @property
    def touch(self) -> FloatArray:
        """Normal force (N) of each touch sensor, shape ``(num_envs, n)``."""
        return self.touch_reader.read(self.world)

    def frame_pose(self, name: str, qpos: npt.ArrayLike | None = None, relative_to: str = "world") -> FloatArray:
        """Pose ``(num_envs, 7)`` of the robot's body, site or end effector ``name``, at the
        measured or given ``qpos`` (``(nq,)`` or ``(num_envs, nq)``), in the world,
        ``"root"`` (the frame of end-effector commands) or another frame of the robot;
        computed on scratch data (the simulation is untouched). A given ``qpos`` is taken
        as it is: joints that follow another through an equality (mimic fingers,
        Stretch's telescope segments) keep the values it gives them, so set them too
        (:class:`~robot_agents.kinematics.IKSolver` moves linear followers itself)."""
        where = f"{type(self).__name__}.frame_pose"
        frame, reference = self.frames.frame(name, where), self.frames.reference(relative_to, where)
        return self.frames.pose(frame, reference, self.state.configurations(qpos, where))

    def frame_jacobian(
        self, name: str, qpos: npt.ArrayLike | None = None, relative_to: str = "world", include_base: bool = False
    ) -> FloatArray:
        """Jacobian ``(num_envs, 6, dof)`` of the origin of ``name``: rows 0-2 linear
        velocity (m/s), rows 3-5 angular velocity (rad/s) per unit joint velocity, one
        column per joint of the robot (a joint's own column: a leader's does not include
        the joints that follow it through equalities; add ``c1`` times theirs for
        ``follower = c0 + c1 * leader``; a free-floating base, whose free joint is not
        one of the robot's joints, has none: the base is held where it is). ``qpos`` as
        in :meth:`frame_pose`;
        ``relative_to``: world axes, or the derivative of the pose relative to ``"root"``
        or a frame (in its axes; a frame the joints move too: its own motion taken out).

        ``include_base=True`` (a free-floating robot only): ``(num_envs, 6, 6 + dof)``,
        the free base's six velocity dofs first, in MuJoCo's free-joint convention (the
        base's ``qvel``: linear velocity of its origin in world axes (m/s), then angular
        velocity in the base body's own axes (rad/s)), then the joints' columns as above;
        ``J @ concatenate([base_vel, qvel])`` is the frame's velocity. Relative to
        ``"root"`` (the base itself) the base's columns are zero."""
        where = f"{type(self).__name__}.frame_jacobian"
        frame, reference = self.frames.frame(name, where), self.frames.reference(relative_to, where)
        dofs = None
        if include_base:
            free = self.index.free_joint
            if free is None:
                raise ConfigError(
                    f"{where}: include_base=True needs a free-floating base (a root with a free joint), got "
                    f"{self.uid!r}, whose base is fixed or mounted; its Jacobian has only its joints' columns "
                    "(include_base=False)."
                )
            dofs = np.concatenate([free.dof_adr + np.arange(6), self.index.dof_adr])
        return self.frames.jacobian(frame, reference, self.state.configurations(qpos, where), dofs)

    # ------------------------------------------------------------------ control
    @property
    def control_mode(self) -> str:
        """The active control mode's name (:meth:`set_control_mode` changes it)."""
        return self.control.mode

    @property
    def controller(self) -> CombinedController:
        """The active mode's controller."""
        return self.control.active

    def set_control_mode(self, mode: str) -> None:
        """Activate ``mode``: the declared drive settings with the mode's overrides (every
        time), holding the measured pose."""
        where = f"{type(self).__name__}.set_control_mode"
        self._check_open(where)
        self.control.activate(mode, where)

    def controller_for(self, mode: Any, where: str = "") -> CombinedController:
        """The controller of ``mode`` (built on first use, not activated; an unknown mode
        is an :class:`~robot_agents.errors.UnknownNameError` naming ``where``)."""
        return self.control.controller_for(mode, where or type(self).__name__)

    @property
    def needs_substep(self) -> bool:
        """True when :meth:`before_substep` must run before every physics substep."""
        return self.control.active.needs_substep

    @property
    def single_action_space(self) -> gym.spaces.Box:
        """Action space of one env, shape ``(action_dim,)``."""
        return self.control.single_action_space

    @property
    def action_space(self) -> gym.spaces.Box:
        """Batched action space, shape ``(num_envs, action_dim)``."""
        return self.control.action_space

    def validate_action(self, action: Any) -> FloatArray:
        """``action`` as float64 ``(num_envs, action_dim)``; raises :class:`ActionError`."""
        return self.control.validate_action(action)

    def set_action(self, action: Any) -> None:
        """Validate ``action``, turn it into joint targets and those into controls.
        Nothing is changed when the action is rejected."""
        if self.world.closed:
            self._check_open(f"{type(self).__name__}.set_action")
        control = self.control
        control.active.set_action(control.checked_action(action), self.world)

    def before_substep(self, substep: int, substeps: int) -> None:
        """Per-substep hook: interpolated targets, explicit PD loops."""
        self.control.active.before_substep(substep, substeps, self.world)

    @property
    def writes_after_step(self) -> bool:
        """True when :meth:`after_step` writes joint state in every env (recomputing their
        poses) before it reads anything but joint positions: a base whose wheels turn or
        that moves kinematically."""
        return self.mobile.moves_each_step

    def before_step(self) -> None:
        """Before a control step's physics: the base remembers its pose (kinematic
        bases and wheels)."""
        self.mobile.before_step()

    def after_step(self) -> None:
        """After a control step's physics: a kinematic base moves by the commanded
        velocity (or refuses a colliding move) and held legs are put back at their
        reset pose (Habitat's leg base); wheels turn with the base."""
        mobile = self.mobile
        if not mobile.moves_each_step:
            return
        active = self.control.active
        seen, base = self._base_controller
        if active is not seen:  # found once per active mode
            base = None
            for controller in active.parts.values():
                if isinstance(controller, PDBaseVelController):
                    base = controller
            self._base_controller = (active, base)
        mobile.after_step(None if base is None else base.target_qvel, float(self._opt.timestep) * self.world.substeps)
        if self._holds_legs and mobile.dynamics == "kinematic":
            if self._held_rows:  # one env: its row of the targets, taken by column
                pose_row = self._held_position_row.take(self._held_columns)
                self.world.write_joint_row(
                    self._held_qpos, pose_row, self._held_dof, self._held_qvel_row, forward=False
                )
                return
            pose = self.drives.targets.position.take(self._held_columns, axis=1)  # [:, columns], faster
            self.world.write_joint_state(
                self._every_env, self._held_qpos, pose, self._held_dof, self._held_qvel, forward=False
            )

    def step_info(self) -> dict[str, npt.NDArray[np.generic]]:
        """What the last control step reports, per env (``(num_envs,)`` arrays): the
        controllers' (``ik_success`` ... in end-effector modes) and, for a robot with a
        planar base, ``base_move_refused`` (a kinematic move refused because it would
        collide; always ``False`` for a dynamic base or without the check)."""
        info = self.control.active.step_info()
        if self.mobile.planar is not None:
            info["base_move_refused"] = self.mobile.last_refused.copy()
        return info

    def set_base_dynamics(self, dynamics: str, refuse_collisions: bool | None = None) -> None:
        """Run this robot's base ``"dynamic"`` or ``"kinematic"`` (overrides ``Base.dynamics``)."""
        self.mobile.set_dynamics(dynamics, refuse_collisions)

    # ------------------------------------------------------------------ reset / state
    def keyframe_qpos(self, name: str) -> FloatArray:
        """Keyframe ``name`` (or an alias of it: :meth:`keyframe_aliases`) as the robot's
        ``qpos`` vector ``(nq,)`` (a copy)."""
        qpos: FloatArray = self.keyframe(name, f"{type(self).__name__}.keyframe_qpos").qpos.copy()
        return qpos

    def keyframe(self, name: str, where: str | None = None) -> ResolvedKeyframe:
        """Keyframe ``name`` (or an alias of it) resolved to the robot's vectors: ``qpos``
        ``(nq,)``, ``qvel`` ``(nv,)``, base pose ``(7,)`` and velocity ``(6,)`` (shared:
        copy before changing them).

        Raises:
            UnknownNameError: no keyframe has that name (``where`` names the call in the
                message; the keyframes and aliases listed)."""
        where = where if where is not None else f"{type(self).__name__}.keyframe"
        checked = self.check()
        found = checked.keyframe_name(name) if isinstance(name, str) else None
        if found is None:
            raise UnknownNameError(where, "keyframe", str(name), checked.keyframes, checked.keyframe_aliases)
        return checked.keyframes[found]

    def reset(
        self,
        keyframe: str | None = None,
        qpos: npt.ArrayLike | None = None,
        qvel: npt.ArrayLike | None = None,
        env_ids: npt.ArrayLike | None = None,
    ) -> None:
        """Put the robot at a keyframe (default: the first) or at ``qpos`` / ``qvel``
        (``(nq,)`` / ``(dof,)`` or one row per env), then hold that pose. Every input is
        checked before anything is written."""
        where = f"{type(self).__name__}.reset"
        self.apply_reset(self.prepare_reset(keyframe, qpos, qvel, env_ids, where))

    def prepare_reset(
        self,
        keyframe: str | None,
        qpos: npt.ArrayLike | None,
        qvel: npt.ArrayLike | None,
        env_ids: npt.ArrayLike | None,
        where: str,
    ) -> JointWrite:
        """Check :meth:`reset`'s input and return the joint write it makes (for
        :meth:`apply_reset`); nothing is written, so a caller resetting several robots
        can check them all first."""
        self._check_open(where)
        ids = self.state.env_ids(env_ids, where)
        name = keyframe if keyframe is not None else (self.default_keyframe() if qpos is None else None)
        frame = None
        if name is not None:
            if not isinstance(name, str):  # agent.reset([0]): the first argument is the keyframe
                choices = ", ".join(map(repr, self.check().keyframe_choices()))
                raise StateError(
                    f"{where}: expected a keyframe name (str) or None as the first argument, got {name!r}; "
                    f"env ids go by keyword: reset(env_ids=...). Keyframes: {choices}."
                )
            frame = self.keyframe(name, where)
        if frame is None and qpos is None:
            raise StateError(f"{where}: {type(self).__name__} has no keyframes; pass qpos of shape ({self.nq},).")
        return self.state.prepare(ids, qpos, qvel, frame, where)

    def apply_reset(self, write: JointWrite) -> None:
        """Write a reset :meth:`prepare_reset` checked, then hold that pose."""
        self.state.apply(write)
        self.control.active.reset(write.ids, self.world)

    def perturbed_qpos(self, env_ids: npt.NDArray[np.int64], std: float, rng: np.random.Generator) -> FloatArray:
        """The measured ``qpos`` of ``env_ids`` plus Gaussian noise of ``std`` (rad / m;
        ball joints turn by a random rotation vector), clipped into the limits: shape
        ``(len(env_ids), nq)``, drawn from ``rng``. Held legs
        (Habitat's leg base) keep the measured pose: they are pinned at the reset pose
        while a kinematic base moves the body, and a perturbed stance would pin their
        feet into the floor (0.02 rad put Spot's up to 9 mm deep)."""
        qpos = self.state.perturbed(env_ids, std, rng)
        if len(self._held_start):
            qpos[:, self._held_start] = self.state.qpos[env_ids][:, self._held_start]
        return qpos

    def get_proprioception(self) -> dict[str, Any]:
        """``qpos`` and ``qvel``, per part what the controller exposes (its current
        targets) and, with touch sensors, ``touch`` ``(num_envs, n)`` (N)."""
        controller = {part: {k: v.copy() for k, v in obs.items()} for part, obs in self.controller.observe().items()}
        proprioception: dict[str, Any] = {"qpos": self.qpos, "qvel": self.qvel, "controller": controller}
        if self.touch_reader.names:
            proprioception["touch"] = self.touch
        return proprioception

    def proprioception_arrays(self) -> list[FloatArray]:
        """:meth:`get_proprioception` as a flat list of ``(num_envs, k)`` arrays, in order
        (read-only views where possible: copy before keeping them)."""
        arrays = self.state.views()
        for controller in self.controller.parts.values():
            arrays.extend(controller.observe().values())
        if self.touch_reader.names:
            arrays.append(self.touch)
        return arrays

    def get_state(self) -> dict[str, Any]:
        """The robot's own state: joint state, base pose, for a free base (a legged robot,
        a floating hand) its velocity ``base_velocity`` ``(num_envs, 6)`` (linear m/s in the
        world frame, angular rad/s in the base's frame: MuJoCo's free-joint ``qvel``), the
        constraint solver's ``warmstart`` of the robot's dofs (``(num_envs, nv)``, ``nv + 6``
        with a free base; rad/s^2, m/s^2), control mode, controller state and drive targets.

        With the rest of the scene as it was, :meth:`set_state` continues bit for bit;
        what else the scene holds (props, other robots, time, sensor readings) is the
        scene's or env's state."""
        state: dict[str, Any] = {"qpos": self.qpos, "qvel": self.qvel, "base_pose": self.base_pose}
        if self.state.has_free_base:
            state["base_velocity"] = self.state.base_velocity
        state["warmstart"] = self.state.warmstart
        return {**state, **self.get_control_state()}

    def get_control_state(self) -> dict[str, Any]:
        """The control part of :meth:`get_state`: ``control_mode``, ``controller`` state,
        ``drives`` targets and, for a robot on a planar base, ``base``: its dynamics
        (dynamic or kinematic, as :meth:`set_base_dynamics` left them) and refusal counters."""
        state: dict[str, Any] = {
            "control_mode": self.control_mode,
            "controller": self.controller.get_state(),
            "drives": self.drives.get_target_state(),
        }
        if self.mobile.planar is not None:
            state["base"] = self.mobile.get_state()
        return state

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state`; everything is checked before anything is written.
        The solver's warm start of the robot's dofs is restored and the other dofs' kept;
        an older state without ``warmstart`` clears every dof's, as a reset does (and one
        without ``base_velocity`` leaves a free base moving as it is)."""
        where = f"{type(self).__name__}.set_state"
        self._check_open(where)
        if isinstance(state, Mapping):
            check_state_keys(state, JOINT_STATE_KEYS + CONTROL_STATE_KEYS, "state", where)
        checked = self.state.check_state(state, where)
        targets = self.check_control_state(state, where)
        self.restore_control_state(state, targets)
        self.state.write_state(checked)
        self.drives.write(self.world.ctrl)

    def check_control_state(self, state: Mapping[str, Any], where: str) -> DriveTargetState | None:
        """Validate the control part of a state (``control_mode``, ``controller`` and,
        when present, ``drives``: :meth:`get_state`'s keys) without applying it; returns
        the checked drive targets for :meth:`restore_control_state`."""
        self.controller_for(state["control_mode"], where).check_state(state["controller"], where)
        if "base" in state:  # an older state without it keeps the base's settings
            self.mobile.check_state(state["base"], where)
        return self.drives.check_target_state(state["drives"], where) if "drives" in state else None

    def restore_control_state(self, state: Mapping[str, Any], targets: DriveTargetState | None) -> None:
        """Activate the state's control mode and restore its controller state and drive
        targets (checked by :meth:`check_control_state`)."""
        self.set_control_mode(state["control_mode"])
        self.controller.set_state(state["controller"])
        if "base" in state:
            self.mobile.set_state(self.mobile.check_state(state["base"], "restore_control_state"))
        if targets is not None:  # joints no action writes (held legs) keep theirs
            self.drives.set_target_state(targets)

    # ------------------------------------------------------------------ part helpers
    def is_static(self, threshold: float = 0.2) -> BoolArray:
        """Per env: every joint except grippers' moves slower than ``threshold`` (rad/s or m/s)."""
        _check_threshold(f"{type(self).__name__}.is_static", "threshold", threshold)
        return self.grippers.is_static(float(threshold))

    def is_standing(self, max_tilt: float = STANDING_TILT) -> BoolArray:
        """Per env, for a robot whose legs carry its free base: the base within
        ``max_tilt`` (rad; default 20 deg) of upright and only the feet touching anything
        outside the robot. Raises :class:`ConfigError` for other robots."""
        where = f"{type(self).__name__}.is_standing"
        _check_threshold(where, "max_tilt", max_tilt, upper=math.pi)
        return self.legs.is_standing(float(max_tilt), where)

    def is_fallen(self) -> BoolArray:
        """Per env, for a robot whose legs carry its free base: a body other than a foot
        touches something outside the robot. Raises :class:`ConfigError` for other robots."""
        return self.legs.is_fallen(f"{type(self).__name__}.is_fallen")

    def gripper(self, name: str | None = None) -> Gripper:
        """The gripper or hand part ``name`` (default: the first)."""
        return self.grippers.part(name)

    def is_grasping(
        self, body: str, min_force: float = 0.5, max_angle: float = 85.0, gripper: str | None = None
    ) -> BoolArray:
        """Per env: two fingers of the gripper (or hand) press on scene body ``body`` from
        opposing sides, each with at least ``min_force`` (N); forces within ``max_angle``
        degrees of directly opposite count (see :mod:`robot_agents.parts.grasp`)."""
        where = f"{type(self).__name__}.is_grasping"
        _check_threshold(where, "min_force", min_force)
        _check_threshold(where, "max_angle", max_angle, upper=180.0)
        return self.grippers.is_grasping(body, float(min_force), float(max_angle), gripper)


def _check_threshold(where: str, name: str, value: Any, upper: float = math.inf) -> None:
    if not is_real(value):
        raise ConfigError(f"{where}: expected {name} to be a number, got {value!r}.")
    if not (math.isfinite(float(value)) and 0.0 <= float(value) <= upper):
        raise ConfigError(f"{where}: expected {name} in [0, {upper:g}], got {value!r}.")
