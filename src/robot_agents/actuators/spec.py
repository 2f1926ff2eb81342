"""Write a robot's actuator declarations into its MjSpec (before compiling).

One function, :func:`apply_actuators`, decides for every joint which actuator drives
it: a declared one (added here, named like its joint), the model file's own (adopted),
or none. A file's actuators are adopted by default, replaced when the robot says so,
and never kept beside a declared drive on the same joint.
"""

from __future__ import annotations

import dataclasses
import re
import warnings
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from enum import Enum

import mujoco
import numpy as np

from robot_agents.actuators.config import (
    ActuatorConfig,
    DCMotorActuator,
    DerivedActuators,
    FileActuators,
    MotorActuator,
    PDActuator,
    PIDActuator,
    VelocityActuator,
    per_joint,
)
from robot_agents.errors import ConfigError
from robot_agents.model.compiler import range_limited
from robot_agents.patterns import claim


class DriveKind(Enum):
    """How targets reach a drive."""

    #: MuJoCo's affine actuator (PD, velocity servo, motor): ``ctrl`` is solved from the targets.
    AFFINE = "affine"
    #: A torque motor under an explicit PD loop closed before every substep.
    EXPLICIT = "explicit"
    #: MuJoCo's ``pid`` actuator: ``ctrl = [q*, qd*]``.
    PID = "pid"
    #: MuJoCo's ``dcmotor`` actuator with a position controller: ``ctrl = [q*, qd*, tau*]``.
    DCMOTOR = "dcmotor"


@dataclass(frozen=True)
class DriveDeclaration:
    """The drive of one joint, as declared (names without the scene prefix).

    Attributes:
        joint: the joint it drives.
        kind: how targets become controls.
        source: the declaration it comes from, for messages.
        stiffness, damping: the explicit PD gains of an ``EXPLICIT`` drive (joint units).
        effort_limit: N*m or N (``inf``: unlimited); velocity_limit: rad/s or m/s.
    """

    joint: str
    kind: DriveKind
    source: str
    stiffness: float = 0.0
    damping: float = 0.0
    effort_limit: float = np.inf
    velocity_limit: float = np.inf
    #: The drive stands in for a model file's torque motor (see :func:`apply_actuators`):
    #: ``joint_effort`` commands the motor's torques through it.
    replaces_motor: bool = False
    #: The joint's own damping is fed forward with velocity targets
    #: (:attr:`ActuatorConfig.damping_feedforward`).
    damping_feedforward: bool = True
    #: The joint damping the declaration gives the joint (N*m*s/rad or N*s/m; a motor's
    #: back-EMF, :attr:`ActuatorConfig.joint_damping`), 0 where it sets none: with
    #: ``damping_feedforward`` it follows velocity targets as the drive's damping does
    #: (a model file's own joint damping, a passive loss, is not counted as a drive's).
    joint_damping: float = 0.0


def _file_actuators(spec: mujoco.MjSpec) -> list[mujoco.MjsActuator]:
    return list(spec.actuators)


#: Gains of derived drives: joint -> (stiffness, damping, effort limit).
DerivedGains = Mapping[str, tuple[float, float, float]]


