"""Unitree H1 humanoid (uid ``unitree_h1``, ManiSkill's): 19 joints on a free pelvis,
standing on its own legs under PD control.

Sources of the numbers:
- Kinematics, link masses and inertias (principal axes as given), joint ranges and the
  collision primitives but the feet: MuJoCo Menagerie's ``unitree_h1/h1.xml`` (read as
  data; Menagerie derived it from Unitree's URDF). Total mass 51.437 kg (Unitree's
  specification: about 47 kg, "Total Weight ~ 47kg", as reproduced from unitree.com/h1
  at drl-test.github.io/posts/humanoid-demo-porting-cpg-to-unitree-h1; the newer
  ``unitree_ros`` URDF's links weigh more again: we keep Menagerie's). See
  ``assets/h1.xml`` for the joint origins.
- Names: the body (link) names are Menagerie's and Unitree's URDF's; the joint names are
  Unitree's URDF's (``unitree_ros/robots/h1_description/urdf/h1.urdf``) and ManiSkill's
  (``left_hip_yaw_joint``; Menagerie writes ``left_hip_yaw``). The action order of every
  mode is ManiSkill's ``UnitreeH1.body_joints`` (:data:`MANISKILL_JOINTS`).
- Feet: Unitree's URDF collision box, 0.28 x 0.03 x 0.024 m centred 0.05 m ahead of and
  0.05 m below the ankle axis: ManiSkill's model's flat foot; its sole lies 0.062 m below
  the ankle, so ManiSkill's ``standing`` pelvis height (0.975 m) puts it 1.9 mm above the
  floor. (Menagerie's three 14 mm capsules reach 0.070 m down and only 3.5 cm behind the
  ankle: the centre of mass, 1.1 cm behind the ankle, stood 2.4 cm from their heel and the
  robot tipped over backwards within 2 s, with ManiSkill's gains and with ours.)
- Joint limits: stiff (``solreflimit`` 5 ms): the H1's are mechanical stops, and with
  MuJoCo's default 20 ms the 300 N*m knee drives pressed 0.27-0.35 rad past them under
  random actions at every step (now 0.05-0.18 rad, bound 0.25).
- Effort and velocity limits: Unitree's URDF (``effort``, ``velocity``; Menagerie's motor
  ``ctrlrange`` has the same efforts): hips and torso 200 N*m, 23 rad/s; knees 300 N*m,
  14 rad/s; ankles 40 N*m, 9 rad/s; shoulder pitch and roll 40 N*m, 9 rad/s; shoulder
  yaw and elbow 18 N*m, 20 rad/s. (Unitree's specification gives peak torques of about
  360 N*m at the knee, 220 at the hip, 59 at the ankle, 75 at the arm: the URDF's are
  the rated values a model should hold.)
- Armature 0.1 kg*m^2 and joint damping 1 N*m*s/rad on every joint: Menagerie's class
  ``h1``.
- Gains: ManiSkill's ``body_stiffness`` 1000 N*m/rad and ``body_damping`` 100 N*m*s/rad
  for the torso, ankles' damping and the arms. The legs need more: with 1000 on every
  joint (ManiSkill's), the standing load (knees 42.5 N*m, hip roll 23 N*m, ankles 5 N*m)
  bends the knees 0.056 rad, the pelvis leans back 6.5 deg and sinks 1.9 cm, on its heels.
  Menagerie's H1 has torque motors (no position gains) to take instead, and Unitree's
  own low-level stand (unitree_sdk2 ``example/h1/low_level/humanoid.hpp``, commit
  21d0a3b: kp 200 / kd 5 on hips, knees and torso, kp 60 / kd 1.5 on ankles and arms,
  towards hip pitch -0.5, knee 1.0, ankle -0.5, shoulder pitch 0.4 rad) would let the
  knees' 42.5 N*m standing load bend them 0.21 rad, so the leg gains are ours, set by
  one rule: each joint gives at most about 5 mrad under the standing load:
  hips and knees kp 10000 N*m/rad (knee 4.2 mrad), ankles kp 2000 N*m/rad (2.3 mrad),
  damping 100 N*m*s/rad as ManiSkill's. The pelvis then leans 0.76 deg and settles 4.2 mm
  below the keyframe (1.9 mm of it the drop to the floor). No gravity is compensated.
- Keyframes: ``standing`` is ManiSkill's (pelvis at 0.975 m; hip pitch -0.4, knee 0.8,
  ankle -0.4 rad, every other joint 0), the default reset; ``rest`` (what tasks reset to)
  is the same pose; ``home`` is Menagerie's (scene.xml: the same joint angles, pelvis at
  0.98 m, the soles 6.9 mm above the floor).
- Parts: ``legs`` (both legs, not held: they carry the robot), ``torso`` and the two
  arms (no end effectors: the H1's arms end in bare forearms; the model has no tool frame).
- Control modes: the six joint modes of :func:`~robot_agents.controllers.rules.joint_control_modes`
  over the whole body in ManiSkill's order (one part, ``body``, as ManiSkill's), the delta
  bound ManiSkill's 0.2 rad, the velocity bounds the URDF's; ``pd_joint_pos`` (ManiSkill's
  first) is the default. They are declared, not generated from the parts: a generated
  table takes the first arm as its main part and gives every other part (the legs)
  deltas from the measured pose in every mode, ``pd_joint_pos`` included, in which the
  robot folds up under the hold action (pelvis 0.975 -> 0.076 m in 2 s), and its action
  order would not be ManiSkill's. In the modes whose zero action re-targets the measured
  pose (``pd_joint_delta_pos``, ``pd_joint_vel``, ``pd_joint_delta_pos_vel``) the loaded
  legs give at every step, as ManiSkill's H1 does in its ``pd_joint_delta_pos``.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Arm, Legs, Torso
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

LEG_PATTERN = "(left|right)_(hip_yaw|hip_roll|hip_pitch|knee|ankle)_joint"
TORSO_JOINT = "torso_joint"
LEFT_ARM_PATTERN = "left_(shoulder_pitch|shoulder_roll|shoulder_yaw|elbow)_joint"
RIGHT_ARM_PATTERN = "right_(shoulder_pitch|shoulder_roll|shoulder_yaw|elbow)_joint"
#: ManiSkill's ``UnitreeH1.body_joints``: the action order of every mode.
MANISKILL_JOINTS = (
    "left_hip_yaw_joint",
    "right_hip_yaw_joint",
    "torso_joint",
    "left_hip_roll_joint",
    "right_hip_roll_joint",
    "left_shoulder_pitch_joint",
    "right_shoulder_pitch_joint",
    "left_hip_pitch_joint",
    "right_hip_pitch_joint",
    "left_shoulder_roll_joint",
    "right_shoulder_roll_joint",
    "left_knee_joint",
    "right_knee_joint",
    "left_shoulder_yaw_joint",
    "right_shoulder_yaw_joint",
    "left_ankle_joint",
    "right_ankle_joint",
    "left_elbow_joint",
    "right_elbow_joint",
)
#: Hip pitch, knee and ankle angles (rad) of ManiSkill's ``standing`` and Menagerie's
#: ``home``; every other joint 0.
STANDING_LEG = (-0.4, 0.8, -0.4)
#: Pelvis heights (m): ManiSkill's ``standing`` and Menagerie's ``home``.
STANDING_HEIGHT = 0.975
HOME_HEIGHT = 0.98

#: ManiSkill's body_stiffness (N*m/rad) and body_damping (N*m*s/rad).
MANISKILL_KP, MANISKILL_KV = 1000.0, 100.0
#: Our leg stiffnesses (N*m/rad): each joint gives at most about 5 mrad under the
#: standing load (see the module doc).
HIP_KNEE_KP, ANKLE_KP = 10000.0, 2000.0
#: Menagerie's class ``h1`` (kg*m^2).
ARMATURE = 0.1
#: Unitree's URDF limits per joint kind: (effort N*m, velocity rad/s).
LIMITS = {
    "hip_yaw": (200.0, 23.0),
    "hip_roll": (200.0, 23.0),
    "hip_pitch": (200.0, 23.0),
    "knee": (300.0, 14.0),
    "ankle": (40.0, 9.0),
    "torso": (200.0, 23.0),
    "shoulder_pitch": (40.0, 9.0),
    "shoulder_roll": (40.0, 9.0),
    "shoulder_yaw": (18.0, 20.0),
    "elbow": (18.0, 20.0),
}


def joint_kind(joint: str) -> str:
    """``left_hip_yaw_joint`` -> ``hip_yaw``."""
    return joint.removesuffix("_joint").removeprefix("left_").removeprefix("right_")


def _drive(kinds: tuple[str, ...], stiffness: float) -> PDActuator:
    """One PD drive declaration for the joints of ``kinds`` on both sides (or the torso),
    with the URDF's limits (all kinds in one declaration share them)."""
    effort, speed = LIMITS[kinds[0]]
    names = "|".join(kinds)
    pattern = TORSO_JOINT if kinds == ("torso",) else f"(left|right)_({names})_joint"
    return PDActuator(
        joints=pattern,
        stiffness=stiffness,
        damping=MANISKILL_KV,
        effort_limit=effort,
        velocity_limit=speed,
        armature=ARMATURE,
    )


