"""PSYONIC Ability Hand, right hand: a piece to mount on arms (:class:`AbilityHandRight`),
and the hand alone on a floating mount (``floating_ability_hand_right``, as ManiSkill's).

Sources of the numbers (all read as data; no model text or mesh is copied):
- ManiSkill 3.0.1's agent (``mani_skill/agents/robots/floating_ability_hand/
  floating_ability_hand.py``): uid, the mount's joint names and drives (kp 1000, kv 100,
  100 N), the ``rest`` keyframe (every joint 0), the distal joints' mimic
  ``q2 = 0.72349796 + 1.05851325 q1``, the pads' material on the ``*_L2`` links (static
  friction 2.0, dynamic 1.5), the end-effector link ``base`` (the wrist), the tip links.
- Kinematics, joint ranges, effort and velocity limits, link masses: its
  ``assets/robots/ability_hand/ability_hand_right_floating.urdf`` (PSYONIC's
  description). The wrist ``base`` is turned -pi/2 about z on the mount (``base_joint``);
  the palm ``thumb_base`` sits at (-24.048, 3.781, 32.330) mm on the wrist, rpy
  (3.14148, -0.08849, -3.14037); knuckles ``<f>_q1`` at (9.49, -13.04, -62.95) (index),
  (-9.653, -15.310, -67.854) (middle), (-29.954, -14.212, -67.286) (ring) and
  (-49.521, -11.005, -63.029) mm (pinky) in the palm; each distal joint 38.473 mm along
  its knuckle link (3.258 mm off, turned 0.0845 rad), its tip 35 mm on and 18 mm back;
  the thumb's rotator at the palm's origin, its flexor (27.828, 0, 14.751) mm along the
  rotator's link, its tip (65, 16, 0) mm on. Every joint turns about its z. Ranges (rad):
  knuckles 0..2.0944, distal 0..2.6586, thumb rotator -2.0944..0, flexor 0..2.0944.
  Limits: 6 N*m and 8.068 rad/s on the fingers and the flexor, 1.2 N*m and 40.34 rad/s on
  the rotator. Masses: knuckle links 6.359 g, distal 6.45 g, thumb 2.683 g and 5.5 g.
  Joint damping and friction 0.001 (the URDF: "not from quantitative measurement").
- PSYONIC's own MuJoCo models (``psyonicinc/ability-hand-api``): ``URDF/mujoco/
  abh_right.xml`` (commit 5da4563e) gives the same joint frames and link masses and a
  0.4 kg palm (the URDF's 0.2 kg is marked "NOT correct"); ``URDF/mujoco/hands/
  abh_right_large.xml`` (commit 47a5e134) the wrist flange (a 0.01591 kg cylinder),
  position servos with kp 1 N*m/rad, and the contact parameters taken here (links
  solref 0.01 0.99, solimp 0.95 0.99 0.002; palm solref 0.01 1, solimp 0.98 0.995
  0.0005). Its distal range, 0.766..2.61 rad, starts near where the coupling puts a
  stretched finger (0.7235). The whole hand: 0.4753 kg.
- Speed: the hand "closes in about 200 milliseconds" (PSYONIC's CEO, WMAR2 News,
  2021-07-14).

The coupling: each finger's distal joint follows its knuckle through a joint equality
with ManiSkill's ratio (the real finger's four-bar linkage, linearised there); only the
six motors (four knuckles, the thumb's rotator and flexor) are driven. The distal joint's range would stop the knuckle at
(2.6586 - 0.7235) / 1.0585 = 1.828 rad, short of the knuckle's own 2.094; driven to 2.094
(60 steps of +0.1 rad, 2026-11-29), the curled fingers meet the palm first, at 1.62 rad.

Shapes and inertias: boxes and capsules fitted to the principal extents of ManiSkill's
collision meshes (palm 117.6 x 84.4 x 47.8 mm; thumb links 44 x 23 x 20 mm and a
25 mm capsule 80 mm long; distal links 15 mm capsules 45 mm long), the knuckle links the
URDF's own box and sphere; each carries its link's mass and MuJoCo computes the inertia
of the solid. The URDF's inertias are not used: they are 100 times PSYONIC's MuJoCo
models' (index_L1: ixx 2.98e-5 kg*m^2 against a smallest principal moment of 2.96e-7) and its thumb_L2's, 1.8e-3 kg*m^2
for 5.5 g, is a radius of gyration of 0.57 m.

Drives (no source gives the real servo's gains):
- kp 1 N*m/rad (PSYONIC's MuJoCo model). ManiSkill's kp 1000 / kv 100 (force limit
  50) do not work in MuJoCo on links of 1e-7..1e-6 kg*m^2 (the Allegro's case,
  robots/wonik/allegro.py): PhysX integrates its drive implicitly, MuJoCo only the damping.
- kv 0.12 N*m*s/rad: an overdamped response on the armature below; a 1.6 rad step of
  the target reaches 90 % in 0.26 s (about the 200 ms closure above) and peaks at
  10.4 rad/s (the URDF's limit is 8.07: a PD drive cannot cap its speed; kv 0.2 would
  keep it under, at 0.45 s), measured at 500 Hz with the hand on the mount
  (2026-11-29). In the control modes the hand's targets move at most 0.1 rad per 20 Hz
  step (2 rad/s).
- Armature 0.001 kg*m^2 on every hand joint, an order-of-magnitude estimate of the
  motors' reflected rotor inertia (as the Allegro's; none is published), 1000 times
  the links' own (1e-7..1e-6 kg*m^2).
- Effort and velocity limits: the URDF's.

The floating mount: ManiSkill's joint names, gains and 100 N / N*m limit; the 2F-85's
mount file (``MANISKILL_MOUNT_MJCF``), whose hinges' armature (0.5 kg, 0.3 kg*m^2)
puts the hinges' torque-limit cycle bound at 166 Hz. The mount stands 0.5 m up
(ManiSkill's keyframe puts the wrist at the origin, in the floor of a scene with one).

Keyframe ``rest``: every joint 0 as ManiSkill's, the distal joints where the coupling
puts them (0.7235 rad; ManiSkill's keyframe writes 0 and its mimic controller drives
them there at the first step): fingers stretched up, the palm facing +x, the thumb out
to the side.

Control modes: ManiSkill's agent has one, ``pd_joint_pos``: the mount's six absolute
targets (m, rad, not normalized) and the hand's six (the knuckles through the mimic, the
thumb's two). Here the modes are generated from the parts (the mount as the arm, the
hand as a hand riding on it): the six joint modes and ``pd_ee_delta_pose`` /
``pd_ee_pose`` for the mount; the hand takes absolute targets where the mount's are
absolute (``pd_joint_pos``, ManiSkill's 12 entries; ``pd_joint_pos_vel``, ``pd_ee_pose``)
and +-0.1 rad deltas from its targets in the other modes (ManiSkill's hands on arms,
``xarm7_ability``'s ``hand_target_delta_pos``; the library's rule for a hand riding on
an arm, ``controllers/rules.py``). The hand's qpos
order is MuJoCo's depth-first :data:`JOINTS` (ManiSkill's is breadth-first: the five
first joints, then the five second ones).

Grasp (tests/test_ability_hand.py): a 3 cm, 27 g cube in front of the upper palm between
the opposed thumb below and the fingers above; closing (``pd_joint_pos``, 2 s, the cube
weightless) the thumb presses it up and into the palm (about 20 N) and the index,
middle and ring fingers down (8-12 N each); given its weight, the hand's contact forces
carry it (0.2649 N of 0.2649 N) and lifting the mount 5 cm moves it 1.3 mm in the hand.
The same grasp is the hand's :data:`POWER_GRASP`, the sweep's grasp claim: 1.02 mm of
slip at 200 Hz (bound 2 mm).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand, PowerGrasp
from robot_agents.registry import register_agent
from robot_agents.robots.floating_mount import MANISKILL_MOUNT_MJCF, MOUNT_JOINTS, mount_arm

ASSETS = Path(__file__).parent / "assets"

#: The four fingers (each a knuckle ``<f>_q1`` and a distal joint ``<f>_q2`` that follows it).
FINGER_NAMES = ("index", "middle", "ring", "pinky")
#: Every hand joint in model order: the thumb's rotator and flexor, then each finger's
#: knuckle and distal joint.
JOINTS = ("thumb_q1", "thumb_q2", *(f"{f}_q{k}" for f in FINGER_NAMES for k in (1, 2)))
JOINT_PATTERN = r"(thumb|index|middle|ring|pinky)_q[12]"
#: The six driven joints (the real hand's six motors); the distal joints follow.
KNUCKLES = r"(index|middle|ring|pinky)_q1"
THUMB_FLEXOR = "thumb_q2"
THUMB_ROTATOR = "thumb_q1"
#: ManiSkill's mimic (the finger's four-bar linkage, linearised): ``q2 = OFFSET + RATIO * q1`` (rad).
COUPLING_OFFSET = 0.72349796
COUPLING_RATIO = 1.05851325
#: Tip links (ManiSkill's ``finger_tip_links`` order) and the pads (its ``hand_front_links``).
TIP_LINKS = ("thumb_tip", "index_tip", "middle_tip", "ring_tip", "pinky_tip")
PAD_LINKS = ("thumb_L2", "index_L2", "middle_L2", "ring_L2", "pinky_L2")
#: Each finger's links, base to tip: thumb, then the four fingers.
FINGERS = tuple((f"{f}_L1", f"{f}_L2", f"{f}_tip") for f in ("thumb", *FINGER_NAMES))
#: The palm link (ManiSkill's ``ee_link_name`` is the wrist, ``base``).
PALM = "thumb_base"
WRIST = "base"
#: The piece's tool centre point for an arm: a body on the wrist axis 0.09 m out, level
#: with the power grasp's cube (the floating robot's end effector is ManiSkill's, the wrist).
TCP = "ability_tcp"


def distal(knuckle: float) -> float:
    """The distal joint's angle (rad) the coupling gives a knuckle angle ``knuckle`` (rad)."""
    return COUPLING_OFFSET + COUPLING_RATIO * knuckle