def drivable_joints(spec: mujoco.MjSpec) -> list[str]:
    """Hinge and slide joints that are not followers of a joint coupling (mimic
    fingers, linkages): the joints a robot without declared drives gets drives on."""
    followers = {eq.name1 for eq in spec.equalities if eq.type == mujoco.mjtEq.mjEQ_JOINT and eq.name2}
    kinds = (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    return [j.name for j in spec.joints if j.type in kinds and j.name not in followers]


def apply_actuators(
    spec: mujoco.MjSpec,
    declarations: Sequence[ActuatorConfig],
    replace_file_actuators: bool,
    derived: DerivedGains | None,
    where: str,
    own_joints: Collection[str] | None = None,
    derive_own: bool = False,
    motors_as_pd: bool = True,
    mocap_held: Sequence[str] = (),
    file_speeds: Mapping[str, float] | None = None,
) -> list[DriveDeclaration]:
    """Edit ``spec`` so that every declared joint has exactly one actuator.

    Args:
        declarations: the robot's actuator declarations.
        replace_file_actuators: delete the file's actuators first.
        derived: gains of derived drives (see :mod:`robot_agents.actuators.gains`):
            when the robot declares no actuators and the file has none, every drivable
            joint gets a PD drive with these gains, and so do the joints a
            :class:`DerivedActuators` claims; ``None``: zero gains for now.
        where: the robot, for messages.
        own_joints: the joints of the robot's own model file (``None``: every joint),
            the only ones a ``DerivedActuators()`` without joints takes: a mounted
            piece's joints are the piece's, and those it leaves undriven are passive by
            its design (a linkage's followers).
        derive_own: the robot itself declares no actuators (``declarations`` are its
            mounted pieces'): when its own file drives none of its own joints either,
            those joints get derived drives, as a ``DerivedActuators()`` would give
            them (a user's arm file with a built-in gripper mounted needs no drive
            declarations, as it needs none alone).
        motors_as_pd: with ``derive_own``, a fixed robot whose file drives each of its
            joints with a torque motor gets PD drives within the motors' efforts in
            their place (off for a robot declaring its own control modes, which were
            written for the motors).
        mocap_held: joints the file moved through a weld to a mocap body that was
            dropped with the file's other bodies (:func:`~robot_agents.model.robot_spec.isolate_robot`):
            with ``derive_own``, those no file actuator drives get derived drives (the
            arm of gymnasium-robotics' Fetch, of Meta-World's Sawyer).
        file_speeds: the model file's joint speed limits (rad/s or m/s; a URDF's
            ``<limit velocity>``, :func:`~robot_agents.model.loading.urdf_velocity_limits`):
            the ``velocity_limit`` of each of those joints' drives that states none.

    Returns:
        The drive of each driven joint, in the model's joint order.
    """
    joints = [j for j in spec.joints if j.type != mujoco.mjtJoint.mjJNT_FREE]
    names = [j.name for j in joints]
    file_actuators = _file_actuators(spec)
    tendons = [a for a in file_actuators if a.trntype != mujoco.mjtTrn.mjTRN_JOINT]
    if tendons and not replace_file_actuators and not declarations:
        # Actuators on tendons (or sites, bodies) cannot follow joint targets: a robot that
        # declares no drives gets what a file without actuators gets, derived PD drives on
        # its joints, in place of all the file's actuators (a partial set would leave the
        # tendon-driven joints without a drive).
        kinds = sorted({a.trntype.name[6:].lower() for a in tendons})
        labels = [a.name or f"#{file_actuators.index(a)}" for a in tendons]
        others = len(file_actuators) - len(tendons)
        warnings.warn(
            f"{where}: {len(labels)} of the model file's actuators ({', '.join(labels[:3])}"
            f"{' ...' if len(labels) > 3 else ''}) drive {' and '.join(t + 's' for t in kinds)}, not joints, and "
            "robot_agents drives joints: every hinge and slide joint gets a PD drive with gains derived from its "
            f"inertia instead{f' (replacing the other {others} file actuators too)' if others else ''}; set "
            "replace_file_actuators = True to say so, or declare actuators to choose the drives.",
            RuntimeWarning,
            stacklevel=4,
        )
        replace_file_actuators = True
    motors: dict[str, float] = {}
    own = set(names if own_joints is None else own_joints)
    replace_motors = motors_as_pd and (derive_own or not declarations)
    if file_actuators and not replace_file_actuators and replace_motors and _fixed_and_motor_driven(spec, own):
        derive_own = False  # the motors' joints only: the file leaves none of its joints undriven
        # A fixed robot the file drives with torque motors (robosuite's arms, gymnasium's
        # reacher): PD drives derived as for a file without actuators, each within its
        # motor's effort, so that joint and end-effector modes work; joint_effort still
        # commands the motors' torques (the drives' stiffness and damping relaxed).
        # A file mixing motors with position servos (an arm's <position> joints and a
        # <motor> wrist): the motors get such PD drives, the servos stay as the file has them.
        motor_actuators = [a for a in file_actuators if _is_motor(a)]
        motors = {a.target: _adopted(a, "the model file", a.target).effort_limit for a in motor_actuators}
        servos = [a.target for a in file_actuators if not _is_motor(a)]
        kept = (
            f"; its position servos on {servos[:4]}{' ...' if len(servos) > 4 else ''} stay as the file has them "
            "(joint_effort relaxes their stiffness and damping too)"
            if servos
            else ""
        )
        warnings.warn(
            f"{where}: the model file drives {len(motors)} joint(s) with torque motors: each gets a PD drive with "
            "gains derived from its inertia, its effort within the motor's, for the joint and end-effector modes; "
            f"joint_effort commands the motors' torques{kept}. Declare actuators = (ra.FileActuators(),) to keep the "
            "motors alone.",
            RuntimeWarning,
            stacklevel=4,
        )
        declarations = (
            *declarations,  # a mounted piece's drives (a built-in gripper on robosuite's arm)
            DerivedActuators(joints=tuple(f"^{re.escape(j)}$" for j in motors), effort_limit=tuple(motors.values())),
        )
        if servos:
            for actuator in motor_actuators:
                spec.delete(actuator)
            file_actuators = [a for a in file_actuators if not _is_motor(a)]
        else:
            replace_file_actuators = True
    elif file_actuators and not replace_file_actuators and replace_motors:
        _note_motors_kept(spec, own, where)
    if replace_file_actuators:
        for actuator in file_actuators:
            spec.delete(actuator)
        file_actuators = []
    on_joint: dict[str, mujoco.MjsActuator] = {}
    for actuator in file_actuators:
        label = actuator.name or f"#{file_actuators.index(actuator)}"
        if actuator.trntype != mujoco.mjtTrn.mjTRN_JOINT:
            raise ConfigError(
                f"{where}: the model file's actuator {label!r} drives a {actuator.trntype.name[6:].lower()}, not a joint, "
                "and robot_agents drives joints only: set replace_file_actuators = True and declare the joint drives "
                "in actuators (or declare no actuators: replace_file_actuators = True alone is enough, every hinge "
                "and slide joint then gets a PD drive with gains derived from its inertia)."
            )
        if actuator.target in on_joint:
            raise ConfigError(
                f"{where}: joint {actuator.target!r} has two actuators in the model file "
                f"({on_joint[actuator.target].name!r}, {label!r}); set replace_file_actuators = True."
            )
        on_joint[actuator.target] = actuator

    implied: DerivedActuators | None = None
    drivable = drivable_joints(spec)
    unheld = [j for j in mocap_held if j not in on_joint and j in drivable]
    if derive_own and unheld and not replace_file_actuators:
        warnings.warn(
            f"{where}: the model file moved joints {unheld[:4]}{' ...' if len(unheld) > 4 else ''} through a "
            "weld to a mocap body, dropped with the file's other bodies: they get PD drives with gains derived from "
            "their inertia. Declare actuators to choose their drives.",
            RuntimeWarning,
            stacklevel=4,
        )
        derive_own = False  # those joints, not every undriven one
        declarations = (
            *declarations,
            DerivedActuators(joints=tuple(f"^{re.escape(j)}$" for j in unheld)),
        )
    if derive_own and (declarations or set(on_joint) - own) and not (set(on_joint) & own):
        # what a robot without pieces gets (the branch at the end), beside its pieces' drives
        # (declared, or their own files' actuators: a user's gripper file driving its fingers)
        implied = DerivedActuators()
        declarations = (*declarations, implied)
    rest = [d for d in declarations if isinstance(d, DerivedActuators) and d.joints is None]
    if len(rest) > 1:
        raise ConfigError(
            f"{where}.actuators: {len(rest)} DerivedActuators() without joints; each takes every joint nobody else "
            "drives, so declare one (or give each its joints)."
        )
    declared = [d for d in declarations if not isinstance(d, FileActuators) and d not in rest]
    adopted = [d for d in declarations if isinstance(d, FileActuators)]
    claims = claim([(d.label, d.joints) for d in declared], names, f"{where}.actuators")
    file_driven = [n for n in names if n in on_joint]
    adopted_claims = claim(
        [(d.label, d.joints) for d in adopted], file_driven, f"{where}.actuators", "joint with a file actuator"
    )
    claimed_by: dict[str, ActuatorConfig] = {}
    driveable = (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    for decl, hits in zip(declared, claims, strict=True):
        for i in hits:
            if joints[i].type not in driveable:
                raise ConfigError(
                    f"{where}.actuators: {decl.label} claims joint {names[i]!r}, a ball joint: a drive needs a hinge "
                    "or a slide (one degree of freedom); leave it out of the pattern (a ball joint is passive)."
                )
            if names[i] in on_joint:
                raise ConfigError(
                    f"{where}.actuators: {decl.label} claims joint {names[i]!r}, which the model file already drives "
                    f"with actuator {on_joint[names[i]].name!r}; adopt it with FileActuators({names[i]!r}) or set "
                    "replace_file_actuators = True."
                )
            claimed_by[names[i]] = decl
    for decl, hits in zip(adopted, adopted_claims, strict=True):
        for i in hits:
            claimed_by[file_driven[i]] = decl
    if rest:
        taken_rest = [n for n in drivable if n not in claimed_by and n not in on_joint and n in own]
        if not taken_rest and implied is None:
            raise ConfigError(
                f"{where}.actuators: DerivedActuators() takes the hinge and slide joints of the robot's own model "
                "file that nothing else drives, and there are none: the declarations and the file's actuators "
                f"drive {sorted(claimed_by) + sorted(on_joint)}."
            )
        for joint in taken_rest:
            claimed_by[joint] = rest[0]
    for joint, decl in claimed_by.items():
        if isinstance(decl, DerivedActuators) and joint not in drivable:
            raise ConfigError(
                f"{where}.actuators: {decl.label} claims joint {joint!r}, which follows another joint through a "
                f"joint coupling (a mimic) and gets no drive of its own. Drivable joints: {drivable} "
                "(DerivedActuators() without joints takes those nothing else drives)."
            )

    drives: dict[str, DriveDeclaration] = {}
    taken = {a.name for a in spec.actuators}
    for decl in declarations:
        matched = [n for n in names if claimed_by.get(n) is decl]
        _set_joint_properties(spec, decl, matched)
        if isinstance(decl, FileActuators):
            for joint in matched:
                drives[joint] = _adopted(on_joint[joint], decl.label, joint)
        elif isinstance(decl, DerivedActuators):
            limits = per_joint(decl.label, "effort_limit", decl.effort_limit, len(matched), np.inf)
            speeds = per_joint(decl.label, "velocity_limit", decl.velocity_limit, len(matched), np.inf)
            for joint, limit, speed in zip(matched, limits, speeds, strict=True):
                if np.isfinite(limit):  # the joint's own limit: the derived gains read it from the model
                    spec.joint(joint).actfrclimited = 1
                    spec.joint(joint).actfrcrange = [-float(limit), float(limit)]
                kp, kv, derived_limit = (derived or {}).get(joint, (0.0, 0.0, np.inf))
                limit = min(float(limit), derived_limit)
                _add_affine(spec, joint, taken, kp=kp, kv=kv, limit=limit)
                source = (
                    f"derived gains (see {_GAINS})"
                    if decl is implied
                    else f"derived gains ({decl.label}; see {_GAINS})"
                )
                if joint in motors:
                    source = f"derived gains, within the model file's motor (see {_GAINS})"
                drives[joint] = DriveDeclaration(
                    joint, DriveKind.AFFINE, source, kp, kv, limit, float(speed), replaces_motor=joint in motors
                )
        else:
            for joint, drive in zip(matched, _add_declared(spec, decl, matched, taken), strict=True):
                drives[joint] = drive
    # Actuators of the file nobody declared: adopted as they are.
    for joint, actuator in on_joint.items():
        if joint not in drives:
            drives[joint] = _adopted(actuator, "the model file", joint)
    if not declarations and not on_joint:
        for joint in drivable:
            kp, kv, limit = (derived or {}).get(joint, (0.0, 0.0, np.inf))
            _add_affine(spec, joint, taken, kp=kp, kv=kv, limit=limit)
            drives[joint] = DriveDeclaration(joint, DriveKind.AFFINE, f"derived gains (see {_GAINS})", kp, kv, limit)
    stated = file_speeds or {}
    return [
        dataclasses.replace(drives[n], velocity_limit=stated[n])
        if n in stated and not np.isfinite(drives[n].velocity_limit)
        else drives[n]
        for n in names
        if n in drives
    ]


_GAINS = "robot_agents.actuators.gains"


def _set_joint_properties(spec: mujoco.MjSpec, decl: ActuatorConfig, matched: list[str]) -> None:
    owner = decl.label
    n = len(matched)
    if decl.armature is not None:
        for joint, value in zip(matched, per_joint(owner, "armature", decl.armature, n, 0.0), strict=True):
            spec.joint(joint).armature = float(value)
    if decl.friction is not None:
        for joint, value in zip(matched, per_joint(owner, "friction", decl.friction, n, 0.0), strict=True):
            spec.joint(joint).frictionloss = float(value)
    if decl.joint_damping is not None:
        for joint, value in zip(matched, per_joint(owner, "joint_damping", decl.joint_damping, n, 0.0), strict=True):
            _set_linear_damping(spec.joint(joint), float(value))


def _set_linear_damping(joint: mujoco.MjsJoint, value: float) -> None:
    """Make ``joint``'s damping ``value`` (N*m*s/rad or N*s/m), linear in its speed:
    MuJoCo 3.4 and later take a polynomial (linear, then higher terms, set to 0), earlier
    versions one number."""
    current = np.asarray(joint.damping, dtype=np.float64)
    if current.ndim == 0:
        joint.damping = value
        return
    polynomial = np.zeros_like(current)
    polynomial[0] = value
    joint.damping = polynomial


def _actuator_name(joint: str, taken: set[str]) -> str:
    name = joint if joint not in taken else f"{joint}_drive"
    taken.add(name)
    return name


def _add_affine(spec: mujoco.MjSpec, joint: str, taken: set[str], kp: float, kv: float, limit: float) -> None:
    """A ``general`` actuator in joint units: gain ``g`` (kp, else kv, else 1), bias
    ``(0, -kp, -kv)``, force clamped to ``limit``. Gear 1 and no activation dynamics are
    set explicitly: a file's default ``<general>`` (dm_control's ``dyntype="filter"``, a
    ``gear``) is meant for its own actuators, not for these drives."""
    gain = kp if kp > 0 else (kv if kv > 0 else 1.0)
    spec.add_actuator(
        name=_actuator_name(joint, taken),
        target=joint,
        trntype=mujoco.mjtTrn.mjTRN_JOINT,
        gear=[1.0] + [0.0] * 5,
        dyntype=mujoco.mjtDyn.mjDYN_NONE,
        dynprm=[1.0] + [0.0] * 9,
        actlimited=0,
        gaintype=mujoco.mjtGain.mjGAIN_FIXED,
        biastype=mujoco.mjtBias.mjBIAS_AFFINE,
        gainprm=[gain] + [0.0] * 9,
        biasprm=[0.0, -kp, -kv] + [0.0] * 7,
        ctrllimited=0,
        forcelimited=int(np.isfinite(limit)),
        forcerange=[-limit, limit] if np.isfinite(limit) else [0.0, 0.0],
    )


def _add_declared(
    spec: mujoco.MjSpec, decl: ActuatorConfig, matched: list[str], taken: set[str]
) -> list[DriveDeclaration]:
    owner, n = decl.label, len(matched)
    limits = per_joint(owner, "effort_limit", decl.effort_limit, n, np.inf)
    speeds = per_joint(owner, "velocity_limit", decl.velocity_limit, n, np.inf)
    result = []
    feedforward = decl.damping_feedforward
    own_damping = per_joint(owner, "joint_damping", decl.joint_damping, n, 0.0)

    def declared(k: int, kind: DriveKind, kp: float, kv: float) -> DriveDeclaration:
        return DriveDeclaration(
            matched[k],
            kind,
            owner,
            kp,
            kv,
            float(limits[k]),
            float(speeds[k]),
            damping_feedforward=feedforward,
            joint_damping=float(own_damping[k]),
        )

    for k, joint in enumerate(matched):
        limit = float(limits[k])
        if isinstance(decl, PDActuator):
            kp = float(per_joint(owner, "stiffness", decl.stiffness, n, 0.0)[k])
            kv = float(per_joint(owner, "damping", decl.damping, n, 0.0)[k])
            _add_affine(spec, joint, taken, kp, kv, limit)
            result.append(declared(k, DriveKind.AFFINE, kp, kv))
        elif isinstance(decl, VelocityActuator):
            kv = float(per_joint(owner, "damping", decl.damping, n, 0.0)[k])
            _add_affine(spec, joint, taken, 0.0, kv, limit)
            result.append(declared(k, DriveKind.AFFINE, 0.0, kv))
        elif isinstance(decl, MotorActuator):
            kp = float(per_joint(owner, "stiffness", decl.stiffness, n, 0.0)[k])
            kv = float(per_joint(owner, "damping", decl.damping, n, 0.0)[k])
            _add_affine(spec, joint, taken, 0.0, 0.0, limit)
            result.append(declared(k, DriveKind.EXPLICIT, kp, kv))
        elif isinstance(decl, (PIDActuator, DCMotorActuator)):
            actuator = spec.add_actuator(
                name=_actuator_name(joint, taken), target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT
            )
            kind = _native(actuator, decl, owner)
            if np.isfinite(limit):
                actuator.forcelimited = 1
                actuator.forcerange = [-limit, limit]
            result.append(declared(k, kind, decl.stiffness, decl.damping))
        else:
            raise ConfigError(f"{owner}: unknown actuator declaration type {type(decl).__name__}.")
    return result


def _native(actuator: mujoco.MjsActuator, decl: PIDActuator | DCMotorActuator, owner: str) -> DriveKind:
    """Make ``actuator`` MuJoCo's ``pid`` or ``dcmotor`` (position and velocity inputs)."""
    setter = "set_to_pid" if isinstance(decl, PIDActuator) else "set_to_dcmotor"
    if not hasattr(actuator, setter):
        raise ConfigError(
            f"{owner}: MuJoCo {mujoco.__version__} has no {setter[7:]} actuator; it needs MuJoCo >= 3.15."
        )
    if isinstance(decl, PIDActuator):
        actuator.set_to_pid(
            kp=decl.stiffness,
            kv=decl.damping,
            ki=decl.integral_gain,
            imax=decl.integral_limit if decl.integral_limit is not None else -1,
        )
        return DriveKind.PID
    # Inputs: position (1), velocity (2) and feed-forward effort (4).
    actuator.set_to_dcmotor(
        motorconst=[decl.motor_constant, decl.motor_constant],
        resistance=decl.resistance,
        controller=[decl.stiffness, 0.0, decl.damping, 0.0, 0.0, 0.0],
        ctrlspec=7,
    )
    return DriveKind.DCMOTOR


def _fixed_and_motor_driven(spec: mujoco.MjSpec, own: Collection[str]) -> bool:
    """A fully actuated robot without a free joint whose file's actuators are all torque
    motors on joints (affine or no bias without stiffness or damping), or torque motors
    and position servos (affine with stiffness: ``<position>``), one on each of the
    drivable joints of its own file (``own``; a mounted piece's are the piece's). A file
    with velocity servos (damping, no stiffness) or another kind is not: its motors'
    joints could be given PD drives, but a part mixing velocity servos with position
    drives has no joint mode that drives both (efforts only, as before)."""
    if any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in spec.joints):
        return False
    if (set(drivable_joints(spec)) & set(own)) - {a.target for a in spec.actuators}:
        return False  # underactuated (gymnasium's hopper on its passive root joints, a pendulum): efforts only
    plain = all(
        actuator.trntype == mujoco.mjtTrn.mjTRN_JOINT
        and actuator.gaintype == mujoco.mjtGain.mjGAIN_FIXED
        and actuator.dyntype == mujoco.mjtDyn.mjDYN_NONE
        and actuator.biastype in (mujoco.mjtBias.mjBIAS_NONE, mujoco.mjtBias.mjBIAS_AFFINE)
        and (_is_motor(actuator) or _is_position_servo(actuator))
        for actuator in spec.actuators
    )
    return plain and any(_is_motor(actuator) for actuator in spec.actuators)


def _note_motors_kept(spec: mujoco.MjSpec, own: Collection[str], where: str) -> None:
    """A note for a fixed, fully actuated robot whose file mixes torque motors with
    velocity servos (or another kind than position servos): its motors stay motors and
    its modes are efforts alone (:func:`_fixed_and_motor_driven` is false), and why."""
    if any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in spec.joints):
        return
    if (set(drivable_joints(spec)) & set(own)) - {a.target for a in spec.actuators}:
        return  # underactuated: efforts only, as the file means
    joint_driven = [a for a in spec.actuators if a.trntype == mujoco.mjtTrn.mjTRN_JOINT]
    motors = [a.target for a in joint_driven if _is_motor(a)]
    others = [a.target for a in joint_driven if not _is_motor(a) and not _is_position_servo(a)]
    if not motors or not others:
        return
    warnings.warn(
        f"{where}: the model file drives {motors[:4]}{' ...' if len(motors) > 4 else ''} with torque motors and "
        f"{others[:4]}{' ...' if len(others) > 4 else ''} with velocity servos (or actuators that are neither motors "
        "nor position servos): no joint mode commands velocity servos, which cannot hold a position, together with "
        "position drives, so the robot gets joint_effort alone. Declare actuators (replace_file_actuators = True "
        "with no actuators gives every joint a derived PD drive and every joint mode), or control_modes.",
        RuntimeWarning,
        stacklevel=5,
    )


