"""Unitree G1 humanoid, simplified upper body (uid ``unitree_g1_simplified_upper_body``,
ManiSkill's): the waist, two 5-joint arms and the early three-finger hands (25 joints) on
a fixed pelvis 0.755 m up, the legs rigid, as in ManiSkill's G1 tasks.

Sources of the numbers:
- Kinematics, joint ranges, link masses, centres of mass and full inertia tensors:
  ManiSkill 3.0.1's ``assets/robots/g1_humanoid/g1_simplified_upper_body.urdf`` (from
  Unitree's ``unitree_ros`` ``robots/g1_description``, BSD-3-Clause; read as data; MuJoCo
  Menagerie's ``unitree_g1/g1.xml`` at commit 95659f9, the same G1 revision, has the same
  joint origins and ranges). Total mass 32.24 kg (legs included). Names: the URDF's links
  and joints. See ``assets/g1_simplified_upper_body.xml`` (the torso, arms and hands in
  ``assets/g1_torso.xml``, the piece the full G1's model includes too,
  :mod:`robot_agents.robots.unitree.g1_full`) for the joint origins and the
  collision shapes (our own primitives sized from the URDF meshes' extents, where the URDF
  gives no primitive).
- Arms: 5 joints each (shoulder pitch, roll, yaw, elbow pitch, elbow roll), as this G1
  revision and ManiSkill's model have, not the 7 of the later G1 (wrist roll, pitch, yaw).
- Effort and velocity limits: the URDF's (``effort``, ``velocity``): torso 88 N*m,
  32 rad/s; arm joints 21 N*m, 53 rad/s; finger joints 0.7 N*m, 23 rad/s (Menagerie's
  ``g1.xml`` motors: arms +-20 N*m, hands +-0.7 N*m). ManiSkill drives every joint with a
  100 N*m force limit; we keep the URDF's.
- Armature 0.01 kg*m^2, joint damping 0.5 N*m*s/rad and friction loss 0.1 N*m on every
  joint: Menagerie's ``g1.xml`` class ``g1``.
- Gains: ManiSkill's (``body_stiffness`` 1000 N*m/rad, ``body_damping`` 100 N*m*s/rad on
  every joint, fingers included) do not fit MuJoCo with the URDF's efforts: a finger's
  0.7 N*m drive at kp 1000 saturates 0.7 mrad from its target, and a clamped drive's
  damping is integrated explicitly (``robot_agents.tuning.cycles``): kv 100 on the fingers'
  and forearms' 0.01 kg*m^2 can cycle between the torque limits below about 5 kHz. Ours:
  the torso's and arms' kp is the effort limit over ManiSkill's largest delta action
  (0.2 rad), so that the largest delta just reaches the rated torque; a finger's kp is
  its effort limit over 0.1 rad: held 0.1 rad short of its target (on an object) it
  presses with its full 0.7 N*m, and a free finger stops within 0.1 / 7 = 0.014 rad of
  its target against the friction loss (the ``Hand`` parts' tolerance is 0.03 rad). (The
  arm rule with ManiSkill's finger delta, 0.5 rad, gives kp 1.4: a free finger can stop
  0.07 rad short, and was still 0.13 rad from its closed target after 1.5 s.) kv = 0.1 s * kp, ManiSkill's kv / kp.
  Torso kp 440, kv 44; arms kp 105, kv 10.5; fingers kp 7 N*m/rad, kv 0.7 N*m*s/rad.
- Gravity: compensated on every body (the library's default for a fixed root), as
  ManiSkill's ``balance_passive_force=True``.
- Joint limits: stiff (``solreflimit`` 5 ms), the G1's are mechanical stops: with MuJoCo's
  default 20 ms random velocity actions pressed an elbow roll 0.36 rad past its stop at
  500 Hz (0.12 rad with them).
- Fingers' contact: ManiSkill's finger material (static and dynamic friction 2.0) on the
  palms and finger links; MuJoCo has one coefficient, 2.0, with the torsional and
  rolling friction the Allegro's pads use and the library's near-rigid pad contact
  (solref 0.01 s, solimp 0.9999, Menagerie's ``trs_so_arm100`` values): with MuJoCo's
  default contact the fingers sank 7-8 mm into a held 50 g cube.
- Self-collisions: ManiSkill's collision groups: a hand's palm, fingers (but the thumb tip,
  ``two_link``, which may meet the other fingers and the palm) and forearm
  (``elbow_roll_link``) do not collide with each other, and the torso not with the
  shoulder roll links (MuJoCo already skips parent-child pairs).
- Keyframes: ManiSkill's ``standing`` (every joint 0, pelvis at 0.755 m) and ``rest``
  (what tasks reset to), the same pose. The root is fixed: the robot is mounted at
  :data:`STANDING_MOUNT`.
- Parts: ``torso``, ``left_arm`` and ``right_arm`` (tool frames: the URDF's
  ``left_tcp_link``/``right_tcp_link``, ManiSkill's TCPs, no end-effector modes: ManiSkill's
  agent has none), ``left_hand`` and ``right_hand`` (7 joints each: thumb base ``zero``,
  thumb ``one``/``two``, upper finger ``three``/``four``, lower finger ``five``/``six``).
- Variants (ManiSkill's): ``..._with_head_camera`` (:data:`HEAD_CAMERA`) and
  ``..._right_arm`` (:class:`UnitreeG1UpperBodyRightArm`: ManiSkill's 11 joints commanded,
  the others passive, damped by their drives' kv where ManiSkill's use its 100).
- Control modes: ManiSkill's ``pd_joint_delta_pos`` (the default, first in ManiSkill's
  table) and ``pd_joint_pos`` (the right-arm variant's default, first in its table) and
  the library's four other joint modes, over the whole body in ManiSkill's order (one part,
  ``body``, :data:`MANISKILL_JOINTS`), the delta bounds ManiSkill's (0.2 rad for the torso
  and arms, 0.5 rad for the fingers), the velocity bounds the URDF's.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.base import ControllerConfig
from robot_agents.controllers.joint import PDJointPosConfig
from robot_agents.controllers.passive import PassiveConfig
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.rotations import FORWARD_X_UP_Z_CAMERA_QUAT, quat_multiply
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, EndEffector, Hand, Part, PowerGrasp, Torso
from robot_agents.registry import register_agent
from robot_agents.sensors.camera import CameraConfig

ASSETS = Path(__file__).parent / "assets"

TORSO_JOINT = "torso_joint"
ARM_KINDS = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "elbow_roll")
#: A hand's joints: thumb base, thumb, thumb tip, upper finger and tip, lower finger and tip.
FINGER_KINDS = ("zero", "one", "two", "three", "four", "five", "six")
#: ManiSkill's ``UnitreeG1UpperBody.body_joints``: the action order of every mode.
MANISKILL_JOINTS = (
    "torso_joint",
    "left_shoulder_pitch_joint",
    "right_shoulder_pitch_joint",
    "left_shoulder_roll_joint",
    "right_shoulder_roll_joint",
    "left_shoulder_yaw_joint",
    "right_shoulder_yaw_joint",
    "left_elbow_pitch_joint",
    "right_elbow_pitch_joint",
    "left_elbow_roll_joint",
    "right_elbow_roll_joint",
    "left_zero_joint",
    "left_three_joint",
    "left_five_joint",
    "right_zero_joint",
    "right_three_joint",
    "right_five_joint",
    "left_one_joint",
    "left_four_joint",
    "left_six_joint",
    "right_one_joint",
    "right_four_joint",
    "right_six_joint",
    "left_two_joint",
    "right_two_joint",
)

#: ManiSkill's largest delta action (rad): torso and arms, fingers.
BODY_DELTA, FINGER_DELTA = 0.2, 0.5
#: How far short of its target (rad) a finger presses with its full torque (kp's rule).
FINGER_PRESS = 0.1
#: A hand's open / closed tolerance (rad): a free finger stops up to friction loss / kp
#: = 0.014 rad short of its target.
HAND_TOLERANCE = 0.03
#: The URDF's limits per joint group: (effort N*m, velocity rad/s).
TORSO_LIMITS = (88.0, 32.0)
ARM_LIMITS = (21.0, 53.0)
FINGER_LIMITS = (0.7, 23.0)
#: ManiSkill's kv / kp (s): body_damping 100 over body_stiffness 1000.
DAMPING_TIME = 0.1
#: Menagerie's class ``g1`` (kg*m^2).
ARMATURE = 0.01
#: Pelvis height (m) of ManiSkill's ``standing``.
STANDING_HEIGHT = 0.755
STANDING_MOUNT = (0.0, 0.0, STANDING_HEIGHT, 1.0, 0.0, 0.0, 0.0)


def side_pattern(side: str, kinds: tuple[str, ...]) -> str:
    """``left`` and ``("zero", "one")`` -> ``left_(zero|one)_joint``."""
    return f"{side}_({'|'.join(kinds)})_joint"


def _drive(joints: str, limits: tuple[float, float], full_torque_error: float) -> PDActuator:
    """A PD drive reaching its effort limit ``full_torque_error`` rad from its target
    (see the module doc); kv = 0.1 s * kp."""
    effort, speed = limits
    stiffness = effort / full_torque_error
    return PDActuator(
        joints=joints,
        stiffness=stiffness,
        damping=DAMPING_TIME * stiffness,
        effort_limit=effort,
        velocity_limit=speed,
        armature=ARMATURE,
    )


BOTH = "(left|right)"
G1_DRIVES = (
    _drive(TORSO_JOINT, TORSO_LIMITS, BODY_DELTA),
    _drive(f"{BOTH}_({'|'.join(ARM_KINDS)})_joint", ARM_LIMITS, BODY_DELTA),
    _drive(f"{BOTH}_({'|'.join(FINGER_KINDS)})_joint", FINGER_LIMITS, FINGER_PRESS),
)


def joint_limits(joint: str) -> tuple[float, float]:
    """The URDF's (effort N*m, velocity rad/s) of the torso, an arm or a finger joint."""
    if joint == TORSO_JOINT:
        return TORSO_LIMITS
    kind = joint.removesuffix("_joint").split("_", 1)[1]
    return FINGER_LIMITS if kind in FINGER_KINDS else ARM_LIMITS


