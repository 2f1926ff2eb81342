"""Wonik Robotics Allegro Hand v4, right hand (``allegro_hand_right``): a 16-DoF
four-finger hand bolted on a fixed mount, as ManiSkill's ``allegro_hand_right``.

Sources of the numbers:
- Product: "four fingers and sixteen independent torque-controlled joints (4 fingers x
  4 DOF ea.)", "capable of holding over 1.5 kg" (the Allegro Hand overview of Wonik's
  allegro_hand_ros package, as quoted at
  https://blog.csdn.net/weixin_52531852/article/details/124179424). The v4 user
  manual's specification table (weight, joint torque) could not be read from the
  stored corpora; no number here rests on it.
- Kinematics, joint axes and ranges: the Allegro Hand URDF (Wonik's
  ``allegro_hand_description_right``; identical in ManiSkill's
  ``assets/robots/allegro/allegro_hand_right.urdf`` and in MuJoCo Menagerie's
  ``wonik_allegro/right_hand.xml``, all read as data). Finger bases at
  (0, +-0.0435, -0.001542) turned -+5 deg about x (index, ring) and (0, 0, 0.0007)
  (middle); base (axis z) -> proximal 0.0164 -> medial 0.054 -> distal 0.0384 -> tip
  0.0267 m along z (axes y). Thumb base at (-0.0182, 0.019333, -0.045987), quaternion
  (0.477714, -0.521334, -0.521334, -0.477714) (the URDF's rpy (0, -1.658063,
  -1.570796)), axis -x; -> (-0.027, 0.005, 0.0399) axis z -> 0.0177 -> 0.0514 ->
  tip 0.0423 m (axes y). Ranges (rad): base +-0.47, proximal -0.196..1.61, medial
  -0.174..1.709, distal -0.227..1.618; thumb 0.263..1.396, -0.105..1.163,
  -0.189..1.644, -0.162..1.719 (Menagerie's actuator ctrlranges are the same).
- Masses: Wonik's official V4 description (``Wonikrobotics-git/allegro_hand_ros2``,
  ``allegro_hand_hardwares/v4/description/urdf/allegro_hand_description_right.xacro``):
  palm 0.4154 kg; per finger base 0.0119, proximal 0.065, medial 0.0355, distal
  0.0096, tip 0.0168; thumb 0.0176, 0.0119, 0.038, 0.0388, tip 0.0168: 0.9549 kg in
  all. Its inertias are placeholders (1e-4 kg*m^2 on every link, a 10 cm radius of
  gyration for a 10 g link) and ManiSkill's differ between identical fingers (its
  middle distal weighs 0.0388 kg, the index's 0.02, the ring's 0.0096), so each link's
  inertia is that of a solid box (tips: capsule) of its mass over its collision shape,
  computed by MuJoCo (link_0.0's equals ManiSkill's, which was made so).
- Joint friction and passive damping: Wonik's V4 description (``frictionloss`` 0.01
  N*m, damping 0.1 N*m*s/rad); its velocity limit, 7 rad/s, bounds the velocity modes.
- Collision shapes: Menagerie's boxes (palm 40.8 x 113 x 95 mm; links 19.6 x 27.5 mm
  in section) and fingertip capsules (radius 12 mm, the URDF's fingertip sphere).
- Fingertip pads: ManiSkill's tip material (static friction 2.0, dynamic 1.0); MuJoCo
  has one coefficient and we take the dynamic 1.0 (silicone on a dry object), with
  torsional friction (condim 4) and the near-rigid pad contact the library's other
  pads use (Menagerie's ``trs_so_arm100`` values).
- Drives: ManiSkill's PD gains, kp 400 N*m/rad and kv 10 N*m*s/rad on every joint,
  and its force limit, 50 N*m.
- Keyframes: ManiSkill's ``palm_side`` and ``palm_up``: every joint at 0 (the thumb's
  base, whose range starts at 0.263 rad, at its lower limit), the root at 0.5 m,
  unturned (fingers up, palm facing +x) or turned -pi/2 about y (palm facing up,
  fingers along -x). A fixed root cannot take a keyframe's root pose here (the mount
  is part of the compiled scene): the robot is mounted as ``palm_side``
  (:attr:`AllegroHandRight.mount_pose`) and ``palm_up`` is the same joint pose with the
  scene mounting the robot at :data:`PALM_UP_MOUNT` (``robot_poses=[PALM_UP_MOUNT]``).
- Control modes: generated from the ``Hand`` part: ManiSkill's ``pd_joint_delta_pos``
  (default, +-0.1 rad per step), ``pd_joint_pos`` (absolute targets, not normalized)
  and ``pd_joint_target_delta_pos``, plus the library's three velocity variants.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

#: ManiSkill's joint order: index 0-3, middle 4-7, ring 8-11, thumb 12-15 (model order too).
JOINTS = tuple(f"joint_{i}.0" for i in range(16))
JOINT_PATTERN = r"joint_\d+\.0"
#: Fingertip bodies in ManiSkill's order: thumb, index, middle, ring.
TIP_LINKS = ("link_15.0_tip", "link_3.0_tip", "link_7.0_tip", "link_11.0_tip")
#: Each finger's links (base to tip): index, middle, ring, thumb.
FINGERS = tuple(tuple(f"link_{4 * f + k}.0" for k in range(4)) + (f"link_{4 * f + 3}.0_tip",) for f in range(4))

#: Thumb base lower limit (rad): the keyframes' 0 clipped into the range.
THUMB_BASE_MIN = 0.263
#: Keyframe joint angles (rad): ManiSkill's zeros, the thumb's base at its lower limit.
ZERO_POSE = {r"joint_([0-9]|1[013-5])\.0": 0.0, r"joint_12\.0": THUMB_BASE_MIN}

#: Where ManiSkill puts the root (m) and the two keyframes' root orientations (w, x, y, z).
ROOT_HEIGHT = 0.5
PALM_SIDE_MOUNT = (0.0, 0.0, ROOT_HEIGHT, 1.0, 0.0, 0.0, 0.0)
PALM_UP_MOUNT = (0.0, 0.0, ROOT_HEIGHT, math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0)

#: ManiSkill's drives: kp (N*m/rad), kv (N*m*s/rad), force limit (N*m); Wonik's 7 rad/s.
STIFFNESS = 10.0
DAMPING = 1.0
EFFORT_LIMIT = 50.0
VELOCITY_LIMIT = 7.0
ALLEGRO_DRIVES = PDActuator(
    joints=JOINT_PATTERN,
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=EFFORT_LIMIT,
    velocity_limit=VELOCITY_LIMIT,
)

#: Open (rad): fingers stretched, the thumb's base turned to its upper limit (1.396 rad),
#: so that it stands up out of the palm at its wrist end, opposite the fingers, ready to
#: close over an object lying on the palm (the keyframes' thumb lies along the palm).
THUMB_OPPOSED = 1.396
OPEN = tuple(THUMB_OPPOSED if j == "joint_12.0" else 0.0 for j in JOINTS)
#: Closed (power grasp, rad): each finger's proximal at its upper limit (standing up
#: from the palm), medial and distal curled back over the palm; the thumb's medial and
#: distal curled towards the fingers. On an object in the palm the joints stop short
#: of these targets and press with kp times the remaining error.
FINGER_CLOSED = (0.0, 1.61, 1.0, 1.0)
THUMB_CLOSED = (THUMB_OPPOSED, 0.3, 0.9, 0.9)
CLOSED = FINGER_CLOSED * 3 + THUMB_CLOSED

ALLEGRO_HAND = Hand(
    name="hand",
    joints=JOINT_PATTERN,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    max_velocity=VELOCITY_LIMIT,
)

#: Fingertip pads (ManiSkill's dynamic friction of its tip material).
TIP_PAD = FrictionMaterial(sliding=1.0, torsional=0.01, rolling=0.0001)


@register_agent()
class AllegroHandRight(Agent):
    """Wonik Allegro Hand v4, right hand, on a fixed mount 0.5 m up (``palm_side``).

    qpos order: ``joint_0.0`` .. ``joint_15.0`` (index, middle, ring, thumb; base,
    proximal, medial, distal each). Fingertip bodies: :data:`TIP_LINKS`.
    """

    uid = "allegro_hand_right"
    mjcf_path = ASSETS / "allegro_hand_right.xml"
    mount_pose: ClassVar[tuple[float, ...]] = PALM_SIDE_MOUNT
    actuators = (ALLEGRO_DRIVES,)
    parts = (ALLEGRO_HAND,)
    link_materials = {tip: TIP_PAD for tip in TIP_LINKS}
    keyframes = {
        "palm_side": Keyframe(qpos=ZERO_POSE),
        "palm_up": Keyframe(qpos=ZERO_POSE),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "ALLEGRO_DRIVES",
    "ALLEGRO_HAND",
    "FINGERS",
    "JOINTS",
    "PALM_SIDE_MOUNT",
    "PALM_UP_MOUNT",
    "TIP_LINKS",
    "AllegroHandRight",
]
