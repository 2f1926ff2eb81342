"""A robot class's declaration, composed and checked.

A robot is declared by class attributes (see :class:`~robot_agents.agent.Agent`);
pieces mounted on it (:class:`~robot_agents.model.compose.Attachment`) bring their
own declarations, renamed with the attachment's prefix. This module merges them
(:func:`composition`), builds the robot's ``MjSpec`` (:func:`build_spec`) and checks
everything against the compiled robot once per class (:func:`check`): parts, drives,
end effectors, fingers, keyframes (names, sizes, limits, quaternions) and control modes.
"""

from __future__ import annotations

import dataclasses
import os
import re
import warnings
import weakref
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from robot_agents.actuators.config import ActuatorConfig
from robot_agents.actuators.gains import friction_gains, gains_from_inertia, gains_over_configurations, grip_gains
from robot_agents.actuators.spec import DerivedGains, DriveDeclaration, apply_actuators
from robot_agents.agent.attribute_names import check_attribute_names
from robot_agents.agent.derived import (
    DERIVED_SOURCE,
    infer_gripper,
    infer_parts,
    resting_base,
    self_contacts,
    torque_only,
    undamped,
    velocity_servos,
)
from robot_agents.agent.derived_drives import drive_configurations, note_friction_cap, stand
from robot_agents.agent.derived_task_space import derive_task_space, note_unlimited_slides, unlimited_slides
from robot_agents.agent.index import JointKind, RobotIndex
from robot_agents.agent.mount_task_space import mount_task_space
from robot_agents.controllers.base import ControllerConfig
from robot_agents.controllers.task_space import FloatingMountTaskSpace, MeasuredTaskSpace
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.keyframe import (
    Keyframe,
    ResolvedKeyframe,
    default_qpos,
    file_keyframe,
    file_keyframe_aliases,
    file_keyframe_names,
    resolve_keyframe,
)
from robot_agents.kinematics.forward import FrameKind, resolve_frame
from robot_agents.model import robot_spec
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.compiling import compile_spec
from robot_agents.model.compose import Attachment, attach
from robot_agents.model.decompose import Decomposition, decompose, note_nonconvex_fingers
from robot_agents.model.fallbacks import compile_with_fallbacks
from robot_agents.model.load_scope import load_spec, one_read_per_file
from robot_agents.model.loading import urdf_velocity_limits
from robot_agents.model.materials import FrictionMaterial
from robot_agents.model.scene import FRICTION_CONES, ROBOT_JACOBIANS
from robot_agents.parts.declaration import Arm, Base, Body, EndEffector, Gripper, Hand, Legs, Part, is_jaw_gripper
from robot_agents.patterns import claim, prefixed
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.spec import add_cameras, add_touch_sensors
from robot_agents.sensors.touch import TouchSensorConfig
from robot_agents.validation import check_pose, outside_limits

if TYPE_CHECKING:
    from robot_agents.agent.definition import AgentDefinition

ModeConfig = ControllerConfig | Mapping[str, ControllerConfig]
#: Part name used when a control mode is a single config rather than a dict of parts.
SINGLE_PART = "main"


@dataclass(frozen=True)
class Composition:
    """Everything a robot and the pieces mounted on it declare, names as in the composed model."""

    actuators: tuple[ActuatorConfig, ...]
    parts: tuple[Part, ...]
    link_materials: dict[str, FrictionMaterial]
    self_collision_exclusions: tuple[tuple[str, str], ...]
    cameras: tuple[CameraConfig, ...]
    touch_sensors: tuple[TouchSensorConfig, ...]
    #: (prefix, piece class) of every mounted piece, outermost first.
    pieces: tuple[tuple[str, type[AgentDefinition]], ...]


def _label(name: str, prefix: str) -> str:
    """A piece's own name (a part's, a sensor's uid) under attachment ``prefix``:
    ``"left/"`` + ``"gripper"`` -> ``"left_gripper"`` (no ``/``, which separates robot
    ids from sensor uids); unchanged without a prefix."""
    label = re.sub(r"\W+", "_", prefix).strip("_")
    return f"{label}_{name}" if label else name


def _prefix_part(part: Part, prefix: str) -> Part:
    """``part`` of a piece attached with ``prefix``: its names prefixed, and its own name
    too (``"left/"`` + ``"gripper"`` -> ``"left_gripper"``), so two hands can coexist."""
    if not prefix:
        return part
    changes: dict[str, Any] = {"joints": prefixed(part.joints, prefix), "name": _label(part.name, prefix)}
    end_effectors = getattr(part, "end_effectors", None)
    if end_effectors:
        changes["end_effectors"] = tuple(
            dataclasses.replace(
                ee,
                link=prefix + ee.link,
                command_frame=None if ee.command_frame is None else prefix + ee.command_frame,
            )
            for ee in end_effectors
        )
    if isinstance(part, Gripper):
        changes["fingers"] = tuple(tuple(prefix + link for link in finger) for finger in part.finger_links)
        if part.grasp_frame is not None:
            changes["grasp_frame"] = prefix + part.grasp_frame
    if isinstance(part, Hand) and part.power_grasp is not None:
        changes["power_grasp"] = dataclasses.replace(part.power_grasp, link=prefix + part.power_grasp.link)
    return dataclasses.replace(part, **changes)