def _body_modes(
    body: tuple[str, ...], passive: tuple[str, ...] = (), finger_delta: float = FINGER_DELTA
) -> dict[str, ModeConfig]:
    """The six joint modes over ``body`` (ManiSkill's order), with ManiSkill's per-joint
    delta bounds (0.2 rad on the torso and arms, ``finger_delta`` on the fingers); the
    ``passive`` joints, if any, move freely in every mode, damped by their drives' own kv
    (ManiSkill's ``PassiveControllerConfig``)."""
    group = JointGroup(body, max_delta=BODY_DELTA, max_velocity=tuple(joint_limits(j)[1] for j in body))
    step = tuple(finger_delta if joint_limits(j) == FINGER_LIMITS else BODY_DELTA for j in body)
    lower = tuple(-s for s in step)
    modes: dict[str, ModeConfig] = {}
    for mode, config in joint_control_modes(group).items():
        if isinstance(config, PDJointPosConfig) and config.use_delta:
            config = dataclasses.replace(config, lower=lower, upper=step)
        parts: dict[str, ControllerConfig] = {"body": config}
        if passive:
            damping = tuple(DAMPING_TIME * joint_limits(j)[0] / _full_torque_error(j) for j in passive)
            parts["passive"] = PassiveConfig(joint_names=passive, damping=damping)
        modes[mode] = parts
    return modes


