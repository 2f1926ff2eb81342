"""Inspire Robots RH56DFX dexterous hand with its 2-DoF wrist, right and left: pieces
(:class:`InspireHandRight`, :class:`InspireHandLeft`) and ManiSkill's four robots made of
them: ``fixed_inspire_hand_right`` / ``_left`` (on a fixed mount) and
``floating_inspire_hand_right`` / ``_left`` (on a 6-DoF floating mount).

Sources of the numbers:
- Product: Inspire's RH56DFX data ("Degrees of freedom 6, Numbers of joints 12"; 540 g;
  fingertip force 10 N for the four fingers, 15 N for the thumb; RS485), as quoted from
  Inspire's product page (fetched 2026-09-17) in a public hand survey's Table 2 (row
  ``inspire_rh56dfx_2023``, found through the code index; the maker's page itself could
  not be read from the stored corpora): six linear actuators (thumb yaw, thumb bend,
  index, middle, ring, pinky), each finger's distal joint coupled to its proximal, the
  thumb's two outer joints to its bend. Fingertip forces measured on a real RH56DFX at
  its full force setting (correlllab/rh56_controller README, 2025-11-04): index 7.06 N,
  middle 6.47 N, thumb bend 12.93 N. The URDF's link masses (below) sum to 344 g with the
  wrist, under the 540 g quoted: we keep the URDF's, which describe its links (where the
  difference sits is not known).
- Kinematics, ranges, couplings, masses and inertias: ManiSkill 3.0.1's
  ``assets/robots/inspire_hand/RH56DFX-2LR/urdf/inspire_hand_{right,left}.urdf`` (from
  Inspire's support team, per its README; read as data; the numbers are written out in
  :mod:`robot_agents.robots.inspire.model`). Wrist base (root, 65.4 g) -> wrist pitch at
  (0, 0, 0.0785) (range -0.3955..0.3861 rad) -> wrist yaw (+-0.4451 rad) -> palm
  (192.9 g); finger MCPs at y = 0.103-0.105 m on the palm (range -1.34..0 rad, closing
  negative), PIPs 0.0322 m further (``PIP = 1.06399 MCP - 0.167348``, range
  -1.5931..0.04545); fingertips 0.045-0.049 m beyond; the thumb's CMC yaw at (0.02125,
  0.0285, +-0.01515) (-1.309..0), CMC pitch (-0.48..0), MCP (``1.3333 pitch -
  0.081449``, -0.8..0) and IP (``0.6667 pitch - 0.040724``, -0.4..0: Inspire's own
  coupling of both to the pitch, which the URDF keeps commented out; ManiSkill chains
  the IP to the MCP at 0.5, the same relation). The hand weighs 0.3444 kg in all
  (wrist included). The left hand is the right one mirrored
  (:mod:`robot_agents.robots.inspire.model`), which reproduces the upstream left URDF's
  joint frames within 3e-7 m / rad (its masses within 0.1 %).
- Collision shapes: boxes, cylinders and capsules over the extents of the URDF's visual
  meshes (palm 80 x 80 x 31 mm below the finger bases; finger links 45 x 25 x 14 mm and
  12.6 mm capsules; thumb links 68 x 33 x 19 mm, 45 x 24 x 16 mm, 30 x 17 x 15 mm).
- Drives: the URDF's effort limit, 1 N*m on every joint (the fingertip forces above at
  the fingers' 0.077 m reach are 0.5-0.8 N*m, the thumb's 12.9-15 N at 0.1 m 1.3-1.5
  N*m), and its
  velocity limit, 0.5 rad/s, which bounds the velocity modes. ManiSkill's PhysX gains
  (kp 1000, kv 100 N*m*s/rad, force limits 20 / 100 N*m) are not the hand's: with them
  1 N*m saturates at 1 mrad of error and PhysX integrates its drives implicitly. Ours:
  kp 10 N*m/rad (the drive saturates 0.1 rad from its target, as the Allegro's), kv 1
  N*m*s/rad, armature 0.01 kg*m^2 on the driven joints: an estimate (no source gives
  one) of a micro linear actuator's reflected inertia, a coreless motor's rotor (of
  order 1e-8 kg*m^2) behind a gearbox of about 30:1 and a 0.5 mm lead screw acting on a
  10 mm lever: 1e-8 * (30 * 2 pi / 0.0005)^2 * 0.01^2 = 0.014 kg*m^2. With 0.001 (the
  Allegro's value) a drive clamped at its 1 N*m has its damping integrated explicitly
  (kv dt / I > 2 below 500 Hz) and flipped between its limits: after random actions the
  fingers' MCP joints still turned at 2.8 rad/s at 160 Hz and 4.6 at 100 Hz (the settle
  claim's bound is 0.05); with 0.01 they come to rest from 100 Hz. The coupled joints
  carry ManiSkill's passive damping (0.001 N*m*s/rad) and 1e-4 kg*m^2 of armature (an
  estimate: the share of the same actuator's inertia the linkage reflects on them; it
  keeps the grams-light links stable against their stiff couplings).
- Contact: ManiSkill's finger material (static and dynamic friction 2.0) on the palm
  and every finger link, with the library's near-rigid pad contact (priority, solref
  0.01, impedance 0.9999: Menagerie's ``trs_so_arm100`` pad values, as the other pads';
  with MuJoCo's default contact a finger's saturated drive pressed 17.5 mm into the
  sweep's 64 g cube); self-collisions off, as ManiSkill's (its note: the hand's design
  keeps its fingers apart).
- Fixed mount: ManiSkill's keyframe poses: the wrist's base 0.4 m up, turned -pi/2
  about z (``palm_side``) and then pi/2 about x (``palm_up``); gravity compensated (the
  library's default for a fixed root). Floating mount: the library's 6-DoF mount
  (``robots/robotiq/assets/floating_mount.xml``: ManiSkill's ``root_*`` joint names; kp
  1000, kv 100, 100 N as ManiSkill's) with the hand's wrist base on it, turned so that
  both keyframes reach ManiSkill's poses clear of the mount's gimbal lock
  (:data:`HAND_ON_MOUNT`).
- Power grasp (ours; tests/test_inspire_hand.py): open is every drive at 0 (the thumb
  stretched out beside the palm); closed swings the thumb in front of the palm (yaw
  -1.2), bends it (-0.47) and curls the fingers to their MCP limit. A 4 cm cube on the
  palm's face 85 mm up the palm is held between the thumb's metacarpal and the curled
  fingers: the sweep's grasp claim (the cube pulled away from the palm at 1 g net) slips
  0.77 mm at 160 Hz on the fixed mount and 0.56 mm at 200 Hz on the floating one; the
  floating hand palm down picks such a cube (50 g) from a pedestal, the thumb pressing
  about 52 N against the fingers, the hand's contacts carrying its weight.

ManiSkill differences: its qpos is in breadth-first order (the MCPs before the PIPs), ours
in the model's depth-first order (each finger's joints together); its keyframes put the
thumb's IP at -0.0723 rad where its own coupling puts it at -0.0407 (ours follow the
coupling). Its two modes are ``pd_joint_pos`` and ``pd_joint_delta_pos`` (wrist and six
drives, +-0.1 rad per step); ours are generated from the parts: the same two (plus the
library's target-delta and velocity variants) for the fixed hands; on the floating mount
the mount is the arm part (the six joint modes, ``pd_ee_delta_pose``, ``pd_ee_pose``) and
the hand takes absolute targets where the mount's are absolute (``pd_joint_pos`` as
ManiSkill's, ``pd_joint_pos_vel``, ``pd_ee_pose``) and +-0.1 rad deltas in the others.
ManiSkill's wrist drive has its own 100 N force limit, ours the URDF's 1 N*m as every
joint's. The example's generic scripted Pick/Push solvers do not fit a hand
(:data:`HAND_TASK_LIMITS`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand, PowerGrasp
from robot_agents.registry import register_agent
from robot_agents.robots.floating_mount import MANISKILL_MOUNT_MJCF, MOUNT_JOINTS, mount_arm
from robot_agents.robots.inspire.model import ASSETS

#: The driven joints in ManiSkill's action order (without the side's prefix): the wrist,
#: then the six actuators.
DRIVEN = (
    "wrist_pitch_joint",
    "wrist_yaw_joint",
    "thumb_CMC_yaw_joint",
    "thumb_CMC_pitch_joint",
    "index_MCP_joint",
    "middle_MCP_joint",
    "ring_MCP_joint",
    "pinky_MCP_joint",
)
#: The coupled joints (each follows a driven one through a joint equality).
COUPLED = (
    "thumb_MCP_joint",
    "thumb_IP_joint",
    "index_PIP_joint",
    "middle_PIP_joint",
    "ring_PIP_joint",
    "pinky_PIP_joint",
)
#: Each finger's links (base to tip), thumb first.
FINGER_LINKS = (
    ("thumb_metacarpal", "thumb_proximal", "thumb_distal", "thumb_tip"),
    ("index_proximal", "index_middle", "index_tip"),
    ("middle_proximal", "middle_middle", "middle_tip"),
    ("ring_proximal", "ring_middle", "ring_tip"),
    ("pinky_proximal", "pinky_middle", "pinky_tip"),
)
#: Links with ManiSkill's finger material.
PAD_LINKS = (
    "hand_base_link",
    "thumb_metacarpal_base",
    "thumb_metacarpal",
    "thumb_proximal",
    "thumb_distal",
    *(f"{f}_{k}" for f in ("index", "middle", "ring", "pinky") for k in ("proximal", "middle")),
)

#: The URDF's effort (N*m) and velocity (rad/s) limits; our kp (N*m/rad), kv (N*m*s/rad)
#: and armature estimate (kg*m^2) (see the module docstring).
EFFORT_LIMIT = 1.0
VELOCITY_LIMIT = 0.5
STIFFNESS = 10.0
DAMPING = 1.0
ARMATURE = 0.01

#: Open (rad, ManiSkill's action order): every drive at 0 (ManiSkill's keyframes): the
#: wrist straight, the fingers stretched, the thumb stretched out beside the palm.
OPEN = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
#: Closed (power grasp, rad): the thumb swung in front of the palm (CMC yaw -1.2 of its
#: -1.309 range) and bent short of its -0.48 limit, the fingers curled to their MCP limit
#: (-1.34); on an object they stop short and press with the drives' saturated 1 N*m.
CLOSED = (0.0, 0.0, -1.2, -0.47, -1.34, -1.34, -1.34, -1.34)

#: ManiSkill's keyframe root poses (x, y, z, qw, qx, qy, qz): 0.4 m up, turned -pi/2
#: about z (palm_side), then pi/2 about x (palm_up: euler2quat(pi/2, 0, -pi/2)).
ROOT_HEIGHT = 0.4
PALM_SIDE_MOUNT = (0.0, 0.0, ROOT_HEIGHT, math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))
PALM_UP_MOUNT = (0.0, 0.0, ROOT_HEIGHT, 0.5, 0.5, -0.5, -0.5)

#: The palm's face in the right palm's frame (m along z; the left's at -z: the fingers
#: curl towards it), and the power grasp's cube: 4 cm, its face 0.5 mm off the palm,
#: under the curling fingers.
PALM_FACE = 0.012
GRASP_CUBE_EDGE = 0.04
GRASP_CUBE_XY = (0.0, 0.085)

#: ManiSkill's finger material (static and dynamic friction 2.0).
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)


def names(side: str, joints: Sequence[str]) -> tuple[str, ...]:
    """``joints`` with the side's ``{side}_hand_`` prefix."""
    return tuple(f"{side}_hand_{j}" for j in joints)


