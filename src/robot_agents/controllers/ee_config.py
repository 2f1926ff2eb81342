"""End-effector control configs: what a robot declares for task-space modes (the
controller that runs them is :mod:`robot_agents.controllers.ee`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np
import numpy.typing as npt

from robot_agents.actuators.config import per_joint
from robot_agents.controllers.base import (
    Controller,
    ControllerConfig,
    ControllerContext,
    FloatArray,
    JointBinding,
    check_bounds,
)
from robot_agents.controllers.task_space import WorkspaceBox
from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.kinematics.ik_config import IKConfig

BoolArray = npt.NDArray[np.bool_]
#: A scalar for x, y and z, or one value per axis.
PerAxis = float | tuple[float, float, float]


class CommandFrame(Enum):
    """Axes a delta command is expressed in."""

    #: The robot's root (base) frame; rotations turn about root-aligned axes through the tool point.
    ROOT = "root"
    #: The end effector's own frame, as it is at the start of the step.
    EE = "ee"


class RotationFormat(Enum):
    """How an absolute orientation is given in the action."""

    #: Rotation vector (axis * angle, rad): 3 numbers.
    ROTVEC = "rotvec"
    #: Unit quaternion ``(w, x, y, z)``: 4 numbers (normalized by the controller).
    QUAT = "quat"
    #: Intrinsic x-y-z Euler angles ``(a, b, c)`` (rad), ``R = Rx(a) Ry(b) Rz(c)``: 3
    #: numbers, ManiSkill's ``pd_ee_pose`` convention (PyTorch3D's ``"XYZ"``).
    EULER = "euler"


def per_axis(owner: str, name: str, value: PerAxis) -> FloatArray:
    return per_joint(owner, name, value, 3)


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDEEPosConfig(ControllerConfig):
    """End-effector position control; the orientation is held.

    Attributes:
        joint_names: the arm joints IK may move (a serial chain to ``ee_link``).
        pos_lower, pos_upper: action bounds (m): per-step translation for delta modes,
            the position in the root frame for absolute ones.
        use_delta: the action moves the target; otherwise it is the target.
        use_target: deltas accumulate on the previous target, not on the measured pose.
        translation_frame: axes of translation deltas (root or end effector).
        end_effector: the controlled end effector, by the name a part declares; default:
            the robot's first end effector (its tool frame and command frame).
        ee_link: a body or site to control instead of a declared end effector
            (commands in the robot's root frame).
        workspace: optional box in the command frame the target position is clipped to.
        hold_orientation: position modes keep the tool's orientation (6-DoF IK); ``False``
            solves for the position alone, for arms with fewer than 6 joints.
        velocity_feedforward: drive the joints with the IK path's velocity as well as
            its position; default on for delta modes, off for absolute ones.
        ik: solver settings.
        rest_qpos: posture of the IK null-space pull (with ``ik.null_space_gain > 0``).
    """

    pos_lower: PerAxis = -0.1
    pos_upper: PerAxis = 0.1
    use_delta: bool = True
    use_target: bool = False
    translation_frame: CommandFrame = CommandFrame.ROOT
    end_effector: str | None = None
    ee_link: str | None = None
    workspace: WorkspaceBox | None = None
    velocity_feedforward: bool | None = None
    hold_orientation: bool = True
    ik: IKConfig = field(default_factory=IKConfig)
    rest_qpos: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        name = type(self).__name__
        if self.use_target and not self.use_delta:
            raise ConfigError(f"{name}({', '.join(self.joint_names)}): use_target=True needs use_delta=True.")
        if not isinstance(self.translation_frame, CommandFrame):
            raise ConfigError(
                f"{name}.translation_frame: expected a CommandFrame ({', '.join(f.name for f in CommandFrame)}), "
                f"got {self.translation_frame!r}."
            )
        if self.stiffness is not None and np.any(np.asarray(self.stiffness, dtype=np.float64) <= 0):
            raise ConfigError(f"{name}: expected stiffness > 0 on every joint, got {self.stiffness}.")
        if not isinstance(self.ik, IKConfig):
            raise ConfigError(f"{name}.ik: expected an IKConfig, got {self.ik!r}.")
        check_bounds(self, "pos_lower", "pos_upper", 3, "axis")

    @property
    def controls_rotation(self) -> bool:
        return False

    @property
    def feedforward(self) -> bool:
        return self.use_delta if self.velocity_feedforward is None else self.velocity_feedforward

    def target_kinds(self) -> tuple[str, ...]:
        return ("position", "velocity") if self.feedforward else ("position",)

    def build(self, binding: JointBinding, context: ControllerContext) -> Controller:
        from robot_agents.controllers.ee import PDEEController

        return PDEEController(self, binding, context)


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDEEPoseConfig(PDEEPosConfig):
    """End-effector pose control: position and orientation.

    Attributes:
        rot_lower, rot_upper: action bounds of the rotation part (rad for rotation
            vectors; quaternion entries are bounded to ``[-1, 1]``).
        rotation_frame: axes rotation deltas turn about (root-aligned through the
            tool point, or the end effector's own).
        rotation_format: absolute modes take a rotation vector, a quaternion or
            intrinsic x-y-z Euler angles; deltas are always rotation vectors.
    """

    rot_lower: PerAxis = -0.1
    rot_upper: PerAxis = 0.1
    rotation_frame: CommandFrame = CommandFrame.ROOT
    rotation_format: RotationFormat = RotationFormat.ROTVEC

    def __post_init__(self) -> None:
        super().__post_init__()
        name = type(self).__name__
        if not isinstance(self.rotation_frame, CommandFrame):
            raise ConfigError(f"{name}.rotation_frame: expected a CommandFrame, got {self.rotation_frame!r}.")
        if not isinstance(self.rotation_format, RotationFormat):
            raise ConfigError(f"{name}.rotation_format: expected a RotationFormat, got {self.rotation_format!r}.")
        check_bounds(self, "rot_lower", "rot_upper", 3, "axis")
        if self.use_delta and self.rotation_format is not RotationFormat.ROTVEC:
            raise ConfigError(
                f"{name}: rotation deltas are rotation vectors; rotation_format={self.rotation_format.name} "
                "applies to absolute poses (use_delta=False) only."
            )

    @property
    def controls_rotation(self) -> bool:
        return True
