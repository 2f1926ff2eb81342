"""Generate control-mode tables from a few rules instead of writing them per robot.

A robot declares its drives once (``actuators``) and its parts; the rules derive every
joint-space mode of a joint group (:func:`joint_control_modes`), the end-effector modes
of an arm (:func:`ee_control_modes`), pair each of them with the robot's other parts
(:func:`combine_parts`), or do all of it from the parts (:func:`modes_from_parts`).
Modes carry action bounds and, only where they must, drive overrides (velocity modes
relax the stiffness of position servos).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields, replace
from typing import Any

from robot_agents.actuators.config import PerJoint
from robot_agents.controllers.base import ControllerConfig
from robot_agents.controllers.base_vel import base_modes
from robot_agents.controllers.ee import PDEEPosConfig, PDEEPoseConfig
from robot_agents.controllers.joint import (
    JointEffortConfig,
    PDJointPosConfig,
    PDJointPosMimicConfig,
    PDJointPosVelConfig,
    PDJointVelConfig,
)
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.keywords import checked_keywords
from robot_agents.parts.declaration import Arm, Base, Gripper, Hand, Legs, Part, is_jaw_gripper
from robot_agents.validation import check_per_joint, check_real

ModeConfig = ControllerConfig | Mapping[str, ControllerConfig]


@checked_keywords
@dataclass(frozen=True)
class JointGroup:
    """Joints commanded together, and how far one action may move them.

    Attributes:
        joint_names: the joints, in action order.
        max_delta: largest joint change one delta action commands (rad or m).
        max_velocity: velocity bound of velocity modes (rad/s or m/s).
        velocity_damping: ``kv`` the drives use in pure velocity mode (their declared
            damping when ``None``).
    """

    joint_names: tuple[str, ...]
    max_delta: float = 0.1
    max_velocity: PerJoint = 1.0
    velocity_damping: PerJoint | None = None

    def __post_init__(self) -> None:
        names = self.joint_names
        if (
            isinstance(names, str)
            or not isinstance(names, Sequence)
            or not names
            or not all(isinstance(n, str) and n for n in names)
        ):
            raise ConfigError(f"JointGroup.joint_names: expected a non-empty tuple of joint names, got {names!r}.")
        object.__setattr__(self, "joint_names", tuple(names))
        check_real(self.max_delta, "max_delta", "JointGroup", minimum=1e-12, unit=" (rad or m per action)")
        check_per_joint(self.max_velocity, "JointGroup.max_velocity", minimum=1e-12)
        if self.velocity_damping is not None:
            check_per_joint(self.velocity_damping, "JointGroup.velocity_damping")


def _check_group(group: object, where: str) -> None:
    """``group`` is a :class:`JointGroup` (a tuple of names is not: its bounds go with it)."""
    if not isinstance(group, JointGroup):
        raise ConfigError(
            f"{where}: expected a JointGroup (joint_names=(...), max_delta, max_velocity), got {group!r}; "
            "e.g. ra.JointGroup(joint_names=('joint1', 'joint2'))."
        )


def joint_control_modes(group: JointGroup) -> dict[str, ControllerConfig]:
    """The six joint-space modes (ManiSkill names) for one joint group.

    ============================  ======================================  ==========
    mode                          action                                  normalized
    ============================  ======================================  ==========
    ``pd_joint_pos``              absolute targets within joint limits    no
    ``pd_joint_delta_pos``        target = measured qpos + delta          yes
    ``pd_joint_target_delta_pos`` target = previous target + delta        yes
    ``pd_joint_vel``              target velocities (stiffness relaxed)   yes
    ``pd_joint_pos_vel``          absolute targets, then velocities       no
    ``pd_joint_delta_pos_vel``    deltas on measured qpos, then velocities yes
    ============================  ======================================  ==========
    """
    _check_group(group, "joint_control_modes")
    names, step = tuple(group.joint_names), group.max_delta
    vmax = group.max_velocity
    vmin = _negated(vmax)
    return {
        "pd_joint_pos": PDJointPosConfig(joint_names=names, normalize_action=False),
        "pd_joint_delta_pos": PDJointPosConfig(joint_names=names, use_delta=True, lower=-step, upper=step),
        "pd_joint_target_delta_pos": PDJointPosConfig(
            joint_names=names, use_delta=True, use_target=True, lower=-step, upper=step
        ),
        "pd_joint_vel": PDJointVelConfig(
            joint_names=names, lower=vmin, upper=vmax, stiffness=0.0, damping=group.velocity_damping
        ),
        "pd_joint_pos_vel": PDJointPosVelConfig(
            joint_names=names, normalize_action=False, vel_lower=vmin, vel_upper=vmax
        ),
        "pd_joint_delta_pos_vel": PDJointPosVelConfig(
            joint_names=names, use_delta=True, lower=-step, upper=step, vel_lower=vmin, vel_upper=vmax
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

#: End-effector modes a :class:`TaskSpace` may list but that are not generated unless it
#: does: ``pd_ee_delta_pose_align`` (ManiSkill 2's ``ee_align`` frame, ManiSkill's Fetch).
OPTIONAL_EE_MODES = ("pd_ee_delta_pose_align",)


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
    ``pd_ee_delta_pose_align``   the same as ``pd_ee_delta_pose``                yes
    ===========================  ===============================================  ==========

    Translations are in the command frame (the robot's root unless the end effector
    names another) and rotations (rotation vectors, rad) turn about its axes through
    the tool point; position modes hold the orientation. ``pd_ee_delta_pose_align``
    (only when listed: see :data:`OPTIONAL_EE_MODES`) is ManiSkill 2's ``ee_align``
    frame, which its Fetch lists: ``target = delta * previous`` with the position then
    set to ``previous.p + d``, a turn about the command frame's axes through the tool
    point, which is what ``pd_ee_delta_pose`` does (ManiSkill 2's ``base`` frame also
    swung the position about the root; ManiSkill 3 dropped both for
    ``root_translation:root_aligned_body_rotation``, this library's ``pd_ee_delta_pose``).
    A turn about the tool's own axes is ``PDEEPoseConfig(rotation_frame=CommandFrame.EE)``.
    """
    _check_group(group, "ee_control_modes")
    if not isinstance(task, TaskSpace):
        raise ConfigError(f"ee_control_modes: expected task to be a TaskSpace, got {task!r}.")
    step, turn = task.max_translation, task.max_rotation
    position = PDEEPosConfig(
        joint_names=tuple(group.joint_names),
        end_effector=task.end_effector,
        workspace=task.workspace,
        hold_orientation=task.hold_orientation,
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
        "pd_ee_delta_pose_align": pose,
    }
    for mode in modes:
        if mode not in table:
            raise UnknownNameError("ee_control_modes", "end-effector mode", mode, (*EE_MODES, *OPTIONAL_EE_MODES))
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