def hand_drives(side: str) -> PDActuator:
    """The six actuators and the wrist's two joints of one side."""
    return PDActuator(
        joints=names(side, DRIVEN),
        stiffness=STIFFNESS,
        damping=DAMPING,
        effort_limit=EFFORT_LIMIT,
        velocity_limit=VELOCITY_LIMIT,
        armature=ARMATURE,
    )


def palm_normal(side: str) -> float:
    """The palm face's side along the palm frame's z: +1 (right), -1 (left, mirrored)."""
    return 1.0 if side == "right" else -1.0


def power_grasp(side: str) -> PowerGrasp:
    """The cube the power grasp holds, in the side's palm frame."""
    z = palm_normal(side)
    return PowerGrasp(
        link=f"{side}_hand_hand_base_link",
        cube_centre=(*GRASP_CUBE_XY, z * (PALM_FACE + 0.5 * GRASP_CUBE_EDGE + 0.0005)),
        cube_edge=GRASP_CUBE_EDGE,
        outward=(0.0, 0.0, z),
    )


def hand_part(side: str) -> Hand:
    """The hand part of one side: the wrist and the six drives take actions (ManiSkill's
    order); the coupled joints follow."""
    return Hand(
        name="hand",
        joints=names(side, DRIVEN),
        open=OPEN,
        closed=CLOSED,
        fingers=tuple(names(side, finger) for finger in FINGER_LINKS),
        max_delta=0.1,
        max_velocity=VELOCITY_LIMIT,
        power_grasp=power_grasp(side),
    )