def composition(cls: type[AgentDefinition]) -> Composition:
    """The robot's declarations merged with those of every mounted piece."""
    actuators = list(cls.actuators)
    parts = list(cls.parts)
    materials = dict(cls.link_materials)
    exclusions = list(cls.self_collision_exclusions)
    cameras = list(cls.cameras)
    touch = list(cls.touch_sensors)
    pieces: list[tuple[str, type[AgentDefinition]]] = []
    for attachment in cls.attachments:
        if not isinstance(attachment, Attachment):
            raise ConfigError(f"{cls.__name__}.attachments: expected Attachment entries, got {attachment!r}.")
        if attachment.piece.collision_links is not None:
            raise ConfigError(
                f"{cls.__name__}.attachments: piece {attachment.piece.__name__} declares collision_links, which "
                "applies to a whole robot; declare them on the robot it is mounted on instead, with the piece's "
                f"bodies under its prefix {attachment.prefix!r}."
            )
        inner = composition(attachment.piece)
        p = attachment.prefix
        actuators += [dataclasses.replace(a, joints=prefixed(a.joints, p)) for a in inner.actuators]
        parts += [_prefix_part(part, p) for part in inner.parts]
        materials.update({p + name: m for name, m in inner.link_materials.items()})
        exclusions += [(p + a, p + b) for a, b in inner.self_collision_exclusions]
        # A piece's sensors are named like its parts (two copies of one piece: two of each).
        cameras += [dataclasses.replace(c, uid=_label(c.uid, p), mount=p + c.mount) for c in inner.cameras]
        touch += [
            dataclasses.replace(
                t,
                uid=_label(t.uid, p),
                link=None if t.link is None else p + t.link,
                site=None if t.site is None else p + t.site,
            )
            for t in inner.touch_sensors
        ]
        pieces.append((p, attachment.piece))
        pieces += [(p + q, piece) for q, piece in inner.pieces]
    return Composition(
        tuple(actuators), tuple(parts), materials, tuple(exclusions), tuple(cameras), tuple(touch), tuple(pieces)
    )


def model_path(cls: type[AgentDefinition]) -> Path:
    """The declared model file (not checked for existence)."""
    for attr in ("mjcf_path", "urdf_path"):
        value = getattr(cls, attr)
        if value is not None and not isinstance(value, (str, os.PathLike)):
            raise ConfigError(f"{cls.__name__}.{attr}: expected a file path (str or pathlib.Path), got {value!r}.")
    paths = [p for p in (cls.mjcf_path, cls.urdf_path) if p is not None]
    if len(paths) != 1:
        raise ConfigError(
            f"{cls.__name__}: expected exactly one of mjcf_path / urdf_path, got mjcf_path={cls.mjcf_path!r}, "
            f"urdf_path={cls.urdf_path!r}."
        )
    return Path(paths[0])


def mount_pose(cls: type[AgentDefinition]) -> tuple[float, ...]:
    """The declared ``mount_pose`` checked: 7 finite numbers ``(x, y, z, qw, qx, qy, qz)``
    (m) with a nonzero quaternion, returned with the quaternion normalized (as
    ``robot_poses`` are)."""
    return check_pose(cls.mount_pose, f"{cls.__name__}.mount_pose")


def mode_parts(cls: type[AgentDefinition], modes: Mapping[str, ModeConfig], mode: str) -> dict[str, ControllerConfig]:
    """The per-part configs of a control mode (a single config becomes part ``"main"``)."""
    if mode not in modes:
        raise UnknownNameError(f"{cls.__name__}", "control mode", str(mode), modes)
    entry = modes[mode]
    return {SINGLE_PART: entry} if isinstance(entry, ControllerConfig) else dict(entry)


def validate_definition(cls: type[AgentDefinition]) -> None:
    """Check the declaration's types and internal consistency without loading a model."""
    name = cls.__name__
    definition = next(k for k in cls.__mro__ if k.__module__ == "robot_agents.agent.definition")
    check_attribute_names(cls, sorted(definition.__annotations__))  # first: a misspelt name explains the rest
    model_path(cls)
    freq = cls.sim_freq
    if freq is not None and (isinstance(freq, bool) or not isinstance(freq, int) or freq <= 0):
        raise ConfigError(f"{name}.sim_freq: expected a positive integer (Hz) or None, got {freq!r}.")
    for flag in ("fix_root_link", "disable_self_collisions", "replace_file_actuators", "convex_decomposition"):
        if not isinstance(getattr(cls, flag), bool):
            raise ConfigError(f"{name}: expected {flag} to be a bool, got {getattr(cls, flag)!r}.")
    links = cls.collision_links
    if links is not None and (
        isinstance(links, str) or not isinstance(links, Sequence) or not all(isinstance(b, str) and b for b in links)
    ):
        raise ConfigError(f"{name}.collision_links: expected a tuple of body names or None, got {links!r}.")
    if cls.rest_on_floor is not None and not isinstance(cls.rest_on_floor, bool):
        raise ConfigError(f"{name}: expected rest_on_floor to be a bool or None, got {cls.rest_on_floor!r}.")
    gravcomp = cls.gravity_compensation
    if not (
        gravcomp is None
        or isinstance(gravcomp, bool)
        or (
            isinstance(gravcomp, Sequence)
            and not isinstance(gravcomp, str)
            and all(isinstance(b, str) for b in gravcomp)
        )
    ):
        raise ConfigError(
            f"{name}: expected gravity_compensation to be a bool, None or a tuple of body names, got {gravcomp!r}."
        )
    mount_pose(cls)
    if cls.tcp is not None and (not isinstance(cls.tcp, str) or not cls.tcp):
        raise ConfigError(f"{name}.tcp: expected a body or site name, or None, got {cls.tcp!r}.")
    if cls.friction_cone not in (None, *FRICTION_CONES):
        raise ConfigError(f"{name}.friction_cone: expected one of {FRICTION_CONES} or None, got {cls.friction_cone!r}.")
    ratio = cls.impratio
    if ratio is not None and (isinstance(ratio, bool) or not isinstance(ratio, (int, float)) or not ratio >= 1.0):
        raise ConfigError(f"{name}.impratio: expected a number >= 1 or None, got {ratio!r}.")
    tol = cls.solver_tolerance
    if tol is not None and (isinstance(tol, bool) or not isinstance(tol, (int, float)) or not 0.0 < tol < 1.0):
        raise ConfigError(f"{name}.solver_tolerance: expected a number in (0, 1) or None, got {tol!r}.")
    if cls.jacobian not in (None, *ROBOT_JACOBIANS):
        raise ConfigError(f"{name}.jacobian: expected one of {ROBOT_JACOBIANS} or None, got {cls.jacobian!r}.")
    for attr, kind in (
        ("actuators", ActuatorConfig),
        ("parts", Part),
        ("cameras", CameraConfig),
        ("touch_sensors", TouchSensorConfig),
        ("attachments", Attachment),
    ):
        value = getattr(cls, attr)
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise ConfigError(f"{name}.{attr}: expected a tuple of {kind.__name__}, got {value!r}.")
        for entry in value:
            if not isinstance(entry, kind):
                raise ConfigError(f"{name}.{attr}: expected {kind.__name__} entries, got {entry!r}.")
    for attr in ("cameras", "touch_sensors"):
        uids = [entry.uid for entry in getattr(cls, attr)]
        for uid in uids:
            if uids.count(uid) > 1:
                raise ConfigError(f"{name}.{attr}: two entries have the uid {uid!r}.")
    part_names = [p.name for p in cls.parts]
    for part in part_names:
        if part_names.count(part) > 1:
            raise ConfigError(f"{name}.parts: two parts are named {part!r}.")
    if not isinstance(cls.keyframes, Mapping):
        raise ConfigError(f"{name}.keyframes: expected a dict of name -> Keyframe, got {cls.keyframes!r}.")
    for key, frame in cls.keyframes.items():
        if not isinstance(key, str) or not key:
            raise ConfigError(f"{name}.keyframes: expected non-empty names (str), got {key!r}.")
        if not isinstance(frame, Keyframe):
            raise ConfigError(f"{name}.keyframes[{key!r}]: expected a Keyframe, got {frame!r}.")
    if not isinstance(cls.control_modes, Mapping):
        raise ConfigError(f"{name}.control_modes: expected a dict of mode name -> config, got {cls.control_modes!r}.")
    if cls.default_control_mode is not None and not isinstance(cls.default_control_mode, str):
        raise ConfigError(
            f"{name}.default_control_mode: expected a mode name (str) or None, got {cls.default_control_mode!r}."
        )
    for mode, entry in cls.control_modes.items():
        if not isinstance(mode, str) or not mode:
            raise ConfigError(f"{name}.control_modes: expected non-empty mode names (str), got {mode!r}.")
        if not isinstance(entry, (ControllerConfig, Mapping)) or (isinstance(entry, Mapping) and not entry):
            raise ConfigError(
                f"{name}.control_modes[{mode!r}]: expected a ControllerConfig or a non-empty dict of part name -> "
                f"ControllerConfig, got {entry!r}."
            )
    for mode in cls.control_modes:
        seen: dict[str, str] = {}
        for part, config in mode_parts(cls, cls.control_modes, mode).items():
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


