"""Generate control-mode tables from a few rules instead of writing them per robot.

A robot declares its joint groups once, with the actuator physics (gains, force
limits) and how far a delta action may move; :func:`joint_control_modes` derives
every joint-space mode from that, and :func:`combine_parts` pairs each of them
with the robot's other parts (e.g. one gripper controller used in every mode).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

from robot_agents.controllers.base import ControllerConfig, PerJoint
from robot_agents.controllers.ee import PDEEPosConfig, PDEEPoseConfig, WorkspaceBox
from robot_agents.controllers.joint import (
    UNLIMITED_FORCE,
    PDJointPosConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
)
from robot_agents.errors import UnknownNameError
from robot_agents.kinematics.ik import IKConfig

ModeConfig = ControllerConfig | Mapping[str, ControllerConfig]


@dataclass(frozen=True)
class JointGroup:
    """Joints driven together, with the physics of their actuators.

    Attributes:
        joint_names: the joints, in action order.
        stiffness: position gain ``kp`` (N*m/rad or N/m), per joint or one for all.
        damping: velocity gain ``kv`` (N*m*s/rad or N*s/m) in position modes.
        force_limit: actuator force limit (N*m or N), e.g. the datasheet torque.
        max_delta: largest joint change one delta action may command (rad or m).
        max_velocity: velocity bound of velocity modes (rad/s or m/s).
        velocity_damping: ``kv`` in pure velocity mode (defaults to ``damping``).
    """

    joint_names: tuple[str, ...]
    stiffness: PerJoint
    damping: PerJoint
    force_limit: PerJoint = UNLIMITED_FORCE
    max_delta: float = 0.1
    max_velocity: PerJoint = 1.0
    velocity_damping: PerJoint | None = None


def joint_control_modes(group: JointGroup) -> dict[str, ControllerConfig]:
    """The six joint-space modes (ManiSkill names) for one joint group.

    ============================  ======================================  ==========
    mode                          action                                  normalized
    ============================  ======================================  ==========
    ``pd_joint_pos``              absolute targets within joint limits    no
    ``pd_joint_delta_pos``        target = measured qpos + delta          yes
    ``pd_joint_target_delta_pos`` target = previous target + delta        yes
    ``pd_joint_vel``              target velocities                       yes
    ``pd_joint_pos_vel``          absolute targets, then velocities       no
    ``pd_joint_delta_pos_vel``    deltas on measured qpos, then velocities yes
    ============================  ======================================  ==========
    """
    names = group.joint_names
    kp, kv, force, step = group.stiffness, group.damping, group.force_limit, group.max_delta
    vmax = group.max_velocity
    vmin: PerJoint = tuple(-v for v in vmax) if isinstance(vmax, tuple) else -vmax
    velocity_kv = group.velocity_damping if group.velocity_damping is not None else kv
    return {
        "pd_joint_pos": PDJointPosConfig(
            joint_names=names, normalize_action=False, stiffness=kp, damping=kv, force_limit=force
        ),
        "pd_joint_delta_pos": PDJointPosConfig(
            joint_names=names, use_delta=True, lower=-step, upper=step, stiffness=kp, damping=kv, force_limit=force
        ),
        "pd_joint_target_delta_pos": PDJointPosConfig(
            joint_names=names,
            use_delta=True,
            use_target=True,
            lower=-step,
            upper=step,
            stiffness=kp,
            damping=kv,
            force_limit=force,
        ),
        "pd_joint_vel": PDJointVelConfig(
            joint_names=names, lower=vmin, upper=vmax, damping=velocity_kv, force_limit=force
        ),
        "pd_joint_pos_vel": PDJointPosVelConfig(
            joint_names=names,
            normalize_action=False,
            stiffness=kp,
            damping=kv,
            force_limit=force,
            vel_lower=vmin,
            vel_upper=vmax,
        ),
        "pd_joint_delta_pos_vel": PDJointPosVelConfig(
            joint_names=names,
            use_delta=True,
            lower=-step,
            upper=step,
            stiffness=kp,
            damping=kv,
            force_limit=force,
            vel_lower=vmin,
            vel_upper=vmax,
        ),
    }


#: The end-effector modes, in ManiSkill's names.
EE_MODES = (
    "pd_ee_delta_pos",
    "pd_ee_delta_pose",
    "pd_ee_pose",
    "pd_ee_target_delta_pos",
    "pd_ee_target_delta_pose",
)


@dataclass(frozen=True)
class TaskSpace:
    """How a joint group's end effector is commanded.

    Attributes:
        position_bounds: action bounds of absolute positions (``pd_ee_pose``), a box in
            the root frame covering the reachable space (m).
        max_translation: largest translation one delta action commands, per axis (m).
        max_rotation: largest rotation one delta action commands, per axis (rad).
        workspace: optional box in the root frame every target is clipped to.
        ee_link: the controlled body or site (default: the robot's ``tcp_link``).
        ik: solver settings.
        rest_qpos: posture of the IK null-space pull.
    """

    position_bounds: WorkspaceBox
    max_translation: float = 0.1
    max_rotation: float = 0.1
    workspace: WorkspaceBox | None = None
    ee_link: str | None = None
    ik: IKConfig = field(default_factory=IKConfig)
    rest_qpos: tuple[float, ...] | None = None


def ee_control_modes(
    group: JointGroup, task: TaskSpace, modes: Sequence[str] = EE_MODES
) -> dict[str, ControllerConfig]:
    """End-effector modes (ManiSkill names) for one joint group, driven by its actuators.

    ===========================  ===============================================  ==========
    mode                         action                                           normalized
    ===========================  ===============================================  ==========
    ``pd_ee_delta_pos``          ``[dx, dy, dz]`` on the measured tool position   yes
    ``pd_ee_delta_pose``         ``[dx, dy, dz, rx, ry, rz]`` on the measured pose yes
    ``pd_ee_pose``               ``[x, y, z, rx, ry, rz]`` absolute, root frame   no
    ``pd_ee_target_delta_pos``   ``[dx, dy, dz]`` on the previous target          yes
    ``pd_ee_target_delta_pose``  ``[dx, dy, dz, rx, ry, rz]`` on the previous one yes
    ===========================  ===============================================  ==========

    Translations are in the root frame and rotations (rotation vectors, rad) turn
    about root-aligned axes through the tool point; position modes hold the orientation.
    """
    step, turn = task.max_translation, task.max_rotation
    position = PDEEPosConfig(
        joint_names=group.joint_names,
        stiffness=group.stiffness,
        damping=group.damping,
        force_limit=group.force_limit,
        ee_link=task.ee_link,
        workspace=task.workspace,
        ik=task.ik,
        rest_qpos=task.rest_qpos,
        pos_lower=-step,
        pos_upper=step,
    )
    shared: dict[str, Any] = {f.name: getattr(position, f.name) for f in fields(position)}
    pose = PDEEPoseConfig(**shared, rot_lower=-turn, rot_upper=turn)
    table: dict[str, ControllerConfig] = {
        "pd_ee_delta_pos": position,
        "pd_ee_delta_pose": pose,
        "pd_ee_pose": replace(
            pose,
            use_delta=False,
            normalize_action=False,
            pos_lower=task.position_bounds.lower,
            pos_upper=task.position_bounds.upper,
            rot_lower=-math.pi,
            rot_upper=math.pi,
        ),
        "pd_ee_target_delta_pos": replace(position, use_target=True),
        "pd_ee_target_delta_pose": replace(pose, use_target=True),
    }
    for mode in modes:
        if mode not in table:
            raise UnknownNameError("ee_control_modes", "end-effector mode", mode, EE_MODES)
    return {mode: table[mode] for mode in modes}


def combine_parts(
    main_part: str, modes: Mapping[str, ControllerConfig], **other_parts: ControllerConfig
) -> dict[str, ModeConfig]:
    """Pair each mode of ``main_part`` with the same configs for the other parts.

    ``combine_parts("arm", joint_control_modes(arm), gripper=gripper_cfg)`` gives
    ``{"pd_joint_pos": {"arm": ..., "gripper": gripper_cfg}, ...}``; the action is the
    main part's action followed by the other parts' in keyword order. Without other
    parts the configs are returned unchanged (a single-part mode).
    """
    if not other_parts:
        return dict(modes)
    return {mode: {main_part: config, **other_parts} for mode, config in modes.items()}