def hand_pose(knuckles: float, rotator: float, flexor: float) -> tuple[float, ...]:
    """Every hand joint (:data:`JOINTS` order, rad): the four knuckles at ``knuckles``,
    their distal joints where the coupling puts them, the thumb at ``rotator`` / ``flexor``."""
    return (rotator, flexor, *(v for _ in FINGER_NAMES for v in (knuckles, distal(knuckles))))


def hand_qpos(knuckles: float, rotator: float, flexor: float, prefix: str = "") -> dict[str, float]:
    """Keyframe entries for :func:`hand_pose` (a keyframe must name the distal joints:
    keyframes do not fill in the coupling's equalities)."""
    return dict(zip((prefix + j for j in JOINTS), hand_pose(knuckles, rotator, flexor), strict=True))


#: Drives (see the module docstring): PSYONIC's kp, damping for a critically damped
#: response on the armature estimate, the URDF's effort and velocity limits.
STIFFNESS = 1.0
DAMPING = 0.12
ARMATURE = 0.001
FINGER_EFFORT = 6.0
FINGER_VELOCITY = 8.0677777442
ROTATOR_EFFORT = 1.2
ROTATOR_VELOCITY = 40.338888721
FINGER_DRIVES = PDActuator(
    joints=rf"{KNUCKLES}|{THUMB_FLEXOR}",
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=FINGER_EFFORT,
    velocity_limit=FINGER_VELOCITY,
    armature=ARMATURE,
)
ROTATOR_DRIVE = PDActuator(
    joints=THUMB_ROTATOR,
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=ROTATOR_EFFORT,
    velocity_limit=ROTATOR_VELOCITY,
    armature=ARMATURE,
)