def _raw_spec(
    cls: type[AgentDefinition], where: str, compiler: CompilerSettings | None = None, attached: bool = True
) -> tuple[mujoco.MjSpec, frozenset[str]]:
    """The model file, as the class's :meth:`~AgentDefinition.edit_model` leaves it, with
    every mounted piece attached (no options applied yet; the file alone with
    ``attached=False``), and the names of the joints of the robot's own
    file (not of its pieces)."""
    spec = load_spec(model_path(cls), compiler if compiler is not None else cls.compiler)
    cls.edit_model(spec, where)
    own = frozenset(j.name for j in spec.joints)
    for attachment in cls.attachments if attached else ():
        attach(spec, _raw_spec(attachment.piece, where)[0], attachment, where)
    return spec, own


def _with_task_space(
    part: Part,
    model: mujoco.MjModel,
    index: RobotIndex,
    part_joints: Mapping[str, Sequence[str]],
    keyframe: np.ndarray,
    name: str,
    derived: bool = True,
) -> Part:
    """``part`` with the task space measured on it (end-effector modes,
    :func:`~robot_agents.agent.derived_task_space.derive_task_space`): a derived arm
    (``derived``: the parts were inferred) without one when it gets one, and an arm
    declared with ``MeasuredTaskSpace()``, which must; a floating mount declared with
    ``FloatingMountTaskSpace()`` gets its box computed
    (:func:`~robot_agents.agent.mount_task_space.mount_task_space`)."""
    if not isinstance(part, Arm):
        return part
    if isinstance(part.task_space, FloatingMountTaskSpace):
        mount = mount_task_space(model, index, part, part.task_space, part_joints[part.name], keyframe, name)
        return dataclasses.replace(part, task_space=mount)
    asked = isinstance(part.task_space, MeasuredTaskSpace)
    if not asked and (part.task_space is not None or not derived):
        return part
    space = derive_task_space(model, index, part, part_joints[part.name], keyframe, name)
    if space is not None:
        slides = unlimited_slides(model, index, part_joints[part.name], name)
        if slides:
            note_unlimited_slides(name, part, slides, space)
    if space is None and asked:
        raise ConfigError(
            f"{name}.parts[{part.name!r}]: MeasuredTaskSpace() cannot be measured on this arm: end-effector modes "
            "need 3 or more hinge or slide joints and an end effector that the joints move; got joints "
            f"{list(part_joints[part.name])} and end effectors {[ee.link for ee in part.end_effectors]}."
        )
    return part if space is None else dataclasses.replace(part, task_space=space)


def _decomposes(cls: type[AgentDefinition]) -> bool:
    """Whether the robot or a piece mounted on it asks for ``convex_decomposition``."""
    return cls.convex_decomposition or any(piece.convex_decomposition for _, piece in composition(cls).pieces)


#: Each class's decomposition per compiler settings, redone on its later builds without
#: compiling the spec again (:func:`robot_agents.model.decompose.decompose`).
_DECOMPOSED: weakref.WeakKeyDictionary[type, dict[CompilerSettings, Decomposition]] = weakref.WeakKeyDictionary()