def _negated(bound: PerJoint) -> PerJoint:
    """The lower bound mirroring an upper one (one value, or one per joint)."""
    return tuple(-v for v in bound) if isinstance(bound, tuple) else -bound


def _velocity_bounds(part: Part, joints: Sequence[str], velocity_limits: Mapping[str, float]) -> PerJoint:
    if part.max_velocity is not None:
        return part.max_velocity
    limits = [velocity_limits.get(j, math.inf) for j in joints]
    return tuple(v if math.isfinite(v) else 1.0 for v in limits)


def gripper_config(part: Gripper, joints: Sequence[str], driven: Sequence[str]) -> ControllerConfig:
    """One normalized action for a gripper: -1 closes (``squeeze`` past ``closed``), +1
    opens; the first driven joint leads and the other driven joints follow linearly."""
    names = [j for j in joints if j in driven]
    if not names:
        raise ConfigError(f"Gripper {part.name!r}: none of its joints {list(joints)} has a drive.")
    n = len(joints)
    opened, closed = part.positions(n)
    pick = [list(joints).index(j) for j in names]
    o, c = opened[pick], closed[pick]
    span = o[0] - c[0]
    if span == 0:
        raise ConfigError(f"Gripper {part.name!r}: open and closed positions of {names[0]!r} are equal.")
    squeeze = part.squeeze if span > 0 else -part.squeeze
    low, high = sorted((c[0] - squeeze, o[0]))
    # -1 closes: when the leader closes towards its upper end, -1 maps onto the upper bound
    reverse = bool(span < 0)
    if len(names) == 1:
        return PDJointPosConfig(
            joint_names=tuple(names), lower=low, upper=high, clip_target=False, reverse_normalization=reverse
        )
    multipliers = (o - c) / span
    offsets = c - multipliers * c[0]
    return PDJointPosMimicConfig(
        joint_names=tuple(names),
        lower=low,
        upper=high,
        multipliers=tuple(float(m) for m in multipliers),
        offsets=tuple(float(v) for v in offsets),
        clip_target=False,
        reverse_normalization=reverse,
    )


#: The mode of robots whose drives are torque motors (a model file's ``<motor>``s).
EFFORT_MODE = "joint_effort"


