"""Boston Dynamics Spot with the Spot Arm (uid ``spot``), on Habitat's "leg" base.

Sources of the numbers:
- Names, kinematics, joint ranges and link inertials: MuJoCo Menagerie's
  ``boston_dynamics_spot/spot_arm.xml`` (read as data): the body ``body``; legs
  ``{fl,fr,hl,hr}_hip / _uleg / _lleg`` with joints ``_hx`` (about x, +-45 deg), ``_hy``
  (about y) and ``_kn`` (about y); the arm ``arm_link_sh0 .. arm_link_wr1`` with joints
  ``arm_sh0, arm_sh1, arm_el0, arm_el1, arm_wr0, arm_wr1`` and the jaw ``arm_link_fngr``
  on ``arm_f1x``. These are Boston Dynamics' URDF names (``fl.hx``,
  ``arm0.sh0``, ``arm0.f1x``; Habitat's ``hab_spot_arm.urdf``) with the dots written
  as underscores, as Menagerie does; see ``assets/spot_arm.xml`` for the joint origins.
  ``arm_f1x`` turns about +y (-1.57..0 rad, open negative) as in the public models.
- Joint limits agree with Boston Dynamics' SDK documentation ("About Spot": HX +-45 deg,
  HY -0.899..2.295 rad, +-91.5 deg about a 40 deg bias (``fr_hy`` to 2.244 rad as in
  the public models), knee 14..160 deg of flexion).
- Masses: Boston Dynamics' specification (dev.bostondynamics.com, "About Spot"): net
  weight 32.5 kg. The legs keep Menagerie's link masses (4 x 4.37 kg); the body carries
  the rest plus 2.0 kg of the arm's mount, so that with Menagerie's arm links (6.0 kg)
  the arm weighs 8 kg (the Spot Arm's published mass, as given in our brief; not found
  in the sources we could read). Total 40.5 kg.
- Drives: Menagerie's position actuators, kp 500 N*m/rad, kv 40 N*m*s/rad, force range
  +-1000 N*m, for legs and arm; reflected rotor inertias (armature) are our estimate
  (0.1 / 0.05 kg*m^2 on the big / wrist joints; none published) to keep the wrist
  drives stable at 500 Hz. The jaw's drive (kp 10 N*m/rad, kv 0.5 N*m*s/rad, 3 N*m:
  about 43 N at 7 cm from the hinge; armature 0.01 kg*m^2) is our choice (this text gave
  kp 20, kv 1, 8 N*m, the first drive's, until 2026-11-29).
- Keyframes: Habitat-lab's ``SpotRobot`` parameters (``habitat/articulated_agents/
  robots/spot_robot.py``, read at commits 0f245d8d and 10dac3b6: the same values):
  ``leg_init_params`` (hx 0, hy 0.7, kn -1.5 rad on every leg: its standing pose) and
  ``arm_init_params`` (sh0 0, sh1 -3.14, hr0 0, el0 3.0, the rest 0: the stowed arm);
  gripper open -1.56 rad / closed 0.0 rad within 0.01 rad (``gripper_open_state``,
  ``gripper_closed_state``, ``gripper_state_eps``). Habitat starts the jaw at 0.0
  (0f245d8d) or open, -1.56 (10dac3b6): our ``standing`` closes it. ``standing``:
  legs standing, arm stowed, jaw closed; ``rest`` (the default, first): legs standing,
  the arm ready (forward and down in front of the body, jaw open), where tasks start.
- Base: Habitat's "leg" base: the body rides on three planar joints (ManiSkill's mobile
  robots' names ``root_x_axis_joint``, ``root_y_axis_joint``, ``root_z_rotation_joint``)
  driven by the base velocity action, at the height the standing legs give it (0.5333 m:
  the feet 2 mm above the floor; Habitat's ``base_offset`` is 0.48 m for its model, 0.5 m
  at 0f245d8d). The legs are a held ``Legs`` part: they take no action (the action is
  arm, jaw, base, as Habitat's Spot) and their PD drives keep the pose of the last
  reset; their feet do not carry the body. Maximum speed 1.6 m/s (the specification); yaw rate 1 rad/s (ours).
- Hand camera: in the gripper's palm, in front of the housing below the jaw line,
  looking out along the gripper (``arm_link_wr1`` +x) with the image's up along its
  +z (the finger side). Habitat places its arm cameras on the same link 0.166 m out,
  inside the jaw's sweep of our primitive model, so ours sits at the housing's face.
  Image: Habitat-lab's ``arm_rgb_sensor`` (``habitat/config/habitat/simulator/
  sensor_setups/spot_agent.yaml``, unchanged since 45ff10c2, 2024-03-14): 640 x 480,
  ``hfov`` 47 deg, which is horizontal in Habitat-sim (``CameraSensor.cpp``: the near
  plane is 1 x height/width, square pixels), so a vertical 36.12 deg here. Habitat-lab
  sets no clipping planes for it; Habitat-sim's defaults are near 0.01 m, far 1000 m
  (``VisualSensor.h``). (Habitat's arm *depth* sensor is another camera, 228 x 240,
  ``hfov`` 60 deg, depth clipped to 1.7 m.)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator, VelocityActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.kinematics.rotations import FORWARD_X_UP_Z_CAMERA_QUAT
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Arm, Base, EndEffector, Gripper, Legs
from robot_agents.registry import register_agent
from robot_agents.sensors import CameraConfig

ASSETS = Path(__file__).parent / "assets"

LEGS = ("fl", "fr", "hl", "hr")
LEG_JOINTS = tuple(f"{leg}_{j}" for leg in LEGS for j in ("hx", "hy", "kn"))
LEG_PATTERN = "(fl|fr|hl|hr)_(hx|hy|kn)"
ARM_JOINTS = ("arm_sh0", "arm_sh1", "arm_el0", "arm_el1", "arm_wr0", "arm_wr1")
ARM_PATTERN = "arm_(sh0|sh1|el0|el1|wr0|wr1)"
GRIPPER_JOINT = "arm_f1x"
BASE_JOINTS = ("root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint")
BASE_PATTERN = "root_(x_axis|y_axis|z_rotation)_joint"

#: Habitat's leg_init_params (hx, hy, kn per leg, rad).
STANDING_LEGS = (0.0, 0.7, -1.5)
#: Habitat's arm_init_params without the fixed hr0 (sh0, sh1, el0, el1, wr0, wr1): stowed.
STOWED_ARM = (0.0, -3.14, 3.0, 0.0, 0.0, 0.0)
#: The arm forward and down in front of the body (ours): the gripper points down 0.7 m
#: ahead of the body's centre, 0.3 m above the floor (Spot picks from the floor); of the
#: poses tried (0.65-0.8 m ahead, 0.15-0.3 m up) the one the generic pick solver does best
#: from.
READY_ARM = (0.0, -0.536, 2.042, 0.0, 0.065, 0.0)
#: Habitat's gripper_open_state (rad): the jaw opens towards negative angles.
GRIPPER_OPEN = -1.56
GRIPPER_CLOSED = 0.0
#: The body's height above the floor on the standing legs (m): feet 2 mm clear.
BODY_HEIGHT = 0.5333

SPOT_LEG_DRIVES = PDActuator(joints=LEG_PATTERN, stiffness=500.0, damping=40.0, effort_limit=1000.0, armature=0.1)
SPOT_ARM_DRIVES = PDActuator(
    joints=ARM_PATTERN,
    stiffness=500.0,
    damping=40.0,
    effort_limit=1000.0,
    armature=(0.1, 0.1, 0.1, 0.05, 0.05, 0.05),
)
SPOT_GRIPPER_DRIVE = PDActuator(joints=GRIPPER_JOINT, stiffness=10.0, damping=0.5, effort_limit=3.0, armature=0.01)
#: The base's velocity drives (N*s/m, N*m*s/rad) on the 40.5 kg robot: a 10 ms time
#: constant in x and y.
SPOT_BASE_DRIVES = VelocityActuator(joints=BASE_PATTERN, damping=(4000.0, 4000.0, 400.0))

#: End-effector commands in the body's frame (it moves with the base): 5 cm / 0.1 rad
#: per step; absolute positions within a box around the arm's reach (0.98 m from the
#: shoulder at (0.292, 0, 0.188)).
SPOT_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-0.8, -1.0, -0.8), upper=(1.3, 1.0, 1.2)),
    max_translation=0.05,
    max_rotation=0.1,
)
#: The grasp point: 2 cm above the lower jaw's face (a 4 cm cube's centre when it rests
#: on the jaw), its far face 2 mm short of the jaw's tooth.
SPOT_ARM = Arm(
    name="arm",
    joints=ARM_PATTERN,
    end_effectors=(EndEffector("grasp_point", name="tcp", command_frame="body"),),
    task_space=SPOT_TASK_SPACE,
)
SPOT_GRIPPER = Gripper(
    name="gripper",
    joints=GRIPPER_JOINT,
    open=GRIPPER_OPEN,
    closed=GRIPPER_CLOSED,
    fingers=("arm_link_jaw", "arm_link_fngr"),
    tolerance=0.01,
)
SPOT_LEGS = Legs(name="legs", joints=LEG_PATTERN, held=True)  # no action: Habitat's leg base
SPOT_BASE = Base(
    name="base", joints=BASE_PATTERN, holonomic=True, max_speed=1.6, max_turn=1.0, dynamics="kinematic"
)  # Habitat's leg base: the body is moved, the legs hold their pose
#: The jaws' rubber-like grip.
JAW_PAD = FrictionMaterial(sliding=1.5, torsional=0.01, rolling=0.0001)

#: Habitat-lab spot_agent.yaml ``arm_rgb_sensor``: (width, height) pixels and the
#: horizontal field of view (deg).
HAND_CAMERA_SIZE = (640, 480)
HAND_CAMERA_HFOV = 47.0
#: The image we render (pixels): Habitat's view (its field of view and 4:3 aspect) at a
#: quarter of its width, the size of the other robots' 128 x 128 sensor cameras (19 times
#: fewer pixels to render each step than 640 x 480); `sensor_configs` sets another.
HAND_CAMERA_IMAGE = (160, 120)
HAND_CAMERA = CameraConfig(
    uid="hand_camera",
    mount="arm_link_wr1",
    pos=(0.101, 0.0, -0.03),
    quat=FORWARD_X_UP_Z_CAMERA_QUAT,
    width=HAND_CAMERA_SIZE[0],
    height=HAND_CAMERA_SIZE[1],
    # Habitat-sim's hfov spans the width; square pixels give the height's angle.
    fovy=math.degrees(
        2 * math.atan(math.tan(math.radians(HAND_CAMERA_HFOV / 2)) * HAND_CAMERA_SIZE[1] / HAND_CAMERA_SIZE[0])
    ),
    near=0.01,  # Habitat-sim's default planes (VisualSensor.h)
    far=1000.0,
).resized(*HAND_CAMERA_IMAGE)


def _keyframe(arm: tuple[float, ...], gripper: float) -> Keyframe:
    return Keyframe(qpos={LEG_PATTERN: STANDING_LEGS * len(LEGS), ARM_PATTERN: arm, GRIPPER_JOINT: gripper})


@register_agent()
class Spot(Agent):
    """Boston Dynamics Spot with the Spot Arm: a planar "leg" base (the legs held in
    their standing pose), a 6-DoF arm, a one-jaw gripper and a hand camera.

    qpos order: ``root_x_axis_joint``, ``root_y_axis_joint``, ``root_z_rotation_joint``,
    the legs ``fl, fr, hl, hr`` x ``hx, hy, kn``, then ``arm_sh0 .. arm_wr1`` and
    ``arm_f1x`` (model order).
    """

    uid = "spot"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23, 20 Hz control; see
    #: docs/timestep.md): every claim holds from 6.25 ms (160 Hz) down to 1 ms (grasp slip
    #: 1.0-1.2 mm, random-action joint-limit overshoot 0.02-0.13 rad) now that the jaw's
    #: limit is stiff (solreflimit 0.005 s; with MuJoCo's default 0.02 s the light jaw was
    #: thrown 0.2-0.3 rad past it at most steps); at 100 Hz the arm overshoots 1.07 rad.
    #: Default one tried step finer, 200 Hz (margin: 5 ms against 6.25 ms). (Rerun 13:15
    #: UTC, after the IK's active set lets pd_ee_pose reach targets near the body: at
    #: 800 Hz one seed's random targets press the jaw into the front-left lower leg and pry
    #: it 0.29 rad past its stop; 160-500 Hz and 1 kHz hold, and seeds 1-2 hold at 200
    #: and 800 Hz: a self-collision of that trajectory, not ordered by the step.) No standing claim: the base is kinematic (its planar
    #: joints are set from the commanded velocity) and the legs, held in their standing
    #: pose, carry no weight, so there is nothing to fall.
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = ASSETS / "spot_arm.xml"
    actuators = (SPOT_BASE_DRIVES, SPOT_LEG_DRIVES, SPOT_ARM_DRIVES, SPOT_GRIPPER_DRIVE)
    parts = (SPOT_ARM, SPOT_GRIPPER, SPOT_LEGS, SPOT_BASE)
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {"arm_link_jaw": JAW_PAD, "arm_link_fngr": JAW_PAD}
    keyframes: ClassVar[Mapping[str, Keyframe]] = {
        "rest": _keyframe(READY_ARM, GRIPPER_OPEN),
        "standing": _keyframe(STOWED_ARM, GRIPPER_CLOSED),
    }
    cameras = (HAND_CAMERA,)
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "ARM_JOINTS",
    "BASE_JOINTS",
    "BODY_HEIGHT",
    "GRIPPER_CLOSED",
    "GRIPPER_OPEN",
    "HAND_CAMERA",
    "LEG_JOINTS",
    "STANDING_LEGS",
    "STOWED_ARM",
    "Spot",
]
