"""SO-100 (SO-ARM100): a 5-DoF low-cost arm with a jaw gripper, six Feetech STS3215.

Sources of the numbers:
- Kinematics, link masses and inertias, joint names and limits: the public SO-100 URDF
  (ManiSkill 3.0.1 ``mani_skill/assets/robots/so100/so100.urdf``, from TheRobotStudio's
  SO-ARM100), read as data into our primitive model ``assets/so100.xml`` (its header
  lists every joint origin); MuJoCo Menagerie's ``trs_so_arm100`` carries the same
  inertials. Link and joint names are the URDF's (``shoulder_pan`` ... ``gripper``,
  ``Base`` ... ``Moving_Jaw``), so the upstream model can be swapped in. (Checked
  2026-11-29, docs/notes/robot-facts-audit.md: our compiled model equals ManiSkill's URDF
  compiled by MuJoCo in every body pose, mass, centre of mass, inertia, axis and range.
  TheRobotStudio's first URDF, ``URDF/SO_5DOF_ARM100_8j_URDF.SLDASM``, commit 71b8863,
  2024-09-25, has the same joint origins and inertials with continuous joints and other
  joint frame rotations; its current ``Simulation/SO100/so100.urdf``, commits bbb9734 and
  0c8e289, 2025, keeps the joint positions and centres of mass but turns the zero pose,
  with other ranges, e.g. ``shoulder_lift`` 0..3.5 rad: ManiSkill's keyframes need the
  ManiSkill frames kept here.)
- Servos: the Feetech STS3215, 7.4 V, 1 : 345 (:data:`~.servos.STS3215`): stall torque
  1.91 N*m is every joint's effort limit, no-load speed 5.45 rad/s its velocity limit,
  BAM's identified reflected inertia 0.0261 kg*m^2 its armature, 0.0515 N*m its
  friction.
- Gains: critically damped at 40 rad/s for each joint's effective inertia at ``rest``
  (armature + the joint-space mass matrix diagonal :data:`REST_LINK_INERTIA`), see
  :func:`~.servos.critically_damped_gains`: kp = 41.8 .. 54.6 N*m/rad, kv = 2.09 .. 2.73
  N*m*s/rad. ManiSkill's SO-100 uses kp = 1000, kv = 100 (an industrial arm's gains).
  Of kv, the STS3215's back-EMF, 1.91 / 5.45 = 0.350 N*m*s/rad, is each joint's own
  damping (``joint_damping``), outside the stall-torque limit, and the drive's damping
  the rest, 1.74 .. 2.38 (:func:`~.servos.split_damping`): at full torque a joint runs
  at most at the no-load speed (plus what gravity adds). Since 2026-11-29; before, a
  saturated drive lost its damping and a full-range ``pd_joint_pos`` jump
  (benchmarks/rated_speed.py) peaked at 10.8 rad/s on ``elbow_flex``, 1.99 times the
  5.45 rad/s; now 5.5 rad/s, 1.00 times (10:12 UTC).
- Keyframes: ManiSkill's ``rest`` (the folded pose, jaw closed) and ``zero``; joint
  delta actions of 0.05 rad per step, as ManiSkill's (the arm is not precise).
- Self-collision exclusions: the pairs of the URDF's SRDF that the kinematics keep apart.
- Gripper: one moving jaw (``Moving_Jaw``, joint ``gripper``) against the fixed jaw of
  the wrist link; closed at -1.1 rad (the tips meet), open at 1.1 rad. Its fingers for
  grasp detection are the fixed jaw's finger (``Fixed_Jaw_tip``, a welded body at the
  URDF's tip frame) and ``Moving_Jaw``. Jaw pads: MuJoCo Menagerie's ``trs_so_arm100``
  pad contact (solref 0.01 s, solimp "2 1 0.01", an impedance MuJoCo clamps to 0.9999):
  with the shared servo pads' 0.95-0.99 the jaw's 12.7 degree wedge on a 31.5 mm cube
  squeezed it out at up to 5 mm/s (MuJoCo's soft friction, inside the friction cone);
  condim 4 gives the pads their torsional friction (a near-rigid pair of point contacts
  lets a carried cube pivot out of the jaw).
- Tool centre point ``tcp``: on ``Fixed_Jaw`` at (0.00705, -0.09548, 0) m, where
  ManiSkill's SO-100 TCP (the midpoint of the URDF's ``Fixed_Jaw_tip`` and
  ``Moving_Jaw_tip`` frames) lies with the jaw closed. End-effector modes command its
  position only (5 DoF): ``pd_ee_delta_pos`` and ``pd_ee_target_delta_pos``, 2 cm per
  step at most, the held orientation only a soft preference of IK (:data:`robot_agents.kinematics.ik_config.POSITION_IK`).

The arm faces -y of its root (the URDF's frame); ManiSkill mounts it turned 90 deg
about z, which ``robot_poses`` reproduces.
"""