#: The thumb's rotator turned to face the fingers across the palm (rad; its range ends
#: at -2.094).
THUMB_OPPOSED = -2.0
#: Open: fingers stretched, the thumb opposed and stretched (standing out of the palm
#: below the grasp's cube).
OPEN = hand_pose(0.0, THUMB_OPPOSED, 0.0)
#: Closed (power grasp, rad): knuckles at 1.4 (the distal joints at 2.205 through the
#: coupling), the thumb's flexor at 1.3: on the cube the joints stop short of these
#: targets and press with kp times the remaining error.
CLOSED = hand_pose(1.4, THUMB_OPPOSED, 1.3)

#: The power grasp's cube: 3 cm, in front of the upper palm (the wrist frame's +y is out
#: of the palm, +z along the fingers), between the opposed thumb below and the curling
#: fingers above (tests/test_ability_hand.py).
GRASP_CUBE_EDGE = 0.03
POWER_GRASP = PowerGrasp(link=WRIST, cube_centre=(0.0, 0.045, 0.09), cube_edge=GRASP_CUBE_EDGE, outward=(0.0, 1.0, 0.0))

ABILITY_HAND = Hand(
    name="hand",
    joints=JOINT_PATTERN,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    power_grasp=POWER_GRASP,
)

#: The distal links' pads: ManiSkill's front_finger material's dynamic friction.
PAD = FrictionMaterial(sliding=1.5, torsional=0.01, rolling=0.0001)
#: Keyframe: ManiSkill's zeros (the distal joints where the coupling puts them).
REST = hand_qpos(0.0, 0.0, 0.0)