def driven_zeros(side: str) -> dict[str, float]:
    """Every driven joint of the side at 0 (rad)."""
    return dict.fromkeys(names(side, DRIVEN), 0.0)


def zero_pose(side: str) -> Keyframe:
    """Every driven joint at 0 (ManiSkill's keyframes); the coupled ones follow."""
    return Keyframe(qpos=driven_zeros(side))


#: Body pairs of a side's hand that touch at its zero pose (the palm on the wrist's base
#: and on the thumb's metacarpal): excluded from contacts where the piece is mounted on
#: another robot (the hand robots below turn every self-collision off, as ManiSkill's).
def touching_pairs(side: str) -> tuple[tuple[str, str], ...]:
    """The pairs of :func:`names`-prefixed links that touch at the zero pose."""
    palm = f"{side}_hand_hand_base_link"
    return ((palm, f"{side}_hand_wrist_base_link"), (palm, f"{side}_hand_thumb_metacarpal"))


#: Why the example's generic scripted solvers cannot do ManiSkill's table-top tasks with
#: the floating hands (measured 2026-11-29 18:34 UTC, ``success_rate`` of
#: examples/scripted_pick.py, 20 seeds): they open and close a gripper at its
#: controller's unit bounds, which for a hand's eight joint targets are every joint's
#: limits, the wrist's too, not a grasp.
HAND_TASK_LIMITS = {
    "PickCube-v1": (
        "the generic solver opens and closes a gripper at its controller's bounds, for a hand every joint's "
        "limits (its wrist's too): 0/20 picks, both sides; the hand's own grasp is its power grasp "
        "(tests/test_inspire_hand.py picks a cube with it)"
    ),
    "PushCube-v1": (
        "the generic solver pushes with the closed gripper's fingertips pointing down, for a hand every "
        "joint at its limit (the wrist's too): 4/20 right, 10/20 left"
    ),
}


