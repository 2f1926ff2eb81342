"""Actuator declarations: the drives of a robot, declared once per joint pattern.

An actuator declaration says *what physically drives* a group of joints (a PD servo
inside MuJoCo, a velocity servo, a torque motor, MuJoCo's ``pid`` or ``dcmotor``, or
the model file's own actuators) with its gains and limits. Control modes never write
MuJoCo controls: they produce joint *targets* (position, velocity, effort) and the
drive stage (:mod:`robot_agents.actuators.drives`) turns those into ``ctrl`` for the
declared actuators. A mode that needs other settings (zero stiffness for velocity
control, stiffer gains for tracking) overrides them explicitly; leaving the mode
restores the declared ones.

Units: stiffness N*m/rad (N/m for slides), damping and joint damping N*m*s/rad (N*s/m),
effort limit N*m (N), velocity limit rad/s (m/s), armature kg*m^2 (kg), friction N*m (N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.patterns import Patterns, as_patterns
from robot_agents.validation import check_per_joint, is_real

#: A scalar for every matched joint, or one value per matched joint (in model order).
PerJoint = float | tuple[float, ...]
FloatArray = npt.NDArray[np.float64]


def per_joint(owner: str, field: str, value: PerJoint | None, n: int, default: float | None = None) -> FloatArray:
    """A scalar or per-joint tuple broadcast to a float64 array ``(n,)`` (the ``n``
    joints in model order; ``None`` gives ``default`` for every joint)."""
    if value is None:
        if default is None:
            raise ConfigError(f"{owner}.{field}: expected a number or {n} numbers (one per joint), got None.")
        return np.full(n, default)
    array = np.asarray(value, dtype=np.float64).reshape(-1)
    if array.size == 1:
        return np.full(n, float(array[0]))
    if array.size != n:
        raise ConfigError(
            f"{owner}.{field}: expected 1 or {n} values (one per joint), got {array.size}: {array.tolist()}."
        )
    return array


def _check_per_joint(owner: str, name: str, value: PerJoint | None, minimum: float = 0.0) -> None:
    if value is not None:
        check_per_joint(value, f"{owner}.{name}", minimum)


@dataclass(frozen=True, kw_only=True)
class ActuatorConfig:
    """What every drive declaration shares.

    Attributes:
        joints: joint name pattern(s) (regular expressions, whole-name match); each must
            match at least one joint and no joint may be claimed by two declarations.
        effort_limit: largest force / torque the drive applies (N*m or N); ``None``:
            unlimited.
        velocity_limit: the motor's rated speed (rad/s or m/s); bounds velocity modes.
        armature: reflected rotor inertia added to each joint (kg*m^2 or kg).
        friction: dry friction of each joint (``frictionloss``, N*m or N).
        joint_damping: passive damping of each joint (the model's ``dof_damping``,
            N*m*s/rad or N*s/m), which acts outside the drive's effort limit: a
            voltage-driven motor's back-EMF (stall torque / no-load speed) slows the
            joint at full effort too, to at most ``effort_limit / joint_damping`` (the
            no-load speed). A PD drive's ``damping`` is part of the clamped drive force,
            and a saturated drive loses it: with it alone the joint accelerates at full
            effort until the position error shrinks. Fed forward with velocity targets
            like any joint damping (``damping_feedforward``). ``None``: the file's.
        damping_feedforward: feed each joint's own damping (the model's
            ``dof_damping``) forward with velocity targets, so that a joint meets them
            (``True``: a drive whose servo loop tracks speed, as Dynamixel-style servos
            with integral action do, and as ManiSkill's drives, which leave URDF joint
            damping out); ``False``: the plain PD loop of a drive that closes
            ``kp (q* - q) + kd (qd* - qd) + tau*`` and nothing more (Unitree's low-level
            motor command): its joint settles at ``kv / (kv + b)`` of a velocity target,
            as the real one does against its joint's damping.
    """

    joints: Patterns
    effort_limit: PerJoint | None = None
    velocity_limit: PerJoint | None = None
    armature: PerJoint | None = None
    friction: PerJoint | None = None
    joint_damping: PerJoint | None = None
    damping_feedforward: bool = True

    def __post_init__(self) -> None:
        owner = type(self).__name__
        object.__setattr__(self, "joints", as_patterns(self.joints, f"{owner}.joints"))
        for name in ("effort_limit", "velocity_limit", "armature", "friction", "joint_damping", "stiffness", "damping"):
            _check_per_joint(owner, name, getattr(self, name, None))
        if not isinstance(self.damping_feedforward, bool):
            raise ConfigError(f"{owner}.damping_feedforward: expected True or False, got {self.damping_feedforward!r}.")
        for name in ("effort_limit", "velocity_limit"):
            value = getattr(self, name)
            if value is not None and np.any(np.asarray(value, dtype=np.float64) <= 0.0):
                raise ConfigError(
                    f"{owner}.{name}: expected values > 0 (a zero limit leaves the drive nothing; None: unlimited), "
                    f"got {value!r}."
                )

    @property
    def label(self) -> str:
        """How messages name this declaration, e.g. ``PDActuator('panda_joint[1-7]')``."""
        return f"{type(self).__name__}({', '.join(repr(p) for p in self.joints)})"


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PDActuator(ActuatorConfig):
    """A PD position servo inside MuJoCo: ``force = kp (q* - q) + kv (qd* - qd) + b qd* +
    tau*`` (``b``: the joint's own damping, fed forward; see
    :mod:`robot_agents.actuators.drives`), integrated implicitly (stable at stiff gains),
    clamped to ``effort_limit``."""

    stiffness: PerJoint
    damping: PerJoint = 0.0


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class VelocityActuator(ActuatorConfig):
    """A velocity servo inside MuJoCo: ``force = kv (qd* - qd) + b qd* + tau*`` (``b``: the
    joint's own damping, fed forward)."""

    damping: PerJoint


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class MotorActuator(ActuatorConfig):
    """A torque motor: MuJoCo applies the commanded effort. With ``stiffness`` or
    ``damping`` > 0 the library closes an explicit PD loop before every physics substep
    (``force = kp (q* - q) + kv (qd* - qd) + b qd* + tau*``, Isaac Lab's ideal PD with
    the joint's own damping ``b`` fed forward), which
    lets position and velocity modes drive it; with both zero it takes efforts only."""

    stiffness: PerJoint = 0.0
    damping: PerJoint = 0.0


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class PIDActuator(ActuatorConfig):
    """MuJoCo's ``pid`` actuator (MuJoCo >= 3.15): a PID servo with an integral state
    bounded by ``integral_limit`` (N*m or N); takes position and velocity targets."""

    stiffness: float
    damping: float = 0.0
    integral_gain: float = 0.0
    integral_limit: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        for name in ("stiffness", "damping", "integral_gain", "integral_limit"):
            value = getattr(self, name)
            if value is not None and not (is_real(value) and math.isfinite(value) and value >= 0):
                raise ConfigError(f"{type(self).__name__}.{name}: expected a finite number >= 0, got {value!r}.")
        if self.stiffness <= 0:
            raise ConfigError(f"{type(self).__name__}.stiffness: expected > 0, got {self.stiffness!r}.")


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class DCMotorActuator(ActuatorConfig):
    """MuJoCo's ``dcmotor`` actuator (MuJoCo >= 3.15): a brushed DC motor (torque
    constant ``motor_constant`` N*m/A, winding ``resistance`` ohm) under its own
    position controller with gains ``stiffness`` (V/rad) and ``damping`` (V*s/rad);
    takes position, velocity and effort (feed-forward) targets."""

    motor_constant: float
    resistance: float
    stiffness: float
    damping: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        for name in ("motor_constant", "resistance", "stiffness", "damping"):
            value = getattr(self, name)
            if not (is_real(value) and math.isfinite(value) and value >= 0):
                raise ConfigError(f"{type(self).__name__}.{name}: expected a finite number >= 0, got {value!r}.")
        if self.motor_constant <= 0 or self.resistance <= 0:
            raise ConfigError(f"{type(self).__name__}: expected motor_constant > 0 and resistance > 0.")


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class FileActuators(ActuatorConfig):
    """Adopt the model file's own actuators on the matched joints as their drives.

    Position actuators (``<position>``, ``<general>`` with an affine bias), velocity
    actuators and motors are adopted with their gains and ranges; control modes drive
    them through the same targets as declared drives."""

    joints: Patterns = ".*"


@checked_keywords
@dataclass(frozen=True, kw_only=True)
class DerivedActuators(ActuatorConfig):
    """PD drives on the matched joints with gains derived from the model's inertia, as a
    file without actuators gets them (:mod:`robot_agents.actuators.gains`), taking the
    limits, armature and friction declared here into account: a file that leaves out
    what a datasheet gives (the mani-skill wheel's ``so100.urdf`` writes ``effort="0"``)
    gets those facts stated without choosing gains. The effort limit bounds the drives
    (and, on a gripper the file implies, how hard its sliding fingers press); the
    armature adds to the inertia the gains are derived from.

    ``joints=None`` (the default) takes every hinge and slide joint of the robot's own
    model file that no other declaration claims and the file does not drive (a mounted
    piece's joints are the piece's: those it leaves undriven are passive by its design),
    so one joint can be declared outright and the rest derived::

        actuators = (ra.PDActuator(joints="gripper", stiffness=2.0, damping=0.1, effort_limit=1.9),
                     ra.DerivedActuators(effort_limit=1.9))
    """

    joints: Patterns | None = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.joints is None:  # the rest: resolved against the model (apply_actuators)
            for name in ("effort_limit", "velocity_limit", "armature", "friction", "joint_damping"):
                _check_per_joint(type(self).__name__, name, getattr(self, name))
            return
        super().__post_init__()

    @property
    def label(self) -> str:
        if self.joints is None:
            return "DerivedActuators()"
        return super().label


#: Every declaration kind, for messages.
ACTUATOR_KINDS = (
    PDActuator,
    VelocityActuator,
    MotorActuator,
    PIDActuator,
    DCMotorActuator,
    FileActuators,
    DerivedActuators,
)