class AbilityHandRight(Agent):
    """The Ability Hand alone (a piece): root body ``base`` (the wrist, z along the
    fingers), palm ``thumb_base``, TCP ``ability_tcp`` (:data:`TCP`), part ``hand``.

    qpos order: :data:`JOINTS`.
    """

    mjcf_path = ASSETS / "ability_hand_right.xml"
    tcp = TCP
    actuators = (FINGER_DRIVES, ROTATOR_DRIVE)
    parts = (ABILITY_HAND,)
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {link: PAD for link in PAD_LINKS}
    #: The knuckle links sit in the palm's box at their hinges (as the real links sit in
    #: the palm's shell); only there do the hand's shapes overlap.
    self_collision_exclusions = tuple((PALM, f"{f}_L1") for f in ("thumb", *FINGER_NAMES))
    keyframes = {"rest": Keyframe(qpos=REST)}


#: The hand on the mount: turned -pi/2 about z (ManiSkill's base_joint).
HAND_ON_MOUNT = (math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))


@register_agent()
class FloatingAbilityHandRight(Agent):
    """The Ability Hand on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges).

    qpos order: the six mount joints, then :data:`JOINTS`.
    """

    uid = "floating_ability_hand_right"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
    #: floating_ability_hand_right``, 2026-11-29 18:49-18:50 UTC, 20 Hz control, after the
    #: hand came to take absolute targets in the absolute modes): every claim holds from
    #: 5 ms (200 Hz; random 0.0006 rad, settle 0.0005 rad/s, grasp slip 0.67 mm, deepest
    #: contact 0.42 mm); at 160 Hz the settle claim fails (0.13 rad/s: the mount's
    #: hinges can cycle between their torque limits below 166 Hz,
    #: ``robot_agents.tuning.cycles``). Default 200 Hz. (With the hand's target deltas
    #: in every mode, 18:19-18:22 UTC, every claim held from 160 Hz.)
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = MANISKILL_MOUNT_MJCF
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(AbilityHandRight, at="root", quat=HAND_ON_MOUNT),)
    actuators = (PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2, effort_limit=100.0),)
    parts = (mount_arm(WRIST),)
    keyframes = {"rest": Keyframe(qpos={"root_.*_joint": 0.0, **REST})}
    default_control_mode = "pd_joint_pos"
    task_limits: ClassVar[Mapping[str, str]] = {
        "PickCube-v1": (
            "the generic scripted solver closes two opposed jaws on the cube from above; the jaw "
            "geometry the task derives from the hand's five fingers has no approach axis (the fingers "
            "close in different directions) and the solver succeeds in 0 of 20 seeds (measured "
            "2026-11-29 18:25 UTC); the hand holds a cube in its own power grasp (tests/test_ability_hand.py)"
        )
    }


__all__ = [
    "ABILITY_HAND",
    "COUPLING_OFFSET",
    "COUPLING_RATIO",
    "JOINTS",
    "POWER_GRASP",
    "TIP_LINKS",
    "AbilityHandRight",
    "FloatingAbilityHandRight",
    "distal",
    "hand_pose",
    "hand_qpos",
]
