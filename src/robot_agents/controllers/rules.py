"""Generate control-mode tables from a few rules instead of writing them per robot.

A robot declares its joint groups once, with the actuator physics (gains, force
limits) and how far a delta action may move; :func:`joint_control_modes` derives
every joint-space mode from that, and :func:`combine_parts` pairs each of them
with the robot's other parts (e.g. one gripper controller used in every mode).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from robot_agents.controllers.base import ControllerConfig, PerJoint
from robot_agents.controllers.joint import (
    UNLIMITED_FORCE,
    PDJointPosConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
)

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