def modes_from_parts(
    parts: Sequence[Part],
    part_joints: Mapping[str, Sequence[str]],
    velocity_limits: Mapping[str, float],
    torque_only: Sequence[str] = (),
    undamped: Sequence[str] = (),
    velocity_only: Sequence[str] = (),
    effort_limits: Mapping[str, float] | None = None,
    motor_joints: Sequence[str] = (),
) -> dict[str, ModeConfig]:
    """The control-mode table of a robot from its parts.

    The main part (the first arm; else the first hand; else the first part that is not
    a gripper) gets the six joint modes and, for an arm with a task space, the five
    end-effector modes; a gripper adds one normalized open/close action to every mode;
    every other part adds delta joint-position actions (a hand riding on an arm: from its
    targets, as ManiSkill's, and absolute targets in the modes where the main part's are
    absolute; a mobile manipulator with a
    torso or head also gets ``pd_joint_delta_pos_stiff_body``: the arm's deltas with the
    body at absolute joint targets). ``velocity_limits`` holds the
    driven joints (rad/s or m/s; ``inf`` where unknown). When any of the main part's
    drives is in ``torque_only`` (motors that cannot follow position targets), the
    table is one mode, ``joint_effort``: normalized efforts within the drives' limits
    over every driven joint of every part. Joints in ``undamped`` have drives without
    damping (a model file's ``<position>`` actuator without ``kv``): a velocity mode
    relaxes their stiffness and nothing would be left to follow its targets, so the
    table has no velocity-only mode (``pd_joint_vel``) over them; the position+velocity
    modes stay (their stiffness follows the positions). Joints in ``velocity_only`` have
    velocity servos (a model file's ``<velocity>`` actuators: damping, no stiffness),
    which cannot hold a position: a main part with any keeps only ``pd_joint_vel``,
    another part takes velocity actions. The effort mode's actions are normalized when
    every drive's effort is bounded, else efforts in N*m or N (a file's ``<motor>``
    without ``ctrlrange`` or ``forcerange`` takes any effort). Joints in
    ``motor_joints`` have PD drives standing in for a file's torque motors: the table
    also has ``joint_effort`` over every driven joint, the drives' stiffness and
    damping relaxed (the motors' torques).
    """
    if not parts:
        return {}
    driven = list(velocity_limits)
    every = tuple(j for p in parts for j in part_joints[p.name] if j in driven)
    bounded = effort_limits is None or all(math.isfinite(effort_limits.get(j, math.inf)) for j in every)
    if set(torque_only) & {j for p in parts for j in part_joints[p.name]}:
        return {EFFORT_MODE: JointEffortConfig(joint_names=every, normalize_action=bounded)}
    main: Part = next(
        (p for p in parts if isinstance(p, Arm)),
        next(
            (p for p in parts if isinstance(p, Hand)), next((p for p in parts if not isinstance(p, Gripper)), parts[0])
        ),
    )
    joints = [j for j in part_joints[main.name] if j in driven]
    if is_jaw_gripper(main):
        table: dict[str, ControllerConfig] = {"pd_joint_pos": gripper_config(main, part_joints[main.name], driven)}
    else:
        group = JointGroup(
            tuple(joints), max_delta=main.max_delta, max_velocity=_velocity_bounds(main, joints, velocity_limits)
        )
        table = dict(joint_control_modes(group))
        if isinstance(main, Arm) and main.task_space is not None:
            task = main.task_space
            if not isinstance(task, TaskSpace):
                raise ConfigError(f"Arm {main.name!r}.task_space: expected a TaskSpace, got {task!r}.")
            ee_names = [ee.name for ee in main.end_effectors]
            if not ee_names:
                raise ConfigError(
                    f"Arm {main.name!r}.task_space: end-effector modes need an end effector; declare "
                    "end_effectors=(EndEffector(link), ...) on the arm."
                )
            if task.end_effector is None:
                task = replace(task, end_effector=ee_names[0])
            elif task.end_effector not in ee_names:
                raise UnknownNameError(f"Arm {main.name!r}.task_space", "end effector", task.end_effector, ee_names)
            table.update(ee_control_modes(group, task, task.modes))
        if set(undamped) & set(joints):
            table = {mode: config for mode, config in table.items() if not _velocity_only(config)}
        if set(velocity_only) & set(joints):
            table = {mode: config for mode, config in table.items() if _velocity_only(config)}
            if not table:
                raise ConfigError(
                    f"{type(main).__name__} {main.name!r}: joints {sorted(set(velocity_only) & set(joints))} have "
                    f"velocity servos (no stiffness) and {sorted(set(undamped) & set(joints))} position servos "
                    "without damping: no joint mode drives both; declare control_modes or actuators."
                )
    others: dict[str, ControllerConfig] = {}
    # a robot standing on its legs has no gravity compensation (it would lighten the body
    # the legs carry): every part riding on it carries its own weight, as the legs do
    standing = any(isinstance(p, Legs) and not p.held for p in parts)
    for part in parts:
        if part is main or (isinstance(part, Legs) and part.held):
            continue  # held legs: no action, their drives keep the reset pose
        names = part_joints[part.name]
        if is_jaw_gripper(part):
            others[part.name] = gripper_config(part, names, driven)
        elif isinstance(part, Base):
            if len(names) != 3:
                raise ConfigError(f"Base {part.name!r}: expected 3 joints (x, y, yaw), got {list(names)}.")
            others[part.name] = base_modes(
                (names[0], names[1], names[2]), part.holonomic, part.max_speed, part.max_turn
            )
        else:
            moving = tuple(j for j in names if j in driven)
            if moving and set(moving) & set(velocity_only):
                speeds = _velocity_bounds(part, moving, velocity_limits)
                others[part.name] = PDJointVelConfig(joint_names=moving, lower=_negated(speeds), upper=speeds)
            elif moving:
                # legs that carry the robot, and the parts riding on them (a head, a tail),
                # take deltas from their targets: a zero delta from the measured pose would
                # let them give under their weight step by step; so does a hand on an arm
                # (ManiSkill's hands on arms: xarm7_ability's hand_target_delta_pos), whose
                # targets then close on an object and keep pressing where a delta from the
                # measured pose would squeeze with one step's delta at most
                others[part.name] = PDJointPosConfig(
                    joint_names=moving,
                    use_delta=True,
                    use_target=standing or isinstance(part, Hand),
                    lower=-part.max_delta,
                    upper=part.max_delta,
                )
    combined = combine_parts(main.name, table, **others)
    # A hand riding on an arm (a floating mount) takes absolute joint targets where the
    # main part does (ManiSkill's floating hands' pd_joint_pos): deltas from the measured
    # pose would let a finger pressing on an object, or the wrist under its load, give.
    hands = {
        name: PDJointPosConfig(joint_names=config.joint_names, normalize_action=False)
        for name, config in others.items()
        if isinstance(next(p for p in parts if p.name == name), Hand) and isinstance(config, PDJointPosConfig)
    }
    for mode, config in table.items():
        entry = combined[mode]
        if hands and _absolute_positions(config) and isinstance(entry, Mapping):
            combined[mode] = {**entry, **hands}
    # A mobile manipulator's body (torso, head) held at absolute targets while the arm
    # takes delta commands: ManiSkill's Fetch mode of that name.
    body = {
        part.name: PDJointPosConfig(joint_names=others[part.name].joint_names, normalize_action=False)
        for part in parts
        if part is not main and part.name in others and not isinstance(part, (Gripper, Base))
    }
    if body and any(isinstance(p, Base) for p in parts) and "pd_joint_delta_pos" in table and others:
        combined[STIFF_BODY_MODE] = {
            main.name: table["pd_joint_delta_pos"],
            **{name: body.get(name, config) for name, config in others.items()},
        }
    if set(motor_joints) & set(every):
        combined[EFFORT_MODE] = JointEffortConfig(
            joint_names=every, normalize_action=bounded, stiffness=0.0, damping=0.0
        )
    return combined


def _absolute_positions(config: ControllerConfig) -> bool:
    """A config that writes absolute position targets (``pd_joint_pos``,
    ``pd_joint_pos_vel``, ``pd_ee_pose``), not deltas or velocities alone."""
    return "position" in config.target_kinds() and not bool(getattr(config, "use_delta", True))


def _velocity_only(config: ControllerConfig) -> bool:
    """A config that writes velocity targets without positions and keeps the drives' damping."""
    kinds = config.target_kinds()
    return "velocity" in kinds and "position" not in kinds and config.damping is None


#: Mobile manipulators with a torso / head: arm deltas, body at absolute targets.
STIFF_BODY_MODE = "pd_joint_delta_pos_stiff_body"


__all__ = [
    "EE_MODES",
    "OPTIONAL_EE_MODES",
    "STIFF_BODY_MODE",
    "JointGroup",
    "TaskSpace",
    "WorkspaceBox",
    "combine_parts",
    "ee_control_modes",
    "gripper_config",
    "joint_control_modes",
    "modes_from_parts",
]