def _build(
    cls: type[AgentDefinition],
    cameras: Sequence[CameraConfig] | None,
    derived: DerivedGains | None,
    compiler: CompilerSettings | None = None,
    exclusions: Sequence[tuple[str, str]] = (),
    quiet: bool = False,
    pads: Sequence[str] = (),
) -> tuple[mujoco.MjSpec, list[DriveDeclaration]]:
    """The robot's spec and drives. ``quiet``: without the load notes (dropped meshes,
    bodies and shapes, replaced actuators), which :func:`check` gives once per class;
    every later build of the same robot would repeat them. ``pads``: bodies that get
    stiff pad contact (a derived gripper's fingers, :attr:`CheckedRobot.derived_pads`)."""
    if quiet:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return _build(cls, cameras, derived, compiler, exclusions, pads=pads)
    validate_definition(cls)
    where = f"{cls.__name__} ({model_path(cls)})"
    parts = composition(cls)
    spec, own_joints = _raw_spec(cls, where, compiler)
    mocap_held = robot_spec.isolate_robot(spec, cls.root_body, where)
    from robot_agents.agent.definition import AgentDefinition  # (imports this module)

    declared = any("fix_root_link" in vars(k) for k in cls.__mro__ if k is not AgentDefinition)
    robot_spec.set_root_joint(spec, cls.fix_root_link, where, declared)
    gravcomp = cls.fix_root_link if cls.gravity_compensation is None else cls.gravity_compensation
    robot_spec.set_gravity_compensation(spec, gravcomp, where)
    robot_spec.keep_collisions(spec, cls.collision_links, where)
    robot_spec.set_materials(spec, parts.link_materials, cls.default_material, where)
    robot_spec.set_pad_contact(spec, [b for b in pads if b not in parts.link_materials], where)
    if derived is not None:  # derived drives: the file's stops get stiff too
        robot_spec.set_stiff_stops(spec)
    robot_spec.set_self_collisions(
        spec, cls.disable_self_collisions, (*parts.self_collision_exclusions, *exclusions), where
    )
    if _decomposes(cls):
        settings = compiler if compiler is not None else cls.compiler
        done = _DECOMPOSED.setdefault(cls, {})
        done[settings] = decompose(spec, where, done.get(settings))
    drives = apply_actuators(
        spec,
        parts.actuators,
        cls.replace_file_actuators,
        derived,
        cls.__name__,
        own_joints,
        derive_own=not cls.actuators,
        motors_as_pd=not cls.control_modes,
        mocap_held=mocap_held,
        file_speeds=urdf_velocity_limits(model_path(cls)),
    )
    add_cameras(spec, parts.cameras if cameras is None else cameras, f"{cls.__name__}.cameras")
    add_touch_sensors(spec, parts.touch_sensors, f"{cls.__name__}.touch_sensors")
    return spec, drives


def build_spec(cls: type[AgentDefinition], cameras: Sequence[CameraConfig] | None = None) -> mujoco.MjSpec:
    """A fresh MjSpec of the composed robot with every declared (or derived) option
    applied. ``cameras`` replaces the declared cameras (an env's overrides)."""
    with one_read_per_file():  # a class not checked yet: its check's reads are the build's
        checked = check(cls)
        return _build(
            cls,
            cameras,
            checked.derived_gains,
            checked.compiler,
            checked.derived_exclusions,
            quiet=True,
            pads=checked.derived_pads,
        )[0]


@dataclass(frozen=True)
class CheckedRobot:
    """A robot class checked against its compiled model (alone, at the origin).

    Attributes:
        index: names to addresses in the robot's own model (prefix ``""``).
        drives: the drive of each driven joint.
        keyframes: every keyframe resolved to the robot's vectors (a robot that declares
            none gets ``"default"`` and its file's other keyframes: see :func:`check`).
        part_joints: each part's joints, in model order.
        parts: the parts (declared, mounted pieces', or inferred).
        modes: the control-mode table (declared, or generated from the parts).
        default_mode: the mode a robot starts in.
        derived_gains: gains of drives derived from the model's inertia (``None`` when
            the robot or its file declares drives).
        compiler: the compiler settings the model compiled with (the declared ones, or
            those the check fell back to for a known compile failure).
        derived_exclusions: body pairs in contact at the default keyframe of a robot
            that declares no self-collision filtering (MoveIt's "default" collisions).
        mount_pose: where a scene puts the robot by default: the declared
            ``mount_pose``; for a fixed-base robot that declares none and would reach
            more than 5 mm into the floor at its default keyframe (a hand, a gripper),
            raised to rest 1 mm above it.
        keyframe_aliases: other names of keyframes, alias -> keyframe name: for a robot
            declaring no keyframes, its file's own name of the first (``{"home":
            "default"}``; :func:`~robot_agents.keyframe.file_keyframe_aliases`).
        derived_pads: the finger bodies of a gripper the file implies, whose colliding
            geoms get the built-in Panda's stiff fingertip contact
            (:func:`robot_agents.model.robot_spec.set_pad_contact`; a body the robot
            gives a ``link_materials`` entry keeps that instead).
    """

    index: RobotIndex
    drives: tuple[DriveDeclaration, ...]
    keyframes: dict[str, ResolvedKeyframe]
    part_joints: dict[str, tuple[str, ...]]
    parts: tuple[Part, ...]
    modes: dict[str, ModeConfig]
    default_mode: str
    derived_gains: DerivedGains | None = None
    compiler: CompilerSettings | None = None
    derived_exclusions: tuple[tuple[str, str], ...] = ()
    mount_pose: tuple[float, ...] = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    derived_pads: tuple[str, ...] = ()
    keyframe_aliases: dict[str, str] = dataclasses.field(default_factory=dict)

    def keyframe_name(self, name: str) -> str | None:
        """The keyframe ``name`` is (itself or the one it is an alias of), ``None`` when none."""
        name = self.keyframe_aliases.get(name, name)
        return name if name in self.keyframes else None

    def keyframe_choices(self) -> list[str]:
        """Every name a keyframe answers to: the keyframes', then the aliases."""
        return [*self.keyframes, *self.keyframe_aliases]


_CHECKED: weakref.WeakKeyDictionary[type, CheckedRobot] = weakref.WeakKeyDictionary()


def check(cls: type[AgentDefinition]) -> CheckedRobot:
    """Compile the robot alone and check its whole declaration against it (cached per class).

    What a robot does not declare is derived here: parts (a serial chain becomes an
    arm whose last body is the end effector, with a task space measured on it; fingers
    at its end a gripper whose finger geoms get stiff pad contact; with pieces mounted,
    the robot's own joints are inferred so, beside the pieces' parts, and an arm ends at
    the ``tcp`` of the piece below it), a ``"default"``
    keyframe (the file's first keyframe or the model's pose, values outside the limits
    moved inside them; a floating robot resting on the floor) and the file's other
    keyframes under their names (:func:`~robot_agents.keyframe.file_keyframe_names`),
    drives (PD gains from
    the model's inertia, over the joints' ranges for a fixed robot, when neither the
    robot nor its file has any, beside its pieces' drives; sliding fingers pressing with
    their effort limit),
    control modes (from the parts: joint and end-effector modes) and the default mode
    (a delta mode).

    Raises:
        ConfigError / UnknownNameError / ModelError: what is wrong, where (the robot,
            the keyframe, the part, the actuator), and what is available.
    """
    cached = _CHECKED.get(cls)
    if cached is not None:
        return cached
    with one_read_per_file():  # the robot's and its pieces' files parsed once each
        checked = _check(cls)
    _CHECKED[cls] = checked
    return checked


