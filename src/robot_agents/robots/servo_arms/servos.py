"""Hobby servos of the low-cost arms, and PD gains derived from them.

A geared servo drives its joint through a reduction of ratio ``N``: the rotor's inertia
``J`` appears at the joint multiplied by ``N**2`` (the *reflected* inertia, MuJoCo's
joint ``armature``). With ``N`` around 300 this dwarfs the 3D-printed links of these
arms: the SO-100's wrist-roll link has 4e-5 kg*m^2 about its joint, its servo's rotor
reflects 0.026 kg*m^2. A PD drive tuned without it treats the joint as hundreds of
times lighter than it is.

Sources of the numbers:

- Dynamixel XL430-W250-T (ROBOTIS e-manual): gear ratio 258.5 : 1; stall torque
  1.5 N*m and no-load speed 61 rev/min at 12 V (the Koch v1.1 follower's supply).
- Dynamixel XM430-W350-T (ROBOTIS e-manual): gear ratio 353.5 : 1; stall torque
  4.1 N*m and no-load speed 46 rev/min (4.82 rad/s) at 12 V (the WidowX 250 S's supply,
  :mod:`robot_agents.robots.widowx.widowx250s`).
- Dynamixel XL330-M288-T (ROBOTIS e-manual): gear ratio 288.35 : 1 (the e-manual's
  table prints it rounded, 288.4 : 1; 288.35 = 70070 / 243); stall torque 0.52 N*m and
  no-load speed 103 rev/min at 5 V (the follower's step-down converter).
- Feetech STS3215, 7.4 V version (the SO-100 follower's servo; Feetech / DFRobot
  ST3215 datasheet): gear ratio 1 : 345; stall torque 19.5 kg*cm = 1.91 N*m and
  no-load speed 0.192 s / 60 deg (52 rev/min) at 7.4 V. (Checked 2026-11-29 against
  what we could read: 19.5 kg*cm at 7.4 V in Seeed Studio's SO-ARM100 specification;
  0.192 s / 60 deg and 19.5 kg*cm in a transcription of Feetech's product page; the
  datasheet itself was not readable here. The 12 V version: 30 kg*cm, 45 rev/min.)
- Reflected inertia (armature) and Coulomb friction, identified on pendulum test
  benches by Rhoban's BAM ("Better Actuator Models", github.com/Rhoban/bam, Apache-2.0),
  Coulomb-viscous model ``m1``: STS3215 7.4 V armature 0.0261 kg*m^2, friction
  0.0515 N*m; XL330 armature 0.00199 kg*m^2, friction 0.0182 N*m (``bam/params/xl330/
  m1.json`` at commit 11bb7ec, 2026-07-22; that file's fit has moved between 0.0015 and
  0.0020 kg*m^2 over the repository's history, so the XL330 armature is good to about
  +-15 %); MX-64 (200 : 1,
  6.0 N*m) armature 0.01195 kg*m^2. Divided by ``N**2`` they are rotor-side inertias
  of 2.2e-7 (STS3215) and 2.4e-8 kg*m^2 (XL330-M288), plausible for 20 mm and 12 mm
  motors with their first gear stages (BAM does not name the XL330 variant; the M077's
  77.4 : 1 would put 3.3e-7 kg*m^2 on the small XL330 rotor, so we read it as the M288).
- XL430-W250: not identified; its rotor-side inertia is interpolated between the
  XL330-M288 and the MX-64 by motor stall torque (output stall torque / ``N``):
  ``J = 2.39e-8 * (5.80e-3 / 1.80e-3) ** 0.898 = 6.8e-8`` kg*m^2, the exponent fitted
  to the two identified servos; times ``258.5**2``: 0.0046 kg*m^2. Its friction is the
  XL330's share of stall torque (3.5 %): 0.05 N*m.
- XM430-W350: not identified either; its rotor inertia comes from a second rule, the
  WidowX 250 S's (:func:`rotor_armature`): the identified armatures of three other
  DYNAMIXELs (BAM's ``params/mx64``, ``mx106``, ``xl330`` ``m1.json``: 0.01195, 0.02661,
  0.00173 kg*m^2 at 200:1, 225:1, 288.35:1; the XL330's from an earlier fit of that file
  than the 0.00199 above, commit 16837b3) give rotor inertias of 1.0e-5 .. 1.4e-5
  kg*m^2 per N*m of motor-side stall torque; with their mean (1.18e-5) the XM430-W350's
  rotor is 1.37e-7 kg*m^2, 0.0171 kg*m^2 at the joint (x 353.5^2; an estimate, +-30 %).
  For the XL430-W250 the same rule gives 6.9e-8 and 0.00458 kg*m^2, which the WidowX uses
  (the interpolation above: 0.0046). Its friction is the XL330's share of stall torque
  (3.5 %): 0.14 N*m (the WidowX's drives model no friction).

Gains (:func:`critically_damped_gains`): each joint is treated as a rigid inertia ``I``
(its armature plus the diagonal of the joint-space mass matrix at the arm's rest pose)
under a PD drive, ``I q'' = kp (q* - q) - kv q'``. A chosen bandwidth ``w`` (rad/s) and
damping ratio ``zeta`` give ``kp = I w**2`` and ``kv = 2 zeta I w``. We use
``w = 40 rad/s`` (6.4 Hz) and ``zeta = 1``: ``w * dt = 0.08`` at the library's 2 ms
step, well inside the stable range of the explicit stiffness term (MuJoCo's
``implicitfast`` integrates only the damping implicitly), and a stiffness of the same
order as the servos' own position loops at their default gains (e.g. an XL430 at
Position P Gain 640 reaches full PWM, i.e. stall torque, at 0.27 rad of error:
about 5.5 N*m/rad, against our 8 N*m/rad). Because the armature dominates, the damping
ratio stays near 1 across poses (it varies as ``sqrt(I_rest / I_pose)``: 0.68 .. 1.004
over the keyframes).

The torque-speed curve (:func:`back_emf_damping`): a servo's torque falls linearly from
stall to zero at its no-load speed (back-EMF). Its slope, stall torque / no-load speed,
is each joint's own damping (``joint_damping``), outside the drive's effort limit, as
the motor's back-EMF is outside its PWM limit, and the PD drive's damping is the rest
of the critically damped ``kv`` (:func:`split_damping`): below saturation the torque is
``kp (q* - q) - kv qd`` as before, and the velocity modes, which feed the joint's
damping forward, are unchanged; a saturated drive now keeps the back-EMF, so a joint
runs at most at its no-load speed (plus what gravity adds). Since 2026-11-29; before,
the drive saturated at the stall torque at any speed and a full-range ``pd_joint_pos``
jump (benchmarks/rated_speed.py) reached 1.99 times the STS3215's 5.45 rad/s on the
SO-100's elbow and 2.03 times the XL430's 6.39 rad/s on the Koch's base. MuJoCo's
``dcmotor`` (``DCMotorActuator``, MuJoCo >= 3.15) models the motor fully.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from robot_agents.errors import ConfigError


def rpm(value: float) -> float:
    """Revolutions per minute in rad/s."""
    return value * 2.0 * math.pi / 60.0


@dataclass(frozen=True)
class Servo:
    """One servo model as the simulation sees it.

    Attributes:
        model: the maker's model name (and supply voltage).
        gear_ratio: motor turns per output turn.
        stall_torque: output torque at stall, the drive's effort limit (N*m).
        no_load_speed: output speed without load, the drive's velocity limit (rad/s).
        armature: reflected rotor inertia at the output (kg*m^2).
        friction: Coulomb friction at the output (N*m).
    """

    model: str
    gear_ratio: float
    stall_torque: float
    no_load_speed: float
    armature: float
    friction: float


#: Dynamixel XL430-W250-T at 12 V (Koch v1.1 joints 1 and 2; WidowX 250 S wrist rotate
#: and gripper).
XL430_W250 = Servo(
    model="Dynamixel XL430-W250-T (12 V)",
    gear_ratio=258.5,
    stall_torque=1.5,
    no_load_speed=rpm(61.0),
    armature=0.0046,
    friction=0.05,
)
#: Rotor inertia per N*m of motor-side stall torque (kg*m^2 / (N*m)), the mean over
#: Rhoban BAM's identified MX-64, MX-106 and XL330-M288 (see the module docstring).
ROTOR_INERTIA_PER_TORQUE = 1.18e-5


def rotor_armature(stall_torque: float, gear_ratio: float) -> float:
    """Reflected rotor inertia (kg*m^2) of a servo with output stall torque
    ``stall_torque`` (N*m) and gear ratio ``gear_ratio``, estimated from its motor-side
    stall torque with :data:`ROTOR_INERTIA_PER_TORQUE`."""
    return ROTOR_INERTIA_PER_TORQUE * (stall_torque / gear_ratio) * gear_ratio**2


#: Dynamixel XM430-W350-T at 12 V (WidowX 250 S waist to wrist angle); armature and
#: friction estimated (see the module docstring).
XM430_W350 = Servo(
    model="Dynamixel XM430-W350-T (12 V)",
    gear_ratio=353.5,
    stall_torque=4.1,
    no_load_speed=rpm(46.0),
    armature=rotor_armature(4.1, 353.5),
    friction=0.14,
)
#: Dynamixel XL330-M288-T at 5 V (Koch v1.1 joints 3 to 6).
XL330_M288 = Servo(
    model="Dynamixel XL330-M288-T (5 V)",
    gear_ratio=288.35,
    stall_torque=0.52,
    no_load_speed=rpm(103.0),
    armature=0.00199,
    friction=0.0182,
)
#: Feetech STS3215, 7.4 V version with the 1 : 345 gear (every SO-100 joint).
STS3215 = Servo(
    model="Feetech STS3215 (7.4 V, 1:345)",
    gear_ratio=345.0,
    stall_torque=1.91,
    no_load_speed=math.radians(60.0) / 0.192,
    armature=0.0261,
    friction=0.0515,
)

#: Feetech STS3215, 12 V version with the same 1 : 345 gear (XLeRobot's arms, whose bill
#: of materials asks for 12 V servos): stall torque 30 kg*cm = 2.94 N*m, no-load speed
#: 45 rev/min (the figures above). Armature and friction are the 7.4 V servo's
#: identified ones (same gearbox and housing; an estimate: the 12 V rotor was not
#: identified).
STS3215_12V = Servo(
    model="Feetech STS3215 (12 V, 1:345)",
    gear_ratio=345.0,
    stall_torque=30.0 * 0.0980665,
    no_load_speed=rpm(45.0),
    armature=0.0261,
    friction=0.0515,
)

#: Closed-loop bandwidth of every joint's PD drive (rad/s).
BANDWIDTH = 40.0
#: Damping ratio of every joint's PD drive.
DAMPING_RATIO = 1.0


def critically_damped_gains(
    inertia: Sequence[float], bandwidth: float = BANDWIDTH, damping_ratio: float = DAMPING_RATIO
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """PD gains ``(kp, kv)`` per joint for effective inertias ``inertia`` (kg*m^2):
    ``kp = I w**2`` (N*m/rad) and ``kv = 2 zeta I w`` (N*m*s/rad)."""
    # gains_from_inertia's rule, on tabled rest inertias (known before compiling) at 40 rad/s, not its 10 Hz.
    kp = tuple(i * bandwidth**2 for i in inertia)
    kv = tuple(2.0 * damping_ratio * i * bandwidth for i in inertia)
    return kp, kv


def back_emf_damping(servo: Servo) -> float:
    """The slope of ``servo``'s torque-speed curve, stall torque / no-load speed
    (N*m*s/rad): the motor's back-EMF under voltage (PWM) control."""
    return servo.stall_torque / servo.no_load_speed