def _full_torque_error(joint: str) -> float:
    """The error (rad) at which ``joint``'s drive reaches its effort limit (kp's rule)."""
    return FINGER_PRESS if joint_limits(joint) == FINGER_LIMITS else BODY_DELTA


G1_MODES = _body_modes(MANISKILL_JOINTS)

#: Open (rad): every finger straight, ManiSkill's open grasp (its ``*_dist_to_open_grasp``
#: measures from 0), in :data:`FINGER_KINDS` order.
OPEN = (0.0,) * 7
#: Closed (power grasp, rad), left hand: the thumb (standing out of the palm's face, -y)
#: swung towards the fingers, the two fingers curled over towards it; on the power
#: grasp's cube the joints stop short of these targets and press with their drives'
#: torque limit (0.7 N*m). Without an object the thumb's tip meets the fingertips outside
#: them (further in, with the thumb at 1.2 rad and the fingers at -1.5, it passed inside
#: the curled fingers and the hand jammed: it did not open again). The right hand's
#: mirror it.
LEFT_CLOSED = (0.0, 0.6, 0.2, -1.15, -0.4, -1.15, -0.4)
RIGHT_CLOSED = tuple(-q for q in LEFT_CLOSED)
#: The power grasp's cube, in the palm link's frame (m): a 4 cm cube 2 cm in front of the
#: palm's face (the face at y = -0.017 on the left hand), between the open thumb (its
#: +x face 7.5 mm from the cube) and the fingers' bases: the thumb pushes it towards the
#: fingers (+x), the fingers' proximal links press back (tests/test_g1.py).
GRASP_CUBE_EDGE = 0.04
GRASP_CUBE_CENTRE = (0.06, -0.058, 0.0)
LEFT_GRASP = PowerGrasp(
    link="left_palm_link",
    cube_centre=GRASP_CUBE_CENTRE,
    cube_edge=GRASP_CUBE_EDGE,
    outward=(0.0, -1.0, 0.0),
)
RIGHT_GRASP = PowerGrasp(
    link="right_palm_link",
    cube_centre=(GRASP_CUBE_CENTRE[0], -GRASP_CUBE_CENTRE[1], GRASP_CUBE_CENTRE[2]),
    cube_edge=GRASP_CUBE_EDGE,
    outward=(0.0, 1.0, 0.0),
)


