"""K-Scale Labs' Stompy humanoid (uid ``stompy``, ManiSkill's): 37 joints on a free
torso, two arms ending in two-finger rack-and-pinion grippers, a two-joint head.

Sources of the numbers:
- Kinematics, masses, inertias, joint axes and ranges: the URDF ManiSkill 3.0.1 downloads
  for ``stompy``, ``haosulab/ManiSkill-Stompy`` ``robot.urdf`` at tag v0.1.0 (commit
  f7cd030c42a1b68b5aa211beec5d5ba948656296; K-Scale Labs' Onshape export, MIT licence),
  read as data into our own primitive MJCF (``assets/stompy.xml``, written by
  ``python benchmarks/stompy_mjcf.py URDF_DIR --write``: one body per moving
  joint with the fixed-joint links merged, one box per URDF mesh fitted to its vertices,
  five boxes sized from their links' inertia where the mesh is absent from the archive;
  its header says how). The bodies' poses match SAPIEN loading that URDF at ManiSkill's
  ``standing`` within 1e-6, and ``tests/test_stompy.py`` chains the URDF's origins
  independently. Total mass 27.601 kg. Body and joint names are the URDF's.
- What the joints are: K-Scale Labs' joint map (``kscalelabs/sim``
  ``sim/stompy/joints.py``, commit 5aade28): per leg hip roll (``legs_1_x8_*``), hip yaw,
  hip pitch, a knee motor, the knee, an ankle motor, the ankle and a foot roll; per arm
  shoulder yaw, pitch and roll, elbow yaw and roll, hand roll, the gripper's pinion
  (``hand_1_x4_2``) and its two racks (``hand_1_slider_1`` / ``_2``); head yaw and
  pitch; torso. The knee and ankle motors drive the knee and ankle through belts the URDF
  does not model: there (and so here) they turn only their own rotor and pulley.
- Names and order: ManiSkill's ``Stompy``: uid ``stompy``, its ``standing`` keyframe, its
  modes ``pd_joint_pos`` (default) and ``pd_joint_delta_pos`` over one part ``body`` in
  SAPIEN's joint order (:data:`MANISKILL_JOINTS`), the delta bound 0.1; its head camera;
  friction 2.0 on the fingers; no self-collisions.
- Differences from ManiSkill's agent, each measured (2026-11-29, ``robot-agents check
  stompy`` and the scripts behind tests/test_stompy.py):

  * ``standing``: the torso 0.972 m up, not 0.965: at 0.965 the soles' boxes reach 5.9 mm
    into the floor (ManiSkill's meshes 4.6 mm); and the head pitch at its upper limit
    0.2618 rad (ManiSkill's 0.5 lies past it). ``rest`` is the same pose.
  * Leg drives: kp 2000 N*m/rad, kv 200 N*m*s/rad (ours). With ManiSkill's 100 / 10 the
    robot falls over from ``standing`` within 1 s (tests). The standing load is up to
    16.6 N*m (knee), 13 N*m (hip roll), 5.3 N*m (foot roll): at kp 2000 each joint gives
    under 9 mrad. kv 200: with 50 (100) the torso still moves 21 (4.4) mm after the
    first second on its feet, with 200 0.8 mm. ManiSkill's own Stompy falls from
    ``standing`` too (its ``Empty-v1`` on CPU PhysX at its 100 Hz, the URDF with the five
    absent collision meshes left out, 2026-11-29 20:39 UTC): repeating the keyframe's
    targets in ``pd_joint_pos`` it tilts 37.7 deg at 1 s and lies on the floor (torso
    0.22 m up) at 1.5 s; with zero ``pd_joint_delta_pos`` actions it is down at 1 s.
  * No effort limits, as ManiSkill's drives (``force_limit`` 1e10): the URDF's efforts
    (:data:`URDF_EFFORT`: 1.5 N*m for the x4 joints, 3 x6, 6 x8 and ankles, 12 x10,
    13.9 knees, 80 N sliders) cannot hold ``standing`` (13 N*m at the 6 N*m hip rolls,
    5.3 at the 1.5 N*m foot rolls); the robot falls with them (tests).
  * Modes: ManiSkill's two only, both with the drives above (ManiSkill's
    ``pd_joint_delta_pos`` sets 20 / 5 on every joint, under which the robot cannot stand).
    The library's velocity modes are left out: with unlimited drives a velocity target
    (kv x 31.4 rad/s, 6280 N*m on the legs) spins the beltless ankle motor rotors 4.8 rad
    through their joint limits (sweep, ``pd_joint_vel``, every step from 40 Hz to 1 kHz).
  * Armature 0.01 kg*m^2 (kg on the sliders) on every joint: an estimate (the URDF gives
    none; MyActuator's geared motors reflect rotor inertia of this order), set so that kp
    2000 stays stable at the step: the beltless rotors weigh 54-203 g (largest kp /
    (4 I / dt^2) 0.2 at 500 Hz).
  * Contacts: the feet near-rigid (``solref`` 5 ms, as PhysX's rigid contacts): ManiSkill's
    ``standing`` sets the soles rolled 4.3 deg and pitched 2 deg (the peer's meshes too),
    so the robot lands on their edges; with MuJoCo's default 20 ms they sank and the torso
    still moved 10.4 mm after the first second (0.8 mm with ours). The fingers take the library's stiff pad
    contact (``PAD_SOLREF``): with MuJoCo's default a held 4 cm cube sank 2 mm into them
    and crept out at 3 mm/s.
- Grippers: each a ``Gripper`` of two rack sliders, open at 0 (68 mm between the finger
  boxes), closed at -0.034 m (they meet); fingers the slider bodies (each carries the
  URDF's ``gripper_1`` / ``gripper_2`` link). A 4 cm cube is held under its weight in
  either (tests). No end effector: ManiSkill's agent has no TCP, so the sweep's grasp claim
  (which needs an end-effector mode) does not apply.
- Camera: ManiSkill's ``head_camera`` on ``link_head_1_head_1`` (a body of its own in our
  model, welded to the head pitch link).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.rules import JointGroup, ModeConfig, joint_control_modes
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.rotations import FORWARD_X_UP_Z_CAMERA_QUAT, quat_multiply
from robot_agents.model.materials import PAD_SOLIMP, PAD_SOLREF, FrictionMaterial
from robot_agents.parts.declaration import Arm, Gripper, Head, Legs, Torso
from robot_agents.registry import register_agent
from robot_agents.sensors.camera import CameraConfig

ASSETS = Path(__file__).parent / "assets"

#: ManiSkill's ``Stompy`` joint order (SAPIEN's active joints of the URDF): the action
#: order of every mode, and the order of :data:`STANDING_QPOS`.
MANISKILL_JOINTS = (
    "joint_right_arm_1_x8_1_dof_x8",
    "joint_left_arm_2_x8_1_dof_x8",
    "joint_head_1_x4_1_dof_x4",
    "joint_torso_1_x8_1_dof_x8",
    "joint_right_arm_1_x8_2_dof_x8",
    "joint_left_arm_2_x8_2_dof_x8",
    "joint_legs_1_x8_1_dof_x8",
    "joint_legs_1_x8_2_dof_x8",
    "joint_head_1_x4_2_dof_x4",
    "joint_right_arm_1_x6_1_dof_x6",
    "joint_left_arm_2_x6_1_dof_x6",
    "joint_legs_1_right_leg_1_x8_1_dof_x8",
    "joint_legs_1_left_leg_1_x8_1_dof_x8",
    "joint_right_arm_1_x6_2_dof_x6",
    "joint_left_arm_2_x6_2_dof_x6",
    "joint_legs_1_right_leg_1_x10_2_dof_x10",
    "joint_legs_1_left_leg_1_x10_1_dof_x10",
    "joint_legs_1_right_leg_1_knee_revolute",
    "joint_legs_1_left_leg_1_knee_revolute",
    "joint_right_arm_1_x4_1_dof_x4",
    "joint_left_arm_2_x4_1_dof_x4",
    "joint_legs_1_right_leg_1_x10_1_dof_x10",
    "joint_legs_1_right_leg_1_ankle_revolute",
    "joint_legs_1_left_leg_1_x10_2_dof_x10",
    "joint_legs_1_left_leg_1_ankle_revolute",
    "joint_legs_1_right_leg_1_x6_1_dof_x6",
    "joint_legs_1_left_leg_1_x6_1_dof_x6",
    "joint_legs_1_right_leg_1_x4_1_dof_x4",
    "joint_legs_1_left_leg_1_x4_1_dof_x4",
    "joint_right_arm_1_hand_1_x4_1_dof_x4",
    "joint_left_arm_2_hand_1_x4_1_dof_x4",
    "joint_right_arm_1_hand_1_slider_1",
    "joint_right_arm_1_hand_1_slider_2",
    "joint_left_arm_2_hand_1_slider_1",
    "joint_left_arm_2_hand_1_slider_2",
    "joint_right_arm_1_hand_1_x4_2_dof_x4",
    "joint_left_arm_2_hand_1_x4_2_dof_x4",
)
#: ManiSkill's ``standing`` keyframe qpos, in :data:`MANISKILL_JOINTS` order (rad, m).
#: ``joint_head_1_x4_2_dof_x4``'s 0.5 rad lies past the URDF's upper limit 0.2618 rad
#: (SAPIEN sets it anyway, its limit then pushes it back); ours is the limit.
MANISKILL_STANDING_QPOS = (
    1.5, -1.5, -0.942, 0.0, 1.5, -1.5, -0.25, 0.25, 0.5, 0.65, -0.65, -0.5, -0.5, 0.0, 0.0, -0.5, 0.5,
    0.78, -0.78, 0.25, -0.25, 0.0, -0.2, 0.0, 0.2, 0.0, 0.0, -0.2, 0.2, 0.2, -2.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
)  # fmt: skip
HEAD_PITCH_JOINT = "joint_head_1_x4_2_dof_x4"
#: The URDF's upper limit of :data:`HEAD_PITCH_JOINT` (rad).
HEAD_PITCH_UPPER = 0.26179939
#: ManiSkill's ``standing`` root height (m): the torso link's origin.
STANDING_HEIGHT = 0.965 + 0.007

LEG_PATTERN = r"joint_legs_1_.*"
TORSO_JOINT = "joint_torso_1_x8_1_dof_x8"
HEAD_PATTERN = r"joint_head_1_x4_[12]_dof_x4"
RIGHT_ARM_PATTERN = r"joint_right_arm_1_.*_dof_x[468]"
LEFT_ARM_PATTERN = r"joint_left_arm_2_.*_dof_x[468]"
RIGHT_GRIPPER_PATTERN = r"joint_right_arm_1_hand_1_slider_[12]"
LEFT_GRIPPER_PATTERN = r"joint_left_arm_2_hand_1_slider_[12]"
#: The finger bodies (the sliders' links; each carries the URDF's ``gripper_1`` or
#: ``gripper_2`` link, merged in).
RIGHT_FINGERS = ("link_right_arm_1_hand_1_slide_1", "link_right_arm_1_hand_1_slide_2")
LEFT_FINGERS = ("link_left_arm_2_hand_1_slide_1", "link_left_arm_2_hand_1_slide_2")
#: Slider positions (m): open at the URDF's upper limit 0 (68 mm between the finger
#: boxes), closed at its lower limit -0.034 (the boxes meet).
GRIPPER_OPEN, GRIPPER_CLOSED = 0.0, -0.034

#: ManiSkill's ``pd_joint_pos`` gains: stiffness (N*m/rad, N/m) and damping (N*m*s/rad,
#: N*s/m), ours for the torso, head, arms and grippers.
MANISKILL_KP, MANISKILL_KV = 100.0, 10.0
#: Our leg gains (N*m/rad, N*m*s/rad): with ManiSkill's 100 the robot falls over forwards
#: from ``standing`` within 1 s; see the module doc.
LEG_KP, LEG_KV = 2000.0, 200.0
#: Armature on every joint (kg*m^2; kg on the sliders): an estimate, see the module doc.
ARMATURE = 0.01
#: ManiSkill's ``pd_joint_delta_pos`` bound (rad or m per step).
MANISKILL_DELTA = 0.1
#: The URDF's effort limits per actuator kind (N*m; the sliders N), documented, not applied
#: (ManiSkill's drives are unlimited; see the module doc), and velocity limits (rad/s; the
#: sliders m/s), the bounds of the velocity modes.
URDF_EFFORT = {"x4": 1.5, "x6": 3.0, "x8": 6.0, "x10": 12.0, "knee": 13.9, "ankle": 6.0, "slider": 80.0}
SPEED = {"x4": 31.4, "x6": 31.4, "x8": 31.4, "x10": 31.4, "knee": 31.4, "ankle": 31.4, "slider": 5.0}


def joint_kind(joint: str) -> str:
    """The actuator kind of a Stompy joint (a key of :data:`SPEED`)."""
    if "slider" in joint:
        return "slider"
    if joint.endswith("knee_revolute"):
        return "knee"
    if joint.endswith("ankle_revolute"):
        return "ankle"
    return joint.rsplit("_", 1)[-1]


STOMPY_DRIVES = (
    PDActuator(
        joints=LEG_PATTERN,
        stiffness=LEG_KP,
        damping=LEG_KV,
        velocity_limit=SPEED["x10"],
        armature=ARMATURE,
    ),
    PDActuator(
        joints=f"{TORSO_JOINT}|{HEAD_PATTERN}|{RIGHT_ARM_PATTERN}|{LEFT_ARM_PATTERN}",
        stiffness=MANISKILL_KP,
        damping=MANISKILL_KV,
        velocity_limit=SPEED["x8"],
        armature=ARMATURE,
    ),
    PDActuator(
        joints=f"{RIGHT_GRIPPER_PATTERN}|{LEFT_GRIPPER_PATTERN}",
        stiffness=MANISKILL_KP,
        damping=MANISKILL_KV,
        velocity_limit=SPEED["slider"],
        armature=ARMATURE,
    ),
)

STOMPY_BODY = JointGroup(
    MANISKILL_JOINTS,
    max_delta=MANISKILL_DELTA,
    max_velocity=tuple(SPEED[joint_kind(j)] for j in MANISKILL_JOINTS),
)
#: ManiSkill's two modes (see the module doc for why not the library's other joint modes).
MANISKILL_MODES = ("pd_joint_pos", "pd_joint_delta_pos")
STOMPY_MODES: dict[str, ModeConfig] = {
    mode: {"body": config} for mode, config in joint_control_modes(STOMPY_BODY).items() if mode in MANISKILL_MODES
}

#: ManiSkill's gripper material (static and dynamic friction 2.0) on the fingers, with the
#: library's stiff pad contact (:data:`~robot_agents.model.materials.PAD_SOLREF`, as PhysX's
#: rigid contacts): with MuJoCo's default contact a held 4 cm cube sank 2 mm into the
#: finger boxes and crept out at 3 mm/s.
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001, solref=PAD_SOLREF, solimp=PAD_SOLIMP)
#: The feet (the bodies carrying the URDF's ``foot_1`` and ``rubber_1`` links): MuJoCo's
#: default friction 1.0, near-rigid contact (``solref`` 5 ms, as PhysX's rigid contacts):
#: ManiSkill's ``standing`` sets the soles 4.3 deg rolled, so the robot lands on their
#: edges; with MuJoCo's default 20 ms the edges sink and the robot rocks (see the module doc).
FOOT_SOLE = FrictionMaterial(sliding=1.0, solref=(0.005, 1.0))
FEET = ("link_legs_1_right_leg_1_x4_1_outer_1", "link_legs_1_left_leg_1_x4_1_outer_1")

#: ManiSkill's ``head_camera``: 0.12 m along ``link_head_1_head_1``'s x and 0.02 m along
#: its z, turned ``euler2quat(-pi/2, 0, 0)`` (about x) in SAPIEN's camera axes (x
#: forward, z up); 128 x 128, field of view 1.57 rad, near 0.01 m, far 100 m.
_HEAD_CAMERA_QUAT = quat_multiply(
    (math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0), FORWARD_X_UP_Z_CAMERA_QUAT
)
HEAD_CAMERA = CameraConfig(
    uid="head_camera",
    mount="link_head_1_head_1",
    pos=(0.12, 0.0, 0.02),
    quat=tuple(float(v) for v in _HEAD_CAMERA_QUAT),  # type: ignore[arg-type]
    width=128,
    height=128,
    fovy=math.degrees(1.57),
    near=0.01,
    far=100.0,
)


def standing_keyframe() -> Keyframe:
    """ManiSkill's ``standing``: the torso link 0.965 m up, level, the joints as
    :data:`MANISKILL_STANDING_QPOS` (the head pitch at its limit)."""
    qpos = dict(zip(MANISKILL_JOINTS, MANISKILL_STANDING_QPOS, strict=True))
    qpos[HEAD_PITCH_JOINT] = min(qpos[HEAD_PITCH_JOINT], HEAD_PITCH_UPPER)
    return Keyframe(qpos=qpos, base_pos=(0.0, 0.0, STANDING_HEIGHT))


@register_agent()
class Stompy(Agent):
    """K-Scale Labs' Stompy: legs, torso, head, two arms and two grippers (37 joints) on
    a free torso. Actions follow ManiSkill's joint order (:data:`MANISKILL_JOINTS`)."""

    uid = "stompy"
    #: Time-step sweep (``PYTHONPATH=src python benchmarks/timestep_sweep.py --jobs 1
    #: stompy``, 2026-11-29 20:34-20:35 UTC, seeds 0-2, 20 Hz control, load average 5.7;
    #: docs/timestep-sweep.md): every claim holds from 400 Hz (standing: the torso moves
    #: 3.6 mm after its first second, 0.8 mm at 500 Hz; random 0.058 rad past a stop);
    #: at 320 Hz the standing claim fails (34.8 mm). Default 500 Hz, one tried step finer.
    #: (No drive has an effort limit, so no torque-limit cycle is possible.)
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "stompy.xml"
    fix_root_link = False
    gravity_compensation = False
    disable_self_collisions = True
    actuators = STOMPY_DRIVES
    parts = (
        Legs(name="legs", joints=LEG_PATTERN, max_delta=MANISKILL_DELTA),
        Torso(name="torso", joints=TORSO_JOINT, max_delta=MANISKILL_DELTA),
        Head(name="head", joints=HEAD_PATTERN, max_delta=MANISKILL_DELTA),
        Arm(name="right_arm", joints=RIGHT_ARM_PATTERN, max_delta=MANISKILL_DELTA),
        Arm(name="left_arm", joints=LEFT_ARM_PATTERN, max_delta=MANISKILL_DELTA),
        Gripper(
            name="right_gripper",
            joints=RIGHT_GRIPPER_PATTERN,
            open=GRIPPER_OPEN,
            closed=GRIPPER_CLOSED,
            fingers=RIGHT_FINGERS,
            tolerance=0.002,
        ),
        Gripper(
            name="left_gripper",
            joints=LEFT_GRIPPER_PATTERN,
            open=GRIPPER_OPEN,
            closed=GRIPPER_CLOSED,
            fingers=LEFT_FINGERS,
            tolerance=0.002,
        ),
    )
    control_modes: ClassVar[Mapping[str, ModeConfig]] = STOMPY_MODES
    default_control_mode = "pd_joint_pos"
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {
        **{name: FINGER_PAD for name in (*RIGHT_FINGERS, *LEFT_FINGERS)},
        **{name: FOOT_SOLE for name in FEET},
    }
    cameras = (HEAD_CAMERA,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "standing": standing_keyframe(),
        "rest": standing_keyframe(),
    }


__all__ = [
    "MANISKILL_JOINTS",
    "MANISKILL_STANDING_QPOS",
    "STANDING_HEIGHT",
    "Stompy",
    "joint_kind",
]
