"""The task space of a floating mount (``Arm(task_space=FloatingMountTaskSpace())``):
slides, then hinges whose axes meet at one point, carrying a tool (the floating
grippers). Its ``pd_ee_pose`` box is computed on the compiled model when the robot is
built, so that it fits whatever tool is mounted:

- the slides move the hinges' common point over a box (each slide's travel, its
  ``range`` measured from the joint's reference position, along its axis, in the
  command frame);
- the hinges turn the tool point about that point on a sphere whose radius is the tool
  point's distance from it (measured at the robot's default keyframe with the mount's
  joints at their reference positions: the distance the hinges cannot change);
- so every tool position the mount reaches lies in that box grown by the radius on
  every side (:func:`reachable_box`), and with hinges that turn every orientation
  (three, each -pi..pi) each face is reached.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.agent.frames import RobotFrames
from robot_agents.agent.index import RobotIndex
from robot_agents.controllers.task_space import FloatingMountTaskSpace, TaskSpace, WorkspaceBox
from robot_agents.errors import ConfigError
from robot_agents.kinematics.rotations import quat_conjugate, quat_rotate
from robot_agents.parts.declaration import Arm

#: How far (m) a hinge's axis may pass from the hinges' common point.
AXES_MEET_TOLERANCE = 1e-9
#: How far (rad or m) each mount joint is moved to see whether the command frame moves with them.
_PROBE = 0.1


def reachable_box(lower: Sequence[float], upper: Sequence[float], tool_offset: float) -> WorkspaceBox:
    """The box of every tool position a floating mount reaches: the box ``lower`` ..
    ``upper`` (m, ``(3,)`` each) the slides move the hinges' common point over, grown by
    ``tool_offset`` (m, the tool point's distance from that point) on every side."""
    low = tuple(float(v) - tool_offset for v in lower)
    high = tuple(float(v) + tool_offset for v in upper)
    return WorkspaceBox(lower=low, upper=high)  # type: ignore[arg-type]


def _misses(point: np.ndarray, anchors: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """How far (m) each hinge axis (through ``anchors`` ``(k, 3)`` along unit ``axes``
    ``(k, 3)``) passes from ``point`` ``(3,)``: ``(k,)``."""
    across = (point - anchors) - np.sum((point - anchors) * axes, axis=1, keepdims=True) * axes
    distances: np.ndarray = np.linalg.norm(across, axis=1)
    return distances


def _common_point(anchors: np.ndarray, axes: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """The point ``(3,)`` the hinge axes (through ``anchors`` ``(k, 3)`` along unit
    ``axes`` ``(k, 3)``) pass closest to: the first anchor where every axis passes
    through it (the built-in mounts: three hinges on one body), else the least-squares
    point nearest ``tool`` (one hinge: the foot of the tool point on its axis)."""
    if np.all(_misses(anchors[0], anchors, axes) <= AXES_MEET_TOLERANCE):
        first: np.ndarray = anchors[0].copy()
        return first
    projections = np.eye(3)[None] - axes[:, :, None] * axes[:, None, :]  # (k, 3, 3): across each axis
    rhs = np.einsum("kij,kj->i", projections, anchors - tool)
    offset = np.linalg.lstsq(projections.sum(axis=0), rhs, rcond=None)[0]
    point: np.ndarray = tool + offset
    return point


def mount_task_space(
    model: mujoco.MjModel,
    index: RobotIndex,
    arm: Arm,
    space: FloatingMountTaskSpace,
    joints: Sequence[str],
    keyframe: np.ndarray,
    where: str,
) -> TaskSpace:
    """The task space of floating mount ``arm`` (see the module's description).

    Args:
        model: the robot's own compiled model.
        index: its names and addresses.
        arm: the mount's arm part (its first end effector is the tool).
        space: its declared :class:`FloatingMountTaskSpace`.
        joints: the arm's joint names, root to tip.
        keyframe: the robot's default keyframe ``(nq,)``.
        where: the robot, for messages.

    Raises:
        ConfigError: the arm's joints are not slides then hinges, a slide has no range,
            the hinges' axes do not meet at one point, or the command frame moves with
            the mount.
    """
    label = f"{where}.parts[{arm.name!r}]: FloatingMountTaskSpace()"
    ids = [index.joint(name, where).id for name in joints]
    kinds = [int(model.jnt_type[j]) for j in ids]
    slide, hinge = int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE)
    slides = [j for j, kind in zip(ids, kinds, strict=True) if kind == slide]
    hinges = [j for j, kind in zip(ids, kinds, strict=True) if kind == hinge]
    if kinds != [slide] * len(slides) + [hinge] * len(hinges) or not arm.end_effectors:
        named = [f"{name} ({mujoco.mjtJoint(kind).name[6:].lower()})" for name, kind in zip(joints, kinds, strict=True)]
        raise ConfigError(
            f"{label}: expected a mount of slides then hinges (root to tip) carrying an end effector, got joints "
            f"{named} and end effectors {[ee.link for ee in arm.end_effectors]}; declare a TaskSpace with its "
            "position_bounds (or MeasuredTaskSpace()) for another arm."
        )
    unlimited = [model.joint(j).name[len(index.prefix) :] for j in slides if not model.jnt_limited[j]]
    if unlimited:
        raise ConfigError(
            f"{label}: slide joint(s) {unlimited} have no range, so the mount's reach has no box; give them a range "
            "(their travel) or declare a TaskSpace with its position_bounds."
        )
    frames = RobotFrames(model, index, arm.end_effectors[:1], where)
    tool, command = frames.end_effectors[arm.end_effectors[0].name]
    home = model.qpos0.copy()
    home[index.qpos_adr] = keyframe
    home[model.jnt_qposadr[ids]] = model.qpos0[model.jnt_qposadr[ids]]  # the mount at its reference
    moved = home.copy()
    moved[model.jnt_qposadr[ids]] += _PROBE
    (tool_pose, command_pose), (_, command_moved) = frames.kinematics.poses(np.vstack([home, moved]), [tool, command])
    if not np.array_equal(command_pose, command_moved):
        raise ConfigError(
            f"{label}: the command frame {command.name!r} moves with the mount's joints, so a box in it bounds "
            "nothing; command the tool in the root frame (the end effector's command_frame=None)."
        )
    data = mujoco.MjData(model)
    data.qpos[:] = home
    mujoco.mj_kinematics(model, data)
    inverse = quat_conjugate(command_pose[3:])

    def in_command(points: np.ndarray) -> np.ndarray:
        return quat_rotate(inverse, points - command_pose[:3])

    if hinges:
        point = _common_point(data.xanchor[hinges], data.xaxis[hinges], tool_pose[:3])
        miss = _misses(point, data.xanchor[hinges], data.xaxis[hinges])
        if np.any(miss > AXES_MEET_TOLERANCE):
            raise ConfigError(
                f"{label}: the hinges' axes do not meet at one point (one passes {1e3 * float(miss.max()):.3g} mm "
                "from the point nearest all of them), so the tool's distance from the slides' carriage changes as "
                "they turn; declare a TaskSpace with its position_bounds (or MeasuredTaskSpace())."
            )
    else:
        point = tool_pose[:3].copy()
    offset = float(np.linalg.norm(tool_pose[:3] - point))
    lower, upper = in_command(point[None])[0], in_command(point[None])[0]
    for j in slides:
        axis = quat_rotate(inverse, data.xaxis[j])
        ends = (model.jnt_range[j] - model.qpos0[model.jnt_qposadr[j]])[:, None] * axis[None]  # (2, 3)
        lower = lower + ends.min(axis=0)
        upper = upper + ends.max(axis=0)
    return TaskSpace(position_bounds=reachable_box(lower, upper, offset), modes=space.modes)


__all__ = ["AXES_MEET_TOLERANCE", "mount_task_space", "reachable_box"]