def hand(side: str, closed: tuple[float, ...], grasp: PowerGrasp) -> Hand:
    """One three-finger hand: thumb (zero, one, two), upper (three, four), lower (five, six)."""
    return Hand(
        name=f"{side}_hand",
        joints=tuple(f"{side}_{k}_joint" for k in FINGER_KINDS),
        open=OPEN,
        closed=closed,
        fingers=(
            (f"{side}_one_link", f"{side}_two_link"),
            (f"{side}_three_link", f"{side}_four_link"),
            (f"{side}_five_link", f"{side}_six_link"),
        ),
        max_delta=FINGER_DELTA,
        max_velocity=FINGER_LIMITS[1],
        tolerance=HAND_TOLERANCE,
        power_grasp=grasp,
    )


def arm(side: str) -> Arm:
    return Arm(
        name=f"{side}_arm",
        joints=side_pattern(side, ARM_KINDS),
        end_effectors=(EndEffector(f"{side}_tcp_link", name=f"{side}_tcp"),),
        max_delta=BODY_DELTA,
        max_velocity=ARM_LIMITS[1],
    )


G1_PARTS = (
    Torso(name="torso", joints=TORSO_JOINT, max_delta=BODY_DELTA, max_velocity=TORSO_LIMITS[1]),
    arm("left"),
    arm("right"),
    hand("left", LEFT_CLOSED, LEFT_GRASP),
    hand("right", RIGHT_CLOSED, RIGHT_GRASP),
)

#: ManiSkill's finger material (one friction coefficient: its static and dynamic 2.0),
#: with the library's near-rigid pad contact (Menagerie's ``trs_so_arm100`` values).
FINGER_PAD = FrictionMaterial(
    sliding=2.0, torsional=0.01, rolling=0.0001, solref=(0.01, 1.0), solimp=(0.9999, 0.9999, 0.01)
)
PAD_LINKS = tuple(f"{s}_{k}_link" for s in ("left", "right") for k in ("palm", *FINGER_KINDS[1:]))

#: ManiSkill's collision groups as body pairs: within a hand (palm, fingers but the thumb
#: tip, forearm) and the torso with the shoulder roll links.
_HAND_GROUP = ("elbow_roll", "palm", "one", "three", "four", "five", "six")
SELF_COLLISION_EXCLUSIONS = tuple(
    (f"{s}_{a}_link", f"{s}_{b}_link")
    for s in ("left", "right")
    for i, a in enumerate(_HAND_GROUP)
    for b in _HAND_GROUP[i + 1 :]
) + tuple(("torso_link", f"{s}_shoulder_roll_link") for s in ("left", "right"))

STANDING = Keyframe(qpos={".*": 0.0})


@register_agent()
class UnitreeG1UpperBody(Agent):
    """Unitree G1 upper body: waist, two 5-joint arms, two three-finger hands (25 joints)
    on a fixed pelvis 0.755 m up.

    qpos order (model order): ``torso_joint``, the left arm (shoulder pitch, roll, yaw,
    elbow pitch, roll), the left hand (zero .. six), the right arm, the right hand. Actions
    follow ManiSkill's order (:data:`MANISKILL_JOINTS`).
    """

    uid = "unitree_g1_simplified_upper_body"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
    #: unitree_g1_simplified_upper_body``, 2026-11-29 18:35 UTC, 20 Hz control; see
    #: docs/timestep.md): every claim holds from 2 ms (500 Hz) down to 1 ms (random-action
    #: overshoot 0.080-0.118 rad, bound 0.25, with the stiff joint limits: with MuJoCo's
    #: default ones an elbow roll went 0.36 rad past its stop at 500 Hz; settle
    #: 0.002-0.007 rad/s, bound 0.05; the power grasp's slip 0.65-0.67 mm; deepest contact
    #: 0.019 mm). At 400 Hz and coarser settle fails (2.33 rad/s at 400 Hz): the forearms'
    #: roll drives (kv 10.5 on 0.0105 kg*m^2 apparent inertia) cycle between their torque
    #: limits below 455 Hz (``robot_agents.tuning.cycles``); the random claim fails from
    #: 200 Hz. Default 500 Hz, the first tried step above that bound (as the H1's).
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "g1_simplified_upper_body.xml"
    mount_pose: ClassVar[tuple[float, ...]] = STANDING_MOUNT
    actuators = G1_DRIVES
    parts: ClassVar[tuple[Part, ...]] = G1_PARTS
    control_modes: ClassVar[Mapping[str, ModeConfig]] = G1_MODES
    default_control_mode = "pd_joint_delta_pos"
    link_materials = {link: FINGER_PAD for link in PAD_LINKS}
    self_collision_exclusions = SELF_COLLISION_EXCLUSIONS
    keyframes: ClassVar[Mapping[str, Keyframe]] = {"standing": STANDING, "rest": STANDING}