H1_DRIVES = (
    _drive(("hip_yaw", "hip_roll", "hip_pitch"), HIP_KNEE_KP),
    _drive(("knee",), HIP_KNEE_KP),
    _drive(("ankle",), ANKLE_KP),
    _drive(("torso",), MANISKILL_KP),
    _drive(("shoulder_pitch", "shoulder_roll"), MANISKILL_KP),
    _drive(("shoulder_yaw", "elbow"), MANISKILL_KP),
)

#: The whole body in ManiSkill's order; ManiSkill's delta bound (rad per step).
H1_BODY = JointGroup(
    MANISKILL_JOINTS,
    max_delta=0.2,
    max_velocity=tuple(LIMITS[joint_kind(j)][1] for j in MANISKILL_JOINTS),
)
H1_MODES: dict[str, ModeConfig] = {mode: {"body": config} for mode, config in joint_control_modes(H1_BODY).items()}


def standing_keyframe(height: float) -> Keyframe:
    """The standing pose with the pelvis ``height`` m above the floor, level."""
    hip_pitch, knee, ankle = STANDING_LEG
    return Keyframe(
        qpos={
            "(left|right)_(hip_yaw|hip_roll)_joint": 0.0,
            "(left|right)_hip_pitch_joint": hip_pitch,
            "(left|right)_knee_joint": knee,
            "(left|right)_ankle_joint": ankle,
            f"{TORSO_JOINT}|(left|right)_(shoulder_pitch|shoulder_roll|shoulder_yaw|elbow)_joint": 0.0,
        },
        base_pos=(0.0, 0.0, height),
    )