def split_damping(damping: Sequence[float], servos: Sequence[Servo]) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """A joint's total damping ``damping`` (N*m*s/rad, one per servo) split into the
    drive's share and the joint's own (the servo's back-EMF, :func:`back_emf_damping`):
    ``(drive, joint)``, their sums ``damping``. Raises :class:`ConfigError` where the
    back-EMF alone exceeds the total."""
    joint = tuple(back_emf_damping(servo) for servo in servos)
    if len(joint) != len(damping):
        raise ConfigError(f"split_damping: expected one servo per damping ({len(damping)}), got {len(joint)}.")
    for index, (total, own) in enumerate(zip(damping, joint, strict=True)):
        if own > total:
            raise ConfigError(
                f"split_damping: damping[{index}] = {total} N*m*s/rad is below the back-EMF of "
                f"{servos[index].model}, {own:.4g} N*m*s/rad; expected a total at least that."
            )
    return tuple(total - own for total, own in zip(damping, joint, strict=True)), joint


def servo_values(servos: Sequence[Servo], field: str) -> tuple[float, ...]:
    """One attribute (``"armature"``, ``"stall_torque"``, ...) of each servo."""
    return tuple(float(getattr(servo, field)) for servo in servos)


__all__ = [
    "BANDWIDTH",
    "DAMPING_RATIO",
    "ROTOR_INERTIA_PER_TORQUE",
    "STS3215",
    "STS3215_12V",
    "XL330_M288",
    "XL430_W250",
    "XM430_W350",
    "Servo",
    "back_emf_damping",
    "critically_damped_gains",
    "rotor_armature",
    "rpm",
    "servo_values",
    "split_damping",
]
