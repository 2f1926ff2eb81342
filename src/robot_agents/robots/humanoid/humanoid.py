"""The classic MuJoCo humanoid (ManiSkill's ``humanoid``): dm_control's 21-joint capsule
character on a free torso. Registered with one keyframe, ``stand``; ManiSkill's
``squat`` is :data:`SQUAT_KEYFRAME`, not a keyframe here (see "Why ``squat`` is not a
keyframe").

It is a simulated character, not a product: there is no maker and no datasheet; every
fact below is the model's.

Sources of the numbers:
- Geometry, joint origins, axes and ranges: dm_control's suite ``humanoid.xml`` as
  ManiSkill 3.0.1 ships it (``mani_skill/assets/robots/humanoid/humanoid.xml``, the torso
  at the origin "for compatibility with set_root_pose"), read as data; our own MJCF in
  ``assets/humanoid.xml`` lists them. Body and joint names are the model's. Gymnasium's
  ``humanoid.xml`` (``gymnasium/envs/mujoco/assets/``) is an older 17-joint variant
  (sphere feet, no ankles): not this robot, not used.
- Masses: MuJoCo's default density (1000 kg/m^3) over the capsules and spheres, as the
  model: 40.844 kg (ManiSkill's loaded links sum to 40.844 kg: its worker, 2026-11-29).
- Torque limits: the model's motor gears (``ctrlrange`` +-1): abdomen and hips x/z
  40 N*m, hip_y 120, knee 80, ankles 20, shoulders 20, elbows 40 (:data:`GEAR`).
- Joint limits: stiff (``solreflimit`` 5 ms), as our H1's: with the model's soft ones
  (``solimplimit`` 0, 0.99, 0.01) random actions pressed the hips 0.30-0.38 rad past
  their stops at 320-1000 Hz, with MuJoCo's default limits 0.25-0.60 (bound 0.25); now
  0.035-0.155 from 200 Hz up.
- Armature 0.01 kg*m^2: the model's class ``body``. The model's passive joint springs
  (1-20 N*m/rad towards the zero pose) and damping (0.2-5 N*m*s/rad) are left out: they
  would bend every held pose off its targets, and ManiSkill's loader drops them too.
- Velocity bound of the velocity modes: 10 rad/s, an estimate (the model's motors are
  torque sources with no rated speed; the order of a person's fastest limb speeds).
- Action orders: ``pd_joint_pos`` and our other modes follow ManiSkill's
  ``active_joints`` (:data:`MANISKILL_JOINTS`), ``pd_joint_delta_pos`` its
  ``joints_dict`` (:data:`DELTA_JOINTS`), bound +-2 rad as ManiSkill's; the other delta
  modes (ours) 0.2 rad.
- Keyframes: ``stand`` (the default; ``rest``, the library's reset pose for tasks, is the
  same): every joint 0, the torso 1.3 m up,
  the pose ManiSkill's humanoid tasks reset to (``envs/tasks/control/humanoid.py``,
  less their +-0.01 rad noise; the soles start 14.5 mm above the floor).
  :data:`SQUAT_KEYFRAME`: ManiSkill's ``squat`` keyframe (its joint angles, the torso
  at 1.13 m, level; the soles 5.7 mm up), which cannot be held (below).
- Gains: ManiSkill's kp 100 / kv 10 on every joint cannot hold the stand: the body is
  an inverted pendulum on its ankles (m g h = 40.84 kg * 9.81 * 0.745 m = 299 N*m/rad
  against two ankles of 100 N*m/rad); it leans 9.1 deg in 0.3 s and 30 deg in 1 s, both
  ankle_y drives reach their 20 N*m, and it is on the floor in 2 s. Ours follow one
  rule: kp = 50 x gear (each drive gives the model's full torque 20 mrad off its
  target; ankles 1000 N*m/rad), kv = kp / 10 (ManiSkill's kv / kp). With kp = 10 x gear
  (ankles 200, kv = gear) it still falls forward (tilt 9.7 deg at 1 s, on the floor in
  2 s); with kp = 50 x gear and ManiSkill's kv 10 (or kv = gear) it stands but sways:
  the torso moves 2.8 (2.2) cm after its first second (the standing bound: 1 cm).
  Measured with the standing claim at 500 Hz, 2026-11-29 18:45 UTC.

Why ``squat`` is not a keyframe: it cannot stand within the model's torques, and every
keyframe of a robot on legs must (the standing claim).
Level, as ManiSkill places it, its feet are pitched 6.4 deg toe-down and rolled 14 deg
(the hip_x and hip_z angles turn the ankle axes): it lands on its toes, and its centre
of mass lies 1.0 mm ahead of their rounded ends. Turned back as far as its soles stay
flat (the torso pitched back 4.2 deg, the inner sole capsules on the floor), the centre
of mass is 11.5 cm ahead of the ankle_y axes: holding that takes 22.6 N*m at each
ankle_y (knee 16.6 N*m, hip_y 9.7 N*m), over the model's 20 N*m; turned back further,
the feet rest on their heels and it tips forward onto its toes. With our gains it
falls from both (ankle_y drives at 20 N*m; tilt 28.5 and 19.2 deg at 1 s, on the floor
at 2 s). Every other claim holds from ``stand`` (tests/test_humanoid.py; the sweep in
:attr:`Humanoid.sim_freq`'s comment). ManiSkill's own humanoid falls from both poses
too (its worker, CPU PhysX, ``pd_joint_pos`` repeating the pose's targets, its drives
unlimited, 2026-11-29 18:45 UTC): from ``squat`` tilt 46.6 deg at 1 s and the torso at
0.27 m at 2 s; from the stand 28.1 deg at 1 s and 0.24 m at 2 s (its tasks train a
policy to stand; nothing holds a pose). So the robot is registered with ``stand``
alone, which ManiSkill's humanoid tasks reset to; ``SQUAT_KEYFRAME`` is there for a
scene that wants the pose (``Scene(..., keyframes=...)`` of a subclass declaring it).
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

#: ManiSkill's ``active_joints`` order: the action order of ``pd_joint_pos`` and of our
#: other modes but ``pd_joint_delta_pos``.
MANISKILL_JOINTS = (
    "abdomen_z",
    "right_shoulder1",
    "left_shoulder1",
    "abdomen_y",
    "right_shoulder2",
    "left_shoulder2",
    "abdomen_x",
    "right_elbow",
    "left_elbow",
    "right_hip_x",
    "left_hip_x",
    "right_hip_z",
    "left_hip_z",
    "right_hip_y",
    "left_hip_y",
    "right_knee",
    "left_knee",
    "right_ankle_y",
    "left_ankle_y",
    "right_ankle_x",
    "left_ankle_x",
)
#: ManiSkill's ``pd_joint_delta_pos`` order (its ``joints_dict``).
DELTA_JOINTS = (
    "abdomen_y",
    "abdomen_z",
    "abdomen_x",
    "right_hip_x",
    "right_hip_z",
    "right_hip_y",
    "right_knee",
    "right_ankle_x",
    "right_ankle_y",
    "left_hip_x",
    "left_hip_z",
    "left_hip_y",
    "left_knee",
    "left_ankle_x",
    "left_ankle_y",
    "right_shoulder1",
    "right_shoulder2",
    "right_elbow",
    "left_shoulder1",
    "left_shoulder2",
    "left_elbow",
)
#: The model's motor gears (``ctrlrange`` +-1): each joint kind's torque limit (N*m).
GEAR: dict[str, float] = {
    "abdomen_y": 40.0,
    "abdomen_z": 40.0,
    "abdomen_x": 40.0,
    "hip_x": 40.0,
    "hip_z": 40.0,
    "hip_y": 120.0,
    "knee": 80.0,
    "ankle_x": 20.0,
    "ankle_y": 20.0,
    "shoulder1": 20.0,
    "shoulder2": 20.0,
    "elbow": 40.0,
}
#: The model's joint armature (its class ``body``), kg*m^2.
ARMATURE = 0.01
#: ManiSkill's ``pd_joint_pos`` gains on every joint: kp (N*m/rad), kv (N*m*s/rad).
MANISKILL_KP, MANISKILL_KV = 100.0, 10.0
#: Our stiffness rule: full torque (the gear) at this error (rad).
FULL_TORQUE_ERROR = 0.02
#: Our damping rule: ManiSkill's kv / kp.
DAMPING_RATIO = MANISKILL_KV / MANISKILL_KP
#: Our gains per joint kind: kp (N*m/rad) and kv (N*m*s/rad).
KP: dict[str, float] = {kind: gear / FULL_TORQUE_ERROR for kind, gear in GEAR.items()}
KV: dict[str, float] = {kind: kp * DAMPING_RATIO for kind, kp in KP.items()}
#: Velocity bound of the velocity modes (rad/s): an estimate (module doc).
MAX_VELOCITY = 10.0

#: ManiSkill's ``squat``: joint angles (rad) and torso height (m).
SQUAT = dict(
    zip(
        MANISKILL_JOINTS,
        (0, 0, 0, 0.12, 0, 0, 0, 0, 0, -0.25, -0.25, -0.25, -0.25, -0.5, -0.5, -1.3, -1.3, -0.8, -0.8, 0, 0),
        strict=True,
    )
)
SQUAT_HEIGHT = 1.13
#: ManiSkill's humanoid tasks' reset height of the torso (m), every joint at 0.
STAND_HEIGHT = 1.3
#: ``stand``: every joint 0, the torso :data:`STAND_HEIGHT` up.
STAND_KEYFRAME = Keyframe(qpos={".*": 0.0}, base_pos=(0.0, 0.0, STAND_HEIGHT))
#: ManiSkill's ``squat`` keyframe: not one of ours (module doc: it cannot be held).
SQUAT_KEYFRAME = Keyframe(qpos=dict(SQUAT), base_pos=(0.0, 0.0, SQUAT_HEIGHT))

LEG_PATTERN = "(left|right)_(hip_x|hip_z|hip_y|knee|ankle_y|ankle_x)"


def joint_kind(joint: str) -> str:
    """``right_hip_y`` -> ``hip_y``; ``abdomen_z`` stays."""
    return joint.removeprefix("left_").removeprefix("right_")


def drives(kp: Mapping[str, float], kv: Mapping[str, float]) -> tuple[PDActuator, ...]:
    """One PD drive declaration per joint kind (both sides), limited at the model's gear.

    Args:
        kp: stiffness per joint kind (N*m/rad), every key of :data:`GEAR`.
        kv: damping per joint kind (N*m*s/rad), every key of :data:`GEAR`.
    """
    return tuple(
        PDActuator(
            joints=kind if kind.startswith("abdomen") else f"(left|right)_{kind}",
            stiffness=kp[kind],
            damping=kv[kind],
            effort_limit=gear,
            armature=ARMATURE,
        )
        for kind, gear in GEAR.items()
    )


BODY = JointGroup(MANISKILL_JOINTS, max_delta=0.2, max_velocity=MAX_VELOCITY)
MODES: dict[str, ModeConfig] = {mode: {"body": config} for mode, config in joint_control_modes(BODY).items()}
MODES["pd_joint_delta_pos"] = {
    "body": joint_control_modes(JointGroup(DELTA_JOINTS, max_delta=2.0, max_velocity=MAX_VELOCITY))[
        "pd_joint_delta_pos"
    ]
}


@register_agent()
class Humanoid(Agent):
    """dm_control's humanoid: abdomen (3 joints), legs (6 each) and arms (3 each) on a
    free torso, standing at its ``stand`` keyframe.

    qpos order (model order): abdomen z, y, x; the right leg (hip x, z, y, knee, ankle y,
    x); the left leg; the right arm (shoulder1, shoulder2, elbow); the left arm.
    """

    uid = "humanoid"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 humanoid``,
    #: 2026-11-29 18:53-18:54 UTC, 20 Hz control; the same as ``sweep_timestep`` on the class
    #: with ``stand`` alone at 18:43 UTC): every claim holds from 160 Hz to 1 kHz
    #: (random-action overshoot 0.233 rad at 160 Hz, 0.155 at 200, 0.13 at 320, 0.068 at 500; standing 7.8, 3.5,
    #: 1.5, 2.2 mm); at 100 Hz hold, random and standing fail. The hips' torque-limit
    #: cycles (``robot_agents.tuning.cycles``: kv 200-600 on 0.02-0.027 kg*m^2) are free
    #: only above 4.8-11 kHz, out of reach; none was seen. With ten random-action seeds
    #: (``--substeps 8,10,16 --seeds 0,1,2,3,4,5,6,7,8,9``, 20:42-20:48 UTC) every claim
    #: holds from 320 Hz (random 0.258 rad at 160 Hz, 0.259 at 200). Default 400 Hz, one
    #: tried step finer (2026-11-29; 500 before, "as our H1's", whose drives' cycle bound
    #: sets its step and which this robot does not share): with the ten seeds every claim
    #: holds there (``--substeps 20 --seeds 0,...,9``, 22:36 UTC: random 0.0829 rad,
    #: standing 1.9 mm, deepest contact 2.1 mm).
    sim_freq: ClassVar[int | None] = 400
    mjcf_path = ASSETS / "humanoid.xml"
    fix_root_link = False
    gravity_compensation = False
    actuators = drives(KP, KV)
    parts = (
        Legs(name="legs", joints=LEG_PATTERN, max_delta=0.2),
        Torso(name="abdomen", joints="abdomen_(z|y|x)", max_delta=0.2),
        Arm(name="right_arm", joints="right_(shoulder1|shoulder2|elbow)", max_delta=0.2),
        Arm(name="left_arm", joints="left_(shoulder1|shoulder2|elbow)", max_delta=0.2),
    )
    control_modes: ClassVar[Mapping[str, ModeConfig]] = MODES
    default_control_mode = "pd_joint_pos"
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "stand": STAND_KEYFRAME,
        "rest": STAND_KEYFRAME,  # the library's reset pose for tasks
    }


__all__ = [
    "DELTA_JOINTS",
    "GEAR",
    "KP",
    "KV",
    "MANISKILL_JOINTS",
    "SQUAT",
    "SQUAT_HEIGHT",
    "SQUAT_KEYFRAME",
    "STAND_HEIGHT",
    "STAND_KEYFRAME",
    "Humanoid",
    "drives",
    "joint_kind",
]