from __future__ import annotations

from pathlib import Path

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.ik_config import POSITION_IK
from robot_agents.parts.declaration import Arm, EndEffector, Gripper
from robot_agents.registry import register_agent
from robot_agents.robots.servo_arms.servos import STS3215, critically_damped_gains, split_damping

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll")
GRIPPER_JOINT = "gripper"
JOINTS = (*ARM_JOINTS, GRIPPER_JOINT)

#: Diagonal of the joint-space mass matrix at ``rest`` without armature (kg*m^2), in
#: ``JOINTS`` order: what the links add to each servo's reflected inertia.
REST_LINK_INERTIA = (3.0432e-3, 2.7393e-3, 8.0064e-3, 1.1516e-3, 4.008e-5, 2.769e-5)
#: Effective inertia of each joint at ``rest``: link inertia plus armature (kg*m^2).
EFFECTIVE_INERTIA = tuple(i + STS3215.armature for i in REST_LINK_INERTIA)
STIFFNESS, DAMPING = critically_damped_gains(EFFECTIVE_INERTIA)
#: ``DAMPING`` split into the drive's share and the STS3215's back-EMF, each joint's own
#: (N*m*s/rad): the back-EMF acts outside the stall-torque limit.
DRIVE_DAMPING, JOINT_DAMPING = split_damping(DAMPING, (STS3215,) * len(JOINTS))

#: Every joint is an STS3215 under a critically damped PD drive.
SO100_DRIVES = PDActuator(
    joints="|".join(JOINTS),
    stiffness=STIFFNESS,
    damping=DRIVE_DAMPING,
    joint_damping=JOINT_DAMPING,
    effort_limit=STS3215.stall_torque,
    velocity_limit=STS3215.no_load_speed,
    armature=STS3215.armature,
    friction=STS3215.friction,
)

#: The tool centre point between the jaw tips (``Fixed_Jaw`` frame, m).
TCP_ON_FIXED_JAW = (0.00705, -0.09548, 0.0)

SO100_ARM = Arm(
    name="arm",
    joints="|".join(ARM_JOINTS),
    end_effectors=(EndEffector("Fixed_Jaw", name="tcp", pos=TCP_ON_FIXED_JAW),),
    # absolute positions: a box around the reach (0.42 m from the shoulder at z = 0.12 m)
    task_space=TaskSpace(
        position_bounds=WorkspaceBox(lower=(-0.5, -0.55, -0.3), upper=(0.5, 0.45, 0.6)),
        max_translation=0.02,
        ik=POSITION_IK,
        modes=("pd_ee_delta_pos", "pd_ee_target_delta_pos"),
    ),
    max_delta=0.05,
)
#: -1 closes 0.3 rad past the closed jaw (squeezes), +1 opens it fully.
SO100_GRIPPER = Gripper(
    name="gripper",
    joints=GRIPPER_JOINT,
    open=1.1,
    closed=-1.1,
    squeeze=0.3,
    fingers=("Fixed_Jaw_tip", "Moving_Jaw"),
)

REST = (0.0, -1.5708, 1.5708, 0.66, 0.0, -1.1)


