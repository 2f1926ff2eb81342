"""Parts: what a robot's joints are *for*, declared by joint pattern.

A robot names its parts (arm, gripper, hand, head, torso, base, legs) with the roles
later features need: end effectors (tool frames with offsets, and the frame their
commands are expressed in), gripper open and closed positions, finger links. Control
modes are generated from parts (:func:`robot_agents.controllers.rules.modes_from_parts`),
``tcp_pose`` works per end effector and ``is_grasping`` for any gripper or hand.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import ClassVar, TypeGuard

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.patterns import Patterns, as_patterns
from robot_agents.validation import check_quat, check_real, is_real


class PartKind(Enum):
    ARM = "arm"
    GRIPPER = "gripper"
    HAND = "hand"
    HEAD = "head"
    TORSO = "torso"
    BASE = "base"
    LEGS = "legs"
    BODY = "body"


def _vector(where: str, value: tuple[float, ...], size: int) -> tuple[float, ...]:
    try:
        floats = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: expected {size} numbers, got {value!r}.") from None
    if len(floats) != size or not all(math.isfinite(v) for v in floats):
        raise ConfigError(f"{where}: expected {size} finite numbers, got {value!r}.")
    return floats


@checked_keywords
@dataclass(frozen=True)
class EndEffector:
    """A tool frame.

    Attributes:
        link: the body or site it is fixed to.
        name: how the robot refers to it (``tcp_pose(name)``); default: ``link``.
        pos, quat: its pose in ``link``'s frame (m; ``w, x, y, z``).
        command_frame: the body or site whose axes end-effector commands are expressed
            in (it may move, e.g. a torso on a mobile base); ``None``: the robot's root.
    """

    link: str
    name: str = ""
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    command_frame: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.link, str) or not self.link:
            raise ConfigError(f"EndEffector: expected link to be a body or site name, got {self.link!r}.")
        if not self.name:
            object.__setattr__(self, "name", self.link)
        object.__setattr__(self, "pos", _vector(f"EndEffector {self.name!r}.pos", self.pos, 3))
        object.__setattr__(self, "quat", check_quat(self.quat, f"EndEffector {self.name!r}.quat"))

    @property
    def has_offset(self) -> bool:
        return self.pos != (0.0, 0.0, 0.0) or self.quat != (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True, kw_only=True)
class Part:
    """Joints that serve one purpose.

    Attributes:
        name: the part's name in control modes (``"arm"``, ``"gripper"``, ...).
        joints: joint name pattern(s); every pattern must match, and no joint may
            belong to two parts. The part's joints, and its actions, follow the order
            of the patterns (model order within one pattern): ``("head_pan_joint",
            "torso_lift_joint")`` puts the head first whatever the model's order.
        max_delta: largest joint change one delta action commands (rad or m).
        max_velocity: velocity bound of velocity modes (rad/s or m/s); ``None``: the
            drives' velocity limits, else 1.
    """

    kind: ClassVar[PartKind]
    name: str
    joints: Patterns
    max_delta: float = 0.1
    max_velocity: float | tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        where = f"{type(self).__name__} {self.name!r}"
        if not isinstance(self.name, str) or not self.name or "/" in self.name:
            raise ConfigError(f"{type(self).__name__}: expected a part name without '/', got {self.name!r}.")
        object.__setattr__(self, "joints", as_patterns(self.joints, f"{where}.joints"))
        if not (is_real(self.max_delta) and 0 < self.max_delta < math.inf):
            raise ConfigError(f"{where}.max_delta: expected a positive number (rad or m), got {self.max_delta!r}.")


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Arm(Part):
    """A manipulator arm. ``end_effectors``: its tool frames (the first is the default);
    ``task_space``: how end-effector modes command it (``None``: joint modes only)."""

    kind: ClassVar[PartKind] = PartKind.ARM
    end_effectors: tuple[EndEffector, ...] = ()
    task_space: object | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "end_effectors", tuple(self.end_effectors))
        for ee in self.end_effectors:
            if not isinstance(ee, EndEffector):
                raise ConfigError(f"Arm {self.name!r}.end_effectors: expected EndEffector entries, got {ee!r}.")


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Gripper(Part):
    """A gripper driven by one action: the first matched driven joint leads, the others
    follow (driven followers get proportional targets, undriven ones follow through
    their joint couplings, e.g. a linkage).

    Attributes:
        open, closed: the positions of the part's joints when open and closed (a
            scalar for every joint, or one per matched joint in the part's order).
        squeeze: how far past ``closed`` the action may command the leader (rad or m),
            so that a grasp keeps pressing when the fingers stop on an object.
        fingers: the links of each finger (a link name, or a tuple of them); a finger
            is its links and the bodies below them, less those below another finger's
            link (a fixed jaw on the hand does not take the moving jaw's contacts); a
            grasp needs opposing contact forces from at least two fingers.
        tolerance: how close to ``open`` / ``closed`` counts as open / closed (rad or m).
        grasp_frame: a body or site between the fingers where a grasped object's centre
            goes, where that is not the arm's tool frame (a tool frame at the fingertips'
            ends, as the Google Robot's URDF puts its ``link_gripper_tcp``): the table-top
            layout measures the gripper's opening, and so its cube, there, and the
            scripted solvers and the time-step sweep's grasp claim put the object's
            centre there. ``None``: the tool frame.
    """

    kind: ClassVar[PartKind] = PartKind.GRIPPER
    open: float | tuple[float, ...]
    closed: float | tuple[float, ...]
    fingers: tuple[str | tuple[str, ...], ...] = ()
    squeeze: float = 0.0
    tolerance: float = 0.005
    grasp_frame: str | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        fingers = tuple((f,) if isinstance(f, str) else tuple(f) for f in self.fingers)
        if fingers and len(fingers) < 2:
            raise ConfigError(
                f"{type(self).__name__} {self.name!r}.fingers: expected at least two fingers, got {fingers}."
            )
        object.__setattr__(self, "fingers", fingers)
        where = f"{type(self).__name__} {self.name!r}"
        check_real(self.squeeze, "squeeze", where, minimum=0.0, unit=" (rad or m past closed)")
        check_real(self.tolerance, "tolerance", where, minimum=0.0, unit=" (rad or m)")
        if self.grasp_frame is not None and not (isinstance(self.grasp_frame, str) and self.grasp_frame):
            raise ConfigError(f"{where}.grasp_frame: expected a body or site name or None, got {self.grasp_frame!r}.")
        for attr in ("open", "closed"):
            value = getattr(self, attr)
            try:
                array = np.asarray(value, dtype=np.float64).reshape(-1)
            except (TypeError, ValueError):
                array = np.array([np.nan])
            if not array.size or not np.all(np.isfinite(array)):
                raise ConfigError(f"{where}.{attr}: expected a finite number or one per joint, got {value!r}.")

    @property
    def finger_links(self) -> tuple[tuple[str, ...], ...]:
        return self.fingers  # type: ignore[return-value]

    def positions(self, joints: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """``open`` and ``closed`` as one position per joint of the part, ``(joints,)``
        each (rad or m; a scalar applies to every joint; read-only views)."""
        opened = np.broadcast_to(np.asarray(self.open, dtype=np.float64).reshape(-1), (joints,))
        closed = np.broadcast_to(np.asarray(self.closed, dtype=np.float64).reshape(-1), (joints,))
        return opened, closed


@checked_keywords
@dataclass(frozen=True)
class PowerGrasp:
    """Where a hand's power grasp (its ``closed`` pose) holds a cube: the time-step
    sweep's grasp claim places a cube there with the hand open, closes the hand and
    pulls the cube away from the palm (:mod:`robot_agents.tuning.grasp_claim`).

    Attributes:
        link: the palm link the numbers below are in.
        cube_centre: the cube's centre in ``link``'s frame (m), with the hand open: its
            face just off the palm, between the fingers' paths as they close; the cube's
            faces are square to ``link``'s axes.
        cube_edge: the cube's edge (m).
        outward: the direction away from the palm in ``link``'s frame (any length;
            stored as a unit vector): the way a held object would fall with the palm
            turned down.
    """

    link: str
    cube_centre: tuple[float, float, float]
    cube_edge: float
    outward: tuple[float, float, float]

    def __post_init__(self) -> None:
        where = "PowerGrasp"
        if not isinstance(self.link, str) or not self.link:
            raise ConfigError(f"{where}.link: expected the palm link's name, got {self.link!r}.")
        object.__setattr__(self, "cube_centre", _vector(f"{where}.cube_centre", self.cube_centre, 3))
        if not (is_real(self.cube_edge) and 0.0 < self.cube_edge < math.inf):
            raise ConfigError(f"{where}.cube_edge: expected a positive length (m), got {self.cube_edge!r}.")
        outward = _vector(f"{where}.outward", self.outward, 3)
        norm = math.sqrt(sum(v * v for v in outward))
        if not norm > 0.0:
            raise ConfigError(f"{where}.outward: expected a nonzero direction, got {self.outward!r}.")
        object.__setattr__(self, "outward", tuple(v / norm for v in outward))


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Hand(Gripper):
    """A multi-finger hand: every joint takes its own action; ``open`` / ``closed`` are
    its open and power-grasp poses, ``fingers`` the links of each finger.

    Attributes:
        power_grasp: where the ``closed`` pose holds a cube (the time-step sweep's grasp
            claim; ``None``: the sweep makes no grasp claim for this hand).
    """

    kind: ClassVar[PartKind] = PartKind.HAND
    power_grasp: PowerGrasp | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.power_grasp is not None and not isinstance(self.power_grasp, PowerGrasp):
            raise ConfigError(
                f"Hand {self.name!r}.power_grasp: expected a PowerGrasp or None, got {self.power_grasp!r}."
            )


def is_jaw_gripper(part: object) -> TypeGuard[Gripper]:
    """A gripper that closes jaws (two fingers, a linkage, one jaw) with one action, not a
    :class:`Hand`, whose joints take their own actions: the parts that get one gripper
    action, stiff pads and grip gains when derived, and the sweep's two-finger grasp."""
    return isinstance(part, Gripper) and not isinstance(part, Hand)


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Head(Part):
    kind: ClassVar[PartKind] = PartKind.HEAD


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Torso(Part):
    kind: ClassVar[PartKind] = PartKind.TORSO


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Legs(Part):
    """Legs: by default they take delta joint-position actions in every mode, like any
    body part.

    Attributes:
        held: the legs take no action; their drives hold the pose of the last reset
            (a keyframe) in every mode: Habitat's "leg" base, where the body is moved
            by the base action and the legs keep ``leg_init_params``.
    """

    kind: ClassVar[PartKind] = PartKind.LEGS
    held: bool = False


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Base(Part):
    """A mobile base on planar joints: ``joints`` match the x slide, the y slide and the
    yaw hinge (in that model order). Every control mode gets its velocity action:
    ``(vx, vy, wz)`` for a ``holonomic`` base, ``(v, wz)`` for a differential drive,
    bounded by ``max_speed`` (m/s) and ``max_turn`` (rad/s)."""

    kind: ClassVar[PartKind] = PartKind.BASE
    holonomic: bool = True
    max_speed: float = 1.0
    max_turn: float = 1.0
    #: ``"dynamic"``: the base joints' drives track the commanded velocity (the base
    #: pushes and is pushed); ``"kinematic"``: after every control step the base pose is
    #: set to the pose at the step's start plus the commanded mount-frame velocity times
    #: the control timestep (Habitat's navmesh-style base: nothing pushes it).
    dynamics: str = "dynamic"
    #: Kinematic bases only: a move that puts the base's geoms (its body, rigidly
    #: attached bodies and wheels) in contact with anything outside the robot is refused.
    refuse_collisions: bool = False
    #: Passive wheel hinge joints, left wheel(s) then right, turned with the base's
    #: actual motion (differential kinematics), for both dynamics.
    wheels: tuple[str, ...] = ()
    wheel_radius: float = 0.0
    wheel_separation: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.dynamics, str) or self.dynamics not in ("dynamic", "kinematic"):
            raise ConfigError(f"Base {self.name!r}: dynamics must be 'dynamic' or 'kinematic', got {self.dynamics!r}.")
        if self.wheels and (len(self.wheels) % 2 or not self.wheel_radius > 0 or not self.wheel_separation > 0):
            raise ConfigError(
                f"Base {self.name!r}: wheels need an even count (left then right) and wheel_radius, "
                f"wheel_separation > 0; got {self.wheels!r}, {self.wheel_radius!r}, {self.wheel_separation!r}."
            )


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class Body(Part):
    """Joints with no more specific role (what a robot that declares no parts gets
    when its joints are not one serial chain: a humanoid, a quadruped, a hand)."""

    kind: ClassVar[PartKind] = PartKind.BODY


PART_TYPES = (Arm, Gripper, Hand, Head, Torso, Legs, Base, Body)