class InspireHandRight(Agent):
    """The right RH56DFX with its wrist (a piece): root body ``right_hand_wrist_base_link``
    (its z axis up the forearm), palm ``right_hand_hand_base_link``, part ``hand``.

    qpos order: wrist pitch, wrist yaw, thumb (CMC yaw, CMC pitch, MCP, IP), then each
    finger's MCP and PIP (index, middle, ring, pinky).
    """

    mjcf_path = ASSETS / "inspire_hand_right.xml"
    tcp = "right_hand_hand_base_link"
    actuators = (hand_drives("right"),)
    parts = (hand_part("right"),)
    link_materials = {link: FINGER_PAD for link in names("right", PAD_LINKS)}
    disable_self_collisions = True
    self_collision_exclusions = touching_pairs("right")
    keyframes = {"rest": zero_pose("right")}


class InspireHandLeft(Agent):
    """The left RH56DFX with its wrist (a piece): the right one mirrored, names
    ``left_hand_*``; the same joint order, angles and keyframes."""

    mjcf_path = ASSETS / "inspire_hand_left.xml"
    tcp = "left_hand_hand_base_link"
    actuators = (hand_drives("left"),)
    parts = (hand_part("left"),)
    link_materials = {link: FINGER_PAD for link in names("left", PAD_LINKS)}
    disable_self_collisions = True
    self_collision_exclusions = touching_pairs("left")
    keyframes = {"rest": zero_pose("left")}


