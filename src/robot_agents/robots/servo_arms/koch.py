"""Koch v1.1: Alexander Koch's low-cost 5-DoF arm with a jaw gripper (Dynamixel servos).

Sources of the numbers:
- Kinematics, link masses, joint names and limits: the public Koch v1.1 follower URDF
  (ManiSkill 3.0.1 ``mani_skill/assets/robots/koch/follower_arm_v1.1.urdf``, from
  jess-moss/koch-v1-1), read as data into our primitive model ``assets/koch.xml`` (its
  header lists every joint origin, and why the URDF's centres of mass are not used).
  Joint and link names are the URDF's (``joint_1`` ... ``joint_6``, ``base_link`` ...
  ``gripper``, the tool frames ``gripper_tcp``, ``gripper_tcp2``, ``back_tcp``).
- Servos (the follower's bill of materials, and LeRobot's Koch follower bus):
  Dynamixel XL430-W250-T on ``joint_1`` and ``joint_2`` at 12 V, XL330-M288-T on
  ``joint_3`` to ``joint_6`` at 5 V (:mod:`.servos`): stall torques 1.5 and 0.52 N*m
  are the effort limits, no-load speeds 6.39 and 10.8 rad/s the velocity limits,
  reflected rotor inertias 0.0046 (estimated) and 0.00199 kg*m^2 (identified) the
  armatures, Coulomb frictions 0.05 and 0.0182 N*m.
- Gains: critically damped at 40 rad/s for each joint's effective inertia at ``rest``
  (armature + the joint-space mass matrix diagonal :data:`REST_LINK_INERTIA`), see
  :func:`~.servos.critically_damped_gains`: kp = 8.1, 8.8 N*m/rad on the XL430s and
  6.0 .. 3.2 N*m/rad on the XL330s, kv = 0.16 .. 0.44 N*m*s/rad. ManiSkill's Koch uses
  kp = 1000, kv = 100 on the arm in ``pd_joint_pos``. Of kv, the servos' back-EMF
  (stall torque / no-load speed: 0.235 N*m*s/rad per XL430, 0.048 per XL330) is each
  joint's own damping (``joint_damping``), outside the stall-torque limit, and the
  drive's damping the rest, 0.11 .. 0.25 (:func:`~.servos.split_damping`): at full
  torque a joint runs at most at its no-load speed (plus what gravity adds). Since
  2026-11-29; before, a saturated drive lost its damping and a full-range
  ``pd_joint_pos`` jump (benchmarks/rated_speed.py) peaked at 13.0 rad/s on
  ``joint_1``, 2.03 times the XL430's 6.39 rad/s; now 0.94 times at most (``joint_2``,
  6.0 rad/s; 10:12 UTC).
- Keyframes: ManiSkill's ``rest``, ``elevated_turn`` and ``zero``; joint delta actions of
  0.05 rad per step, as ManiSkill's.
- Self-collision exclusions: the pairs of the URDF's SRDF (the fixed finger, a body of
  its own here, counts as part of ``link_6``).
- Gripper: one moving finger (link ``gripper``, ``joint_6``) against the fixed finger
  of ``link_6``; closed at 0 rad, open at 1.6 rad. Its fingers for grasp detection are
  ``fixed_jaw`` (the fixed finger, a welded body) and ``gripper``.
- Tool centre point ``tcp``: the URDF's ``gripper_tcp`` on ``link_6`` (-0.008, 0,
  -0.065) m, between the finger tips. End-effector modes command its position only
  (5 DoF): ``pd_ee_delta_pos`` and ``pd_ee_target_delta_pos``, 2 cm per step at most,
  the held orientation only a soft preference of IK (:data:`robot_agents.kinematics.ik_config.POSITION_IK`).

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
from robot_agents.robots.servo_arms.servos import (
    XL330_M288,
    XL430_W250,
    critically_damped_gains,
    servo_values,
    split_damping,
)

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = ("joint_1", "joint_2", "joint_3", "joint_4", "joint_5")
GRIPPER_JOINT = "joint_6"
JOINTS = (*ARM_JOINTS, GRIPPER_JOINT)
#: The servo of each joint, in ``JOINTS`` order.
SERVOS = (XL430_W250, XL430_W250, XL330_M288, XL330_M288, XL330_M288, XL330_M288)

#: Diagonal of the joint-space mass matrix at ``rest`` without armature (kg*m^2), in
#: ``JOINTS`` order: what the links add to each servo's reflected inertia.
REST_LINK_INERTIA = (4.7128e-4, 8.8044e-4, 1.743e-3, 2.2210e-4, 1.2739e-5, 9.334e-6)
#: Effective inertia of each joint at ``rest``: link inertia plus armature (kg*m^2).
EFFECTIVE_INERTIA = tuple(i + a for i, a in zip(REST_LINK_INERTIA, servo_values(SERVOS, "armature"), strict=True))
STIFFNESS, DAMPING = critically_damped_gains(EFFECTIVE_INERTIA)
#: ``DAMPING`` split into the drive's share and the servos' back-EMF, each joint's own
#: (N*m*s/rad): the back-EMF acts outside the stall-torque limit.
DRIVE_DAMPING, JOINT_DAMPING = split_damping(DAMPING, SERVOS)

#: XL430-W250 on the base and shoulder, XL330-M288 from the elbow on, each under a
#: critically damped PD drive.
KOCH_DRIVES = PDActuator(
    joints="joint_[1-6]",
    stiffness=STIFFNESS,
    damping=DRIVE_DAMPING,
    joint_damping=JOINT_DAMPING,
    effort_limit=servo_values(SERVOS, "stall_torque"),
    velocity_limit=servo_values(SERVOS, "no_load_speed"),
    armature=servo_values(SERVOS, "armature"),
    friction=servo_values(SERVOS, "friction"),
)

KOCH_ARM = Arm(
    name="arm",
    joints="joint_[1-5]",
    end_effectors=(EndEffector("gripper_tcp", name="tcp"),),
    # absolute positions: a box around the reach (0.33 m from the shoulder at z = 0.056 m)
    task_space=TaskSpace(
        position_bounds=WorkspaceBox(lower=(-0.4, -0.45, -0.3), upper=(0.4, 0.3, 0.45)),
        max_translation=0.02,
        ik=POSITION_IK,
        modes=("pd_ee_delta_pos", "pd_ee_target_delta_pos"),
    ),
    max_delta=0.05,
)
#: -1 closes 0.3 rad past the closed finger (squeezes), +1 opens it fully.
KOCH_GRIPPER = Gripper(
    name="gripper",
    joints=GRIPPER_JOINT,
    open=1.6,
    closed=0.0,
    squeeze=0.3,
    fingers=("fixed_jaw", "gripper"),
)

REST = (0.0, 2.2, 3.017, -0.25, 0.0, 0.6044)


@register_agent()
class Koch(Agent):
    """Koch v1.1 follower arm: XL430-W250 base and shoulder, XL330-M288 elbow, wrist
    and gripper.

    qpos order: ``joint_1`` (base yaw) ... ``joint_5`` (wrist roll), ``joint_6`` (gripper).
    """

    uid = "koch-v1.1"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23, 20 Hz control, every
    #: step): with the pads' near-rigid contact (koch.xml) every claim holds from 12.5 ms
    #: (80 Hz) down to 1 ms (grasp slip 1.2 mm at 80 Hz, 0.1 mm at 200 Hz; it was 2.5 mm
    #: at 200 Hz with the softer pads, whose claims held only from 320 Hz; joint-limit
    #: overshoot 0.09-0.2 rad). The critically damped 0.2 rad joint step
    #: (tests/test_servo_arms.py) overshoots past 1 mrad at 100-200 Hz and holds at
    #: 320 Hz: default 320 Hz (was 400), set by that test, not by the claims' margin.
    #: Rerun 2026-11-29 10:15 UTC after the back-EMF became the joints' damping: every
    #: claim still holds from 80 Hz (joint-limit overshoot 0.062 rad at 320 Hz, was 0.12).
    sim_freq = 320
    mjcf_path = ASSETS / "koch.xml"
    actuators = (KOCH_DRIVES,)
    parts = (KOCH_ARM, KOCH_GRIPPER)
    self_collision_exclusions = (
        ("link_1", "link_2"),  # link_1 is welded to the base, so MuJoCo does not filter it as link_2's parent
        ("link_6", "link_4"),
        ("fixed_jaw", "link_4"),
        ("link_1", "link_3"),
        ("gripper", "link_3"),
        ("gripper", "link_4"),
        ("gripper", "link_5"),
    )
    keyframes = {
        "rest": Keyframe(qpos={"joint_[1-6]": REST}),
        "elevated_turn": Keyframe(qpos={"joint_[1-6]": (0.0, 2.2, 2.75, -0.25, -1.5707963267948966, 1.0)}),
        "zero": Keyframe(qpos={"joint_[1-6]": 0.0}),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = ["ARM_JOINTS", "EFFECTIVE_INERTIA", "GRIPPER_JOINT", "REST_LINK_INERTIA", "SERVOS", "Koch"]
