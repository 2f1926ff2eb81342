"""ANYbotics ANYmal C (uid ``anymal_c``): a quadruped whose legs carry a free base.

Sources of the numbers:
- Names, kinematics, joint ranges, masses and inertias: MuJoCo Menagerie's
  ``anybotics_anymal_c/anymal_c.xml`` (read as data; derived by Menagerie from ANYbotics'
  public ``anymal_c_simple_description`` URDF). Bodies ``base``, ``{LF,RF,LH,RH}_HIP``,
  ``_THIGH``, ``_SHANK``; joints ``_HAA`` (about x), ``_HFE`` and ``_KFE`` (about y at the
  zero pose), with Menagerie's (the URDF's) signs and zero pose, so that ManiSkill's and
  Isaac Lab's joint angles mean the same here. Our body frames are parallel to the base's
  at the zero pose (Menagerie keeps the URDF's rotated joint frames); joint origins, axes,
  centres of mass and inertia tensors are Menagerie's re-expressed in them (the joint-space
  mass matrix agrees with Menagerie's to 1e-6 at random poses; ``assets/anymal_c.xml`` has
  the offsets). HAA -0.72..0.49 rad (left legs) / -0.49..0.72 (right); HFE and KFE
  +-9.42478 rad. Masses: base 19.2035 kg, hip 2.781, thigh 3.071, shank 0.58842 (with the
  URDF's foot): 44.965 kg in all. Foot: the URDF's ``FOOT`` frame (site ``<leg>_FOOT``) at
  (+-0.08795, +-0.01305, -0.33797) m in the shank, a 0.03 m sphere 0.0225 m above it,
  friction 0.8, condim 3 (Menagerie's foot class, friction 0.8 / 0.02 / 0.01 at condim
  6, without its torsional and rolling friction: the standing robot's base creeps 0.22 mm
  from 1 s to 5 s either way, and standing while its legs move it runs 1.5x as many
  control steps per second, 1535 against 996; `python benchmarks/legged_contacts.py
  anymal_c`, 2026-11-28 01:46 UTC; the sweep's claims hold from 320 Hz as before; its
  softened foot ``solimp`` is not taken: MuJoCo's default contact).
- Contacts: Menagerie's ``<option cone="elliptic" impratio="100"/>``, declared as
  ``friction_cone`` / ``impratio`` (a scene with this robot uses them). With MuJoCo's
  default pyramidal cone and impratio 1 the feet creep outwards under the standing robot
  (soft friction under a steady sideways load: 6 mm from 1 s to 5 s of standing at our
  gains, 0.5 mm with the elliptic cone; 0.22 m in 5 s at ManiSkill's gains, the belly
  coming down to 0.31 m; ``tests/test_anymal_c.py``). Self-collisions stay on, except base / thighs
  (Menagerie's exclusions: the HFE drives sit against the base); ManiSkill turns them off.
- Constraint Jacobian: sparse (declared: ``jacobian``). Its scene steps 1.14-1.30x as
  fast as with MuJoCo's choice for 18 degrees of freedom (dense), the same physics up to
  rounding: nearly all of the step is the constraint solve under the elliptic cone with
  impratio 100 (54 of 79 µs a physics step standing, MuJoCo's timers). Measured on
  recorded controls: ``python benchmarks/sim_options.py anymal_c --variants "as
  built,jacobian sparse" --blocks 15 --clock cpu`` 1.32 (``pd_joint_delta_pos``, the legs
  folded, 2026-11-29 20:37 UTC); standing (``pd_joint_target_delta_pos``) 1.14 and
  ``pd_joint_pos`` 1.16 (a replay of 100 control steps, 20:40 UTC). No other robot gains
  (the other legged robots 0.92-0.97: ``benchmarks/sim_options.py``, docs/benchmarks.md).
- Drives: position PD on every joint, effort limit 80 N*m and velocity limit 7.5 rad/s:
  ANYbotics' own ``anymal_c_simple_description`` URDF (``urdf/anymal.urdf``, commit
  87b68511: ``effort="80.0"``, ``velocity="7.5"`` on all 12 joints; Menagerie's
  ``forcerange`` 80, after the ANYdrive's specification in Hutter et al. 2017, doi
  10.1080/01691864.2017.1378591; Isaac Lab's ``ANYDRIVE_3_SIMPLE_ACTUATOR_CFG`` has the
  same 80 N*m and 7.5 rad/s, where 7.5 is its DC-motor model's zero-torque speed, with
  120 N*m at stall); joint friction 0.1 N*m (Menagerie's ``frictionloss``: the drives'
  torque resolution); no armature: the URDF has no rotor inertia (its drives are 2.04 kg
  housings fixed to the parent links, ``<dynamics damping="0" friction="0"/>``),
  Menagerie adds none, Isaac Lab's ``anymal.py`` sets none, and no rotor inertia or gear
  ratio is published, so the light shanks whip at up to about 230 rad/s under random
  absolute targets. Joint limits are stiff (``solreflimit`` 0.005 s; at MuJoCo's 0.02 s
  random absolute targets pushed HAA 0.6-0.8 rad past its stop).
- Gains: kp 400 N*m/rad, kv 10 N*m*s/rad (ours). ManiSkill's kp 80 / kv 2 (force limit
  100) carry only the base there (ManiSkill switches gravity off on the leg links); here,
  where the 25.8 kg of legs weigh too, they let the knees give 0.17 rad (base 0.512 m) with
  the elliptic cone, and the robot sinks to its belly under MuJoCo's default cone. Menagerie's
  kp 100 with joint damping 1: 0.136 rad. Five times ManiSkill's kp at its kv / kp
  (25 ms) holds the standing pose within 0.05 rad: the legs give 0.026 rad (KFE; max 0.042
  while landing), the base settles at 0.538 m and stays within 0.3 mm.
- Keyframes: ``standing`` (the default reset): ManiSkill's (root at 0.545 m; HAA
  +-0.03, HFE +-0.4, KFE -+0.8 rad; the feet 2.3 mm above the floor); ``rest`` (where tasks
  reset a robot) is the same pose. Menagerie's model has no keyframe.
- Control: one ``Legs`` part over the 12 joints in ManiSkill's action order (the four HAA,
  the four HFE, the four KFE); deltas within +-0.225 rad (ManiSkill's
  ``pd_joint_delta_pos``). Default mode ``pd_joint_target_delta_pos``: ManiSkill's
  normalized deltas, added to the previous target; ManiSkill's default,
  ``pd_joint_delta_pos`` (deltas on the measured pose), lets loaded legs fold at a zero
  action (each step's target follows the sag: the base is on the floor within 5 s), as
  do the velocity modes; absolute and target modes stand.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Legs
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

LEGS = ("LF", "RF", "LH", "RH")
#: ManiSkill's joint (action) order: the four HAA, the four HFE, the four KFE.
LEG_JOINTS = tuple(f"{leg}_{joint}" for joint in ("HAA", "HFE", "KFE") for leg in LEGS)
LEG_PATTERNS = ("(LF|RF|LH|RH)_HAA", "(LF|RF|LH|RH)_HFE", "(LF|RF|LH|RH)_KFE")
#: ManiSkill's ``standing`` keyframe: joint angles (rad) in :data:`LEG_JOINTS` order.
STANDING_QPOS = (0.03, -0.03, 0.03, -0.03, 0.4, 0.4, -0.4, -0.4, -0.8, -0.8, 0.8, 0.8)
#: ManiSkill's ``standing`` root height (m).
STANDING_HEIGHT = 0.545

ANYMAL_DRIVES = PDActuator(
    joints="(LF|RF|LH|RH)_(HAA|HFE|KFE)",
    stiffness=400.0,
    damping=10.0,
    effort_limit=80.0,
    velocity_limit=7.5,
    friction=0.1,
)
ANYMAL_LEGS = Legs(name="legs", joints=LEG_PATTERNS, max_delta=0.225)


def _standing() -> Keyframe:
    return Keyframe(qpos=dict(zip(LEG_JOINTS, STANDING_QPOS, strict=True)), base_pos=(0.0, 0.0, STANDING_HEIGHT))


@register_agent()
class AnymalC(Agent):
    """ANYbotics ANYmal C: 12 position-driven leg joints carrying a free base.

    qpos order (model order): ``LF``, ``RF``, ``LH``, ``RH`` x ``HAA``, ``HFE``, ``KFE``;
    actions follow ManiSkill's order (:data:`LEG_JOINTS`).
    """

    uid = "anymal_c"
    #: Time-step sweep (``robot-agents check anymal_c --sweep``, 2026-11-23 18:30 UTC, 20 Hz
    #: control; docs/timestep.md): every claim holds at every step from 3.125 ms (320 Hz)
    #: down to 1 ms (standing: the base still to 0.22 mm; hold 0.0003 rad after settling;
    #: random-action overshoot 0.11-0.21 rad, HAA; settle 0.004-0.016 rad/s; penetration
    #: 2.7-4.5 mm). At 200 Hz the hold drifts 0.013 rad, random actions push HAA 0.40 rad
    #: past its stop, settle 0.95 rad/s, the feet press 7 mm into the floor; at 160 Hz the
    #: base moves 6 cm while standing; from 100 Hz down MuJoCo goes unstable. Default one
    #: tried step finer than 320 Hz: 400 Hz (margin: 2.5 ms against 3.125 ms). Rerun
    #: 2026-11-29 20:37-20:44 UTC with the sparse Jacobian (``python
    #: benchmarks/timestep_sweep.py anymal_c``; and ``--substeps 16,20 --seeds 0,...,9``
    #: with either Jacobian): random actions push a hip 0.392 rad past its stop at 320 Hz
    #: (ten seeds, dense: 0.256; both over the bound), 0.17-0.22 from 400 Hz; so 400 Hz is
    #: the largest passing step itself, no margin step (the 320 Hz pass was three seeds' luck).
    sim_freq: ClassVar[int | None] = 400
    mjcf_path = ASSETS / "anymal_c.xml"
    fix_root_link = False
    actuators = (ANYMAL_DRIVES,)
    parts = (ANYMAL_LEGS,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {"standing": _standing(), "rest": _standing()}
    default_control_mode = "pd_joint_target_delta_pos"
    friction_cone = "elliptic"
    impratio = 100.0
    jacobian = "sparse"


__all__ = ["ANYMAL_DRIVES", "ANYMAL_LEGS", "LEG_JOINTS", "STANDING_HEIGHT", "STANDING_QPOS", "AnymalC"]