def _is_position_servo(actuator: mujoco.MjsActuator) -> bool:
    """An affine actuator with stiffness (``<position>``, or ``<general>`` written so)
    whose gain matches it (``gainprm[0] == -biasprm[1]``): its control is a joint target."""
    return bool(
        actuator.biastype == mujoco.mjtBias.mjBIAS_AFFINE
        and float(actuator.biasprm[1]) < 0.0
        and np.isclose(float(actuator.gainprm[0]), -float(actuator.biasprm[1]))
    )


def _is_motor(actuator: mujoco.MjsActuator) -> bool:
    """An affine actuator without stiffness or damping (``<motor>``, or ``<general>`` with
    a zero bias): its control sets the force."""
    if actuator.biastype != mujoco.mjtBias.mjBIAS_AFFINE:
        return True
    return float(actuator.biasprm[1]) == 0.0 and float(actuator.biasprm[2]) == 0.0


def _adopted(actuator: mujoco.MjsActuator, source: str, joint: str) -> DriveDeclaration:
    """A file's actuator on ``joint``: affine gain and bias are driven through targets."""
    label = f"{source} (actuator {actuator.name!r})" if actuator.name else source
    if actuator.gaintype != mujoco.mjtGain.mjGAIN_FIXED or actuator.biastype not in (
        mujoco.mjtBias.mjBIAS_NONE,
        mujoco.mjtBias.mjBIAS_AFFINE,
    ):
        raise ConfigError(
            f"{label} on joint {joint!r} has gain type {actuator.gaintype.name} and bias type "
            f"{actuator.biastype.name}; robot_agents adopts position, velocity and motor actuators only: "
            "set replace_file_actuators = True and declare the drive."
        )
    gear = abs(float(actuator.gear[0]))
    limit = speed = np.inf
    autolimits = bool(actuator.compiler.autolimits)
    if range_limited(actuator.forcelimited, actuator.forcerange, autolimits):
        limit = gear * max(abs(float(actuator.forcerange[0])), abs(float(actuator.forcerange[1])))
    largest_ctrl = np.inf
    if range_limited(actuator.ctrllimited, actuator.ctrlrange, autolimits):
        largest_ctrl = max(abs(float(c)) for c in actuator.ctrlrange)
    if _is_motor(actuator):
        # a motor (or a general actuator without stiffness or damping: dm_control's
        # soccer walkers): the largest control times its gain bounds the effort too
        limit = min(limit, gear * abs(float(actuator.gainprm[0])) * largest_ctrl)
    elif float(actuator.biasprm[1]) == 0.0 and gear > 0.0:
        # a velocity servo (force kv * (ctrl - gear * qvel)): its control is the target
        # speed of its transmission, the joint's times the gear
        speed = largest_ctrl / gear
    return DriveDeclaration(joint, DriveKind.AFFINE, label, effort_limit=limit, velocity_limit=speed)