@register_agent()
class UnitreeH1(Agent):
    """Unitree H1: legs, torso and arms (19 joints) on a free pelvis.

    qpos order (model order): the left leg (hip yaw, hip roll, hip pitch, knee, ankle),
    the right leg, ``torso_joint``, the left arm (shoulder pitch, roll, yaw, elbow), the
    right arm. Actions follow ManiSkill's order (:data:`MANISKILL_JOINTS`).
    """

    uid = "unitree_h1"
    #: Time-step sweep (``robot-agents check unitree_h1 --sweep``, 2026-11-23, 20 Hz
    #: control; see docs/timestep.md): hold, standing, random and penetration hold from
    #: 5 ms (200 Hz) down to 1 ms (standing: the base moves 1.8-6.0 mm after settling,
    #: tilt 0.8-1.2 deg; random-action overshoot 0.05-0.18 rad with the stiff joint
    #: limits, 0.27-0.35 rad at every step with MuJoCo's default soft ones); at 160 Hz the
    #: hold drifts 0.0104 rad and the pelvis 1.4 cm. Settle fails at every step: in
    #: ``pd_joint_vel`` (and the measured-delta modes) a loaded joint creeps at load / kv
    #: (0.05-0.15 rad/s: the modes keep no target), and in the others a robot the random
    #: actions threw down can still be rolling, or sinking onto an 18 N*m elbow, 3 s into
    #: the hold (500 Hz, seed 0: the torso turns at 0.29 rad/s at 3 s, everything is still
    #: at 3.5 s); at 200 Hz an ankle cycles (0.98 rad/s). The sweep takes every other
    #: claim as holding from 320 Hz; the light drives (ankles, shoulders, elbows: kv 100
    #: on 0.10-0.11 kg*m^2) can cycle between their torque limits below 473-485 Hz
    #: (``robot_agents.tuning.cycles``): default 500 Hz, the first tried step above them.
    #: Since the settle claim leaves out, for robots standing on their legs, the modes that
    #: keep no targets and counts only joints that cycle (docs/timestep.md), every claim
    #: holds from 200 Hz (``python benchmarks/timestep_sweep.py --jobs 2``, 2026-11-29
    #: 03:38-03:47 UTC: hold 0.0050 rad, random 0.157 rad, settle 0, standing 6.0 mm at
    #: 200 Hz; docs/timestep-sweep.md); the default stays 500 Hz, above the cycle bound.
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "h1.xml"
    fix_root_link = False
    gravity_compensation = False
    actuators = H1_DRIVES
    parts = (
        Legs(name="legs", joints=LEG_PATTERN, max_delta=0.2),
        Torso(name="torso", joints=TORSO_JOINT, max_delta=0.2),
        Arm(name="left_arm", joints=LEFT_ARM_PATTERN, max_delta=0.2),
        Arm(name="right_arm", joints=RIGHT_ARM_PATTERN, max_delta=0.2),
    )
    control_modes: ClassVar[Mapping[str, ModeConfig]] = H1_MODES
    default_control_mode = "pd_joint_pos"
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "standing": standing_keyframe(STANDING_HEIGHT),
        "rest": standing_keyframe(STANDING_HEIGHT),
        "home": standing_keyframe(HOME_HEIGHT),
    }