def _check(cls: type[AgentDefinition]) -> CheckedRobot:
    """:func:`check`, uncached."""
    name = cls.__name__
    compiler = cls.compiler
    spec, drives = _build(cls, None, None, compiler)
    model, compiler = compile_with_fallbacks(
        name,
        spec,
        compiler,
        lambda settings: _build(cls, None, None, settings, quiet=True)[0],
        model_path(cls),
        pieces=bool(cls.attachments),
    )
    if compiler is not cls.compiler:
        spec, drives = _build(cls, None, None, compiler, quiet=True)
    index = RobotIndex(model, "", name)
    composed = composition(cls)
    parts = composed.parts
    if cls.tcp is not None:
        resolve_frame(model, cls.tcp, "", f"{name}.tcp")
    # parts the robot's own joints imply, beside those its pieces declare
    inferred = not cls.parts and not cls.control_modes
    own_parts: tuple[Part, ...] = ()
    if inferred:
        piece_joints, piece_bodies = _piece_names(composed)
        parts = parts + _pieces_own_parts(composed, {d.joint for d in drives})
        held = any(isinstance(p, (Gripper, Hand)) for p in parts)  # a piece's gripper is the gripper
        own_driven = [d.joint for d in drives if d.joint not in piece_joints]
        file_fingers: list[str] = []
        if held and own_driven:
            # the file's own fingers beside a mounted gripper: out of the arm (whose end
            # effector would sit on a finger), in no part, with a note naming them
            own_driven, file_fingers = _file_gripper_beside_piece(cls, compiler, index, own_driven, composed)
        own_parts = infer_parts(model, index, own_driven, grippers=not held)
        own_parts = tuple(_to_piece_tool(p, composed, piece_bodies, model, index) for p in own_parts)
        if not _decomposes(cls):
            note_nonconvex_fingers(name, model, own_parts)
        parts = own_parts + parts
    part_joints = _resolve_parts(cls, parts, index, model)
    if inferred:
        in_parts = {joint for joints in part_joints.values() for joint in joints}
        idle = [d.joint for d in drives if d.joint not in in_parts and d.joint not in file_fingers]
        if idle:  # a mounted piece's arm: its parts are not inferred
            warnings.warn(
                f"{name}: joints {idle[:6]}{' ...' if len(idle) > 6 else ''} have drives and are in none of the "
                "robot's inferred parts: no control mode commands them (they hold their default pose); declare "
                "parts to command them.",
                RuntimeWarning,
                stacklevel=3,
            )
    keyframes = {}
    aliases: dict[str, str] = {}
    mount = mount_pose(cls)
    # a floating robot's mount turns it (a file drawn y-up stands under a mount turned about x)
    mount_quat = None if tuple(mount[3:]) == (1.0, 0.0, 0.0, 0.0) else np.array(mount[3:])
    if cls.keyframes:
        default = _composed_default(cls, index)
        for key, frame in cls.keyframes.items():
            keyframes[key] = resolve_keyframe(frame, index, f"{name}.keyframes[{key!r}]", default)
    else:  # every keyframe of the file, the first as "default" (file_keyframe_names), with its velocities
        aliases = file_keyframe_aliases(model)
        _note_file_activations(name, index)
        for number, key in enumerate(file_keyframe_names(model)):
            default = _composed_default(cls, index, number)
            _note_file_keyframe_moved(name, index, default, number)
            frame = file_keyframe(model, index, number)
            keyframes[key] = resolve_keyframe(frame, index, f"{name}.keyframes[{key!r}]", default)
            if index.free_joint is not None:
                base = resting_base(model, index, keyframes[key].qpos, mount_quat, number)
                keyframes[key] = dataclasses.replace(keyframes[key], base=base)
    from robot_agents.agent.definition import AgentDefinition  # (imports this module)

    # the robot's own classes, wherever AgentDefinition (whose default this is) sits in the MRO
    declared_mount = any("mount_pose" in vars(k) for k in cls.__mro__ if k is not AgentDefinition)
    on_floor = not declared_mount if cls.rest_on_floor is None else cls.rest_on_floor
    if index.free_joint is None and on_floor:
        # the lowest point as the mount turns and places it
        lift = float(resting_base(model, index, next(iter(keyframes.values())).qpos, mount_quat)[2]) - mount[2]
        if lift > 0.006:
            mount = (mount[0], mount[1], mount[2] + lift, *mount[3:])
    exclusions: tuple[tuple[str, str], ...] = ()
    if not cls.disable_self_collisions and not composed.self_collision_exclusions:
        exclusions = self_contacts(model, index, next(iter(keyframes.values())).qpos)
        if exclusions:
            warnings.warn(
                f"{name}: {len(exclusions)} body pair(s) touch at the default keyframe and will not collide with each "
                f"other: {list(exclusions)[:4]}{' ...' if len(exclusions) > 4 else ''} (declare "
                "self_collision_exclusions to choose yourself).",
                RuntimeWarning,
                stacklevel=3,
            )
    derived: DerivedGains | None = None
    derived_joints = [d.joint for d in drives if d.source.startswith(DERIVED_SOURCE)]
    if derived_joints:
        full = model.qpos0.copy()
        full[index.qpos_adr] = next(iter(keyframes.values())).qpos
        from robot_agents.sim.scene import DEFAULT_SIM_FREQ

        timestep = 1.0 / int(cls.sim_freq or DEFAULT_SIM_FREQ)
        driven_joints = [d.joint for d in drives]
        if index.free_joint is None:  # a fixed base: gains that hold over the joints' whole ranges
            configurations = drive_configurations(model, index, driven_joints, full)
            gains = gains_over_configurations(model, derived_joints, configurations, timestep)
        else:  # a floating robot: gains at its pose (its stance stiffens the legs below)
            gains = gains_from_inertia(model, derived_joints, full)
        # sliding fingers press with their motor's force, not a light finger's spring (hinged
        # jaws and linkages keep their inertia gains: their torque reaches the object
        # through levers, and a linkage's loop gives under a full-effort squeeze)
        strokes: dict[str, float] = {}
        unbounded: list[str] = []  # jaws and fingers the file gives no effort: pressing is their job
        for gripper in (p for p in parts if is_jaw_gripper(p)):
            names = part_joints[gripper.name]
            opened, closed = gripper.positions(len(names))
            if all(j in driven_joints for j in names):  # not a linkage (its loop gives under a squeeze)
                unbounded.extend(j for j in names if j in derived_joints)
            strokes.update(
                {
                    j: float(abs(o - c))
                    for j, o, c in zip(names, opened, closed, strict=True)
                    if j in derived_joints and index.joint(j, name).kind is JointKind.SLIDE
                }
            )
        gains, _ = grip_gains(gains, strokes, timestep, unbounded)
        # dry friction in the file (frictionloss) would stall inertia gains short of their targets
        gains, capped = friction_gains(gains, timestep)
        if capped:
            note_friction_cap(name, index, gains, capped, timestep)
        if index.free_joint is not None and len(derived_joints) == len(drives):
            # the stance is found with the robot's self-collision filtering
            filtered = _build(cls, None, None, compiler, exclusions, quiet=True)[0] if exclusions else spec
            gains, legs = stand(
                name,
                filtered,
                index,
                gains,
                next(iter(keyframes.values())).qpos,
                timestep,
                cls.friction_cone or "pyramidal",
                mount_quat,
            )
            if legs and inferred and len(parts) == 1 and isinstance(parts[0], (Body, Hand)):
                # a floating robot standing on bodies below its joints: those joints are its
                # legs (a quadruped's four short legs below its trunk were inferred a hand)
                rest = [j for j in part_joints[parts[0].name] if j not in legs]
                parts = (Legs(name="legs", joints=tuple(re.escape(j) for j in legs)),) + (
                    (Body(name="body", joints=tuple(re.escape(j) for j in rest)),) if rest else ()
                )
                part_joints = _resolve_parts(cls, parts, index, model)
        derived = {
            j: (float(kp), float(kv), float(lim))
            for j, kp, kv, lim in zip(gains.joints, gains.stiffness, gains.damping, gains.effort_limit, strict=True)
        }
        drives = [
            dataclasses.replace(
                d, stiffness=derived[d.joint][0], damping=derived[d.joint][1], effort_limit=derived[d.joint][2]
            )
            if d.joint in derived
            else d
            for d in drives
        ]
    measured = any(
        isinstance(p, Arm) and isinstance(p.task_space, (MeasuredTaskSpace, FloatingMountTaskSpace)) for p in parts
    )
    if (inferred and not torque_only(model, drives)) or measured:
        # an arm the file implies (or one declared so) gets a task space measured on it
        keyframe = next(iter(keyframes.values())).qpos
        parts = tuple(
            _with_task_space(part, model, index, part_joints, keyframe, name, part in own_parts) for part in parts
        )
    driven = {d.joint for d in drives}
    for declared in parts:
        if not any(joint in driven for joint in part_joints[declared.name]):
            raise ConfigError(
                f"{name}.parts[{declared.name!r}]: none of its joints {list(part_joints[declared.name])} has a drive, so no "
                "control mode could move it; declare actuators for them (ra.DerivedActuators() derives gains from "
                "the model; a mounted piece's actuators drive the piece's joints only)."
            )
    from robot_agents.controllers.rules import modes_from_parts

    modes: dict[str, ModeConfig] = (
        dict(cls.control_modes)
        if cls.control_modes
        else modes_from_parts(
            parts,
            part_joints,
            {d.joint: d.velocity_limit for d in drives},
            torque_only=torque_only(model, drives),
            undamped=undamped(model, drives),
            velocity_only=velocity_servos(model, drives),
            effort_limits={d.joint: d.effort_limit for d in drives},
            motor_joints=[d.joint for d in drives if d.replaces_motor],
        )
    )
    if not modes:
        raise ConfigError(f"{name}: no control mode: declare control_modes, or parts with driven joints.")
    if cls.default_control_mode is not None and cls.default_control_mode not in modes:
        raise UnknownNameError(f"{name}.default_control_mode", "control mode", cls.default_control_mode, modes)
    # legs carrying the robot take deltas from their targets (a delta from the measured
    # pose would let them give under the body's weight step by step)
    derived_mode = "pd_joint_target_delta_pos" if any(isinstance(p, Legs) for p in parts) else "pd_joint_delta_pos"
    default_mode = cls.default_control_mode or (
        derived_mode if not cls.control_modes and derived_mode in modes else next(iter(modes))
    )
    for mode in modes:
        for part, config in mode_parts(cls, modes, mode).items():
            for joint in config.joint_names:
                if joint not in index.joint_names:
                    raise UnknownNameError(
                        f"{name}.control_modes[{mode!r}][{part!r}] {type(config).__name__}",
                        "joint",
                        joint,
                        index.joint_names,
                    )
                if joint not in driven:
                    raise ConfigError(
                        f"{name}.control_modes[{mode!r}][{part!r}]: joint {joint!r} has no drive; declare one in "
                        f"actuators. Driven joints: {sorted(driven)}."
                    )
    checked = CheckedRobot(
        index,
        tuple(drives),
        keyframes,
        part_joints,
        tuple(parts),
        modes,
        default_mode,
        derived,
        compiler,
        exclusions,
        mount,
        # a derived gripper's fingers (a derived hand's links keep the file's contacts)
        derived_pads=tuple(
            dict.fromkeys(link for p in own_parts if is_jaw_gripper(p) for f in p.finger_links for link in f)
        ),
        keyframe_aliases=aliases,
    )
    return checked


