"""ROBEL D'Claw (``dclaw``): three fingers of three Dynamixel servos each on a mount,
pointing down, as ManiSkill's ``dclaw`` (its valve-turning robot).

Sources of the numbers:
- Kinematics, joint axes and ranges, masses and inertias: ManiSkill 3.0.1's
  ``assets/robots/dclaw/dclaw_gripper_glb.urdf`` (ROBEL's D'Claw, Apache-2.0; read as
  data). ``base`` -> ``base_link`` turned -1.57079 rad about y (``base_joint``); finger
  bases (``joint_fN_0``) at (0.013836, 0.026467, 0.054269) turned 2.618 rad about x,
  (0.013836, 0.033322, -0.050972) turned -5 pi / 6 and (0.013836, -0.059633, 0.000224)
  turned pi / 2 (three fingers about 120 deg apart, 60 mm from the axis); then about
  68.5 mm along x to ``joint_fN_1``, 68.5 mm to ``joint_fN_2`` and 84 mm to the tip's
  end (``link_fN_head``): the stretched fingers' ends 0.2348 m below the mount. Axes:
  ``joint_fN_0`` about -z of its frame (the finger swings sideways), ``joint_fN_1``
  and ``joint_fN_2`` about +-y (the finger curls): the URDF's axes, whose signs differ
  between fingers (curling inwards is ``joint_f1_1`` < 0, ``joint_f1_2`` > 0,
  ``joint_f2_1`` > 0, ``joint_f2_2`` < 0, ``joint_f3_1`` > 0, ``joint_f3_2`` > 0).
  Ranges (rad): ``joint_f1_0`` -0.524..1.32, ``joint_f2_0`` and ``joint_f3_0``
  -1.32..0.524, the others +-1.57. Masses (kg): base 0.23695, proximal and middle links
  0.0501, distal links 0.0260 each: 0.6156 kg in all; the URDF's inertias (its CAD's)
  as they are. ROBEL's own scene (``google-research/robel-scenes``
  ``dclaw/assets/dependencies3xh.xml``, commit f5089db) narrows the joints' commands
  (+-0.48 rad at the base servos, +-1.57 elsewhere); we keep ManiSkill's ranges.
- Collision shapes: the URDF's boxes (servo bodies 58 x 38 x 30 and 58 x 36 x 30 mm,
  bracket plates 30 x 24 x 10 mm, the base servos 26 x 40 x 50 mm) and, for its two
  meshes, primitives of their extents: the mounting disc (160 mm across, 11 mm thick)
  and each fingertip (a 48 x 26 x 9.5 mm flange and a rod of 10 mm radius ending
  round 83 mm out).
- Servos: ROBEL's scene names the D'Claw's servos DYNAMIXEL X-series 430s (its class
  ``dclaw3xh``, meshes ``xh_*``); the model variant was not readable in the sources we
  could reach, so the drives take the project's cited XM430-W350-T
  (:data:`~robot_agents.robots.servo_arms.servos.XM430_W350`; the XH430-W350 has its
  28.5 x 46.5 x 34 mm case and 353.5 : 1 gearing, and 3.4 N*m stall torque and 30
  rev/min at 12 V, ROBOTIS e-manual ``emanual.robotis.com/docs/en/dxl/x/xh430-w350``):
  its stall torque (4.1 N*m) is the effort limit, its no-load speed (4.82 rad/s) the
  velocity limit, its estimated reflected rotor inertia (0.0171 kg*m^2) the joints'
  armature.
- Drives: ManiSkill's gains, kp 100 N*m/rad and kv 10 N*m*s/rad on every joint. Its
  force limit, 20 N*m, is five times what the servo can give; we take the stall torque.
  ROBEL's scene's position servos (kp 2 N*m/rad, joint damping 0.1 N*m*s/rad,
  armature 0.001 kg*m^2) are far softer; ManiSkill's kp with the servo's armature
  gives a joint bandwidth of about sqrt(100 / 0.02) = 70 rad/s, overdamped (kv / (2
  sqrt(kp I)) = 3.5), a time constant of kv / kp = 0.1 s.
- Fingertips: ManiSkill's tip material on ``link_fN_3`` (static friction 2.0, dynamic
  1.0); MuJoCo has one coefficient and we take the dynamic 1.0, with torsional friction
  (condim 4) and near-rigid contact against objects, as the Allegro Hand's pads; the
  links take contact priority over the tips (a tip on another finger meets MuJoCo's
  default contact).
- Gravity: compensated on every body (the library's default for a fixed root), so the
  keyframe is held exactly.
- Keyframe: ManiSkill's ``rest``: every joint at 0 (the fingers straight down), the
  root 0.5 m up, turned pi about y (``q = (0, 0, -1, 0)``): the mount
  (:data:`MOUNT`), with ``base_link``'s x (the fingers) pointing down.
- Control modes: generated from the ``Hand`` part, in ManiSkill's action order
  (:data:`ACTION_JOINTS`: the three base joints, the three middle, the three distal):
  ``pd_joint_delta_pos`` (default, +-0.1 rad per step), ``pd_joint_pos`` (absolute
  targets, not normalized) and ``pd_joint_target_delta_pos``, plus the library's three
  velocity variants. ``qpos`` is in the model's order, finger by finger
  (:data:`JOINTS`).
- Grasp: the three fingertips pinch a 4 cm cube between them (:data:`CLOSED`: each
  finger's middle joint curled in by :data:`PINCH` rad, the rest straight); declared as
  the hand's :data:`POWER_GRASP` (the time-step sweep's grasp claim: the cube pulled
  down, away from the mount, by its weight again) and checked in tests/test_dclaw.py.
  Curled in further with the distal joints back out (fingertips vertical, 0.6 rad
  each), the middle links of neighbouring fingers met and pressed on each other
  (about 30 N) before the tips pressed the cube.
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand, PowerGrasp
from robot_agents.registry import register_agent
from robot_agents.robots.servo_arms.servos import XM430_W350

ASSETS = Path(__file__).parent / "assets"

FINGER_IDS = (1, 2, 3)
#: Model (qpos) order: finger by finger, base to tip.
JOINTS = tuple(f"joint_f{f}_{k}" for f in FINGER_IDS for k in range(3))
#: ManiSkill's action order: the base joints, then the middle, then the distal joints.
ACTION_JOINTS = tuple(f"joint_f{f}_{k}" for k in range(3) for f in FINGER_IDS)
#: ManiSkill's tip links (``tip_link_names``): the fingertips' ends.
TIP_LINKS = tuple(f"link_f{f}_head" for f in FINGER_IDS)
#: Each finger's links, base to tip.
FINGERS = tuple(tuple(f"link_f{f}_{k}" for k in (1, 2, 3)) for f in FINGER_IDS)

#: Where ManiSkill puts the root (m, quaternion w, x, y, z): 0.5 m up, turned pi about y.
ROOT_HEIGHT = 0.5
MOUNT = (0.0, 0.0, ROOT_HEIGHT, 0.0, 0.0, -1.0, 0.0)

#: ManiSkill's kp (N*m/rad) and kv (N*m*s/rad); the servo's stall torque (N*m), no-load
#: speed (rad/s) and reflected rotor inertia (kg*m^2).
STIFFNESS = 100.0
DAMPING = 10.0
DCLAW_DRIVES = PDActuator(
    joints=r"joint_f[123]_[012]",
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=XM430_W350.stall_torque,
    velocity_limit=XM430_W350.no_load_speed,
    armature=XM430_W350.armature,
)

#: How far each finger's middle joint curls in to pinch (rad), its distal joint straight:
#: the fingertips' rods, tilted in by as much, would meet 5 mm from the claw's axis;
#: on a 4 cm cube the servos press at their stall torque.
PINCH = 0.4
#: Which way each finger's middle joint curls in (+1 / -1; see the module doc).
CURL_IN = {1: -1.0, 2: 1.0, 3: 1.0}
OPEN = (0.0,) * 9
#: The pinch (ManiSkill's action order): the base and distal joints at 0, each middle
#: joint curled in by PINCH.
CLOSED = (*(0.0 for _ in FINGER_IDS), *(CURL_IN[f] * PINCH for f in FINGER_IDS), *(0.0 for _ in FINGER_IDS))

#: The pinched cube: 4 cm, its centre on the claw's axis 0.205 m below ``base_link``
#: (along its x), level with the pinching fingertips' rods (their axes 0.185..0.213 m)
#: and below their flanges (at most 0.181 m down).
GRASP_CUBE_EDGE = 0.04
GRASP_DEPTH = 0.205
POWER_GRASP = PowerGrasp(
    link="base_link",
    cube_centre=(GRASP_DEPTH, 0.0, 0.0),
    cube_edge=GRASP_CUBE_EDGE,
    outward=(1.0, 0.0, 0.0),
)

DCLAW_HAND = Hand(
    name="hand",
    joints=ACTION_JOINTS,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    max_velocity=XM430_W350.no_load_speed,
    power_grasp=POWER_GRASP,
)

#: Fingertips (ManiSkill's dynamic friction of its tip material).
TIP_PAD = FrictionMaterial(sliding=1.0, torsional=0.01, rolling=0.0001)


@register_agent()
class DClaw(Agent):
    """ROBEL D'Claw on a fixed mount 0.5 m up, fingers pointing down (``rest``).

    qpos order: :data:`JOINTS` (finger 1's base, middle and distal joints, then finger
    2's, finger 3's); actions in ManiSkill's order, :data:`ACTION_JOINTS`. Fingertip
    ends: :data:`TIP_LINKS`.
    """

    uid = "dclaw"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 dclaw``,
    #: 2026-11-29 18:17 UTC, 20 Hz control): every claim holds from 3.125 ms (320 Hz) down
    #: to 1 ms (random-action overshoot 0.0167 rad at 320 Hz, bound 0.25; settle below
    #: 4e-9 rad/s; the pinch's slip 0.96-1.27 mm, bound 2). At 200 Hz and coarser the
    #: settle claim fails (0.689 rad/s at 200 Hz): a drive pressed at its stall torque has
    #: ManiSkill's kv 10 N*m*s/rad integrated explicitly, and a joint can cycle between its
    #: torque limits below 291 Hz (``joint_f1_2``, ``robot_agents.tuning.cycles``). Default
    #: one tried step finer: 400 Hz.
    sim_freq: ClassVar[int | None] = 400
    mjcf_path = ASSETS / "dclaw.xml"
    mount_pose: ClassVar[tuple[float, ...]] = MOUNT
    actuators = (DCLAW_DRIVES,)
    parts = (DCLAW_HAND,)
    link_materials = {f"link_f{f}_3": TIP_PAD for f in FINGER_IDS}
    #: each finger's first link holds the bracket around its base servo's horn (parent
    #: and child: MuJoCo never lets them collide; declared so that nothing is guessed)
    self_collision_exclusions = tuple(("base_link", f"link_f{f}_1") for f in FINGER_IDS)
    keyframes = {"rest": Keyframe(qpos={r"joint_f[123]_[012]": 0.0})}
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "ACTION_JOINTS",
    "CLOSED",
    "DCLAW_DRIVES",
    "DCLAW_HAND",
    "FINGERS",
    "GRASP_CUBE_EDGE",
    "JOINTS",
    "MOUNT",
    "OPEN",
    "POWER_GRASP",
    "TIP_LINKS",
    "DClaw",
]
