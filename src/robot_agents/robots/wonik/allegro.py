"""Wonik Robotics Allegro Hand v4, right hand (``allegro_hand_right``): a 16-DoF
four-finger hand bolted on a fixed mount, as ManiSkill's ``allegro_hand_right``.

Sources of the numbers:
- Product: "four fingers and sixteen independent torque-controlled joints (4 fingers x
  4 DOF ea.)", "capable of holding over 1.5 kg" (the Allegro Hand overview of Wonik's
  allegro_hand_ros package, as quoted at
  https://blog.csdn.net/weixin_52531852/article/details/124179424). The v4 user
  manual's specification table (weight, joint torque) could not be read from the
  stored corpora; no number here rests on it.
- Kinematics, joint axes and ranges: the Allegro Hand URDF (Wonik's
  ``allegro_hand_description_right``; identical in ManiSkill's
  ``assets/robots/allegro/allegro_hand_right.urdf`` and in MuJoCo Menagerie's
  ``wonik_allegro/right_hand.xml``, all read as data). Finger bases at
  (0, +-0.0435, -0.001542) turned -+5 deg about x (index, ring) and (0, 0, 0.0007)
  (middle); base (axis z) -> proximal 0.0164 -> medial 0.054 -> distal 0.0384 -> tip
  0.0267 m along z (axes y). Thumb base at (-0.0182, 0.019333, -0.045987), quaternion
  (0.477714, -0.521334, -0.521334, -0.477714) (the URDF's rpy (0, -1.658063,
  -1.570796)), axis -x; -> (-0.027, 0.005, 0.0399) axis z -> 0.0177 -> 0.0514 ->
  tip 0.0423 m (axes y). Ranges (rad): base +-0.47, proximal -0.196..1.61, medial
  -0.174..1.709, distal -0.227..1.618; thumb 0.263..1.396, -0.105..1.163,
  -0.189..1.644, -0.162..1.719 (Menagerie's actuator ctrlranges are the same).
- Masses: Wonik's official V4 description (``Wonikrobotics-git/allegro_hand_ros2``,
  ``allegro_hand_hardwares/v4/description/urdf/allegro_hand_description_right.xacro``):
  palm 0.4154 kg; per finger base 0.0119, proximal 0.065, medial 0.0355, distal
  0.0096, tip 0.0168; thumb 0.0176, 0.0119, 0.038, 0.0388, tip 0.0168: 0.9549 kg in
  all. Its inertias are placeholders (1e-4 kg*m^2 on every link, a 10 cm radius of
  gyration for a 10 g link) and ManiSkill's differ between identical fingers (its
  middle distal weighs 0.0388 kg, the index's 0.02, the ring's 0.0096), so each link's
  inertia is that of a solid box (tips: capsule) of its mass over its collision shape,
  computed by MuJoCo (link_0.0's ixx and iyy equal ManiSkill's, which are a box's too).
- Joint friction and passive damping: Wonik's V4 description (``frictionloss`` 0.01
  N*m, damping 0.1 N*m*s/rad); its velocity limit, 7 rad/s, bounds the velocity modes.
- Collision shapes: Menagerie's boxes (palm 40.8 x 113 x 95 mm; links 19.6 x 27.5 mm
  in section) and fingertip capsules (radius 12 mm, the URDF's fingertip sphere).
- Fingertip pads: ManiSkill's tip material (static friction 2.0, dynamic 1.0); MuJoCo
  has one coefficient and we take the dynamic 1.0 (silicone on a dry object), with
  torsional friction (condim 4), against objects only: the hand's other collision geoms
  take a higher contact priority, so a fingertip pressing on another finger meets the
  links' contact. The pads' contact itself is MuJoCo's default (solref 0.02 s, critically
  damped; solimp 0.9-0.95 over 1 mm), as Menagerie's ``wonik_allegro/right_hand.xml``
  (commit 28ffb48) leaves its fingertip capsules. Until 2026-11-29 they had the
  near-rigid pad contact of the library's servo-arm pads (Menagerie's ``trs_so_arm100``
  values: solref 0.01 s, impedance 0.9999), and a fingertip pressed on a fixed block
  never came to rest (tests/test_allegro_press.py: the middle finger's proximal target
  0.3 rad past contact, ``palm_side``, the last second of 3 s; 2026-11-29): the tip lost
  and regained the block, 0-43 N and 1.3-1.5 rad/s at 160-320 Hz, 21-38 N and 0.87
  rad/s at 500 Hz, 25-36 N and 0.66 rad/s at 1 kHz, 32-35 N and 0.10 rad/s at 2 kHz,
  its tangential force at the edge of the friction cone. Varied one at a time (200 Hz
  to 2 kHz): condim 3 gave the same numbers and condim 1 (no friction) still 0.25-1.1
  rad/s, so it is no stick-slip of the torsional or sliding friction; nor a torque-limit
  cycle (the drive asks for 3 N*m of its 50; without the 7 rad/s clamp the numbers are
  identical); without the joints' frictionloss, with armature 0 or 0.01 kg*m^2, drive
  kv 0.1-3 N*m*s/rad, or the Euler or implicit integrator it still chattered (0.1-3.9
  rad/s; RK4 came to rest only at 4 kHz). The contact's impedance decides it: at 0.9999
  the tip chattered at every solref tried (0.01-0.03 s), at 0.99 below 500 Hz, at
  MuJoCo's default 0.9-0.95 with solref 0.01 s at 160-200 Hz (2 time steps or less
  there, which MuJoCo raises to 2), and with MuJoCo's default contact it rests at every
  step from 160 Hz to 2 kHz (18.4 N, steady to 2e-5 N, every joint below 1.4e-5 rad/s,
  0.85 mm deep). The links' priority was added on 2026-11-28 for the near-rigid pads: a
  thumb tip pressed by its drive on the index finger (the targets random
  ``pd_joint_target_delta_pos`` actions left, seed 2, held) chattered, sliding at the
  edge of its friction cone and losing and regaining contact every 0.24 s, at 200-400
  Hz, and random actions pressed joints 0.78 rad past their limits at 160 Hz (0.14 rad
  with the links first). With the default pad contact the thumb rests on the index
  with or without the links' priority (4.6e-6 and 4.0e-6 rad/s at 320 Hz,
  tests/test_allegro.py); the priority is kept.
- Drives: MuJoCo Menagerie's ``wonik_allegro/right_hand.xml`` (commit 28ffb48):
  position servos with kp 10 N*m/rad on every joint and its joint damping, 1 N*m*s/rad,
  taken as the drives' kv (as the UR10e takes Menagerie's joint damping); ManiSkill's
  force limit, 50 N*m, which kp 10 never reaches within the joint ranges (at most
  19 N*m), and Wonik's 7 rad/s. ManiSkill's gains (kp 400, kv 10 N*m*s/rad) do not
  work in MuJoCo: PhysX integrates a drive implicitly, MuJoCo only its damping, and on
  links of 3e-6 to 1e-4 kg*m^2 kp 400 is unstable at 2 ms (kp / (4 I / dt^2) = 42);
  with the armature below they pass the random-action claim at 400-500 Hz, but a drive
  clamped at its limit has its damping integrated explicitly (kv * dt / I = 10 at
  1 kHz) and the settle claim fails at every step, 40 Hz-1 kHz (25-580 rad/s).
- Armature: 0.001 kg*m^2 per joint, an order-of-magnitude estimate of the reflected
  rotor inertia (no public model or datasheet we could read gives one): a small
  coreless DC motor's rotor, of order 1e-8 kg*m^2, behind a reduction of about 300:1
  (1e-8 * 300^2 = 9e-4). Without it the random actions press the joints (distal
  links: 3e-6 kg*m^2) 0.51-0.60 rad past their limits at 500 Hz-1 kHz and after the
  settle claim's hold a joint still turns at 97 rad/s at 500 Hz (0.026 rad/s from
  800 Hz); with it the fingers' response is unchanged (kv / kp = 0.1 s).
- Gravity: compensated on every body (the library's default for a fixed root, as the
  Panda's), so the keyframes are held exactly; without it Menagerie's soft kp lets the
  fingers sag 0.058 rad (``palm_side``) and 0.089 rad (``palm_up``) in 2 s.
- Keyframes: ManiSkill's ``palm_side`` and ``palm_up``: every joint at 0 (the thumb's
  base, whose range starts at 0.263 rad, at its lower limit), the root at 0.5 m,
  unturned (fingers up, palm facing +x) or turned -pi/2 about y (palm facing up,
  fingers along -x). A fixed root cannot take a keyframe's root pose here (the mount
  is part of the compiled scene): the robot is mounted as ``palm_side``
  (:attr:`AllegroHandRight.mount_pose`) and ``palm_up`` is the same joint pose with the
  scene mounting the robot at :data:`PALM_UP_MOUNT` (``robot_poses=[PALM_UP_MOUNT]``).
- Control modes: generated from the ``Hand`` part: ManiSkill's ``pd_joint_delta_pos``
  (default, +-0.1 rad per step), ``pd_joint_pos`` (absolute targets, not normalized)
  and ``pd_joint_target_delta_pos``, plus the library's three velocity variants.
- Grasp (tests/test_allegro.py): the palm up, the hand open (:data:`OPEN`: the thumb
  stands up opposite the fingers), a 5.5 cm, 100 g cube laid flat in the palm 15 mm
  from the finger bases; closing (:data:`CLOSED`, ``pd_joint_pos``, 2 s) the middle
  finger and the thumb press on it from opposite sides (the middle finger's links 40-48
  N in all, the thumb's 34-37 N, the ring finger 6 N, the index misses it; 200 Hz-1
  kHz) and ``is_grasping`` holds; its weight cancelled and as much again pulling it away
  from the palm for 2 s (1 g net, as with the hand turned over) it moves 0.09 mm
  relative to the palm at 200 Hz (0.08 mm at 320 Hz, 0.07 mm at 1 kHz; with the former
  near-rigid pads 0.088, 0.073 and 0.069 mm; 2026-11-29). Opened, ``is_grasping`` is
  false. The same grasp is declared as the hand's :data:`POWER_GRASP`, the time-step
  sweep's grasp claim (a 166 g cube of water's density there): 0.15 mm at 200 Hz,
  0.14 mm at 320 Hz, held from 80 Hz up.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand, PowerGrasp
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

#: ManiSkill's joint order: index 0-3, middle 4-7, ring 8-11, thumb 12-15 (model order too).
JOINTS = tuple(f"joint_{i}.0" for i in range(16))
JOINT_PATTERN = r"joint_\d+\.0"
#: Fingertip bodies in ManiSkill's order: thumb, index, middle, ring.
TIP_LINKS = ("link_15.0_tip", "link_3.0_tip", "link_7.0_tip", "link_11.0_tip")
#: Each finger's links (base to tip): index, middle, ring, thumb.
FINGERS = tuple((*(f"link_{4 * f + k}.0" for k in range(4)), f"link_{4 * f + 3}.0_tip") for f in range(4))

#: Thumb base lower limit (rad): the keyframes' 0 clipped into the range.
THUMB_BASE_MIN = 0.263
#: Keyframe joint angles (rad): ManiSkill's zeros, the thumb's base at its lower limit.
ZERO_POSE = {r"joint_([0-9]|1[013-5])\.0": 0.0, r"joint_12\.0": THUMB_BASE_MIN}

#: Where ManiSkill puts the root (m) and the two keyframes' root orientations (w, x, y, z).
ROOT_HEIGHT = 0.5
PALM_SIDE_MOUNT = (0.0, 0.0, ROOT_HEIGHT, 1.0, 0.0, 0.0, 0.0)
PALM_UP_MOUNT = (0.0, 0.0, ROOT_HEIGHT, math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0)

#: Menagerie's kp (N*m/rad) and kv (N*m*s/rad), ManiSkill's force limit (N*m), Wonik's
#: velocity limit (rad/s).
STIFFNESS = 10.0
DAMPING = 1.0
EFFORT_LIMIT = 50.0
VELOCITY_LIMIT = 7.0
#: Reflected rotor inertia (kg*m^2), an estimate (see the module doc).
ARMATURE = 0.001
ALLEGRO_DRIVES = PDActuator(
    joints=JOINT_PATTERN,
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=EFFORT_LIMIT,
    velocity_limit=VELOCITY_LIMIT,
    armature=ARMATURE,
)

#: Open (rad): fingers stretched, the thumb's base turned to its upper limit (1.396 rad),
#: so that it stands up out of the palm at its wrist end, opposite the fingers, ready to
#: close over an object lying on the palm (the keyframes' thumb lies along the palm).
THUMB_OPPOSED = 1.396
OPEN = tuple(THUMB_OPPOSED if j == "joint_12.0" else 0.0 for j in JOINTS)
#: Closed (power grasp, rad): each finger's proximal at its upper limit (standing up
#: from the palm), medial and distal curled back over the palm; the thumb's medial and
#: distal curled towards the fingers. On an object in the palm the joints stop short
#: of these targets and press with kp times the remaining error.
FINGER_CLOSED = (0.0, 1.61, 1.0, 1.0)
THUMB_CLOSED = (THUMB_OPPOSED, 0.3, 0.9, 0.9)
CLOSED = FINGER_CLOSED * 3 + THUMB_CLOSED

#: The palm's face, 0.0111 m along ``base_link``'s x axis (the URDF's palm box), and the
#: power grasp's cube: 5.5 cm, its centre 15 mm from the finger bases towards the wrist
#: (clear of the thumb's base), its face 0.5 mm off the palm (tests/test_allegro.py).
PALM_FACE = 0.0111
GRASP_CUBE_EDGE = 0.055
POWER_GRASP = PowerGrasp(
    link="base_link",
    cube_centre=(PALM_FACE + 0.5 * GRASP_CUBE_EDGE + 0.0005, 0.0, -0.015),
    cube_edge=GRASP_CUBE_EDGE,
    outward=(1.0, 0.0, 0.0),
)

ALLEGRO_HAND = Hand(
    name="hand",
    joints=JOINT_PATTERN,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    max_velocity=VELOCITY_LIMIT,
    power_grasp=POWER_GRASP,
)

#: Fingertip pads (ManiSkill's dynamic friction of its tip material).
TIP_PAD = FrictionMaterial(sliding=1.0, torsional=0.01, rolling=0.0001)


@register_agent()
class AllegroHandRight(Agent):
    """Wonik Allegro Hand v4, right hand, on a fixed mount 0.5 m up (``palm_side``).

    qpos order: ``joint_0.0`` .. ``joint_15.0`` (index, middle, ring, thumb; base,
    proximal, medial, distal each). Fingertip bodies: :data:`TIP_LINKS`.
    """

    uid = "allegro_hand_right"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 allegro_hand_right
    #: allegro_hand_left allegro_hand_right_touch``, 2026-11-29 18:48 UTC, after the pads
    #: took MuJoCo's default contact; 20 Hz control): every claim holds from 6.25 ms (160
    #: Hz) down to 1 ms (random-action overshoot 0.147 rad at 160 Hz, 0.102 at 200 Hz,
    #: bound 0.25; settle below 1e-4 rad/s, bound 0.05; the power grasp's slip 0.13-0.16
    #: mm; deepest contact 4.5 mm, bound 5); at 100 Hz and coarser the random actions
    #: press joints 0.3-1.7 rad past their limits (with the former near-rigid pads,
    #: 2026-11-28: 0.136 and 0.095 rad at 160 and 200 Hz, slip 0.06-0.13 mm, deepest
    #: 4.2-4.5 mm). Default one tried step finer: 200 Hz (5 ms; 320 Hz until
    #: the fingertips' pad contact stopped applying between fingers, see the module
    #: docstring). The distal joints could cycle between their torque limits below 397
    #: Hz, but not at the joints' rated speed (``robot_agents.tuning.cycles``). Without
    #: the armature estimate the random claim failed at every step (0.51 rad at 1 kHz)
    #: and settle below 800 Hz (97 rad/s at 500 Hz).
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = ASSETS / "allegro_hand_right.xml"
    mount_pose: ClassVar[tuple[float, ...]] = PALM_SIDE_MOUNT
    actuators = (ALLEGRO_DRIVES,)
    parts = (ALLEGRO_HAND,)
    link_materials = {tip: TIP_PAD for tip in TIP_LINKS}
    keyframes = {
        "palm_side": Keyframe(qpos=ZERO_POSE),
        "palm_up": Keyframe(qpos=ZERO_POSE),
        # the name every built-in robot has, for tasks that reset to it
        "rest": Keyframe(qpos=ZERO_POSE),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "ALLEGRO_DRIVES",
    "ALLEGRO_HAND",
    "FINGERS",
    "GRASP_CUBE_EDGE",
    "JOINTS",
    "PALM_FACE",
    "PALM_SIDE_MOUNT",
    "PALM_UP_MOUNT",
    "POWER_GRASP",
    "TIP_LINKS",
    "AllegroHandRight",
]
