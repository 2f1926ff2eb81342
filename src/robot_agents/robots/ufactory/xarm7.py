"""UFactory xArm7 with the PSYONIC Ability Hand (``xarm7_ability``, as ManiSkill's).

Sources of the numbers:
- ManiSkill 3.0.1's agent (``mani_skill/agents/robots/xarm/xarm7_ability.py``): uid, the
  ``rest`` keyframe (arm (0, -0.4, 0, 0.5, 0, 0.9, -3.0) rad, the hand's joints 0), the
  end-effector link ``base`` (the hand's wrist), the hand's ``hand_target_delta_pos`` in
  every mode (+-0.1 rad from its targets), the arm's joint and end-effector modes
  (+-0.1 rad, 0.1 m, 0.1 rad per step). Its gains (arm kp 1000, kv 100, 500 N*m; hand kp
  1000, kv 100, 50 N*m) are PhysX's; see below for ours.
- Kinematics, joint ranges, torque and speed limits, inertials: UFactory's
  ``xarm_description`` as ManiSkill's ``assets/robots/xarm7/xarm7_ability_right_hand.urdf``
  gives it (MuJoCo Menagerie's ``ufactory_xarm7/xarm7.xml``, commit 4f04d622, has the same
  joint origins, ranges, masses and principal inertias): see assets/xarm7.xml. Torque
  limits 50, 50, 30, 30, 30, 20, 20 N*m, 3.14 rad/s on every joint.
- The hand: our Ability Hand piece (robot_agents/robots/psyonic/ability_hand.py, its
  sources there), its wrist ``base`` on ``link7`` turned +pi/2 about z, as the URDF's
  ``joint_eef`` (rpy 0 0 1.57079, no offset).
- Gains: MuJoCo Menagerie's xArm7 (``size1`` / ``size2`` / ``size3`` classes: kp 1500 /
  1000 / 800 N*m/rad on joints 1-2 / 3-5 / 6-7, kv = kp / 10, force ranges 50 / 30 / 20
  N*m as the URDF's) and its armature, 0.1 kg*m^2 per joint, on top of exact gravity
  compensation, as our xArm6 (robots/ufactory/xarm6.py). ManiSkill's kp 1000 / kv 100 is
  of the same order.
- End-effector commands: absolute positions bounded by the xArm6's box (the xArm7's
  reach, 700 mm, is the xArm6's), grown by nothing: the end effector is the wrist on the
  flange.

- Link shapes: cylinders and boxes fitted to the extents of each link's collision mesh
  in ManiSkill's xarm7 assets (assets/xarm7.xml), massless; the hand's as its piece's.

Keyframe ``rest``: ManiSkill's (arm (0, -0.4, 0, 0.5, 0, 0.9, -3.0) rad, the hand pointing
down, every hand joint 0 with the distal joints where the coupling puts them).

Control modes: generated from the parts: the arm's six joint modes and five end-effector
modes (on the wrist ``base``), ManiSkill's four (``pd_joint_delta_pos``, the default,
``pd_joint_pos``, ``pd_ee_delta_pose``, ``pd_ee_target_delta_pose``) among them; the
hand's six motors take +-0.1 rad deltas from their targets, as ManiSkill's
``hand_target_delta_pos`` (ManiSkill drives all ten hand joints so, the distal ones too;
here they follow through the coupling), except where the arm's targets are absolute
(``pd_joint_pos``, ``pd_joint_pos_vel``, ``pd_ee_pose``): there the hand's are absolute
too (the library's rule for a hand riding on an arm; ManiSkill keeps the deltas in its
``pd_joint_pos``). The hand's qpos order is MuJoCo's depth-first
one (ManiSkill's: breadth-first).

Grasp (tests/test_xarm7_ability.py): at the rest pose the hand's power grasp holds the
3 cm, 27 g cube: the contact forces carry its weight (2 %) and lifting it 5 cm with
``pd_ee_delta_pose`` moves it 0.5 mm in the wrist's frame. With the hand pointing down
the palm takes part of the load: after the lift the thumb's and the index's forces are
94 deg apart, just short of ``is_grasping``'s 95 (it holds before the lift); the sweep's
grasp claim (1 g pull away from the palm) counts the slip, 1.08 mm at 640 Hz (0.65 at
500 Hz), and reports the fingers' forces as not opposed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.parts.declaration import Arm, EndEffector
from robot_agents.registry import register_agent
from robot_agents.robots.psyonic import ability_hand

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 8))
#: The flange body: tools are attached here (z out of the flange face).
FLANGE = "link7"

#: Menagerie's PD servos by joint size (kp N*m/rad, kv N*m*s/rad), the URDF's torque
#: limits (N*m) and 3.14 rad/s.
XARM7_DRIVES = PDActuator(
    joints="joint[1-7]",
    stiffness=(1500.0, 1500.0, 1000.0, 1000.0, 1000.0, 800.0, 800.0),
    damping=(150.0, 150.0, 100.0, 100.0, 100.0, 80.0, 80.0),
    effort_limit=(50.0, 50.0, 30.0, 30.0, 30.0, 20.0, 20.0),
    velocity_limit=3.14,
    armature=0.1,
)

#: ManiSkill's delta bounds (10 cm, 0.1 rad per step); absolute positions in the xArm6's box.
XARM7_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-0.8, -0.8, -0.5), upper=(0.8, 0.8, 1.1)),
    max_translation=0.1,
    max_rotation=0.1,
)

#: The hand's wrist on the flange: turned +pi/2 about z (the URDF's joint_eef, 1.57079 rad).
HAND_ON_FLANGE = (math.cos(1.57079 / 2), 0.0, 0.0, math.sin(1.57079 / 2))
#: ManiSkill's rest pose of the arm (rad).
REST_ARM = (0.0, -0.4, 0.0, 0.5, 0.0, 0.9, -3.0)


@register_agent()
class XArm7Ability(Agent):
    """UFactory xArm7 with the PSYONIC Ability Hand on its flange, composed at load; end
    effector ``tcp`` = the hand's wrist ``base`` (ManiSkill's ee link).

    qpos order: ``joint1``..``joint7``, then the hand's :data:`ability_hand.JOINTS`.
    """

    uid = "xarm7_ability"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 xarm7_ability``,
    #: 2026-11-29 18:34-18:38 UTC, 20 Hz control; the same figures declared at 500 Hz):
    #: every claim holds from 2 ms (500 Hz: random 0.092 rad, settle 5.2e-4 rad/s, grasp
    #: slip 0.65 mm, deepest contact 0.40 mm) to 1 kHz; at 400 Hz and coarser the settle
    #: claim fails (0.38 rad/s at 400 Hz: joint 1 can cycle between its torque limits
    #: below 550 Hz, ``robot_agents.tuning.cycles``, as the xArm6's), at 100 Hz and
    #: coarser random actions press past a limit. Default one tried step finer, 640 Hz,
    #: above joint 1's cycle bound (as ``xarm6_nogripper``'s); grasp slip 1.08 mm there.
    sim_freq: ClassVar[int | None] = 640
    mjcf_path = ASSETS / "xarm7.xml"
    attachments: ClassVar[Sequence[Attachment]] = (
        Attachment(ability_hand.AbilityHandRight, at=FLANGE, quat=HAND_ON_FLANGE),
    )
    actuators = (XARM7_DRIVES,)
    parts = (
        Arm(
            name="arm",
            joints="joint[1-7]",
            end_effectors=(EndEffector(ability_hand.WRIST, name="tcp"),),
            task_space=XARM7_TASK_SPACE,
            max_delta=0.1,
        ),
    )
    keyframes = {"rest": Keyframe(qpos={"joint[1-7]": REST_ARM, **ability_hand.REST})}
    default_control_mode = "pd_joint_delta_pos"
    task_limits: ClassVar[Mapping[str, str]] = {
        "PickCube-v1": (
            "the generic scripted solver closes two opposed jaws on the cube from above; the jaw "
            "geometry the task derives from the hand's five fingers has no approach axis and the solver "
            "succeeds in 0 of 20 seeds (measured 2026-11-29 18:34 UTC); the hand holds a cube in its own "
            "power grasp (tests/test_xarm7_ability.py)"
        ),
        "PushCube-v1": (
            "the generic scripted solver, written for grippers, pushes with the tool's end effector, here "
            "ManiSkill's, the hand's wrist, with the fingers 18 cm beyond it; it succeeds in 10 of 20 seeds "
            "(measured 2026-11-29 18:34 UTC; 18 needed)"
        ),
    }


__all__ = ["ARM_JOINTS", "FLANGE", "HAND_ON_FLANGE", "REST_ARM", "XARM7_DRIVES", "XArm7Ability"]
