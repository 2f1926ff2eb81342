"""Unitree G1 humanoid, full (uids ``unitree_g1`` and ``unitree_g1_simplified_legs``,
ManiSkill's): two 6-joint legs on a free pelvis, the waist, two 5-joint arms and the
early three-finger hands (37 joints), standing on its own legs under PD control.

Sources of the numbers:
- Kinematics, joint ranges, link masses, centres of mass and full inertia tensors:
  ManiSkill 3.0.1's ``assets/robots/g1_humanoid/g1.urdf`` (from Unitree's ``unitree_ros``
  ``robots/g1_description``, BSD-3-Clause; read as data; MuJoCo Menagerie's
  ``unitree_g1/g1.xml`` at commit 0a809cf has the same leg joint origins and ranges). Its
  links are those of the upper-body model's URDF (:mod:`robot_agents.robots.unitree.g1`),
  there with the leg joints fixed; total mass 32.24 kg. Our model
  (``assets/unitree_g1.xml``) is the pelvis and the jointed legs, with the torso, arms and
  hands included from ``assets/g1_torso.xml``, the piece the upper-body model includes
  too. Names: the URDF's links and joints.
- Leg effort and velocity limits: the URDF's (``effort``, ``velocity``): hips 88 N*m,
  32 rad/s; knees 139 N*m, 20 rad/s; ankles 40 N*m, 53 rad/s. The torso, arms and
  fingers: the upper-body model's drives (:data:`robot_agents.robots.unitree.g1.G1_DRIVES`:
  URDF limits, kp = effort / 0.2 rad, fingers effort / 0.1 rad, kv = 0.1 s * kp).
  ManiSkill drives every joint with a 100 N*m force limit; we keep the URDF's.
- Armature 0.01 kg*m^2, joint damping 0.5 N*m*s/rad and friction loss 0.1 N*m on every
  joint: Menagerie's ``g1.xml`` class ``g1``.
- Leg gains: ManiSkill's (``body_stiffness`` 50 N*m/rad, ``body_damping`` 1 N*m*s/rad on
  every joint) cannot hold the robot up: two ankles give 100 N*m/rad against gravity's
  toppling stiffness about them, m g h = 31.46 kg * 9.81 m/s^2 * 0.617 m = 191 N*m/rad
  (the body above the ankle axes, its centre of mass 0.617 m above them and 2.6 cm
  ahead), and it falls on its face within 2 s (tests/test_unitree_g1_full.py: pelvis
  0.094 m, tilted 94 deg). ManiSkill's own ``unitree_g1`` does the same: from
  ``standing``, repeating its targets in ``pd_joint_pos`` (its worker on CPU PhysX,
  2026-11-29 20:44 UTC), tilted 13 deg at 1 s, on the floor at 2 s (pelvis 0.099 m,
  94 deg); its ``unitree_g1_simplified_legs``, whose body has no contacts, falls
  through the floor (pelvis -0.31 m at 2 s): its standing task trains a policy. Ours:
  kp 1000 N*m/rad on every leg joint (the ``body_stiffness`` of ManiSkill's G1 upper-body
  agent): the standing load (ankle pitch 4.1 N*m, knees 3.1, hip pitch 1.2) bends no joint
  more than 4.1 mrad, and the ankles' 2000 N*m/rad are 10 times gravity's 191. kv 10
  N*m*s/rad = 0.01 s * kp (the H1's leg kv / kp): ManiSkill's upper-body kv, 100, on the
  0.010 kg*m^2 of an ankle roll would cycle between its torque limits below 4.9 kHz
  (``robot_agents.tuning.cycles``); kv 10 below 442 Hz, under the forearms' 455 Hz. No
  gravity is compensated (ManiSkill's ``balance_passive_force=False``).
- Feet: a box over the foot mesh's bounds (0.2024 x 0.066 x 0.03 m, the sole at the
  mesh's lowest points, 0.034 m below the ankle roll axis): ManiSkill's ``g1.urdf``
  collides the foot mesh (the URDF's four 1 mm foot spheres are commented out there;
  Menagerie's feet are those spheres). ManiSkill's ``standing`` pelvis height, 0.755 m,
  leaves the soles 1.3 mm above the floor. Other leg shapes: the URDF's knee cylinder
  (r 0.015 m), our primitives over the other links' meshes (``assets/unitree_g1.xml``).
- Keyframes: ManiSkill's ``standing`` (pelvis 0.755 m, legs straight, shoulder roll
  +-0.2 rad, elbows 0.9 rad, fingers half curled), the default reset; ``rest`` (what tasks
  reset to) the same pose. ManiSkill's ``right_knee_up`` and ``left_knee_up`` (one hip
  pitch -1.5 rad, its knee 1.5 rad) are left out: they stand on one foot with the centre
  of mass at y = 0.5 mm, 8.4 cm inside the stance foot's inner edge (y 0.085-0.151 m):
  no position hold keeps that up, and the standing claim holds every keyframe.
- Parts: ``legs`` (both legs, not held: they carry the robot), then the upper-body
  model's ``torso``, ``left_arm``/``right_arm`` and ``left_hand``/``right_hand`` with its
  power grasps (checked standing on the floor). The arms declare no tool frame:
  ManiSkill's full G1 (``g1.urdf``, ``UnitreeG1``) has no TCP, unlike its upper body
  (the ``*_tcp_link`` bodies of the shared torso piece are in the model, unused), so it
  has no end-effector modes and the table-top tasks, which place a table under a tool,
  do not take it (as the H1); ManiSkill's only task for a full G1 is its humanoid
  standing task (``unitree_g1_simplified_legs``).
  Finger pads, self-collision exclusions: the upper-body model's (ManiSkill's collision
  groups).
- Control modes: ManiSkill's ``pd_joint_pos`` (the default, first in its table) and
  ``pd_joint_delta_pos`` and the library's four other joint modes, over the whole body
  in ManiSkill's order (one part, ``body``, :data:`MANISKILL_JOINTS`), the delta bound
  ManiSkill's 0.2 rad on every joint, the velocity bounds the URDF's. Declared, not
  generated from the parts (as the H1's: a generated table would give the legs deltas in
  every mode and not follow ManiSkill's order).
- ``unitree_g1_simplified_legs`` (:class:`UnitreeG1SimplifiedLegs`): ManiSkill's
  ``g1_simplified_legs.urdf`` keeps collision shapes on the knee links (the URDF's
  cylinder) and the feet alone; ours likewise (``collision_links``). Its hands have no
  contacts, so it declares no power grasp. Everything else is ``unitree_g1``'s.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Arm, Hand, Legs, Part
from robot_agents.registry import register_agent
from robot_agents.robots.unitree import g1

ASSETS = Path(__file__).parent / "assets"

LEG_KINDS = ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
LEG_PATTERN = f"(left|right)_({'|'.join(LEG_KINDS)})_joint"
#: ManiSkill's ``UnitreeG1.body_joints``: the action order of every mode (also the order
#: of ManiSkill's keyframe ``qpos``).
MANISKILL_JOINTS = (
    "left_hip_pitch_joint",
    "right_hip_pitch_joint",
    "torso_joint",
    "left_hip_roll_joint",
    "right_hip_roll_joint",
    "left_shoulder_pitch_joint",
    "right_shoulder_pitch_joint",
    "left_hip_yaw_joint",
    "right_hip_yaw_joint",
    "left_shoulder_roll_joint",
    "right_shoulder_roll_joint",
    "left_knee_joint",
    "right_knee_joint",
    "left_shoulder_yaw_joint",
    "right_shoulder_yaw_joint",
    "left_ankle_pitch_joint",
    "right_ankle_pitch_joint",
    "left_elbow_pitch_joint",
    "right_elbow_pitch_joint",
    "left_ankle_roll_joint",
    "right_ankle_roll_joint",
    "left_elbow_roll_joint",
    "right_elbow_roll_joint",
    *g1.MANISKILL_JOINTS[11:],
)
#: ManiSkill's ``standing`` keyframe ``qpos``, in :data:`MANISKILL_JOINTS` order.
MANISKILL_STANDING = (
    (0.0,) * 9
    + (0.2, -0.2)
    + (0.0,) * 6
    + (0.9, 0.9)
    + (0.0,) * 5
    + (-0.77, -0.77, 0.0, 0.77, 0.77, 0.1, -0.92, -0.92, -0.1, 0.92, 0.92, 0.92, -0.92)
)
#: Pelvis height (m) of ManiSkill's keyframes.
STANDING_HEIGHT = 0.755
#: The URDF's limits per leg joint: (effort N*m, velocity rad/s).
LEG_LIMITS = {
    "hip_pitch": (88.0, 32.0),
    "hip_roll": (88.0, 32.0),
    "hip_yaw": (88.0, 32.0),
    "knee": (139.0, 20.0),
    "ankle_pitch": (40.0, 53.0),
    "ankle_roll": (40.0, 53.0),
}
#: Every leg joint's stiffness (N*m/rad): the ``body_stiffness`` of ManiSkill's G1
#: upper-body agent (see the module doc).
LEG_STIFFNESS = 1000.0
#: kv / kp (s) of the legs: the H1's (kv 100 over kp 10000).
LEG_DAMPING_TIME = 0.01


def leg_drive(kind: str) -> PDActuator:
    """Both legs' drives of one joint kind: the URDF's limits, kp 1000 N*m/rad, kv 10 N*m*s/rad."""
    effort, speed = LEG_LIMITS[kind]
    return PDActuator(
        joints=f"(left|right)_{kind}_joint",
        stiffness=LEG_STIFFNESS,
        damping=LEG_DAMPING_TIME * LEG_STIFFNESS,
        effort_limit=effort,
        velocity_limit=speed,
        armature=g1.ARMATURE,
    )


def joint_limits(joint: str) -> tuple[float, float]:
    """(effort N*m, velocity rad/s) of any of the 37 joints (the URDF's)."""
    kind = joint.removesuffix("_joint").split("_", 1)[-1]
    return LEG_LIMITS[kind] if kind in LEG_LIMITS else g1.joint_limits(joint)


G1_FULL_DRIVES = tuple(leg_drive(kind) for kind in LEG_KINDS) + g1.G1_DRIVES
G1_BODY = JointGroup(
    MANISKILL_JOINTS,
    max_delta=0.2,
    max_velocity=tuple(joint_limits(j)[1] for j in MANISKILL_JOINTS),
)
G1_FULL_MODES: dict[str, ModeConfig] = {mode: {"body": config} for mode, config in joint_control_modes(G1_BODY).items()}
#: ``legs``, then the upper body's parts, the arms without tool frames (ManiSkill's full
#: G1 has no TCP; see the module doc).
G1_FULL_PARTS: tuple[Part, ...] = (
    Legs(name="legs", joints=LEG_PATTERN, max_delta=0.2),
    *(dataclasses.replace(p, end_effectors=()) if isinstance(p, Arm) else p for p in g1.G1_PARTS),
)
STANDING = Keyframe(
    qpos=dict(zip(MANISKILL_JOINTS, MANISKILL_STANDING, strict=True)), base_pos=(0.0, 0.0, STANDING_HEIGHT)
)


@register_agent()
class UnitreeG1(Agent):
    """Unitree G1: legs, waist, arms and three-finger hands (37 joints) on a free pelvis.

    qpos order (model order): the left leg (hip pitch, roll, yaw, knee, ankle pitch, roll),
    the right leg, ``torso_joint``, the left arm, the left hand (zero .. six), the right
    arm, the right hand. Actions follow ManiSkill's order (:data:`MANISKILL_JOINTS`).
    """

    uid = "unitree_g1"
    #: Time-step sweep (``PYTHONPATH=src python benchmarks/timestep_sweep.py --jobs 1
    #: unitree_g1 unitree_g1_simplified_legs``, 2026-11-29 20:30-20:36 UTC, 20 Hz control;
    #: docs/timestep.md): every claim holds from 400 Hz to 1 kHz (random-action overshoot
    #: 0.119-0.237 rad, bound 0.25; standing: the pelvis moves 0.38-0.45 mm after settling;
    #: hold 0.00095; the power grasp, standing on the floor, slips 0.51-0.72 mm; deepest
    #: contact 1.5 mm); at 320 Hz random actions press a joint 0.288 rad past its stop, and
    #: from 200 Hz coarser they blow up. Default 500 Hz, the first tried step above the
    #: forearm roll drives' torque-limit cycle bound (455 Hz) and the ankle rolls' (442 Hz),
    #: as the upper body's.
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "unitree_g1.xml"
    fix_root_link = False
    gravity_compensation = False
    actuators = G1_FULL_DRIVES
    parts: ClassVar[tuple[Part, ...]] = G1_FULL_PARTS
    control_modes: ClassVar[Mapping[str, ModeConfig]] = G1_FULL_MODES
    default_control_mode = "pd_joint_pos"
    link_materials = {link: g1.FINGER_PAD for link in g1.PAD_LINKS}
    self_collision_exclusions = g1.SELF_COLLISION_EXCLUSIONS
    keyframes: ClassVar[Mapping[str, Keyframe]] = {"standing": STANDING, "rest": STANDING}


#: The links that keep contacts in ``unitree_g1_simplified_legs``: those with a collision
#: shape in ManiSkill's ``g1_simplified_legs.urdf`` (the knee cylinder, the foot mesh).
SIMPLIFIED_COLLISION_LINKS = tuple(f"{s}_{k}_link" for s in ("left", "right") for k in ("knee", "ankle_roll"))


@register_agent()
class UnitreeG1SimplifiedLegs(UnitreeG1):
    """``unitree_g1`` colliding only through its shins and feet (ManiSkill's
    ``UnitreeG1Simplified``, ``g1_simplified_legs.urdf``): the knee links' cylinders and
    the foot boxes keep their contacts (:data:`SIMPLIFIED_COLLISION_LINKS`), every other
    link has none, hands included, so no power grasp is declared. Everything else
    (drives, keyframes, modes, ``sim_freq``) is ``unitree_g1``'s, as ManiSkill's variant
    changes only the URDF."""

    uid = "unitree_g1_simplified_legs"
    #: Time-step sweep (the ``unitree_g1`` run): every claim holds from 320 Hz (hold,
    #: standing and penetration equal to ``unitree_g1``'s to the digit: the links without
    #: contacts touch nothing while standing); ``unitree_g1``'s 500 Hz kept.
    sim_freq: ClassVar[int | None] = 500
    collision_links = SIMPLIFIED_COLLISION_LINKS
    parts: ClassVar[tuple[Part, ...]] = tuple(
        dataclasses.replace(p, power_grasp=None) if isinstance(p, Hand) else p for p in UnitreeG1.parts
    )


__all__ = [
    "G1_BODY",
    "G1_FULL_DRIVES",
    "G1_FULL_PARTS",
    "LEG_KINDS",
    "LEG_LIMITS",
    "MANISKILL_JOINTS",
    "MANISKILL_STANDING",
    "SIMPLIFIED_COLLISION_LINKS",
    "STANDING_HEIGHT",
    "UnitreeG1",
    "UnitreeG1SimplifiedLegs",
    "joint_limits",
    "leg_drive",
]
