"""The end-effector task space of an arm a model file implies (a robot that declares
no parts), so that a two-line robot has the end-effector control modes a declared arm
has (``pd_ee_delta_pose``, ``pd_ee_pose`` ...).

Measured on the arm itself, at the robot's default keyframe, in its root frame (the
frame end-effector commands are given in):

- **Reach**: :data:`REACH_SAMPLES` configurations are drawn with a fixed seed
  uniformly within the arm joints' limits (``±pi`` for an unlimited hinge; an unlimited
  slide, a rail or a telescope without stops, held at its keyframe value), the other
  joints at the keyframe; the reach is the farthest the tool point gets from the arm's
  first joint (the keyframe's tool point included), as the task layout measures it
  (:mod:`robot_agents.envs.tasks.layout`).
- **Absolute positions** (``pd_ee_pose``'s bounds): the box around the sampled tool
  points, grown by :data:`BOUNDS_MARGIN` of the reach on every side.
- **Deltas**: :data:`TRANSLATION_PER_REACH` of the reach per step (ManiSkill's Panda:
  0.1 m at a reach of about 0.95 m), rounded to 1 mm; :data:`MAX_ROTATION` rad per
  step (ManiSkill's).
- **Modes**: an arm of 6 joints or more gets every end-effector mode with the default
  IK; one of 3-5 joints the two position modes with
  :data:`~robot_agents.kinematics.ik_config.POSITION_IK` (as the SO-100 and the Koch);
  one of fewer joints, or with a ball or free joint, none.
- **Unlimited slides**: an arm with a slide without limits gets its modes too (IK moves
  it like any joint, so the delta modes carry the tool along it without bound), but its
  reach and ``pd_ee_pose``'s box are those of the other joints with the slide at its
  keyframe value (a travel without end has no box); a note says so
  (:func:`note_unlimited_slides`). Give the slide a ``range`` to cover its travel, or
  declare the arm's ``TaskSpace``.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.agent.derived import random_configurations
from robot_agents.agent.frames import RobotFrames
from robot_agents.agent.index import RobotIndex
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.kinematics.ik_config import POSITION_IK
from robot_agents.kinematics.rotations import quat_conjugate, quat_rotate
from robot_agents.parts.declaration import Arm

#: Configurations drawn to measure the reach and the box (fixed seed: deterministic).
REACH_SAMPLES = 1024
#: Largest translation of one delta action, as a share of the reach.
TRANSLATION_PER_REACH = 0.1
#: Largest rotation of one delta action (rad).
MAX_ROTATION = 0.1
#: How far the absolute-position box reaches past the sampled tool points, as a share of the reach.
BOUNDS_MARGIN = 0.05
#: Arm joints needed for the position modes / for every end-effector mode.
POSITION_JOINTS, POSE_JOINTS = 3, 6
_ONE_DOF = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


def derive_task_space(
    model: mujoco.MjModel, index: RobotIndex, arm: Arm, joints: Sequence[str], keyframe: np.ndarray, where: str
) -> TaskSpace | None:
    """The task space of ``arm`` (see the module's description), or ``None`` when it
    gets no end-effector modes (fewer than 3 joints, a joint that is not a hinge or a
    slide, or a tool that does not move).

    Args:
        model: the robot's own compiled model (alone, at the origin).
        index: its names and addresses.
        arm: the derived arm (its first end effector is the tool).
        joints: the arm's joint names, root to tip.
        keyframe: the robot's default keyframe ``(nq,)`` of the robot.
        where: the robot, for messages.
    """
    ids = [index.joint(name, where).id for name in joints]
    if len(ids) < POSITION_JOINTS or not arm.end_effectors:
        return None
    if any(int(model.jnt_type[j]) not in _ONE_DOF for j in ids):
        return None
    frames = RobotFrames(model, index, arm.end_effectors[:1], where)
    tool, command = frames.end_effectors[arm.end_effectors[0].name]
    rest = model.qpos0.copy()
    rest[index.qpos_adr] = keyframe
    samples = random_configurations(model, index, joints, rest, REACH_SAMPLES, where)
    configs = np.vstack([samples, rest])  # the last row: the keyframe itself
    poses = frames.kinematics.poses(configs, [tool, command])  # (n, 2, 7)
    # the tool point in the command frame, and the arm's first joint at the keyframe
    inverse = quat_conjugate(poses[:, 1, 3:])
    points = quat_rotate(inverse, poses[:, 0, :3] - poses[:, 1, :3])
    data = mujoco.MjData(model)
    data.qpos[:] = rest
    mujoco.mj_kinematics(model, data)
    shoulder = quat_rotate(inverse[-1], data.xanchor[ids[0]] - poses[-1, 1, :3])
    reach = float(np.max(np.linalg.norm(points - shoulder, axis=1)))
    if not reach > 1e-3:
        return None
    margin = BOUNDS_MARGIN * reach
    box = WorkspaceBox(
        lower=tuple(float(v) for v in points.min(axis=0) - margin),  # type: ignore[arg-type]
        upper=tuple(float(v) for v in points.max(axis=0) + margin),  # type: ignore[arg-type]
    )
    translation = max(round(TRANSLATION_PER_REACH * reach, 3), 0.001)
    if len(ids) >= POSE_JOINTS:
        return TaskSpace(position_bounds=box, max_translation=translation, max_rotation=MAX_ROTATION)
    return TaskSpace(
        position_bounds=box,
        max_translation=translation,
        max_rotation=MAX_ROTATION,
        ik=POSITION_IK,
        modes=("pd_ee_delta_pos", "pd_ee_target_delta_pos"),
    )


def unlimited_slides(model: mujoco.MjModel, index: RobotIndex, joints: Sequence[str], where: str) -> list[str]:
    """The slides of ``joints`` without limits (their travel has no end: the measured
    reach and box hold them at the keyframe)."""
    return [
        name
        for name in joints
        if int(model.jnt_type[index.joint(name, where).id]) == mujoco.mjtJoint.mjJNT_SLIDE
        and not model.jnt_limited[index.joint(name, where).id]
    ]


def note_unlimited_slides(where: str, arm: Arm, slides: Sequence[str], space: TaskSpace) -> None:
    """A note for an arm whose measured task space holds unlimited ``slides`` at the
    keyframe: ``pd_ee_pose`` reaches only the box of the other joints, the delta modes
    move along the slides without bound. Points at the caller of
    :func:`~robot_agents.agent.declaration.check` (through ``_with_task_space`` and the
    generator that calls it there)."""
    box = space.position_bounds
    lower = ", ".join(f"{v:.3g}" for v in box.lower)
    upper = ", ".join(f"{v:.3g}" for v in box.upper)
    absolute = " pd_ee_pose's bounds," if "pd_ee_pose" in space.modes else ""
    warnings.warn(
        f"{where}: arm {arm.name!r} has slide joint(s) {list(slides)} without limits: its end-effector modes' reach "
        f"and{absolute} the box ({lower}) .. ({upper}) m, are measured with them held at the keyframe (a travel "
        "without end has no box); the delta modes move the tool along them without bound. Give them a range to "
        "cover their travel, or declare the arm's TaskSpace.",
        RuntimeWarning,
        stacklevel=6,
    )