@register_agent()
class SO100(Agent):
    """SO-100: five STS3215 joints and a jaw gripper.

    qpos order: ``shoulder_pan``, ``shoulder_lift``, ``elbow_flex``, ``wrist_flex``,
    ``wrist_roll``, ``gripper``.
    """

    uid = "so100"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23, 20 Hz control, every
    #: step): every claim holds from 12.5 ms (80 Hz) down to 1 ms, the grasp included
    #: with the jaw pads' near-rigid contacts (``so100.xml``: the 31.5 mm cube moves
    #: 0.22-1.3 mm in the 2 s hold at 100 Hz-1 kHz, 1.9 mm at 80 Hz; with the former pad
    #: impedance the jaw's wedge squeezed it out, 0.9-11 mm, not ordered by the step).
    #: Default 200 Hz, not one tried step finer than 80 Hz: at 100 Hz the critically
    #: damped 0.2 rad joint step (tests/test_servo_arms.py) overshoots 1.007 mrad (bound
    #: 1 mrad); at 160 Hz 0.22 mrad, but the scripted PickCube-v1 solver succeeds in 19
    #: of 20 seeds (20 at 200 Hz, the test asks 18). Was 320 Hz while the grasp failed
    #: at 200 Hz. Rerun 2026-11-29 10:14 UTC after the back-EMF became the joints' damping:
    #: every claim still holds from 80 Hz (joint-limit overshoot 0.027 rad at 200 Hz, was
    #: 0.069; grasp slip 0.26 mm as before). Tried 160 Hz again (2026-11-29 22:40-22:42
    #: UTC, after the back-EMF change: the joint step overshoots 0.12 mrad there): the
    #: scripted solvers over 200 seeds fall to 185/200 PickCube-v1 and 188/200 PushCube-v1
    #: (196 and 194 at 200 Hz; ``python examples/scripted_pick.py --task T --robots so100
    #: --seeds 200``); kept 200 Hz. Why (scratch runs, 2026-11-29 23:05-23:28 UTC): all
    #: 15 PickCube failures at 160 Hz (and the 4 at 200 Hz) drop the cube on the solver's
    #: first raise step: the fixed pad's near-rigid contact, whose force does not grow
    #: with depth, keeps its 28-29 N while its depth shrinks 6-9 um a physics step from
    #: 0.02-0.04 mm until the contact is gone (seeds 29, 40, 58, 121), and the jaw closes
    #: on nothing. That pad carries 24.6-25.4 N along its face (the jaw's wedge; the cube
    #: weighs 0.31 N), 0.77-0.82 of MuJoCo's pyramidal friction bound ``|f_t1| + |f_t2|
    #: <= mu f_n``. Not MuJoCo's ``refsafe`` (pad solref 0.025 s at 160 Hz: 170/200),
    #: nor the solver's tolerance (1e-10: 185/200; the XLeRobot's cause), the elliptic
    #: cone (160/200) or noslip (176/200). ManiSkill's SO-100 gripper friction 2.0 on the
    #: pads (1.5 here) makes PickCube 200/200 at 160 Hz and 199/200 at 200 Hz, but
    #: PushCube-v1 191/200 at both (194 now at 200 Hz; seed 5 at 160 Hz pushes the cube
    #: past the goal, no grasp involved); a pad impedance rising with depth (solimp
    #: "0.99 0.9999 0.0005", so the contact settles deeper) makes PickCube 200/200 at 160
    #: and 200 Hz, PushCube 192 and 189 (23:30-23:34 UTC): neither taken.
    sim_freq = 200
    mjcf_path = ASSETS / "so100.xml"
    actuators = (SO100_DRIVES,)
    parts = (SO100_ARM, SO100_GRIPPER)
    self_collision_exclusions = (
        ("Rotation_Pitch", "Lower_Arm"),
        ("Rotation_Pitch", "Wrist_Pitch_Roll"),
        ("Upper_Arm", "Wrist_Pitch_Roll"),
        ("Upper_Arm", "Base"),
        ("Moving_Jaw", "Wrist_Pitch_Roll"),
    )
    keyframes = {
        "rest": Keyframe(qpos={"|".join(JOINTS): REST}),
        "zero": Keyframe(qpos={".*": 0.0}),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = ["ARM_JOINTS", "EFFECTIVE_INERTIA", "GRIPPER_JOINT", "REST_LINK_INERTIA", "SO100", "TCP_ON_FIXED_JAW"]
