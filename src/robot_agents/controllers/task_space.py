"""Where end-effector commands may go: workspace boxes and the task space of an arm."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.kinematics.ik_config import IKConfig
from robot_agents.kinematics.rotations import quat_conjugate, quat_multiply, quat_to_rotvec


@checked_keywords
@dataclass(frozen=True)
class WorkspaceBox:
    """An axis-aligned box in the robot's root frame; targets are clipped into it (m)."""

    lower: tuple[float, float, float]
    upper: tuple[float, float, float]

    def __post_init__(self) -> None:
        low, high = np.asarray(self.lower, dtype=np.float64), np.asarray(self.upper, dtype=np.float64)
        if low.shape != (3,) or high.shape != (3,) or not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
            raise ConfigError(
                f"WorkspaceBox: expected finite lower and upper corners of 3 values, got {self.lower}, {self.upper}."
            )
        if np.any(low > high):
            raise ConfigError(f"WorkspaceBox: expected lower <= upper on every axis, got {self.lower}, {self.upper}.")


@checked_keywords
@dataclass(frozen=True)
class TaskSpace:
    """How an arm's end effector is commanded (end-effector control modes).

    Attributes:
        position_bounds: action bounds of absolute positions (``pd_ee_pose``), a box in
            the command frame covering the reachable space (m).
        max_translation: largest translation one delta action commands, per axis (m).
        max_rotation: largest rotation one delta action commands, per axis (rad).
        workspace: optional box in the command frame every target is clipped to.
        end_effector: which of the arm's end effectors (default: its first).
        ik: solver settings.
        rest_qpos: posture of the IK null-space pull.
        modes: which end-effector modes the arm offers (ManiSkill names): any of
            ``rules.EE_MODES`` (the default) and ``rules.OPTIONAL_EE_MODES``
            (``pd_ee_delta_pose_align``: rotations about the tool's own axes).
        hold_orientation: position modes keep the tool's orientation; ``False`` for arms
            with fewer than 6 joints (IK then solves for the position alone).
    """

    position_bounds: WorkspaceBox
    max_translation: float = 0.1
    max_rotation: float = 0.1
    workspace: WorkspaceBox | None = None
    end_effector: str | None = None
    ik: IKConfig = field(default_factory=IKConfig)
    rest_qpos: tuple[float, ...] | None = None
    modes: tuple[str, ...] = (
        "pd_ee_delta_pos",
        "pd_ee_delta_pose",
        "pd_ee_pose",
        "pd_ee_target_delta_pos",
        "pd_ee_target_delta_pose",
    )
    hold_orientation: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.position_bounds, WorkspaceBox):
            raise ConfigError(f"TaskSpace.position_bounds: expected a WorkspaceBox, got {self.position_bounds!r}.")
        if self.workspace is not None and not isinstance(self.workspace, WorkspaceBox):
            raise ConfigError(f"TaskSpace.workspace: expected a WorkspaceBox or None, got {self.workspace!r}.")
        if self.workspace is not None:
            bounds, box = self.position_bounds, self.workspace
            low, high = np.asarray(bounds.lower), np.asarray(bounds.upper)
            box_low, box_high = np.asarray(box.lower), np.asarray(box.upper)
            apart = [axis for axis, out in zip("xyz", (box_high < low) | (box_low > high), strict=True) if out]
            if apart:
                raise ConfigError(
                    f"TaskSpace.workspace: expected a box overlapping position_bounds (every target is "
                    f"clipped into it, so no absolute action could reach a point of a box outside them), "
                    f"got workspace {box.lower}..{box.upper} apart from position_bounds "
                    f"{bounds.lower}..{bounds.upper} along {', '.join(apart)}."
                )
        for name, unit in (("max_translation", "m"), ("max_rotation", "rad")):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < np.inf:
                raise ConfigError(f"TaskSpace.{name}: expected a finite number > 0 ({unit} per action), got {value!r}.")
        if self.end_effector is not None and (not isinstance(self.end_effector, str) or not self.end_effector):
            raise ConfigError(
                f"TaskSpace.end_effector: expected an end-effector name or None, got {self.end_effector!r}."
            )


@checked_keywords
@dataclass(frozen=True)
class MeasuredTaskSpace:
    """``Arm(task_space=MeasuredTaskSpace())``: the arm's task space measured on its model,
    as an arm a model file implies gets it
    (:func:`robot_agents.agent.derived_task_space.derive_task_space`: the reach over
    seeded configurations, a ``pd_ee_pose`` box around the tool points sampled, a tenth of
    the reach and 0.1 rad per delta action; every end-effector mode with 6 or more joints,
    the position modes below). For an arm declared by hand on a model file (a user's arm
    with a gripper piece mounted) whose workspace nobody has measured."""


@checked_keywords
@dataclass(frozen=True)
class FloatingMountTaskSpace:
    """``Arm(task_space=FloatingMountTaskSpace())``: the task space of a floating mount
    (slides, then hinges whose axes meet at one point, carrying a tool: the floating
    grippers), its ``pd_ee_pose`` box computed on the compiled model when the robot is
    built (:func:`robot_agents.agent.mount_task_space.mount_task_space`: the slides'
    travel grown on every side by the tool point's distance from the hinges' common
    point, so it fits whatever tool is mounted); deltas of up to 0.1 m and 0.1 rad.

    Attributes:
        modes: the end-effector modes the arm offers (as :attr:`TaskSpace.modes`).
    """

    modes: tuple[str, ...] = ("pd_ee_delta_pose", "pd_ee_pose")

    def __post_init__(self) -> None:
        if not isinstance(self.modes, tuple) or not self.modes or not all(isinstance(m, str) for m in self.modes):
            raise ConfigError(
                f"FloatingMountTaskSpace.modes: expected a non-empty tuple of end-effector mode names, got {self.modes!r}."
            )


def delta_action(
    space: TaskSpace, before: npt.ArrayLike, after: npt.ArrayLike, rotation: bool = True
) -> npt.NDArray[np.float64] | None:
    """The normalized action of a delta end-effector mode that moves the tool from pose
    ``before`` to pose ``after`` (each ``(7,)``: position m, quaternion ``w, x, y, z``, in
    the command frame): ``[dx, dy, dz, rx, ry, rz]`` for ``pd_ee_delta_pose`` /
    ``pd_ee_target_delta_pose`` (the turn about the command frame's axes through the
    tool point), ``[dx, dy, dz]`` with ``rotation=False`` (the position modes); ``None``
    when one action cannot: a translation past ``max_translation`` on an axis, or a turn
    outside the ``max_rotation`` ellipsoid the controllers clip rotation vectors to."""
    start, end = np.asarray(before, dtype=np.float64), np.asarray(after, dtype=np.float64)
    move = (end[:3] - start[:3]) / space.max_translation
    if np.abs(move).max() > 1.0:
        return None
    if not rotation:
        return move
    turn = quat_to_rotvec(quat_multiply(end[3:], quat_conjugate(start[3:]))) / space.max_rotation
    if np.linalg.norm(turn) > 1.0:
        return None
    return np.concatenate([move, turn])
