"""The declaration half of a robot class: the class attributes a robot sets and the
class-level questions about them (its model file, its checked declaration, its modes
and keyframes). :class:`~robot_agents.agent.Agent` adds the bound, per-instance half."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import ClassVar

import mujoco

from robot_agents.actuators.config import ActuatorConfig
from robot_agents.agent import declaration
from robot_agents.agent.declaration import CheckedRobot, ModeConfig
from robot_agents.controllers.base import ControllerConfig
from robot_agents.keyframe import Keyframe
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Part
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.touch import TouchSensorConfig


class AgentDefinition:
    """Base class of every robot. Subclass it, set the class attributes, register it.

    Declaration (class attributes):
        uid: registry id, e.g. ``"panda"``.
        mjcf_path / urdf_path: the model file (exactly one); a variant may change it as
            read in :meth:`edit_model`.
        fix_root_link: weld the root to the world (arms) or give it a free joint.
        root_body: which top-level body of the file is the robot, when it has several
            (a target marker beside it); ``None``: the one holding the actuated joints.
        mount_pose: where a scene puts the robot's root by default, ``(x, y, z, qw, qx,
            qy, qz)`` (m): a hand or gripper mounted above the floor; ``make_env(...,
            robot_poses=...)`` overrides it. Undeclared, a fixed-base robot that would
            reach into the floor is raised to rest on it. A floating robot's mount
            orientation turns its derived keyframe and stance: ``(0, 0, 0, 0.7071068,
            0.7071068, 0, 0)`` stands a file drawn y-up.
        rest_on_floor: a fixed-base robot reaching more than 5 mm into the floor at its
            default keyframe is raised to rest 1 mm above it: ``None`` when it declares
            no ``mount_pose``; ``True`` under its declared mount too, turned as the
            mount turns it (:func:`robot_agents.robot_source.robot_from_file`'s ``up``:
            a mount that only names the file's up axis); ``False`` never.
        compiler: MuJoCo compiler settings for the file (angle units, balanceinertia,
            boundmass, meshdir, package search paths; see :class:`CompilerSettings`).
        actuators: the drives, per joint pattern (:mod:`robot_agents.actuators`); a
            model file's own actuators are adopted unless ``replace_file_actuators``.
        parts: arm(s), gripper(s) or hand(s), head, torso, base, legs, with their roles
            (end effectors, gripper open / closed, fingers).
        attachments: pieces (other Agent classes) mounted at a body or site; their
            actuators, parts, sensors and default keyframe come along.
        tcp: a piece's tool centre point, a body or site of its model (a gripper's
            grasp point, a stick's tip): an arm inferred on a robot the piece is
            mounted on (one that declares no parts) takes it as its end effector.
        keyframes: name -> :class:`Keyframe` (joints by name); the first is the default.
        control_modes: name -> controller config, or ``{part: config}``; empty:
            generated from the parts.
        default_control_mode: defaults to the first control mode.
        disable_self_collisions / self_collision_exclusions: contact filtering.
        collision_links: the bodies whose geoms take part in contacts (names as in the
            composed robot); every other body's geoms are drawn only. ``None``: every
            body's, as the file has them. A simplified collision model, as ManiSkill's
            ``unitree_go2_simplified_locomotion`` (base, thighs and feet).
        convex_decomposition: split each markedly non-convex colliding mesh (a jaw with
            a notch: MuJoCo collides a mesh as its convex hull) into convex pieces for
            contacts, with CoACD (the ``robot-agents[meshes]`` extra; seconds per mesh,
            cached on disk); the drawn meshes, masses and inertias stay the same. It
            applies to the whole composed robot when the robot or a mounted piece sets
            it (:mod:`robot_agents.model.decompose`).
        gravity_compensation: ``True`` (every body), ``False``, or body names; ``None``
            means ``fix_root_link`` (on for fixed-base arms, off for free robots).
        link_materials / default_material: friction per body / for every other geom.
        cameras / touch_sensors: sensors that travel with the robot.
        sim_freq: the physics rate (Hz) this robot is simulated at unless a user passes
            one: the largest step at which all its physics claims hold, found by the
            time-step sweep (:mod:`robot_agents.tuning.timestep`), with a margin;
            ``None``: the library's default (500 Hz).
        friction_cone / impratio: MuJoCo's contact friction model this robot's contacts
            need (``"elliptic"`` or ``"pyramidal"``; the ratio of frictional to normal
            constraint impedance), as a model file's ``<option cone impratio>`` gives them
            (a robot's own options are lost when it is composed into a scene). A scene
            uses the elliptic cone when any of its robots asks for it, and the largest
            ``impratio`` asked for; ``None``: MuJoCo's defaults (pyramidal, 1).
        jacobian: MuJoCo's constraint Jacobian this robot's scenes step fastest with
            (``"sparse"``, ``"dense"``; the same physics up to rounding), measured
            (``benchmarks/sim_options.py``). A scene uses the sparse one when any of its
            robots asks for it, else the dense one when any asks for that; ``None``:
            MuJoCo's choice (dense below 60 degrees of freedom).
        solver_tolerance: the constraint solver's tolerance this robot's contacts need,
            where MuJoCo's 1e-8 stops the solver early: MuJoCo compares it with the
            cost and gradient divided by ``meaninertia * nv``, so a heavy robot loosens
            it, in absolute terms, for a light body it holds. A scene uses the smallest
            declared; ``None``: MuJoCo's 1e-8.
        task_limits: task id -> why this robot cannot do it although it has the parts
            the task asks for (read by the tests of the tasks' scripted solvers).
    """

    uid: ClassVar[str] = ""
    mjcf_path: ClassVar[str | Path | None] = None
    urdf_path: ClassVar[str | Path | None] = None
    fix_root_link: ClassVar[bool] = True
    root_body: ClassVar[str | None] = None
    mount_pose: ClassVar[tuple[float, ...]] = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    rest_on_floor: ClassVar[bool | None] = None
    compiler: ClassVar[CompilerSettings] = CompilerSettings()
    actuators: ClassVar[tuple[ActuatorConfig, ...]] = ()
    replace_file_actuators: ClassVar[bool] = False
    parts: ClassVar[tuple[Part, ...]] = ()
    attachments: ClassVar[Sequence[Attachment]] = ()
    tcp: ClassVar[str | None] = None
    keyframes: ClassVar[Mapping[str, Keyframe]] = {}
    control_modes: ClassVar[Mapping[str, ModeConfig]] = {}
    default_control_mode: ClassVar[str | None] = None
    disable_self_collisions: ClassVar[bool] = False
    convex_decomposition: ClassVar[bool] = False
    self_collision_exclusions: ClassVar[tuple[tuple[str, str], ...]] = ()
    collision_links: ClassVar[tuple[str, ...] | None] = None
    gravity_compensation: ClassVar[bool | tuple[str, ...] | None] = None
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {}
    default_material: ClassVar[FrictionMaterial | None] = None
    cameras: ClassVar[tuple[CameraConfig, ...]] = ()
    touch_sensors: ClassVar[tuple[TouchSensorConfig, ...]] = ()
    task_limits: ClassVar[Mapping[str, str]] = {}
    sim_freq: ClassVar[int | None] = None
    friction_cone: ClassVar[str | None] = None
    impratio: ClassVar[float | None] = None
    jacobian: ClassVar[str | None] = None
    solver_tolerance: ClassVar[float | None] = None

    # ------------------------------------------------------------------ declaration
    @classmethod
    def edit_model(cls, spec: mujoco.MjSpec, where: str) -> None:
        """Change the model file's spec as read, before any declared option is applied
        to it: a variant built from another robot's file (the left Allegro Hand, the
        right one's file mirrored). ``where`` names the robot for error messages. The
        default changes nothing."""

    @classmethod
    def model_path(cls) -> Path:
        """The declared model file (not checked for existence)."""
        return declaration.model_path(cls)

    @classmethod
    def validate_definition(cls) -> None:
        """Check the declaration's types without loading the model (see :meth:`check`)."""
        declaration.validate_definition(cls)

    @classmethod
    def check(cls) -> CheckedRobot:
        """Compile the robot alone and check its whole declaration (parts, drives,
        keyframes, control modes) against it; cached per class. Run at registration."""
        return declaration.check(cls)

    @classmethod
    def build_spec(cls, cameras: Sequence[CameraConfig] | None = None) -> mujoco.MjSpec:
        """A fresh MjSpec of the composed robot with every declared (or derived) option
        applied; ``cameras`` replaces the declared cameras (an env's overrides)."""
        return declaration.build_spec(cls, cameras)

    @classmethod
    def modes(cls) -> dict[str, ModeConfig]:
        """The control-mode table: ``control_modes``, or generated from the parts."""
        return cls.check().modes

    @classmethod
    def mode_parts(cls, mode: str) -> dict[str, ControllerConfig]:
        """The per-part configs of a control mode (a single config becomes part ``"main"``)."""
        return declaration.mode_parts(cls, cls.modes(), mode)

    @classmethod
    def default_mode(cls) -> str:
        """The declared default mode; for a generated table a delta mode (random actions
        are then small), else the first mode."""
        return cls.check().default_mode

    @classmethod
    def keyframe_names(cls) -> list[str]:
        """Keyframe names, the default first (``["default"]`` for a robot that declares none),
        each keyframe once (an alias is not listed: :meth:`keyframe_aliases`)."""
        return list(cls.check().keyframes)

    @classmethod
    def keyframe_aliases(cls) -> dict[str, str]:
        """Other names keyframes answer to, alias -> keyframe name: a robot declaring no
        keyframes answers to its model file's own name of its first keyframe beside
        ``"default"`` (``{"home": "default"}``); empty otherwise."""
        return dict(cls.check().keyframe_aliases)

    @classmethod
    def default_keyframe(cls) -> str | None:
        """The keyframe a reset uses unless told (the first of :meth:`keyframe_names`)."""
        return next(iter(cls.check().keyframes), None)
