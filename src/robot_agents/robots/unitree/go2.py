"""Unitree Go2 quadruped (uid ``unitree_go2``, ManiSkill's), standing on its own legs.

Sources of the numbers:
- Names, kinematics, joint ranges, link masses and inertias: MuJoCo Menagerie's
  ``unitree_go2/go2.xml`` (read as data), whose names are Unitree's URDF names
  (``unitree_ros/robots/go2_description``): links ``base``, ``{FL,FR,RL,RR}_hip / _thigh
  / _calf / _foot``, joints ``*_hip_joint`` (abduction, about x, +-1.0472 rad),
  ``*_thigh_joint`` (about y, front -1.5708..3.4907, rear -0.5236..4.5379 rad) and
  ``*_calf_joint`` (knee, about y, -2.7227..-0.83776 rad). Hips at (+-0.1934, +-0.0465,
  0) m in the base, thighs 0.0955 m outwards, thigh and calf 0.213 m long; the foot
  sphere (r 0.022 m) 2 mm behind the calf's end. See ``assets/go2.xml``.
- Masses: Menagerie's link inertials: base 6.921 kg, hip 0.678, thigh 1.152, calf (with
  the foot) 0.241352 kg per leg; 15.206 kg in all. Unitree's own URDF sums to 15.02 kg
  (its calf 0.154 + foot 0.04 kg; 16.09 kg since it added three 0.089 kg rotor links
  per leg, commit a615577, 2024-09-11); about 15 kg is the Go2's commonly listed weight
  (e.g. the ros-claw unitree-sdk2-mcp robot table; Unitree's own spec page was not
  among the sources we could read).
- Drives: position PD per joint with Unitree's standing gains (unitree_sdk2's
  ``example/go2/go2_stand_example.cpp``, read at commit 21d0a3b: Kp 60 N*m/rad, Kd 5
  N*m*s/rad on every joint, which it uses to stand at hip 0, thigh 0.67, calf -1.3 rad;
  unitree_mujoco's ``example/python/stand_go2.py`` stands its simulated Go2 with Kp 50,
  Kd 3.5;
  ManiSkill's ``unitree_go2.py`` has kp 1000, kv 100, which in MuJoCo need a 4 kHz step:
  see :data:`UNITREE_KP`); effort limits Menagerie's actuator ranges
  (hip and thigh +-23.7 N*m; knee +-45.43 N*m), the same as Unitree's URDF
  (``unitree_ros`` ``go2_description.urdf``; its knee has been 45.43 N*m and 15.70 rad/s
  since commit 79f054e, 2023-10-11, "modify knee joint info", before it 35.55 N*m and
  20.07 rad/s); velocity limits Unitree's URDF (30.1 rad/s hip and thigh, 15.70 rad/s
  knee; until 2026-11-29 we had the old knee's 20.07, docs/notes/robot-facts-audit.md);
  armature 0.01 kg*m^2 and frictionloss 0.2 N*m per joint, and the joints' passive
  damping 2 N*m*s/rad (in the MJCF), Menagerie's (Unitree's own ``unitree_mujoco``
  ``unitree_robots/go2/go2.xml``, commit c598f10: the same armature, frictionloss and
  actuator ranges, joint damping 0.1). No gravity compensation:
  the legs carry the robot's weight (ManiSkill switches gravity off on the leg links).
- Action order: ManiSkill's ``active_joints`` of Unitree's URDF, a breadth-first walk
  of the tree: the four hips, then the four thighs, then the four calves, each in the
  URDF's leg order FL, FR, RL, RR (so its ``standing`` qpos reads 0 x 4, 0.9 x 4,
  -1.8 x 4). Our ``Legs`` part lists its patterns in that order, so actions match
  ManiSkill's; ``qpos`` is in MuJoCo's model order, leg by leg (FL hip, thigh, calf,
  FR ..., RL ..., RR ...): :data:`LEG_JOINTS` and :data:`ACTION_JOINTS`.
- Modes: the six joint modes generated from the ``Legs`` part, deltas bounded by
  ManiSkill's +-0.7 rad per step (its ``pd_joint_delta_pos``). The default is
  ManiSkill's ``pd_joint_pos``: its hold (the keyframe's targets, repeated) keeps the
  robot standing. ManiSkill's first mode, ``pd_joint_delta_pos``, retargets the
  measured pose every control step, so under the robot's weight a zero action lets the
  legs sink by the drives' steady-state error each step (6 cm in 3 s here; the same in
  ManiSkill); ``pd_joint_target_delta_pos`` keeps its targets and stands.
- Keyframes: ``rest`` (the default reset, where tasks start) and ``standing`` are
  ManiSkill's ``standing``: root at 0.29 m, hips 0, thighs 0.9, calves -1.8 rad (the
  feet 1.6 mm above the floor). ``home`` is Menagerie's: the same joint angles with the
  root at 0.27 m, where Menagerie's soft feet sink into the floor; our rigid feet would
  be 18 mm below it, so ``home`` puts the root where they touch (0.2885 m).
- Standing: the legs give 0.12 rad (knees) under the 15.2 kg while settling onto the
  floor at Unitree's gains (Unitree's own stand sags alike), then hold still: the base
  level, on its four feet.
- Feet: Menagerie's foot contact (friction 0.8) at condim 3, without its torsional
  (0.02) and rolling (0.01) friction: standing, the base creeps 1.77 mm from 1 s to 5 s
  (1.83 with them), and standing while its legs move it runs 4171 control steps/s
  against 3483 (`python benchmarks/legged_contacts.py unitree_go2`, 2026-11-28 01:46
  UTC); the sweep's claims hold from 320 Hz as before.
  ManiSkill's foot material (friction 2.0) is PhysX's; Menagerie's is MuJoCo's.
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

LEGS = ("FL", "FR", "RL", "RR")
#: The leg joints in qpos (model) order: leg by leg.
LEG_JOINTS = tuple(f"{leg}_{j}_joint" for leg in LEGS for j in ("hip", "thigh", "calf"))
#: The leg joints in action order (ManiSkill's): hips, thighs, calves.
ACTION_PATTERNS = tuple(f"(FL|FR|RL|RR)_{j}_joint" for j in ("hip", "thigh", "calf"))
ACTION_JOINTS = tuple(f"{leg}_{j}_joint" for j in ("hip", "thigh", "calf") for leg in LEGS)
#: ManiSkill's standing pose (rad): hip, thigh, calf, the same on every leg.
STANDING_LEG = (0.0, 0.9, -1.8)
#: ManiSkill's standing root height (m).
STANDING_HEIGHT = 0.29
#: The root height at which the feet touch the floor in the standing pose (m): the
#: soles 0.288372 m below the root, so 0.1 mm clear.
TOUCHING_HEIGHT = 0.2885
#: ManiSkill's delta bound of pd_joint_delta_pos (rad per step).
MAX_DELTA = 0.7

#: Unitree's joint gains for standing (N*m/rad, N*m*s/rad): ``Kp = 60.0``, ``Kd = 5.0`` in
#: unitree_sdk2's ``example/go2/go2_stand_example.cpp`` (the low-level stand of the real
#: robot). ManiSkill's kp 1000 / kv 100 need a physics step of 4 kHz in MuJoCo (below
#: 2.5-3.6 kHz the drives bang between their torque limits: kv over these joints'
#: 0.013-0.019 kg*m^2); PhysX integrates its drives implicitly, limits included.
UNITREE_KP = 60.0
UNITREE_KD = 5.0
#: The real motors close ``tau = kp (q* - q) + kd (dq* - dq) + tau_ff`` (unitree_sdk2's
#: low-level command, the fields ``kp``, ``kd``, ``q``, ``dq``, ``tau`` of ``MotorCmd``)
#: and nothing more, so the joints' own damping (2 N*m*s/rad in the MJCF) is not fed
#: forward: a velocity target is met at kd / (kd + b) = 5/7 of it, as on the robot.
#: (Fed forward, random velocity targets also pushed a calf 0.25-0.31 rad past its limit
#: at 320-400 Hz, against 0.19-0.21: the time-step sweep of 2026-11-29, docs/timestep.md.)
UNITREE_DAMPING_FEEDFORWARD = False
#: Hip and thigh drives, and the knees' (stronger): Unitree's gains, Menagerie's efforts.
GO2_HIP_THIGH_DRIVES = PDActuator(
    joints=ACTION_PATTERNS[:2],
    stiffness=UNITREE_KP,
    damping=UNITREE_KD,
    effort_limit=23.7,
    velocity_limit=30.1,
    armature=0.01,
    friction=0.2,
    damping_feedforward=UNITREE_DAMPING_FEEDFORWARD,
)
GO2_KNEE_DRIVES = PDActuator(
    joints=ACTION_PATTERNS[2],
    stiffness=UNITREE_KP,
    damping=UNITREE_KD,
    effort_limit=45.43,
    velocity_limit=15.70,
    armature=0.01,
    friction=0.2,
    damping_feedforward=UNITREE_DAMPING_FEEDFORWARD,
)
GO2_LEGS = Legs(name="legs", joints=ACTION_PATTERNS, max_delta=MAX_DELTA)


def _standing(height: float) -> Keyframe:
    hip, thigh, calf = STANDING_LEG
    return Keyframe(
        qpos={ACTION_PATTERNS[0]: hip, ACTION_PATTERNS[1]: thigh, ACTION_PATTERNS[2]: calf},
        base_pos=(0.0, 0.0, height),
    )


@register_agent()
class UnitreeGo2(Agent):
    """Unitree Go2: a free-floating base on four 3-joint legs under PD control.

    qpos order (model): ``FL_hip_joint, FL_thigh_joint, FL_calf_joint, FR_..., RL_...,
    RR_...``; action order (ManiSkill's): the hips, thighs and calves of FL, FR, RL, RR.
    """

    uid = "unitree_go2"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py unitree_go2``, seeds 0-2,
    #: 20 Hz control, 2026-11-23 with the standing claim; docs/timestep.md): every claim
    #: holds from 320 Hz to 1 kHz; at 200 Hz random actions push a calf 0.27 rad past its
    #: limit (bound 0.25). Default 400 Hz, one tried step finer. The drives cannot bang
    #: between their torque limits above 37 Hz (``tuning.cycles``, the calves). With the
    #: knee's velocity limit at Unitree's 15.70 rad/s (2026-11-29 07:58 UTC rerun,
    #: docs/timestep-sweep.md) every claim holds from 200 Hz (random 0.227 rad there);
    #: the default stays 400 Hz.
    sim_freq: ClassVar[int | None] = 400
    mjcf_path = ASSETS / "go2.xml"
    fix_root_link = False
    gravity_compensation = False
    actuators = (GO2_HIP_THIGH_DRIVES, GO2_KNEE_DRIVES)
    parts = (GO2_LEGS,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "rest": _standing(STANDING_HEIGHT),
        "standing": _standing(STANDING_HEIGHT),
        "home": _standing(TOUCHING_HEIGHT),
    }
    default_control_mode = "pd_joint_pos"


#: The bodies of ManiSkill's ``go2_description_simplified_locomotion.urdf`` that keep a
#: collision shape: the base (with the head, whose URDF links ``Head_upper`` and
#: ``Head_lower`` are fixed to it; our head's cylinder and sphere are on ``base``), the
#: thighs and the feet. The hips' motor cylinders and the calves' two cylinders collide
#: no more.
SIMPLIFIED_COLLISION_LINKS = ("base", *(f"{leg}_{link}" for leg in LEGS for link in ("thigh", "foot")))


@register_agent()
class UnitreeGo2Simplified(UnitreeGo2):
    """Unitree Go2 with ManiSkill's simplified collision model for locomotion (uid
    ``unitree_go2_simplified_locomotion``, ManiSkill's ``UnitreeGo2Simplified``): our
    ``unitree_go2`` whose contacts are those of the base (with the head), the thighs and
    the feet, as ManiSkill 3.0.1's ``go2_description_simplified_locomotion.urdf`` (read
    as data) keeps them; the hips and calves are drawn only.

    What differs from the peer: the shapes are our Go2's (Menagerie's primitives), which
    ManiSkill's simplified URDF also has on these links (the base box 0.3762 x 0.0935 x
    0.114 m, the head's cylinder r 0.05 m and sphere r 0.047 m, the thigh boxes 0.213 x
    0.0245 x 0.034 m, the foot spheres r 0.022 m): the simplification removes the same
    links' shapes, as in ManiSkill (where the full model's are the same primitives too).
    Everything else (drives, keyframes, modes) is ``unitree_go2``'s, as ManiSkill's
    variant changes only the URDF; its physics step is its own sweep's (320 Hz, below).
    """

    uid = "unitree_go2_simplified_locomotion"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
    #: unitree_go2_simplified_locomotion unitree_h1_simplified``, 2026-11-29 18:33-18:35
    #: UTC, seeds 0-2, 20 Hz control; docs/timestep-sweep.md): every claim holds from 200
    #: Hz, as the full Go2's (hold, standing and penetration the same to the digit: it
    #: stands on its feet alone; random 0.224 rad at 200 Hz, the full Go2's 0.227). With
    #: ten random-action seeds it still passes at 200 Hz (20:42-20:48 UTC, docs/timestep.md;
    #: the full Go2 then needs 320). Default 320 Hz, one tried step finer (2026-11-29; the
    #: full Go2's 400 Hz before): with the ten seeds every claim holds there
    #: (``--substeps 16 --seeds 0,...,9``, 22:36 UTC: hold 0.00705 rad, random 0.177 rad,
    #: standing 1.8 mm, deepest contact 3.8 mm).
    sim_freq: ClassVar[int | None] = 320
    collision_links = SIMPLIFIED_COLLISION_LINKS


__all__ = [
    "ACTION_JOINTS",
    "LEG_JOINTS",
    "MAX_DELTA",
    "SIMPLIFIED_COLLISION_LINKS",
    "STANDING_HEIGHT",
    "STANDING_LEG",
    "TOUCHING_HEIGHT",
    "UNITREE_KD",
    "UNITREE_KP",
    "UnitreeGo2",
    "UnitreeGo2Simplified",
]