def _file_gripper_beside_piece(
    cls: type[AgentDefinition],
    compiler: CompilerSettings,
    index: RobotIndex,
    driven: list[str],
    composed: Composition,
) -> tuple[list[str], list[str]]:
    """``driven`` (the robot's own driven joints, a gripper piece mounted on it) less
    the joints of a gripper its own file has (:func:`infer_gripper` on the file alone,
    compiled without the pieces: a piece mounted on the hand moves there, which the
    linkage and one-jaw rules refuse), and those finger joints with their followers
    (empty when it has none). The piece is the robot's gripper: the file's fingers stay
    out of the arm, whose end effector is the piece's ``tcp`` (on a finger before), in
    no part, holding their default pose; a note names them."""
    name = cls.__name__
    alone = type(name, (cls,), {"attachments": ()})
    spec, drives = _build(alone, None, None, compiler, quiet=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # its notes were given for the composed robot
        model = compile_spec(spec, name)
    found = infer_gripper(model, RobotIndex(model, "", name), [d.joint for d in drives])
    if found is None:
        return driven, []
    gripper, hand, _, count = found
    leaders = [d.joint for d in drives][-count:]
    fingers = leaders + [c.follower for c in index.couplings if c.leader in leaders]
    if not set(leaders) <= set(driven) or not all(f in index.joint_names for f in fingers):
        return driven, []  # (the file's joints are the composed robot's own, by name)
    links = [link for finger in gripper.finger_links for link in finger]
    pieces = ", ".join(f"{piece.__name__} ({prefix!r})" for prefix, piece in composed.pieces)
    warnings.warn(
        f"{name}: the model file has its own gripper on {hand!r} (fingers {links[:4]}, joints {fingers[:6]}"
        f"{' ...' if len(fingers) > 6 else ''}) beside the mounted {pieces}: the mounted piece is the robot's gripper "
        "and its tool point the arm's end effector; the file's fingers are in no part and hold their default pose "
        "(no control mode commands them). Mount no gripper to use the file's own, or declare parts to command both.",
        RuntimeWarning,
        stacklevel=4,
    )
    return [j for j in driven if j not in leaders], fingers


def _piece_names(composed: Composition) -> tuple[frozenset[str], frozenset[str]]:
    """The joints and bodies of the mounted pieces, as named in the composed model (each
    piece's own file's, under its full prefix: nested pieces are listed too)."""
    joints: set[str] = set()
    bodies: set[str] = set()
    for prefix, piece in composed.pieces:
        spec, own = _raw_spec(piece, piece.__name__, piece.compiler, attached=False)
        joints.update(prefix + joint for joint in own)
        bodies.update(prefix + body.name for body in spec.bodies if body.name and body.name != "world")
    return frozenset(joints), frozenset(bodies)


def _note_file_keyframe_moved(name: str, index: RobotIndex, default: np.ndarray, key: int = 0) -> None:
    """A note naming the joints whose value in the file's keyframe at place ``key`` (from
    0) lies outside their limits, and where the derived keyframe puts them instead
    (:func:`~robot_agents.keyframe.default_qpos`): the file's pose was changed silently."""
    model = index.model
    if model.nkey <= key:
        return
    given = np.asarray(model.key_qpos[key][index.qpos_adr], dtype=np.float64)
    moved = [
        f"{joint.name} {given[joint.qpos_start]:.4g} -> {default[joint.qpos_start]:.4g}"
        for joint in index.joints
        if joint.nq == 1
        and not np.isclose(given[joint.qpos_start], default[joint.qpos_start])
        and joint.limited
        and outside_limits(float(given[joint.qpos_start]), *index.qpos_limits[joint.qpos_start])
    ]
    if moved:
        warnings.warn(
            f"{name}: the file's keyframe {model.key(key).name or f'#{key}'!r} puts joints outside their limits; "
            f"its {file_keyframe_names(model)[key]!r} keyframe moves them inside: {', '.join(moved[:4])}{' ...' if len(moved) > 4 else ''} "
            "(declare keyframes to choose).",
            RuntimeWarning,
            stacklevel=3,
        )


def _note_file_activations(name: str, index: RobotIndex) -> None:
    """A note when the file's keyframes set actuator activations (``act``, for actuators
    with their own dynamics: a filter, an integrator), which a reset does not write: it
    sets the robot's joints (positions, velocities) and the control mode's targets, and
    an activation starts where the scene's does (zero), then follows the controls the
    mode gives. Writing the file's would start an actuator on a command the mode did
    not give."""
    model = index.model
    keys = [k for k in range(model.nkey) if model.na and np.any(model.key_act[k])]
    if keys:
        names = ", ".join(repr(model.key(k).name or f"key{k}") for k in keys[:4])
        warnings.warn(
            f"{name}: the model file's keyframe(s) {names}{' ...' if len(keys) > 4 else ''} set actuator activations "
            "(act); a reset does not: activations start at zero and follow the control mode's commands (joint "
            "positions and velocities are the keyframe's).",
            RuntimeWarning,
            stacklevel=4,
        )


def _pieces_own_parts(composed: Composition, driven: set[str]) -> tuple[Part, ...]:
    """The gripper or hand each mounted piece that declares neither parts nor control
    modes (nor pieces of its own) infers alone, under its prefix, where that is all it
    infers: a two-line gripper file's fingers are its ``Gripper``. Pieces bring the parts
    they declare, and such a piece's driven joints were in no part: no control mode
    commanded them. A piece without a driven joint (a camera housing) brings none, nor
    does one that infers an arm (a second arm file: left as before)."""
    found: list[Part] = []
    for prefix, piece in composed.pieces:
        if piece.parts or piece.control_modes or piece.attachments:
            continue
        _, own = _raw_spec(piece, piece.__name__, piece.compiler, attached=False)
        if not any(prefix + joint in driven for joint in own):
            continue
        inferred = piece.check().parts
        if inferred and all(isinstance(part, (Gripper, Hand)) for part in inferred):
            found += [_prefix_part(part, prefix) for part in inferred]
    return tuple(found)


def _to_piece_tool(
    part: Part, composed: Composition, piece_bodies: frozenset[str], model: mujoco.MjModel, index: RobotIndex
) -> Part:
    """An inferred arm's end effector on a robot with pieces mounted: the ``tcp`` of the
    one piece below the arm's last joint that declares one (a gripper's grasp point);
    else the arm's deepest own body on the way to the end it was inferred at (a camera
    mount on the flange is not the tool)."""
    if not isinstance(part, Arm) or not composed.pieces:
        return part
    last = [n for n in index.joint_names if re.fullmatch(part.joints[-1], n)][-1]
    below = set(index.subtree_bodies(int(model.jnt_bodyid[index.joint(last, "composition").id])))
    tools = []
    for prefix, piece in composed.pieces:
        if piece.tcp is None:
            continue
        frame = resolve_frame(model, prefix + piece.tcp, "", f"{piece.__name__}.tcp")
        body = frame.id if frame.kind is FrameKind.BODY else int(model.site_bodyid[frame.id])
        if body in below:
            tools.append(prefix + piece.tcp)
    ee = part.end_effectors[0]
    if len(set(tools)) == 1:
        ee = dataclasses.replace(ee, link=tools[0], pos=(0.0, 0.0, 0.0), quat=(1.0, 0.0, 0.0, 0.0))
    else:
        body = index.body_id(ee.link, "composition")
        while model.body(body).name in piece_bodies:
            body = int(model.body_parentid[body])
        if model.body(body).name != ee.link:
            ee = dataclasses.replace(ee, link=model.body(body).name, pos=(0.0, 0.0, 0.0), quat=(1.0, 0.0, 0.0, 0.0))
    return dataclasses.replace(part, end_effectors=(ee,))


def _resolve_parts(
    cls: type[AgentDefinition], parts: Sequence[Part], index: RobotIndex, model: mujoco.MjModel
) -> dict[str, tuple[str, ...]]:
    where = f"{cls.__name__}.parts"
    names = [p.name for p in parts]
    for duplicate in names:
        if names.count(duplicate) > 1:
            raise ConfigError(f"{where}: two parts are named {duplicate!r} (a mounted piece brings one; rename it).")
    hits = claim([(f"part {p.name!r}", p.joints) for p in parts], index.joint_names, where)
    resolved = {
        p.name: _in_pattern_order([index.joint_names[i] for i in h], p.joints) for p, h in zip(parts, hits, strict=True)
    }
    ee_names = [ee.name for part in parts for ee in getattr(part, "end_effectors", ())]
    for name in ee_names:
        if ee_names.count(name) > 1:
            raise ConfigError(f"{where}: two end effectors are named {name!r}; give each its own name.")
    for part in parts:
        for ee in getattr(part, "end_effectors", ()):
            assert_frame(model, ee, f"{where} {part.name!r} end effector {ee.name!r}")
        if isinstance(part, Gripper):
            for finger in part.finger_links:
                for link in finger:
                    index.body_id(link, f"{where} {part.name!r}.fingers")
            if part.grasp_frame is not None:
                resolve_frame(model, part.grasp_frame, "", f"{where} {part.name!r}.grasp_frame")
            n = len(resolved[part.name])
            for attr in ("open", "closed"):
                value = np.asarray(getattr(part, attr), dtype=np.float64).reshape(-1)
                if value.size not in (1, n):
                    raise ConfigError(
                        f"{where} {part.name!r}.{attr}: expected 1 or {n} values (one per joint: "
                        f"{', '.join(resolved[part.name])}), got {value.size}."
                    )
                for joint_name, position in zip(resolved[part.name], np.broadcast_to(value, (n,)), strict=True):
                    joint = index.joint(joint_name, where)
                    low, high = joint.range
                    if joint.limited and outside_limits(float(position), low, high):
                        raise ConfigError(
                            f"{where} {part.name!r}.{attr}: joint {joint_name!r} at {position:.6g} is outside its "
                            f"limits [{low:.6g}, {high:.6g}] (the drive would press it into its stop)."
                        )
        if isinstance(part, Hand) and part.power_grasp is not None:
            index.body_id(part.power_grasp.link, f"{where} {part.name!r}.power_grasp.link")
        if isinstance(part, Base):
            kinds = tuple(index.joint(j, where).kind for j in resolved[part.name])
            if kinds != (JointKind.SLIDE, JointKind.SLIDE, JointKind.HINGE):
                found = ", ".join(f"{j} ({k.value})" for j, k in zip(resolved[part.name], kinds, strict=True))
                raise ConfigError(
                    f"{where} {part.name!r}: a Base moves on an x slide, a y slide and a yaw hinge, in that order; "
                    f"its joints are {found}."
                )
    return resolved


def _in_pattern_order(names: Sequence[str], patterns: Sequence[str]) -> tuple[str, ...]:
    """``names`` (model order) reordered by the first of ``patterns`` each matches: a
    part's joints (and its actions) follow the order its patterns are listed in, model
    order within one pattern."""
    compiled = [re.compile(p) for p in patterns]
    rank = {n: next(k for k, c in enumerate(compiled) if c.fullmatch(n)) for n in names}
    return tuple(sorted(names, key=lambda n: rank[n]))  # stable: model order within a pattern


def assert_frame(model: mujoco.MjModel, ee: EndEffector, where: str) -> None:
    """Raise unless the end effector's link (and command frame) exist in ``model``."""
    resolve_frame(model, ee.link, "", where)
    if ee.command_frame is not None:
        resolve_frame(model, ee.command_frame, "", where + " command_frame")


def _composed_default(cls: type[AgentDefinition], index: RobotIndex, key: int = 0) -> np.ndarray:
    """The default pose: the model's (its file's keyframe at place ``key``, from 0), with
    each mounted piece's first keyframe on its joints."""
    default = default_qpos(index, key)
    for prefix, piece in composition(cls).pieces:
        if not piece.keyframes:
            continue
        piece_checked = check(piece)
        frame = next(iter(piece_checked.keyframes.values()))
        for joint in piece_checked.index.joints:
            full = prefix + joint.name
            if full in index.joint_names:
                target = index.joint(full, "composition")
                default[target.qpos_start : target.qpos_start + target.nq] = frame.qpos[
                    joint.qpos_start : joint.qpos_start + joint.nq
                ]
    return default