#: ManiSkill's ``head_camera``: 0.05 m ahead of and 0.46 m above ``head_link``'s origin,
#: pitched down pi/6 (``euler2quat(0, pi/6, 0)`` in SAPIEN's camera axes: x forward, z
#: up), 128 x 128, vertical field of view pi/2, near 0.01 m, far 100 m.
HEAD_CAMERA_PITCH = math.pi / 6
_HEAD_CAMERA_QUAT = quat_multiply(
    (math.cos(HEAD_CAMERA_PITCH / 2), 0.0, math.sin(HEAD_CAMERA_PITCH / 2), 0.0), FORWARD_X_UP_Z_CAMERA_QUAT
)
HEAD_CAMERA = CameraConfig(
    uid="head_camera",
    mount="head_link",
    pos=(0.05, 0.0, 0.46),
    quat=(
        float(_HEAD_CAMERA_QUAT[0]),
        float(_HEAD_CAMERA_QUAT[1]),
        float(_HEAD_CAMERA_QUAT[2]),
        float(_HEAD_CAMERA_QUAT[3]),
    ),
    width=128,
    height=128,
    fovy=90.0,
    near=0.01,
    far=100.0,
)


@register_agent()
class UnitreeG1UpperBodyWithHeadCamera(UnitreeG1UpperBody):
    """``unitree_g1_simplified_upper_body`` with ManiSkill's ``head_camera`` (:data:`HEAD_CAMERA`)."""

    uid = "unitree_g1_simplified_upper_body_with_head_camera"
    cameras = (HEAD_CAMERA,)


#: ManiSkill's ``UnitreeG1UpperBodyRightArm.body_joints``: the right arm but its shoulder
#: pitch, and the right hand, in ManiSkill's order; every other joint is passive.
RIGHT_ARM_JOINTS = (
    "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",
    "right_elbow_pitch_joint",
    "right_elbow_roll_joint",
    "right_zero_joint",
    "right_three_joint",
    "right_five_joint",
    "right_one_joint",
    "right_four_joint",
    "right_six_joint",
    "right_two_joint",
)
RIGHT_ARM_PASSIVE = tuple(j for j in MANISKILL_JOINTS if j not in RIGHT_ARM_JOINTS)


@register_agent()
class UnitreeG1UpperBodyRightArm(UnitreeG1UpperBody):
    """``unitree_g1_simplified_upper_body`` commanding its right arm (but the shoulder
    pitch) and right hand, as ManiSkill's ``..._right_arm``: the torso, the left arm and
    hand and the right shoulder pitch are passive (no action), damped by their drives' kv
    and held up by the gravity compensation. ManiSkill's delta bound, 0.2 rad, on all 11
    joints (its base robot gives the fingers 0.5)."""

    uid = "unitree_g1_simplified_upper_body_right_arm"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
    #: unitree_g1_simplified_upper_body_right_arm``, 2026-11-29 18:35 UTC): every claim
    #: holds from 400 Hz (settle 2.91 rad/s at 320 Hz); the base robot's 500 Hz kept, above
    #: the right forearm roll drive's cycle bound (455 Hz).
    parts = (G1_PARTS[2], G1_PARTS[4])
    control_modes: ClassVar[Mapping[str, ModeConfig]] = _body_modes(
        RIGHT_ARM_JOINTS, RIGHT_ARM_PASSIVE, finger_delta=BODY_DELTA
    )
    default_control_mode = "pd_joint_pos"


__all__ = [
    "G1_DRIVES",
    "GRASP_CUBE_CENTRE",
    "GRASP_CUBE_EDGE",
    "HEAD_CAMERA",
    "LEFT_CLOSED",
    "LEFT_GRASP",
    "MANISKILL_JOINTS",
    "RIGHT_ARM_JOINTS",
    "RIGHT_CLOSED",
    "RIGHT_GRASP",
    "STANDING_HEIGHT",
    "STANDING_MOUNT",
    "UnitreeG1UpperBody",
    "UnitreeG1UpperBodyRightArm",
    "UnitreeG1UpperBodyWithHeadCamera",
]
