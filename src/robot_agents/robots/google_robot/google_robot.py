"""Google Robot (``google_robot``): Everyday Robots' mobile manipulator, the robot of
RT-1 and of SimplerEnv's ``google_robot_static``.

Sources of the numbers:
- Kinematics (every joint origin, axis and range), link and joint names, the drive wheels
  (``joint_wheel_left`` / ``_right`` at y = +-0.18333 m), the rear casters (at
  x = -0.338 m, 0.0293 m below the drive axle), the head (``joint_head_pan`` 1.169 m
  above the base link, range -3.79 .. 2.22 rad; ``joint_head_tilt`` 0.0718 m forward and
  0.1185 m above it, +-1.17 rad) and the head camera's mount (``link_camera``, 0.10488 m
  forward of the tilt link, OpenCV axes): ManiSkill2_real2sim's
  ``googlerobot_description/google_robot_meta_sim_fix_fingertip.urdf``
  (github simpler-env/ManiSkill2_real2sim), the model of SimplerEnv's Google Robot.
- The tool frame ``link_gripper_tcp``, which the end-effector modes command, is the
  URDF's (``gripper_tcp_joint``: xyz (0.0043374896, 0.0018852949, 0.16353297) m, rpy
  (-0.0013289, -0.0044397, -0.00086865) rad on ``link_gripper``), the frame SimplerEnv's
  end-effector controllers command (``ee_link_name``), so RT-1 / SimplerEnv policies'
  end-effector actions mean the same here; the finger tips are turned 0.45 rad on the
  fingers, as the URDF's ``joint_finger_tip_*``.
- Ours: the gripper's ``grasp_frame`` ``link_gripper_grasp``, 0.1439 m along the
  gripper's axis (19.6 mm short of the TCP, which lies near the fingertips' ends): the
  middle of our fingertip boxes where they stand parallel (fingers at 1.15 - 0.45 =
  0.70 rad, the tips' faces 75.2 mm apart). The table-top layout measures the open
  gripper there (cube 77.9 mm) and the scripted solvers and the sweep's grasp claim put
  the cube's centre there. Measured at the URDF's TCP the open fingers are 19.2 cm
  apart, and the cube (95.8 mm) is wider than the parallel tips: the fingers close on it
  at 0.53 rad with the tips flared 0.17 rad, touching it only along their knuckles' edges,
  and the cube swings on those edges under its weight: the sweep's grasp claim moves it
  7.4 mm at 500 Hz, 6.7-42.6 mm at 200-800 Hz, 95.8 mm at 160 Hz, 3.4 mm at
  1 kHz (15.0 mm at 500 Hz with friction 1.0); at the grasp frame 0.16-0.64 mm at
  200 Hz-1 kHz, 1.74 mm at 160 Hz (tests/test_google_robot.py; 2026-11-29 10:16 UTC,
  with SimplerEnv's current arm gains; 12.9 mm and 0.33 mm at 500 Hz before them).
  Until 2026-11-29 the TCP was ours, 0.15 m out on the axis, with 0.6 rad tips
  (docs/notes/robot-facts-audit.md).
  The arm's joint names, origins and ranges agree with MuJoCo Menagerie's
  ``google_robot/robot.xml`` (which fixes the head and wheels to the base).
- Masses, centres of mass and inertias: Menagerie's ``robot.xml`` (torso, shoulder,
  bicep, gripper; elbow, forearm and wrist masses) and the URDF (base 52.9 kg, wheels,
  head, fingers; the elbow, forearm and wrist centres of mass and inertias).
- Base: a differential drive. The real robot drives on two wheels with rear casters;
  ManiSkill2_real2sim's mobile Google Robot config drives ``joint_wheel_left`` /
  ``joint_wheel_right`` through ``PDBaseVelControllerConfig`` with bounds +-0.5
  (``base_pd_joint_vel``); ManiSkill 3.0.1's ``googlerobot`` agent has no base controller
  (its TODO: "Add mobile base"). Here the base moves on ManiSkill's planar joints
  (``root_x_axis_joint``, ``root_y_axis_joint``, ``root_z_rotation_joint``) under
  ``pd_base_forward_vel`` (forward speed, yaw rate), at most 0.5 m/s as in that config.
  Wheel radius 0.06205 m (the base link's height above the floor, on which SimplerEnv
  places the robot), separation 2 x 0.18333 m.
- Drives: the arm's stiffness and force limits are SimplerEnv's real-to-sim tuned
  values ("force" drive mode; ManiSkill2_real2sim ``GoogleRobotDefaultConfig``, the
  config of ``google_robot_static``, at ef7a4d4f, the commit SimplerEnv's main (4ab7178)
  pins; unchanged since b1b757c, 2024-01-07; tuned for
  ``arm_pd_ee_delta_pose_align_interpolate_by_planner``, the arm controller SimplerEnv's
  RT-1 evaluations use): stiffness 1700, 1737.05, 979.98, 930, 1212.15, 432.97, 468.00
  N*m/rad, force limits 300, 300, 100, 100, 100, 100, 100 N*m (torso .. gripper joint).
  Until 2026-11-29 they were that config's rough first tune (commit 54efc89,
  2023-12-19, "roughly tune control pd parameters": stiffness 2000, 1800, 1200, 1000,
  650, 500, 500, damping 850, 810, 500, 480, 460, 190, 250, limits 400, 400, 300, 300,
  200, 200, 100; replaced in SimplerEnv on 2024-01-01). The head: SimplerEnv's 2000
  N*m/rad and 100 N*m (the config's last two "arm" joints) with damping a tenth of its
  900: with 900 on the head's 0.106 kg*m^2 (armature 0.1 included) kv * dt / I is 17 at
  2 ms and, once the drive's force is clamped, MuJoCo's explicit damping cycles the tilt
  between its torque limits (0.94 rad/s after random actions); 90 is still overdamped
  (critical: 29) and settles.
  The arm's damping is a seventh of SimplerEnv's (1059.98, 1010.47, 767.28, 680.00,
  674.99, 274.61, 340.53 N*m*s/rad: ours 151.4, 144.4, 109.6, 97.1, 96.4, 39.2, 48.6), for
  the same reason: MuJoCo integrates a drive's damping implicitly only while its force is
  inside its limits, and a clamped drive with kv * dt / I >= 2 can flip between its
  limits every step (``robot_agents.tuning.cycles``). With SimplerEnv's full damping
  every arm drive can at our 2 ms step (cycle-free only above 2146-3311 Hz), and after
  10 steps of +2.5 cm in ``pd_ee_delta_pose`` (whose joint targets carry a velocity
  feed-forward) and then zero commands the tool runs on 200 mm in 2 s, joints still at
  1.4 rad/s. A fifth (the factor until 2026-11-29) leaves the forearm, bicep and torso
  able to cycle at 500 Hz (cycle-free above 654, 632, 599 Hz; the sweep's settle claim
  fails at 400 Hz). A seventh is the largest 1/n at which no drive can cycle at the
  default 500 Hz (forearm 465, bicep 449, torso 427 Hz); after the same motion the tool
  comes to rest 4.5 mm on (it lagged the command), and every arm joint stays
  overdamped (kv / (2 sqrt(kp I)) 1.3-5.1 over 256 sampled configurations).
  The fingers take Menagerie's drive (kp 20, damping 2 (Menagerie's joint damping; ours
  on the drive), armature 0.1, +-30 N*m),
  not SimplerEnv's (200 N*m/rad, damping 8 since 2024-01-06 (80 in the 2023-12-19 tune),
  60 N*m, no armature: PhysX's implicit drives): without armature on the fingers' small
  inertia either damping cycles between the limits at our 2 ms step (closing from open,
  0.07 rad after 1 s, 88 rad/s). The URDF's joint speed limits (2.0 .. 3.0 rad/s arm,
  1.3 rad/s fingers, 2.0 rad/s head).
- Fingertip contact: MuJoCo Menagerie's ``trs_so_arm100`` pad values (solref 0.01 s,
  solimp "2 1 0.01", an impedance MuJoCo clamps to 0.9999), with priority; Menagerie's
  Google Robot sets none. With MuJoCo's default contact the sweep's 83 mm cube, squeezed
  at 130 N per finger (|f_t| / f_n < 0.04 against 1.0), crept 3 mm/s along the tips:
  MuJoCo's soft friction (creep about (1 - d) / d * a / b, d the impedance,
  b = 2 / (d * time constant)), not sliding. Friction on the tips: SimplerEnv's 2.0
  (``FINGER_PAD``; 1.0 until 2026-11-29, SimplerEnv's "HalfFingerFriction" variant).
- Gripper action: -1 closed (1.3 rad), +1 open (0 rad), as every built-in gripper;
  ManiSkill's mimic gripper has the opposite sign (negate that action to port a policy).
- Keyframes: ``rest`` is SimplerEnv's start pose of ``google_robot_static`` (arm, open
  fingers, head pan -0.00286 and tilt 0.785 looking down at the table); ManiSkill 3.0.1
  has no keyframe for this robot. ``stow`` folds the arm (all arm joints at 0: upright).
- Camera: ManiSkill's ``overhead_camera`` on ``link_camera`` with SimplerEnv's tuned
  intrinsics (``GoogleRobotManualTunedIntrinsicConfig``: 640 x 512, fx 425, fy 413.1,
  cx 305, cy 233 px, which SAPIEN counts from the image's edge: 304.5 and 232.5 px in our
  pixel-centre convention) at a quarter of the resolution, same field of view; near
  0.01 m and far 100 m (ManiSkill 3.0.1's defaults; SimplerEnv's own are 0.1 and 10 m).
  Until 2026-11-29 the matrix was divided by 4 as is (cx 76.25, cy 58.25 at 160 x 128):
  half a pixel right of and below SimplerEnv's view, and far was 10 m.

Geometry is primitive shapes of about the real robot's size (white chassis and column,
head with a dark face, white arm, two-finger gripper). The chassis rides 3 cm above the
floor on the planar joints; the drive wheels are passive hinges turned for show.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator, VelocityActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, Base, EndEffector, Gripper, Head
from robot_agents.registry import register_agent
from robot_agents.sensors import CameraConfig
from robot_agents.sensors.camera import Matrix3

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = (
    "joint_torso",
    "joint_shoulder",
    "joint_bicep",
    "joint_elbow",
    "joint_forearm",
    "joint_wrist",
    "joint_gripper",
)
ARM_PATTERN = "|".join(ARM_JOINTS)
FINGER_JOINTS = ("joint_finger_right", "joint_finger_left")
FINGER_PATTERN = "|".join(FINGER_JOINTS)
HEAD_PATTERN = "joint_head_pan|joint_head_tilt"
BASE_PATTERN = "root_x_axis_joint|root_y_axis_joint|root_z_rotation_joint"
WHEELS = ("joint_wheel_left", "joint_wheel_right")
#: Drive-wheel radius (m) and the distance between the wheels' contact points (m).
WHEEL_RADIUS = 0.06205
WHEEL_SEPARATION = 2 * 0.18333

#: SimplerEnv's real-to-sim arm gains ("force" drive mode; ManiSkill2_real2sim
#: ``GoogleRobotDefaultConfig`` at ef7a4d4f, the ``google_robot_static`` config), N*m/rad,
#: N*m*s/rad, N*m; torso .. gripper joint.
SIMPLER_ENV_ARM_STIFFNESS = (
    1700.0,
    1737.0471680861954,
    979.975871856535,
    930.0,
    1212.154500274304,
    432.96500923932535,
    468.0013365498738,
)
SIMPLER_ENV_ARM_DAMPING = (
    1059.9791902443303,
    1010.4720585373592,
    767.2803161582076,
    680.0,
    674.9946964336588,
    274.613381336198,
    340.532560578637,
)
SIMPLER_ENV_ARM_FORCE_LIMIT = (300.0, 300.0, 100.0, 100.0, 100.0, 100.0, 100.0)
#: Ours: the fraction of SimplerEnv's arm damping we use (see the module doc).
ARM_DAMPING_SCALE = 1.0 / 7.0
ARM_STIFFNESS = SIMPLER_ENV_ARM_STIFFNESS
ARM_DAMPING = tuple(ARM_DAMPING_SCALE * d for d in SIMPLER_ENV_ARM_DAMPING)
ARM_EFFORT = SIMPLER_ENV_ARM_FORCE_LIMIT
#: The URDF's joint speed limits (rad/s).
ARM_VELOCITY = (2.0, 2.0, 2.0, 2.5, 3.0, 3.0, 3.0)

GOOGLE_ROBOT_DRIVES = (
    VelocityActuator(joints=BASE_PATTERN, damping=(8000.0, 8000.0, 2000.0)),
    PDActuator(
        joints=ARM_PATTERN,
        stiffness=ARM_STIFFNESS,
        damping=ARM_DAMPING,
        effort_limit=ARM_EFFORT,
        velocity_limit=ARM_VELOCITY,
    ),
    PDActuator(joints=HEAD_PATTERN, stiffness=2000.0, damping=90.0, effort_limit=100.0, velocity_limit=2.0),
    PDActuator(joints=FINGER_PATTERN, stiffness=20.0, damping=2.0, effort_limit=30.0, velocity_limit=1.3, armature=0.1),
)

#: End-effector commands in ``link_base``'s frame (it moves and turns with the base); 5 cm
#: and 0.1 rad per step; absolute targets within the arm's reach (about 1.03 m from the
#: shoulder, 0.71 m above link_base) down to the floor.
GOOGLE_ROBOT_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-1.1, -1.1, -0.1), upper=(1.1, 1.1, 1.75)),
    max_translation=0.05,
    max_rotation=0.1,
)
GOOGLE_ROBOT_ARM = Arm(
    name="arm",
    joints=ARM_PATTERN,
    end_effectors=(EndEffector("link_gripper_tcp", name="tcp", command_frame="link_base"),),
    task_space=GOOGLE_ROBOT_TASK_SPACE,
)
#: Open at the URDF's lower stop; the closed state is the URDF's upper stop (1.3 rad).
#: ``grasp_frame``: ours, see the module doc.
GOOGLE_ROBOT_GRIPPER = Gripper(
    name="gripper",
    joints=FINGER_PATTERN,
    open=0.0,
    closed=1.3,
    fingers=(
        ("link_finger_right", "link_finger_tip_right"),
        ("link_finger_left", "link_finger_tip_left"),
    ),
    tolerance=0.02,
    grasp_frame="link_gripper_grasp",
)
GOOGLE_ROBOT_HEAD = Head(name="head", joints=HEAD_PATTERN)
GOOGLE_ROBOT_BASE = Base(
    name="base",
    joints=BASE_PATTERN,
    holonomic=False,
    max_speed=0.5,
    max_turn=1.0,
    wheels=WHEELS,
    wheel_radius=WHEEL_RADIUS,
    wheel_separation=WHEEL_SEPARATION,
)

#: Finger tips: SimplerEnv's static and dynamic friction 2.0
#: (``GoogleRobotDefaultConfig(finger_friction=2.0)``, the config of
#: ``google_robot_static``; the URDF's tips say ``lateral_friction`` 2.0 too). SimplerEnv
#: gives the finger links 2.0 as well; ours keep MuJoCo's 1.0: with 2.0 on them the soft
#: edge of a finger base sank 7.0 mm into the sweep's cube during the hold (the
#: penetration claim failed at every step, 2026-11-29).
FINGER_PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)

#: SimplerEnv's tuned overhead camera intrinsics (ManiSkill2_real2sim
#: ``GoogleRobotManualTunedIntrinsicConfig``; ManiSkill 3.0.1's ``googlerobot.py`` has the
#: same) for 640 x 512 images, pixels, as SAPIEN takes them: its principal point counts
#: from the image's edge (SAPIEN's centred camera has ``cx = W / 2``), ours from the first
#: pixel's centre, so in our (OpenCV) convention it is half a pixel less.
SIMPLER_ENV_INTRINSIC: Matrix3 = ((425.0, 0.0, 305.0), (0.0, 413.1, 233.0), (0.0, 0.0, 1.0))
SIMPLER_ENV_SIZE = (640, 512)


def opencv_intrinsic(sapien: Matrix3) -> Matrix3:
    """SAPIEN's intrinsic matrix (pixels, principal point from the image's edge) in the
    OpenCV convention of :class:`CameraConfig` (from the first pixel's centre)."""
    (fx, _, cx), (_, fy, cy), _ = sapien
    return ((fx, 0.0, cx - 0.5), (0.0, fy, cy - 0.5), (0.0, 0.0, 1.0))


#: ManiSkill's ``overhead_camera`` on ``link_camera`` (an optical frame, OpenCV axes: the
#: MuJoCo camera is turned 180 degrees about x), SimplerEnv's intrinsics at a quarter of
#: its 640 x 512 resolution (160 x 128: fx 106.25, fy 103.275, cx 75.75, cy 57.75 px),
#: ManiSkill 3.0.1's clipping planes (CameraConfig defaults 0.01 and 100 m).
OVERHEAD_CAMERA = CameraConfig(
    uid="overhead_camera",
    mount="link_camera",
    pos=(0.0, 0.0, 0.0),
    quat=(0.0, 1.0, 0.0, 0.0),
    width=SIMPLER_ENV_SIZE[0],
    height=SIMPLER_ENV_SIZE[1],
    intrinsic=opencv_intrinsic(SIMPLER_ENV_INTRINSIC),
    near=0.01,
    far=100.0,
).resized(160, 128)

#: SimplerEnv's google_robot_static start pose: arm (7), head pan and tilt.
REST_ARM = (
    -0.2639457174606611,
    0.0831913360274175,
    0.5017611504652179,
    1.156859026208673,
    0.028583671314766423,
    1.592598203487462,
    -1.080652960128774,
)
REST_HEAD = (-0.00285961, 0.7851361)


@register_agent()
class GoogleRobot(Agent):
    """Google Robot (Everyday Robots) on a differential base.

    Action of every mode: arm (7 joints, or the end-effector command), gripper (1), head
    (pan, tilt), base (forward speed, yaw rate). qpos order: the three planar base
    joints, the two passive drive wheels, head pan and tilt, the arm's seven joints,
    ``joint_finger_right``, ``joint_finger_left``.
    """

    uid = "google_robot"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 20 Hz control, every step;
    #: docs/timestep.md), rerun 2026-11-29 with SimplerEnv's current arm gains and a
    #: seventh of its damping: hold, end-effector tracking and penetration hold at every
    #: step from 40 Hz to 1 kHz, random actions (three seeds) from 80 Hz; grasp, with the
    #: fingertips' near-rigid contacts (``google_robot.xml``) and the grasp frame, from
    #: 160 Hz (the 77.9 mm cube moves 0.16-0.39 mm in the 2 s hold at 400 Hz-1 kHz);
    #: settle from 400 Hz (at 320 Hz the forearm cycles between its torque limits, 1.38
    #: rad/s, ``pd_joint_vel`` seed 0). The analysis of ``robot_agents.tuning.cycles``
    #: puts every drive's cycle below 465 Hz (the forearm's): default one tried step
    #: finer than the largest passing one, 500 Hz. (With the gains before, 2026-11-23:
    #: every claim from 400 Hz with three seeds, forearm cycle below 443 Hz; 500 Hz.)
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "google_robot.xml"
    actuators = GOOGLE_ROBOT_DRIVES
    parts = (GOOGLE_ROBOT_ARM, GOOGLE_ROBOT_GRIPPER, GOOGLE_ROBOT_HEAD, GOOGLE_ROBOT_BASE)
    disable_self_collisions = True
    link_materials = {"link_finger_tip_right": FINGER_PAD, "link_finger_tip_left": FINGER_PAD}
    cameras = (OVERHEAD_CAMERA,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "rest": Keyframe(qpos={ARM_PATTERN: REST_ARM, FINGER_PATTERN: 0.0, HEAD_PATTERN: REST_HEAD}),
        "stow": Keyframe(qpos={ARM_PATTERN: 0.0, FINGER_PATTERN: 0.0, HEAD_PATTERN: 0.0}),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = ["OVERHEAD_CAMERA", "WHEELS", "WHEEL_RADIUS", "WHEEL_SEPARATION", "GoogleRobot"]