#: The bodies of our H1 that keep their collision shapes in ``unitree_h1_simplified``:
#: those where ManiSkill's ``h1_simplified.urdf`` has a body-sized shape, and ours has
#: one too: ``torso_link`` (our torso box, head and the capsule across the pelvis; the
#: URDF's torso box 0.08 x 0.16 x 0.1 m and pelvis sphere r 0.05 m), the thighs
#: (``*_hip_pitch_link``; the URDF's cylinder r 0.05 x 0.2 m), the shins
#: (``*_knee_link``; the same), the feet (``*_ankle_link``; the URDF's box 0.28 x 0.03 x
#: 0.024 m, the same as ours) and the forearms (``*_elbow_link``; r 0.03 x 0.09 m). The
#: URDF gives the hip yaw and roll links and the shoulder roll and yaw links only token
#: shapes (cylinders r 0.01-0.04 m, 0.01-0.02 m long, 6-50 cm^3), which our hip motor
#: cylinders, shoulders and upper arms are not: on those links ours collide no more.
#: (``*_shoulder_pitch_link`` has no collision shape in ours.)
SIMPLIFIED_COLLISION_LINKS = (
    "torso_link",
    *(f"{side}_{link}_link" for side in ("left", "right") for link in ("hip_pitch", "knee", "ankle", "elbow")),
)


@register_agent()
class UnitreeH1Simplified(UnitreeH1):
    """Unitree H1 with a simplified collision model (uid ``unitree_h1_simplified``,
    ManiSkill's ``UnitreeH1Simplified``): our ``unitree_h1`` whose contacts are those of
    :data:`SIMPLIFIED_COLLISION_LINKS`.

    What differs from the peer: ManiSkill's ``unitree_h1`` collides CoACD convex pieces of
    every link's mesh, and its ``h1_simplified.urdf`` (read as data) swaps them for one
    primitive per link; our ``unitree_h1`` is already primitive (Menagerie's capsules,
    cylinders and spheres, 1-4 per link), so our simplification keeps its shapes and
    takes the contacts off the links where the peer's simplified model leaves only a
    token shape (the hip yaw, hip roll, shoulder roll and shoulder yaw links). Everything
    else (drives, keyframes, modes, ``sim_freq``) is ``unitree_h1``'s, as ManiSkill's
    variant changes only the URDF.
    """

    uid = "unitree_h1_simplified"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1
    #: unitree_go2_simplified_locomotion unitree_h1_simplified``, 2026-11-29 18:33-18:35
    #: UTC, seeds 0-2, 20 Hz control; docs/timestep-sweep.md): every claim holds from 200
    #: Hz, as the full H1's (hold, standing and penetration the same to the digit; random
    #: 0.199 rad at 200 Hz, the full H1's 0.157); the default stays the full H1's 500 Hz,
    #: above its light drives' torque-limit cycle bound (485 Hz).
    sim_freq: ClassVar[int | None] = 500
    collision_links = SIMPLIFIED_COLLISION_LINKS


__all__ = [
    "H1_BODY",
    "HOME_HEIGHT",
    "MANISKILL_JOINTS",
    "SIMPLIFIED_COLLISION_LINKS",
    "STANDING_HEIGHT",
    "STANDING_LEG",
    "UnitreeH1",
    "UnitreeH1Simplified",
    "joint_kind",
]
