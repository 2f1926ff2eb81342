"""The inverse-kinematics solver's settings and per-env result (plain data; the solver
is :mod:`robot_agents.kinematics.ik`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.validation import check_real, check_whole

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


@checked_keywords
@dataclass(frozen=True)
class IKConfig:
    """Settings of the damped-least-squares solver.

    Attributes:
        damping: ``lambda`` of DLS (m); larger is more robust near singularities and
            joint limits, smaller converges faster.
        max_iterations: iterations per solve (each costs one forward kinematics per env).
        position_tolerance: success threshold on the position error (m).
        rotation_tolerance: success threshold on the rotation error (rad).
        rotation_weight: metres per radian when position and rotation errors share one
            least-squares problem.
        max_step: largest change of any joint in one iteration (rad or m).
        max_task_step: largest weighted task-space error one iteration tries to remove
            (m); far targets are approached in straight steps of this size.
        null_space_gain: pull toward the rest posture per iteration (0 disables it).
    """

    damping: float = 0.01
    max_iterations: int = 10
    position_tolerance: float = 1e-3
    rotation_tolerance: float = math.radians(1.0)
    rotation_weight: float = 0.5
    max_step: float = 0.3
    max_task_step: float = 0.2
    null_space_gain: float = 0.0

    def __post_init__(self) -> None:
        positive = {
            "position_tolerance": self.position_tolerance,
            "rotation_tolerance": self.rotation_tolerance,
            "rotation_weight": self.rotation_weight,
            "max_step": self.max_step,
            "max_task_step": self.max_task_step,
        }
        for name, value in positive.items():
            if check_real(value, name, "IKConfig", minimum=0.0) <= 0.0:
                raise ConfigError(f"IKConfig: expected {name} to be a finite value > 0, got {value!r}.")
        check_real(self.damping, "damping", "IKConfig", minimum=0.0)
        check_real(self.null_space_gain, "null_space_gain", "IKConfig", minimum=0.0, maximum=1.0)
        check_whole(self.max_iterations, "max_iterations", "IKConfig", minimum=1)


@dataclass(frozen=True)
class IKResult:
    """What a solve returns, per env.

    Attributes:
        qpos: the chain's joint positions ``(num_envs, n)`` (the best iterate).
        success: both tolerances met ``(num_envs,)``.
        position_error: remaining position error (m) ``(num_envs,)``.
        rotation_error: remaining rotation error (rad) ``(num_envs,)``; 0 for
            position-only solves.
        iterations: DLS updates made ``(num_envs,)``.
    """

    qpos: FloatArray
    success: BoolArray
    position_error: FloatArray
    rotation_error: FloatArray
    iterations: IntArray


#: IK settings of the end-effector position modes of an arm with fewer than 6 joints.
#: The library's position modes (``pd_ee_delta_pos``, ``pd_ee_target_delta_pos``) hold
#: the tool's orientation: their IK solves for position and orientation together. A
#: 5-DoF arm cannot hold a full orientation while its tool moves (turning the base turns
#: the tool), so that solve fails whenever the base must turn. Here the held orientation
#: is a soft preference instead: IK weighs it 0.01 m per rad (a 1 mm position error
#: outweighs a 0.1 rad orientation error) and does not require it (tolerance pi), so a
#: solve succeeds when the position is within 1 mm and, among the postures that reach
#: it, prefers the one that keeps the tool's orientation (the SO-100, the Koch, a file's
#: arm with fewer than 6 joints).
POSITION_IK = IKConfig(rotation_weight=0.01, rotation_tolerance=math.pi)