#: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
#: fixed_inspire_hand_right fixed_inspire_hand_left floating_inspire_hand_right
#: floating_inspire_hand_left``, 2026-11-29 18:28-18:31 UTC, 20 Hz control; both sides
#: alike): on the fixed mount every claim holds from 100 Hz to 1 kHz (at 100 Hz the power
#: grasp's slip 1.18 mm, bound 2; random-action overshoot 0.006 rad, bound 0.25; deepest
#: contact 0.5 mm, bound 5); at 80 Hz the grasp slips 2.6 mm. Default one tried step
#: finer: 160 Hz (slip 0.77 mm). No drive can cycle between its torque limits above
#: 50 Hz (``robot_agents.tuning.cycles``; 496 Hz with the Allegro's armature, 0.001).
FIXED_SIM_FREQ = 160
#: On the floating mount every claim holds from 160 Hz (random-action overshoot 0.126
#: rad right, 0.089 left; at 100 Hz 0.309 / 0.328 FAIL), as the other floating grippers':
#: the mount's hinges (100 N*m, kv 100 on 0.3 kg*m^2) could cycle between their torque
#: limits below 166 Hz. Default one tried step finer: 200 Hz, above that bound, until
#: 2026-11-29 21:10 UTC: with ten random-action seeds (``python
#: benchmarks/timestep_sweep.py floating_inspire_hand_right floating_inspire_hand_left
#: --substeps 10,16,20,25 --seeds 0,1,2,3,4,5,6,7,8,9``, 20:59-21:01 UTC) absolute mount
#: targets (``pd_ee_pose``, seed 3) fling the right hand's thumb MCP follower 0.308 rad
#: past its stop at 200 Hz (0.025 at 500 Hz: the step's doing); every claim of both
#: hands holds at 320, 400 and 500 Hz (overshoot at most 0.083 rad). Default 320 Hz, the
#: next tried step, for both sides (the left passed all ten at 200 Hz: 0.167 rad).
FLOATING_SIM_FREQ = 320


@register_agent()
class FixedInspireHandRight(InspireHandRight):
    """The right RH56DFX on a fixed mount, ManiSkill's ``fixed_inspire_hand_right``:
    mounted as ``palm_side``; ``palm_up`` is the same joint pose with the scene mounting
    the robot at :data:`PALM_UP_MOUNT` (``robot_poses=[PALM_UP_MOUNT]``)."""

    uid = "fixed_inspire_hand_right"
    sim_freq: ClassVar[int | None] = FIXED_SIM_FREQ
    mount_pose: ClassVar[tuple[float, ...]] = PALM_SIDE_MOUNT
    keyframes = {"palm_side": zero_pose("right"), "palm_up": zero_pose("right"), "rest": zero_pose("right")}
    default_control_mode = "pd_joint_delta_pos"


