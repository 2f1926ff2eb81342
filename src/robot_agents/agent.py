"""The Agent base class: a declarative robot definition plus its lifecycle.

A robot is a subclass that declares, as class attributes, its model file, how to
load it, keyframes, control modes and tool frame; see ``docs/defining-a-robot.md``.
An *instance* is the robot loaded into a :class:`~robot_agents.sim.BatchedWorld`:
every array it returns has a leading ``num_envs`` axis and is a copy.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import gymnasium as gym
import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.contacts import contact_force_between
from robot_agents.controllers.base import ControllerConfig, ControllerContext, JointBinding
from robot_agents.controllers.combined import CombinedController
from robot_agents.errors import ActionError, ConfigError, ModelError, StateError, UnknownNameError
from robot_agents.indexing import index_selector
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.forward import FrameKind, FrameRef, Kinematics, resolve_frame
from robot_agents.kinematics.rotations import quat_to_matrix, relative_pose
from robot_agents.model import robot_spec
from robot_agents.model.loading import load_model_spec
from robot_agents.model.materials import FrictionMaterial
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.spec import add_cameras, add_touch_sensors
from robot_agents.sensors.touch import TouchReader, TouchSensorConfig

if TYPE_CHECKING:
    from robot_agents.sim.world import BatchedWorld

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
ModeConfig = ControllerConfig | Mapping[str, ControllerConfig]
#: Part name used when a control mode is a single config rather than a dict of parts.
SINGLE_PART = "main"


def ctrl_addresses(model: mujoco.MjModel, actuator_ids: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """Index in ``ctrl`` of each actuator's (first) control input.

    Since MuJoCo 3.15 an actuator may take several controls (``model.nu`` counts
    controls, not actuators) and ``actuator_ctrladr`` maps them; before that, control
    ``i`` belongs to actuator ``i``.
    """
    adr = getattr(model, "actuator_ctrladr", None)
    return (np.asarray(adr)[actuator_ids] if adr is not None else actuator_ids).astype(np.int64)


class Agent:
    """Base class of every robot. Subclass it, set the class attributes, register it.

    Declaration (class attributes):
        uid: registry id, e.g. ``"panda"``.
        mjcf_path / urdf_path: the model file (exactly one).
        fix_root_link: weld the root to the world (arms) or give it a free joint.
        disable_self_collisions: ignore every contact between the robot's own bodies;
            otherwise only ``self_collision_exclusions`` pairs (and parent/child) are ignored.
        gravity_compensation: ``True`` (every body), ``False``, or body names; ``None``
            means ``fix_root_link`` (on for fixed-base arms, off for free robots).
        link_materials: body name -> :class:`FrictionMaterial`; ``default_material``
            for every other colliding geom (``None`` keeps the file's friction).
        keyframes: name -> :class:`Keyframe`; the first one is the default reset pose.
        control_modes: name -> controller config, or ``{part: config}``.
        default_control_mode: defaults to the first control mode.
        tcp_link: body name of the tool centre point, if the robot has a tool.
        finger_links: ``(left, right)`` finger bodies used by :meth:`is_grasping`.
        gripper_joint_names: joints ignored by :meth:`is_static`.
        cameras: :class:`CameraConfig` per camera mounted on a link (moves with it).
        touch_sensors: :class:`TouchSensorConfig` per touch sensor (normal force, N;
            read as ``touch`` in the proprioception).
    """

    uid: ClassVar[str] = ""
    mjcf_path: ClassVar[str | Path | None] = None
    urdf_path: ClassVar[str | Path | None] = None
    fix_root_link: ClassVar[bool] = True
    disable_self_collisions: ClassVar[bool] = False
    self_collision_exclusions: ClassVar[tuple[tuple[str, str], ...]] = ()
    gravity_compensation: ClassVar[bool | tuple[str, ...] | None] = None
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {}
    default_material: ClassVar[FrictionMaterial | None] = None
    keyframes: ClassVar[Mapping[str, Keyframe]] = {}
    control_modes: ClassVar[Mapping[str, ModeConfig]] = {}
    default_control_mode: ClassVar[str | None] = None
    tcp_link: ClassVar[str | None] = None
    finger_links: ClassVar[tuple[str, str] | None] = None
    gripper_joint_names: ClassVar[tuple[str, ...]] = ()
    cameras: ClassVar[tuple[CameraConfig, ...]] = ()
    touch_sensors: ClassVar[tuple[TouchSensorConfig, ...]] = ()

    # ------------------------------------------------------------------ declaration
    @classmethod
    def model_path(cls) -> Path:
        """The declared model file (not checked for existence)."""
        paths = [p for p in (cls.mjcf_path, cls.urdf_path) if p is not None]
        if len(paths) != 1:
            raise ConfigError(
                f"{cls.__name__}: expected exactly one of mjcf_path / urdf_path, got mjcf_path={cls.mjcf_path!r}, "
                f"urdf_path={cls.urdf_path!r}."
            )
        return Path(paths[0])

    @classmethod
    def mode_parts(cls, mode: str) -> dict[str, ControllerConfig]:
        """The per-part configs of a control mode (a single config becomes part ``"main"``)."""
        if mode not in cls.control_modes:
            raise UnknownNameError(f"{cls.__name__}", "control mode", str(mode), cls.control_modes)
        entry = cls.control_modes[mode]
        return {SINGLE_PART: entry} if isinstance(entry, ControllerConfig) else dict(entry)

    @classmethod
    def controlled_joints(cls) -> list[str]:
        """Every joint named by any control mode, in first-seen order."""
        seen: dict[str, None] = {}
        for mode in cls.control_modes:
            for config in cls.mode_parts(mode).values():
                seen.update(dict.fromkeys(config.joint_names))
        return list(seen)

    @classmethod
    def validate_definition(cls) -> None:
        """Check the declaration without loading the model file (run at registration)."""
        name = cls.__name__
        cls.model_path()
        if not cls.control_modes:
            raise ConfigError(f"{name}: expected at least one entry in control_modes, got none.")
        for mode in cls.control_modes:
            parts = cls.mode_parts(mode)
            seen: dict[str, str] = {}
            for part, config in parts.items():
                if not isinstance(config, ControllerConfig):
                    raise ConfigError(
                        f"{name}.control_modes[{mode!r}][{part!r}]: expected a ControllerConfig, got {config!r}."
                    )
                for joint in config.joint_names:
                    if joint in seen:
                        raise ConfigError(
                            f"{name}.control_modes[{mode!r}]: joint {joint!r} is driven by both part {seen[joint]!r} and {part!r}."
                        )
                    seen[joint] = part
        if cls.default_control_mode is not None and cls.default_control_mode not in cls.control_modes:
            raise UnknownNameError(
                f"{name}.default_control_mode", "control mode", cls.default_control_mode, cls.control_modes
            )
        for key, frame in cls.keyframes.items():
            if not isinstance(frame, Keyframe):
                raise ConfigError(f"{name}.keyframes[{key!r}]: expected a Keyframe, got {frame!r}.")
        for attr, kind in (("cameras", CameraConfig), ("touch_sensors", TouchSensorConfig)):
            uids: set[str] = set()
            for entry in getattr(cls, attr):
                if not isinstance(entry, kind):
                    raise ConfigError(f"{name}.{attr}: expected {kind.__name__} entries, got {entry!r}.")
                if entry.uid in uids:
                    raise ConfigError(f"{name}.{attr}: two entries have the uid {entry.uid!r}.")
                uids.add(entry.uid)

    @classmethod
    def build_spec(cls, cameras: Sequence[CameraConfig] | None = None) -> mujoco.MjSpec:
        """A fresh MjSpec of this robot with every declared option applied.

        ``cameras`` replaces the declared :attr:`cameras` (an env's overrides)."""
        cls.validate_definition()
        where = f"{cls.__name__} ({cls.model_path()})"
        spec = load_model_spec(cls.model_path())
        robot_spec.set_root_joint(spec, cls.fix_root_link, where)
        gravcomp = cls.fix_root_link if cls.gravity_compensation is None else cls.gravity_compensation
        robot_spec.set_gravity_compensation(spec, gravcomp, where)
        robot_spec.set_materials(spec, cls.link_materials, cls.default_material, where)
        robot_spec.set_self_collisions(spec, cls.disable_self_collisions, cls.self_collision_exclusions, where)
        robot_spec.add_joint_actuators(spec, cls.controlled_joints(), where)
        add_cameras(spec, cls.cameras if cameras is None else cameras, f"{cls.__name__}.cameras")
        add_touch_sensors(spec, cls.touch_sensors, f"{cls.__name__}.touch_sensors")
        return spec

    # ------------------------------------------------------------------ binding
    def __init__(
        self,
        world: BatchedWorld,
        prefix: str = "",
        control_mode: str | None = None,
        mount_pose: npt.ArrayLike = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0),
    ) -> None:
        """Bind to a robot attached with ``prefix`` in ``world`` and activate a control mode.

        ``mount_pose`` ``(x, y, z, qw, qx, qy, qz)`` is where the scene attached the
        robot; a free robot's keyframe base poses are taken relative to it."""
        self.world = world
        self.prefix = prefix
        self.num_envs = world.num_envs
        model = world.model
        name = type(self).__name__
        joints = [j for j in range(model.njnt) if model.joint(j).name.startswith(prefix)]
        if not joints:
            raise ModelError(f"{name}: no joint with prefix {prefix!r} in the compiled model.")
        free = [j for j in joints if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
        moving = [j for j in joints if model.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE]
        self.joint_names: tuple[str, ...] = tuple(model.joint(j).name[len(prefix) :] for j in moving)
        self._joint_ids = np.array(moving, dtype=np.int64)
        self.qpos_adr = model.jnt_qposadr[self._joint_ids].astype(np.int64)
        self.dof_adr = model.jnt_dofadr[self._joint_ids].astype(np.int64)
        self._qpos_sel = index_selector(self.qpos_adr)
        self._dof_sel = index_selector(self.dof_adr)
        limited = model.jnt_limited[self._joint_ids].astype(bool)
        ranges = model.jnt_range[self._joint_ids].copy()
        ranges[~limited] = (-math.inf, math.inf)
        self.qpos_limits: FloatArray = ranges
        self.root_body_id = int(model.jnt_bodyid[joints[0]]) if free else self._find_root_body(model, prefix)
        self._free_qpos_adr = int(model.jnt_qposadr[free[0]]) if free else -1
        self._mount_pose = np.array(mount_pose, dtype=np.float64).reshape(7)
        self._free_dof_adr = int(model.jnt_dofadr[free[0]]) if free else -1
        self.tcp_body_id = self._body_id(self.tcp_link) if self.tcp_link else -1
        self._finger_body_ids = [self._body_id(link) for link in self.finger_links or ()]
        for joint in self.gripper_joint_names:
            if joint not in self.joint_names:
                raise UnknownNameError(f"{name}.gripper_joint_names", "joint", joint, self.joint_names)
        self._static_dofs = np.array(
            [a for n, a in zip(self.joint_names, self.dof_adr, strict=True) if n not in self.gripper_joint_names],
            dtype=np.int64,
        )
        for key, frame in self.keyframes.items():
            if frame.dof != self.dof:
                raise ConfigError(
                    f"{name}.keyframes[{key!r}]: expected {self.dof} joint positions ({', '.join(self.joint_names)}), "
                    f"got {frame.dof}."
                )
        #: Side-effect-free kinematics of the scene (a private scratch MjData).
        self.kinematics = Kinematics(model)
        # Commands "in the root frame" use the robot's fixed (or free-floating) base. When the
        # root body itself moves on joints (a floating mount), the root frame is where that
        # body sits with its joints at zero: a fixed pose in its parent.
        root = self.root_body_id
        if model.body_jntnum[root] > 0 and not free:
            home = (*model.body_pos[root], *model.body_quat[root])
            parent = int(model.body_parentid[root])
            self.root_frame = FrameRef(FrameKind.BODY, parent, model.body(root).name + " (home)", tuple(home))
        else:
            self.root_frame = FrameRef(FrameKind.BODY, root, model.body(root).name)
        self.tool_frame = (
            FrameRef(FrameKind.BODY, self.tcp_body_id, model.body(self.tcp_body_id).name) if self.tcp_link else None
        )
        self._controller_context = ControllerContext(
            num_envs=self.num_envs,
            model=model,
            control_timestep=float(model.opt.timestep) * world.substeps,
            kinematics=self.kinematics,
            root_frame=self.root_frame,
            tool_frame=self.tool_frame,
            prefix=prefix,
            owner=name,
        )
        self.touch_reader = TouchReader(model, prefix, self.touch_sensors)
        self._controllers: dict[str, CombinedController] = {}
        self.controller: CombinedController
        #: True when the active controller needs :meth:`before_substep` every substep.
        self.needs_substep = False
        self._control_mode = ""
        self.set_control_mode(control_mode if control_mode is not None else self.default_mode())

    @classmethod
    def default_mode(cls) -> str:
        return cls.default_control_mode or next(iter(cls.control_modes))

    @classmethod
    def default_keyframe(cls) -> str | None:
        return next(iter(cls.keyframes), None)

    def _find_root_body(self, model: mujoco.MjModel, prefix: str) -> int:
        for body in range(1, model.nbody):
            if model.body_parentid[body] == 0 and model.body(body).name.startswith(prefix):
                return body
        raise ModelError(f"{type(self).__name__}: no root body with prefix {prefix!r} in the compiled model.")

    def _body_id(self, body: str) -> int:
        model = self.world.model
        body_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, self.prefix + body)
        if body_id < 0:
            names = [
                model.body(b).name[len(self.prefix) :]
                for b in range(model.nbody)
                if model.body(b).name.startswith(self.prefix)
            ]
            raise UnknownNameError(type(self).__name__, "body", body, names)
        return int(body_id)

    def _binding(self, config: ControllerConfig) -> JointBinding:
        model = self.world.model
        ids, actuators = [], []
        for joint in config.joint_names:
            if joint not in self.joint_names:
                raise UnknownNameError(
                    f"{type(self).__name__} {type(config).__name__}", "joint", joint, self.joint_names
                )
            ids.append(self.joint_names.index(joint))
            actuators.append(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, self.prefix + joint))
        index = np.array(ids, dtype=np.int64)
        actuator_ids = np.array(actuators, dtype=np.int64)
        return JointBinding(
            joint_names=config.joint_names,
            qpos_adr=self.qpos_adr[index],
            dof_adr=self.dof_adr[index],
            actuator_ids=actuator_ids,
            ctrl_adr=ctrl_addresses(model, actuator_ids),
            qpos_range=self.qpos_limits[index],
        )

    # ------------------------------------------------------------------ properties
    @property
    def dof(self) -> int:
        """Number of joints (free root excluded)."""
        return len(self.joint_names)

    @property
    def qpos(self) -> FloatArray:
        """Joint positions, shape ``(num_envs, dof)`` (rad / m), a copy."""
        qpos: FloatArray = self.world.qpos[:, self._qpos_sel].copy()
        return qpos

    @property
    def qvel(self) -> FloatArray:
        """Joint velocities, shape ``(num_envs, dof)`` (rad/s / m/s), a copy."""
        qvel: FloatArray = self.world.qvel[:, self._dof_sel].copy()
        return qvel

    @property
    def base_pose(self) -> FloatArray:
        """Root body pose in the world, shape ``(num_envs, 7)``: ``x, y, z, qw, qx, qy, qz``."""
        return self._body_pose(self.root_body_id)

    @property
    def tcp_pose(self) -> FloatArray:
        """Tool centre point pose in the world, shape ``(num_envs, 7)``: position (m), quaternion (w, x, y, z)."""
        if self.tcp_body_id < 0:
            raise ConfigError(f"{type(self).__name__}: this robot declares no tcp_link.")
        return self._body_pose(self.tcp_body_id)

    @property
    def touch(self) -> FloatArray:
        """Normal force (N) of each of :attr:`touch_sensors`, shape ``(num_envs, n)``."""
        return self.touch_reader.read(self.world.datas)

    def _body_pose(self, body_id: int) -> FloatArray:
        if self.num_envs == 1:
            data = self.world.datas[0]
            single: FloatArray = np.concatenate((data.xpos[body_id], data.xquat[body_id])).reshape(1, 7)
            return single
        pose = np.empty((self.num_envs, 7))
        for row, data in zip(pose, self.world.datas, strict=True):
            row[:3] = data.xpos[body_id]
            row[3:] = data.xquat[body_id]
        return pose

    # ------------------------------------------------------------------ kinematics
    def _configurations(self, qpos: npt.ArrayLike | None, where: str) -> FloatArray:
        """Full scene configurations ``(num_envs, nq)``: the measured state with this
        robot's joints replaced by ``qpos`` ``(dof,)`` or ``(num_envs, dof)`` when given."""
        full = np.array(self.world.qpos, dtype=np.float64)
        if qpos is not None:
            full[:, self.qpos_adr] = self._batch(qpos, self.num_envs, self.dof, "qpos", where)
        return full

    def frame_pose(self, name: str, qpos: npt.ArrayLike | None = None, relative_to: str = "world") -> FloatArray:
        """Pose ``(num_envs, 7)`` of the robot's body or site ``name``: position (m) and
        quaternion (w, x, y, z), computed on scratch data (the simulation is untouched).

        Args:
            name: a body or site of this robot (unprefixed).
            qpos: joint positions ``(dof,)`` or ``(num_envs, dof)``; default: measured.
            relative_to: ``"world"``, ``"root"`` (the robot's base frame, the frame of
                end-effector commands) or another body / site of this robot.
        """
        where = f"{type(self).__name__}.frame_pose"
        frame = self._frame(name, where)
        reference = self._reference_frame(relative_to, where)
        configurations = self._configurations(qpos, where)
        if reference is None:
            return self.kinematics.pose(configurations, frame)
        poses = self.kinematics.poses(configurations, (frame, reference))
        return relative_pose(poses[:, 0], poses[:, 1])

    def frame_jacobian(self, name: str, qpos: npt.ArrayLike | None = None, relative_to: str = "world") -> FloatArray:
        """Jacobian ``(num_envs, 6, dof)`` of the origin of body or site ``name``: rows 0-2
        give its linear velocity (m/s), rows 3-5 its angular velocity (rad/s) per unit
        velocity of each of this robot's joints (a free base's 6 DoF are not columns).
        Axes are the world's, or those of ``"root"`` or a named body / site of the robot."""
        where = f"{type(self).__name__}.frame_jacobian"
        frame = self._frame(name, where)
        reference = self._reference_frame(relative_to, where)
        configurations = self._configurations(qpos, where)
        jacobian = self.kinematics.jacobian(configurations, frame, self.dof_adr)
        if reference is None:
            return jacobian
        rotation = quat_to_matrix(self.kinematics.pose(configurations, reference)[:, 3:])
        rotated: FloatArray = np.concatenate(
            (np.swapaxes(rotation, 1, 2) @ jacobian[:, :3], np.swapaxes(rotation, 1, 2) @ jacobian[:, 3:]), axis=1
        )
        return rotated

    def _frame(self, name: str, where: str) -> FrameRef:
        return resolve_frame(self.world.model, name, self.prefix, where)

    def _reference_frame(self, relative_to: str, where: str) -> FrameRef | None:
        if relative_to == "world":
            return None
        if relative_to == "root":
            return self.root_frame
        return self._frame(relative_to, where)

    # ------------------------------------------------------------------ control
    @property
    def control_mode(self) -> str:
        return self._control_mode

    def set_control_mode(self, mode: str) -> None:
        """Activate ``mode``: apply its gains (every time) and hold the measured pose."""
        controller = self.controller_for(mode, where=f"{type(self).__name__}.set_control_mode")
        controller.activate(self.world.model, self.world)
        self.controller = controller
        self._control_mode = mode
        self.needs_substep = controller.needs_substep

    def controller_for(self, mode: str, where: str = "") -> CombinedController:
        """The controller of ``mode`` (built on first use, not activated)."""
        if mode not in self.control_modes:
            raise UnknownNameError(where or type(self).__name__, "control mode", str(mode), self.control_modes)
        controller = self._controllers.get(mode)
        if controller is None:
            parts = {
                part: config.build(self._binding(config), self._controller_context)
                for part, config in self.mode_parts(mode).items()
            }
            controller = self._controllers[mode] = CombinedController(mode, parts)
        return controller

    @property
    def single_action_space(self) -> gym.spaces.Box:
        """Action space of one env, shape ``(action_dim,)``."""
        c = self.controller
        return gym.spaces.Box(c.action_low.astype(np.float32), c.action_high.astype(np.float32), dtype=np.float32)

    @property
    def action_space(self) -> gym.spaces.Box:
        """Batched action space, shape ``(num_envs, action_dim)``."""
        c = self.controller
        low = np.tile(c.action_low.astype(np.float32), (self.num_envs, 1))
        high = np.tile(c.action_high.astype(np.float32), (self.num_envs, 1))
        return gym.spaces.Box(low, high, dtype=np.float32)

    def validate_action(self, action: Any) -> FloatArray:
        """Check an action and return it as float64 of shape ``(num_envs, action_dim)``.

        Accepts shape ``(num_envs, action_dim)``, or ``(action_dim,)`` which is applied to
        every env. Raises :class:`ActionError` for other shapes, non-numeric dtypes and
        NaN / inf values.
        """
        dim = self.controller.action_dim
        try:
            array = np.asarray(action)
        except (TypeError, ValueError) as err:
            raise ActionError(
                f"{self._action_where()}: expected a numeric array of shape ({self.num_envs}, {dim}), got {type(action).__name__}: {err}."
            ) from None
        if array.dtype.kind not in "fiu":
            raise ActionError(f"{self._action_where()}: expected a float (or integer) array, got dtype {array.dtype}.")
        if array.shape == (dim,):
            array = np.broadcast_to(array, (self.num_envs, dim))
        elif array.shape != (self.num_envs, dim):
            parts = ", ".join(f"{p}: {s.stop - s.start}" for p, s in self.controller.slices.items())
            raise ActionError(
                f"{self._action_where()}: expected shape ({self.num_envs}, {dim}) or ({dim},) [{parts}], got {array.shape}."
            )
        array = np.asarray(array, dtype=np.float64)
        # Fast path: a finite sum means every entry is finite (an overflowing sum of huge
        # finite values falls through to the exact check).
        if not math.isfinite(array.sum()) and not np.isfinite(array).all():
            bad = np.argwhere(~np.isfinite(array))[:3].tolist()
            raise ActionError(f"{self._action_where()}: expected finite values, got NaN or inf at (env, index) {bad}.")
        problem = self.controller.check_action(array)
        if problem is not None:
            raise ActionError(f"{self._action_where()}: {problem}")
        return array

    def _action_where(self) -> str:
        return f"{type(self).__name__}.set_action (mode {self._control_mode!r})"

    def set_action(self, action: Any) -> None:
        """Validate ``action`` and write the resulting targets into the controls.

        Nothing is changed when the action is rejected.
        """
        checked = self.validate_action(action)
        world = self.world
        self.controller.set_action(checked, world)

    def before_substep(self, substep: int, substeps: int) -> None:
        """Per-substep hook: lets the controller update ``ctrl`` (e.g. interpolation)."""
        self.controller.before_substep(substep, substeps, self.world)

    # ------------------------------------------------------------------ reset / state
    def _env_ids(self, env_ids: Sequence[int] | npt.ArrayLike | None, where: str) -> npt.NDArray[np.int64]:
        if env_ids is None:
            return np.arange(self.num_envs)
        ids = np.asarray(env_ids).reshape(-1)
        if ids.dtype.kind not in "iu" or np.any(ids < 0) or np.any(ids >= self.num_envs):
            raise StateError(f"{where}: expected env ids in [0, {self.num_envs}), got {ids.tolist()}.")
        return ids.astype(np.int64)

    def _batch(self, value: npt.ArrayLike, n_envs: int, size: int, what: str, where: str) -> FloatArray:
        array = np.asarray(value)
        if array.dtype.kind not in "fiu":
            raise StateError(f"{where}: expected numeric {what}, got dtype {array.dtype}.")
        if array.shape == (size,):
            array = np.broadcast_to(array, (n_envs, size))
        if array.shape != (n_envs, size):
            raise StateError(f"{where}: expected {what} of shape ({size},) or ({n_envs}, {size}), got {array.shape}.")
        array = array.astype(np.float64)
        if not np.all(np.isfinite(array)):
            raise StateError(f"{where}: {what} contains NaN or inf.")
        return array

    def reset(
        self,
        keyframe: str | None = None,
        qpos: npt.ArrayLike | None = None,
        qvel: npt.ArrayLike | None = None,
        env_ids: npt.ArrayLike | None = None,
    ) -> None:
        """Put the robot at a keyframe (default: the first) or at ``qpos`` / ``qvel``.

        ``qpos`` / ``qvel`` have shape ``(dof,)`` or ``(len(env_ids), dof)`` and override
        the keyframe's. The controller then holds the new pose. Every input is checked
        before anything is written.
        """
        where = f"{type(self).__name__}.reset"
        ids = self._env_ids(env_ids, where)
        frame: Keyframe | None = None
        name = keyframe if keyframe is not None else (self.default_keyframe() if qpos is None else None)
        if name is not None:
            if name not in self.keyframes:
                raise UnknownNameError(where, "keyframe", str(name), self.keyframes)
            frame = self.keyframes[name]
        if frame is None and qpos is None:
            raise StateError(f"{where}: {type(self).__name__} has no keyframes; pass qpos of shape ({self.dof},).")
        new_qpos = self._batch(qpos if qpos is not None else frame.qpos_array(), len(ids), self.dof, "qpos", where)  # type: ignore[union-attr]
        if qvel is not None:
            new_qvel = self._batch(qvel, len(ids), self.dof, "qvel", where)
        else:
            new_qvel = np.broadcast_to(
                frame.qvel_array() if frame is not None else np.zeros(self.dof), (len(ids), self.dof)
            )
        low, high = self.qpos_limits[:, 0], self.qpos_limits[:, 1]
        outside = (new_qpos < low - 1e-9) | (new_qpos > high + 1e-9)
        if np.any(outside):
            env, joint = np.argwhere(outside)[0]
            raise StateError(
                f"{where}: qpos of joint {self.joint_names[joint]!r} is {new_qpos[env, joint]:.6g}, outside its limits "
                f"[{low[joint]:.6g}, {high[joint]:.6g}]."
            )
        model = self.world.model
        for row, env in enumerate(ids):
            data = self.world.datas[env]
            data.qpos[self.qpos_adr] = new_qpos[row]
            data.qvel[self.dof_adr] = new_qvel[row]
            if frame is not None and self._free_qpos_adr >= 0:
                data.qpos[self._free_qpos_adr : self._free_qpos_adr + 7] = self._keyframe_base(frame)
                data.qvel[self._free_dof_adr : self._free_dof_adr + 6] = 0.0
            data.qacc_warmstart[:] = 0.0
            mujoco.mj_forward(model, data)
        self.world.invalidate()
        self.controller.reset(ids, self.world)
        for env in ids:
            self.world.datas[env].ctrl[:] = self.world.ctrl[env]

    def _keyframe_base(self, frame: Keyframe) -> FloatArray:
        """World pose ``(x, y, z, qw, qx, qy, qz)`` of a keyframe's base: the keyframe's
        ``base_pos`` / ``base_quat`` taken in the frame where the scene mounted the robot."""
        mount = self._mount_pose
        pose = np.empty(7)
        mujoco.mju_rotVecQuat(pose[:3], np.array(frame.base_pos), mount[3:])
        pose[:3] += mount[:3]
        mujoco.mju_mulQuat(pose[3:], mount[3:], np.array(frame.base_quat))
        return pose

    def get_proprioception(self) -> dict[str, Any]:
        """``qpos`` and ``qvel`` ``(num_envs, dof)``, per part what the controller
        exposes (its current ``target_qpos`` / ``target_qvel``) and, with touch sensors,
        ``touch`` ``(num_envs, n)`` (N)."""
        controller = {part: {k: v.copy() for k, v in obs.items()} for part, obs in self.controller.observe().items()}
        proprioception: dict[str, Any] = {"qpos": self.qpos, "qvel": self.qvel, "controller": controller}
        if self.touch_sensors:
            proprioception["touch"] = self.touch
        return proprioception

    def proprioception_arrays(self) -> list[FloatArray]:
        """:meth:`get_proprioception` as a flat list of ``(num_envs, k)`` arrays, in order
        (read-only views where possible: copy before keeping them)."""
        world = self.world
        arrays = [world.qpos[:, self._qpos_sel], world.qvel[:, self._dof_sel]]
        for controller in self.controller.parts.values():
            arrays.extend(controller.observe().values())
        if self.touch_sensors:
            arrays.append(self.touch)
        return arrays

    def get_state(self) -> dict[str, Any]:
        """The robot's own state: joint state, base pose, control mode and controller state."""
        return {
            "qpos": self.qpos,
            "qvel": self.qvel,
            "base_pose": self.base_pose,
            "control_mode": self._control_mode,
            "controller": self.controller.get_state(),
        }

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state` (joints, free base, control mode, controller targets)."""
        where = f"{type(self).__name__}.set_state"
        missing = [k for k in ("qpos", "qvel", "control_mode", "controller") if k not in state]
        if missing:
            raise StateError(f"{where}: expected keys qpos, qvel, control_mode, controller; missing {missing}.")
        qpos = self._batch(state["qpos"], self.num_envs, self.dof, "qpos", where)
        qvel = self._batch(state["qvel"], self.num_envs, self.dof, "qvel", where)
        base = self._batch(state["base_pose"], self.num_envs, 7, "base_pose", where) if "base_pose" in state else None
        if state["control_mode"] not in self.control_modes:
            raise UnknownNameError(where, "control mode", str(state["control_mode"]), self.control_modes)
        self.controller_for(state["control_mode"]).check_state(state["controller"], where)
        self.set_control_mode(state["control_mode"])
        for env, data in enumerate(self.world.datas):
            data.qpos[self.qpos_adr] = qpos[env]
            data.qvel[self.dof_adr] = qvel[env]
            if base is not None and self._free_qpos_adr >= 0:
                data.qpos[self._free_qpos_adr : self._free_qpos_adr + 7] = base[env]
            mujoco.mj_forward(self.world.model, data)
        self.world.invalidate()
        self.controller.set_state(state["controller"])

    # ------------------------------------------------------------------ helpers
    def is_static(self, threshold: float = 0.2) -> BoolArray:
        """Per env: every joint except the gripper's moves slower than ``threshold`` (rad/s or m/s)."""
        qvel = self.world.qvel[:, self._static_dofs]
        return np.asarray(np.max(np.abs(qvel), axis=1, initial=0.0) <= threshold)

    def is_grasping(self, body: str, min_force: float = 0.5, max_angle: float = 85.0) -> BoolArray:
        """Per env: both fingers press on ``body`` (a scene body name) inward.

        A finger grasps when the total contact force it exerts on the body exceeds
        ``min_force`` (N) and, for sliding fingers, points within ``max_angle`` degrees of
        its closing direction (the negative axis of its slide joint).
        """
        if self.finger_links is None:
            raise ConfigError(f"{type(self).__name__}: is_grasping needs finger_links; this robot declares none.")
        model = self.world.model
        target = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if target < 0:
            raise UnknownNameError(
                f"{type(self).__name__}.is_grasping", "body", body, [model.body(b).name for b in range(model.nbody)]
            )
        fingers = self._finger_body_ids
        cos_limit = math.cos(math.radians(max_angle))
        result = np.zeros(self.num_envs, dtype=bool)
        for env, data in enumerate(self.world.datas):
            grasped = []
            for finger in fingers:
                force = contact_force_between(model, data, finger, target)
                magnitude = float(np.linalg.norm(force))
                ok = magnitude >= min_force
                joint = model.body_jntadr[finger]
                if ok and joint >= 0 and model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_SLIDE:
                    closing = -data.xaxis[joint]
                    ok = float(force @ closing) >= cos_limit * magnitude
                grasped.append(ok)
            result[env] = all(grasped)
        return result
