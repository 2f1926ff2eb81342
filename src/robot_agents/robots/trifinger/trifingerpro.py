"""TriFinger Pro (``trifingerpro``): three 3-DoF fingers hanging from a hub 0.29 m
above an arena floor, pointing down into it, as ManiSkill's ``trifingerpro``.

Sources of the numbers:
- Kinematics, joint axes and ranges, masses and inertias: the TriFinger Pro URDF
  (``open-dynamic-robot-initiative/robot_properties_fingers``, ``trifingerpro.urdf``,
  generated from ``xacro/pro/trifingerpro.urdf.xacro``; identical in ManiSkill 3.0.1's
  ``assets/robots/trifinger/trifingerpro.urdf``, read as data). Hub
  (``upper_holder_link``) 0.29 m above ``base_link``; finger bases on the hub turned 0,
  -120 and -240 deg about z. Per finger: ``finger_base_to_upper_joint`` at the base,
  axis y, -0.33..1.0 rad; ``finger_upper_to_middle_joint`` at (0.01685, 0.0505, 0),
  axis x, 0..1.57 rad; ``finger_middle_to_lower_joint`` at (0.05015, 0, -0.16), axis x,
  -2.7..0 rad; the tip frame at (0.019, 0, -0.16) (the URDF: "joint limits are set
  according to soft limits in the configuration of the real robot"). Masses (kg),
  centres of mass and full inertia tensors as the URDF's: upper 0.26689, middle
  0.27163, lower 0.05569, tip 0.031 (the URDF's tip link has a second ``inertial``,
  0.0092 kg, which URDF parsers that read one ignore; we take the first): 1.876 kg of
  moving links in all. Hub and links carry no other mass (the URDF's are 0).
- Collision shapes: boxes sized from the extents of the URDF's meshes (``pro/prox-sim``:
  y 0.0235..0.2404, z +-0.021 m over most of its length, x -0.0085..0.0165 there (it
  widens to +-0.022 at its outer end, the motor's mount); ``int_sim``: a joint housing
  x 0..0.045, z -0.03..0.02 and a leg x 0.026..0.05, y +-0.021, down to z -0.184;
  ``tip_link_sim``: a housing x 0..0.026 and a shaft x 0.0105..0.0275 down to z -0.1385
  that tapers from y +-0.015 at z -0.027 to +-0.0085 below z -0.11, three boxes over
  it with the mesh's extents: +-0.015 to z -0.0789, +-0.0099 to -0.0996 and +-0.0087
  to its end (its fillet into the housing, up to +-0.0168 in the last 5 mm above
  z -0.02, left out; ``center_axis_sim``: 58 x 50 x 36 mm); fingertips: capsules of the
  tip mesh's 10 mm radius (``tip_sim``: +-0.01 m, up to 0.0215 m), their centre on the
  tip frame, which stand out of the shaft's end. Until 2026-11-29 the shaft was one box,
  y +-0.012 down to z -0.138: 2 mm out of the tip's side, it met a flat block the tip
  was pressed on (tests/test_pad_press.py) beside the tip.
- Drives: the makers' simulation of the Pro (``open-dynamic-robot-initiative/
  trifinger_simulation``, ``sim_finger.py``, ``SimFinger``; commit 0b34b04): PD gains
  kp (15, 15, 9) N*m/rad and kd (0.5, 1.0, 0.5) N*m*s/rad (upper, middle, lower), its
  ``max_motor_torque`` 0.396 N*m; ``trifingerpro_limits.py`` (commit f9d7170): torque
  0.396 N*m ("the actual max. torque is 0.396"), velocity 10 rad/s. The real robot's
  driver (``open-dynamic-robot-initiative/robot_fingers``,
  ``include/robot_fingers/trifinger_driver.hpp``, ``TriFingerDriver``; commit e2cb3ec):
  motor torque constant 0.02 N*m/A, gear ratio 9. ManiSkill's gains
  (kp 100, kv 10 N*m*s/rad, force limit 20 N*m, 50 times the motors' torque) are not
  the robot's and are not used.
- Armature: 8e-4 kg*m^2 per joint, an order-of-magnitude estimate of the rotor's
  inertia reflected through the 9:1 reduction (no public model or datasheet we could
  read gives one): a small outrunner's rotor, of order 1e-5 kg*m^2, times 9^2. Without
  it random actions leave a lower joint turning at 1.8 rad/s at 160 Hz (a drive's
  torque-limit cycle; settle bound 0.05) and the pinch below slips 1.1 mm at 200 Hz
  (0.27 mm with it; ``claims.measure_step`` on the robot without armature, 2026-11-29
  20:29 UTC; ``test_without_the_armature_estimate_a_drive_cycles_and_the_pinch_slips_more``).
  With the tips' former critically damped contact it slipped 8.8 mm (0.74 with it).
- Fingertip pads: ManiSkill's tip material (static friction 2.0, dynamic 1.0); MuJoCo
  has one coefficient and we take the dynamic 1.0, with torsional friction (condim 4)
  and the near-rigid pad contact of the library's servo-arm pads (solref 0.01 s,
  impedance 0.9999), overdamped (damping ratio 4, :data:`TIP_DAMPING_RATIO`), against
  objects only (the fingers' other geoms take a higher contact priority). Why
  overdamped (2026-11-29, scratch runs 20:22-20:32 UTC): MuJoCo drives a contact's
  depth r with the reference acceleration -b v - k r, b = 2 / (dmax tau) and
  k = 1 / (dmax^2 tau^2 zeta^2); at tau = 0.01 s, two steps of 200 Hz, and zeta = 1,
  k dt^2 = 1/4: a near-rigid tip gives back a quarter of its depth each step (0.109,
  0.079, 0.058 mm ...), is out in about 12 steps and, with no contact margin, loses
  the surface. Its drive, saturated against the surface, is then a constant 0.396 N*m
  without damping (a clamped PD's kv is gone), and the finger falls back in over one
  free step (0.58 rad/s, 0.46 mm deep): a cycle of 12-13 steps. A tip driven onto the
  floor by random actions (``pd_joint_pos_vel``, seed 2) cycled so at 0.26 rad/s, and
  a tip pressed on a fixed block (tests/test_pad_press.py), the old shaft box touching
  the block beside it, at 3.2-8.1 N and 0.145 rad/s (at 1 kHz, where a free step
  presses 25 times less deep, the block press rested: 6.61-6.68 N). With zeta = 4, k is 16 times smaller (1/64 of the
  depth per step) and b, which alone acts along the friction directions, is unchanged:
  at 200 Hz the tip pressed on the block rests (2.724-2.725 N, 6e-4 rad/s; with the
  old shaft box 6.26-6.29 N), the sweep's settle claim is 3e-5 to 3e-4 rad/s from
  160 Hz to 1 kHz, and the pinch slips 0.27-0.28 mm (0.37-1.0 mm before: the tips
  chattered on the cube too); zeta = 2 rests as well, the pinch 0.35-1.0 mm. The block
  press rests from 160 Hz to 1 kHz (2.716-2.735 N, at most 7.1e-4 rad/s), and with ten
  other random-action seeds (3-12) the settle claim is 7.2e-4, 1.2e-4, 2.9e-4 and
  3.6e-3 rad/s at 160, 200, 320 Hz and 1 kHz (the former model: 0.066 at 160 Hz, past
  the bound, 0.047 at 200; 2026-11-29 20:36-20:37 UTC). Rejected
  earlier the same day: MuJoCo's default tip contact (the press rests, the pinch claim
  fails) and impedance 0.99-0.999 (the pinch slips 1.7 mm at 200 Hz); and the fitted
  shaft alone leaves the floor cycle (``test_a_tip_pressed_on_the_floor_rests_only_with_the_overdamped_contact``,
  ``test_a_flat_block_pressed_on_a_tip_meets_the_tip_alone``).
- Gravity: compensated on every body (the library's default for a fixed root): the
  keyframe is held exactly and the 0.396 N*m is left to motion and contact (the real
  robot's position controller has no gravity term). A finger's weight loads its upper
  and middle joints with 0.24 N*m each at ``rest``, and its middle joint with more than
  its motor's 0.396 N*m with the middle link level
  (``test_the_fingers_weight_exceeds_a_motor_without_gravity_compensation``).
- The frame: the URDF's hub (``center_axis_sim``) is all of it the public model has;
  the structure the three finger modules are bolted to (with the upper joints' motors)
  is static, not in the URDF, and not modelled. The upper and middle links carry the
  URDF's motor visuals (``motor_sim``: 44 mm across, 16 mm deep).
- Mount: ``base_link`` on the arena floor (the makers' simulation loads the robot at the
  origin over its table's top at z = 0); the floor, the arena's boundary and the cube
  are a task's, not the robot's. ManiSkill's RotateCube task raises the robot 0.0545 m.
- Keyframes: ManiSkill's agent declares none (its RotateCube task resets to all joints
  at 0 plus noise, the tips 30 mm below ``base_link``: below the floor with the robot
  on it). ``rest`` is the makers' default pose (``trifingerpro_limits.py``:
  (0, 0.9, -1.7) rad per finger), the tips 79 mm above the floor.
- Control modes: generated from the ``Hand`` part: ManiSkill's six: ``pd_joint_delta_pos``
  (default, +-0.1 rad per step), ``pd_joint_pos`` (absolute targets, not normalized),
  ``pd_joint_target_delta_pos``, ``pd_joint_vel`` (+-1 rad/s, ManiSkill's bound),
  ``pd_joint_pos_vel`` and ``pd_joint_delta_pos_vel``.
- Grasp: three tips pinching a cube on the axis under the hub (:data:`POWER_GRASP`, the
  time-step sweep's grasp claim): a cube of the makers' cube's weight (80 g: 65 mm at
  291.3 kg/m^3, ``cube_multicolor_rrc.urdf``) at the library's cube density, 43 mm.
  Statically the middle joints bound the pinch (0.254 N*m per newton a tip presses,
  0.028 per newton it carries): 4.22 N up for that cube (pulled with 0.78 N), 4.57 N for
  ManiSkill's RotateCube cube (65 mm at water's density, 275 g: 2.69 N)
  (``test_the_drives_can_hold_both_cubes_statically``). Pinched the same way at 200 Hz,
  ManiSkill's cube creeps 2.5 mm in the claim's 2 s (bound 2;
  ``test_maniskills_cube_creeps_past_the_claims_bound``, 2026-11-29 20:29 UTC; 57 mm,
  out of the pinch, while the tips chattered). In tests/test_trifinger.py the cube is
  also lifted off the arena floor, the tips' contact forces summing to its weight.
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

ASSETS = Path(__file__).parent / "assets"

#: The fingers by their URDF suffix (the angle their base is turned, deg, clockwise).
FINGER_ANGLES = (0, 120, 240)
#: ManiSkill's joint order (model order too): per finger upper, middle, lower.
JOINTS = tuple(
    f"{joint}_{n}"
    for n in FINGER_ANGLES
    for joint in ("finger_base_to_upper_joint", "finger_upper_to_middle_joint", "finger_middle_to_lower_joint")
)
JOINT_PATTERN = r"finger_(base_to_upper|upper_to_middle|middle_to_lower)_joint_\d+"
#: Fingertip bodies in ManiSkill's order (``tip_link_names``).
TIP_LINKS = tuple(f"finger_tip_link_{n}" for n in FINGER_ANGLES)
#: Each finger's links (base to tip).
FINGERS = tuple(
    (f"finger_upper_link_{n}", f"finger_middle_link_{n}", f"finger_lower_link_{n}", f"finger_tip_link_{n}")
    for n in FINGER_ANGLES
)
#: The hub the fingers hang from, and its height above ``base_link`` (m).
HUB = "upper_holder_link"
HUB_HEIGHT = 0.29

#: The makers' gains per finger joint (upper, middle, lower): kp (N*m/rad), kd
#: (N*m*s/rad); the motors' torque (N*m) and velocity (rad/s) limits.
STIFFNESS = (15.0, 15.0, 9.0)
DAMPING = (0.5, 1.0, 0.5)
EFFORT_LIMIT = 0.396
VELOCITY_LIMIT = 10.0
#: Reflected rotor inertia (kg*m^2), an estimate (see the module doc).
ARMATURE = 8e-4
TRIFINGER_DRIVES = PDActuator(
    joints=JOINT_PATTERN,
    stiffness=STIFFNESS * 3,
    damping=DAMPING * 3,
    effort_limit=EFFORT_LIMIT,
    velocity_limit=VELOCITY_LIMIT,
    armature=ARMATURE,
)
#: ManiSkill's ``pd_joint_vel`` bound (rad/s).
VEL_MODE_BOUND = 1.0

#: The makers' default pose per finger (rad): upper, middle, lower.
REST_FINGER = (0.0, 0.9, -1.7)
REST = REST_FINGER * 3

#: The grasp's cube: the weight of the makers' cube (65 mm at 291.3 kg/m^3: 80 g; the
#: ``cube_multicolor_rrc.urdf`` shipped with ManiSkill's TriFinger assets) at the
#: library's cube density (water's): 43 mm, 79.5 g; on the fingers' axis, resting on the
#: arena floor (its centre half an edge up: 0.2685 m below the hub).
GRASP_CUBE_EDGE = 0.043
GRASP_CUBE_CENTRE = (0.0, 0.0, -(HUB_HEIGHT - 0.5 * GRASP_CUBE_EDGE))
#: Open and closed per finger (rad): the tip's centre at the cube's centre height, in
#: its finger base frame's x = 0 plane (the finger turned about its upper joint until
#: the tip is over the axis' radial line), 59 mm from the axis (open: 27.5 mm off the
#: cube's faces) and 21.5 mm from it (closed: 10 mm into the cube, so the drives press
#: with kp times the remaining error). Solved from the URDF chain (tests/test_trifinger.py
#: checks the tips' positions).
OPEN_FINGER = (0.326, 0.6847, -1.3026)
CLOSED_FINGER = (0.326, 0.53, -1.287)
OPEN = OPEN_FINGER * 3
CLOSED = CLOSED_FINGER * 3
POWER_GRASP = PowerGrasp(
    link=HUB,
    cube_centre=GRASP_CUBE_CENTRE,
    cube_edge=GRASP_CUBE_EDGE,
    outward=(0.0, 0.0, -1.0),
)

TRIFINGER_HAND = Hand(
    name="hand",
    joints=JOINT_PATTERN,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    max_velocity=VEL_MODE_BOUND,
    power_grasp=POWER_GRASP,
)

#: Fingertip pads (ManiSkill's dynamic friction of its tip material).
TIP_PAD = FrictionMaterial(sliding=1.0, torsional=0.01, rolling=0.0001)
#: The damping ratio of the tips' contact (solref 0.01 s; the model's ``tf_tip`` class):
#: overdamped, so that a tip pressed by a saturated drive rests (see the module doc).
TIP_DAMPING_RATIO = 4.0


@register_agent()
class TriFingerPro(Agent):
    """TriFinger Pro: three fingers on a hub 0.29 m above the arena floor (``base_link``).

    qpos order: :data:`JOINTS` (fingers 0, 120, 240; upper, middle, lower each).
    Fingertip bodies: :data:`TIP_LINKS` (their origin is the tip hemisphere's centre).
    """

    uid = "trifingerpro"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 trifingerpro``,
    #: 2026-11-29 20:32-20:33 UTC, 20 Hz control, with the overdamped tips): every claim
    #: holds from 6.25 ms (160 Hz) down to 1 ms (random-action overshoot 0.009-0.045 rad,
    #: bound 0.25; settle 3.2e-4 rad/s at 160 Hz, 3.4e-5 at 200 Hz, bound 0.05; the
    #: pinch's slip 0.27-0.28 mm, bound 2; deepest contact 0.064 mm); at 100 Hz and
    #: coarser settle fails (1.4-5.7 rad/s). Default one tried step finer: 200 Hz (5 ms),
    #: where a tip pressed on a fixed block rests (tests/test_pad_press.py).
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = ASSETS / "trifingerpro.xml"
    actuators = (TRIFINGER_DRIVES,)
    parts = (TRIFINGER_HAND,)
    link_materials = {tip: TIP_PAD for tip in TIP_LINKS}
    keyframes = {
        "rest": Keyframe(qpos=dict(zip(JOINTS, REST, strict=True))),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "CLOSED",
    "FINGERS",
    "GRASP_CUBE_CENTRE",
    "GRASP_CUBE_EDGE",
    "HUB",
    "JOINTS",
    "OPEN",
    "POWER_GRASP",
    "REST",
    "TIP_DAMPING_RATIO",
    "TIP_LINKS",
    "TRIFINGER_DRIVES",
    "TRIFINGER_HAND",
    "TriFingerPro",
]