@register_agent()
class FixedInspireHandLeft(InspireHandLeft):
    """The left RH56DFX on a fixed mount, ManiSkill's ``fixed_inspire_hand_left``."""

    uid = "fixed_inspire_hand_left"
    sim_freq: ClassVar[int | None] = FIXED_SIM_FREQ
    mount_pose: ClassVar[tuple[float, ...]] = PALM_SIDE_MOUNT
    keyframes = {"palm_side": zero_pose("left"), "palm_up": zero_pose("left"), "rest": zero_pose("left")}
    default_control_mode = "pd_joint_delta_pos"


#: The mount's slide height (m): the floating mount's root is 0.5 m up, ManiSkill's hand 0.4.
MOUNT_DROP = ROOT_HEIGHT - 0.5


#: The hand on the mount turned -pi/2 about z (ManiSkill's keyframes' turn) and then
#: -pi/4 about the mount's y: ``palm_side`` is the mount's y hinge at +pi/4 and
#: ``palm_up`` (a quarter turn further about world y) at -pi/4, both clear of that
#: hinge's gimbal lock at +-pi/2 (with the hand unturned on it, ``palm_up`` would sit
#: on it).
HAND_ON_MOUNT = (
    math.cos(math.pi / 8) * math.sqrt(0.5),
    math.sin(math.pi / 8) * math.sqrt(0.5),
    -math.sin(math.pi / 8) * math.sqrt(0.5),
    -math.cos(math.pi / 8) * math.sqrt(0.5),
)
QUARTER_PI = math.pi / 4


def floating(side: str, palm_up: bool) -> Keyframe:
    """The mount with the wrist's base 0.4 m up as in ManiSkill's keyframe poses (turned
    -pi/2 about z; ``palm_up``: then pi/2 about its own x), every driven joint of the hand
    at 0."""
    return Keyframe(
        qpos={
            "root_[xy]_axis_joint": 0.0,
            "root_z_axis_joint": MOUNT_DROP,
            "root_[xz]_rot_joint": 0.0,
            "root_y_rot_joint": -QUARTER_PI if palm_up else QUARTER_PI,
            **driven_zeros(side),
        }
    )


MOUNT_DRIVES = PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2, effort_limit=100.0)


@register_agent()
class FloatingInspireHandRight(Agent):
    """The right RH56DFX on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges),
    ManiSkill's ``floating_inspire_hand_right``. qpos order: the six mount joints, then
    the hand's (:class:`InspireHandRight`)."""

    uid = "floating_inspire_hand_right"
    sim_freq: ClassVar[int | None] = FLOATING_SIM_FREQ
    mjcf_path = MANISKILL_MOUNT_MJCF
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(InspireHandRight, at="root", quat=HAND_ON_MOUNT),)
    actuators = (MOUNT_DRIVES,)
    disable_self_collisions = True
    task_limits: ClassVar[Mapping[str, str]] = HAND_TASK_LIMITS
    parts = (mount_arm("right_hand_hand_base_link"),)
    keyframes = {
        "palm_side": floating("right", palm_up=False),
        "palm_up": floating("right", palm_up=True),
        "rest": floating("right", palm_up=False),
    }
    default_control_mode = "pd_joint_delta_pos"


@register_agent()
class FloatingInspireHandLeft(FloatingInspireHandRight):
    """The left RH56DFX on the same floating mount, ManiSkill's ``floating_inspire_hand_left``."""

    uid = "floating_inspire_hand_left"
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(InspireHandLeft, at="root", quat=HAND_ON_MOUNT),)
    parts = (mount_arm("left_hand_hand_base_link"),)
    keyframes = {
        "palm_side": floating("left", palm_up=False),
        "palm_up": floating("left", palm_up=True),
        "rest": floating("left", palm_up=False),
    }


__all__ = [
    "COUPLED",
    "DRIVEN",
    "PALM_SIDE_MOUNT",
    "PALM_UP_MOUNT",
    "FixedInspireHandLeft",
    "FixedInspireHandRight",
    "FloatingInspireHandLeft",
    "FloatingInspireHandRight",
    "InspireHandLeft",
    "InspireHandRight",
    "hand_drives",
    "hand_part",
]
