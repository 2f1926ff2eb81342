"""PSYONIC Ability Hand, right hand: a piece to mount on arms (:class:`AbilityHandRight`),
and the hand alone on a floating mount (``floating_ability_hand_right``, as ManiSkill's).

DOCSTRING-TODO
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Hand, PowerGrasp
from robot_agents.registry import register_agent
from robot_agents.robots.floating_mount import MOUNT_JOINTS, mount_arm

ASSETS = Path(__file__).parent / "assets"

#: The four fingers (each a knuckle ``<f>_q1`` and a distal joint ``<f>_q2`` that follows it).
FINGER_NAMES = ("index", "middle", "ring", "pinky")
#: Every hand joint in model order: the thumb's rotator and flexor, then each finger's
#: knuckle and distal joint.
JOINTS = ("thumb_q1", "thumb_q2", *(f"{f}_q{k}" for f in FINGER_NAMES for k in (1, 2)))
JOINT_PATTERN = r"(thumb|index|middle|ring|pinky)_q[12]"
#: The six driven joints (the real hand's six motors); the distal joints follow.
KNUCKLES = r"(index|middle|ring|pinky)_q1"
THUMB_FLEXOR = "thumb_q2"
THUMB_ROTATOR = "thumb_q1"
#: ManiSkill's mimic (and PSYONIC's linearised four-bar): ``q2 = OFFSET + RATIO * q1`` (rad).
COUPLING_OFFSET = 0.72349796
COUPLING_RATIO = 1.05851325
#: Tip links (ManiSkill's ``finger_tip_links`` order) and the pads (its ``hand_front_links``).
TIP_LINKS = ("thumb_tip", "index_tip", "middle_tip", "ring_tip", "pinky_tip")
PAD_LINKS = ("thumb_L2", "index_L2", "middle_L2", "ring_L2", "pinky_L2")
#: Each finger's links, base to tip: thumb, then the four fingers.
FINGERS = tuple((f"{f}_L1", f"{f}_L2", f"{f}_tip") for f in ("thumb", *FINGER_NAMES))
#: The palm link (ManiSkill's ``ee_link_name`` is the wrist, ``base``).
PALM = "thumb_base"
WRIST = "base"
#: The piece's tool centre point for an arm: a body on the wrist axis 0.09 m out, level
#: with the power grasp's cube (the floating robot's end effector is ManiSkill's, the wrist).
TCP = "ability_tcp"


def distal(knuckle: float) -> float:
    """The distal joint's angle (rad) the coupling gives a knuckle angle ``knuckle`` (rad)."""
    return COUPLING_OFFSET + COUPLING_RATIO * knuckle


def hand_pose(knuckles: float, rotator: float, flexor: float) -> tuple[float, ...]:
    """Every hand joint (:data:`JOINTS` order, rad): the four knuckles at ``knuckles``,
    their distal joints where the coupling puts them, the thumb at ``rotator`` / ``flexor``."""
    return (rotator, flexor, *(v for _ in FINGER_NAMES for v in (knuckles, distal(knuckles))))


def hand_qpos(knuckles: float, rotator: float, flexor: float, prefix: str = "") -> dict[str, float]:
    """Keyframe entries for :func:`hand_pose` (a keyframe must name the distal joints:
    keyframes do not fill in the coupling's equalities)."""
    return dict(zip((prefix + j for j in JOINTS), hand_pose(knuckles, rotator, flexor), strict=True))


#: Drives (see the module docstring): PSYONIC's kp, damping for a critically damped
#: response on the armature estimate, the URDF's effort and velocity limits.
STIFFNESS = 1.0
DAMPING = 0.12
ARMATURE = 0.001
FINGER_EFFORT = 6.0
FINGER_VELOCITY = 8.0677777442
ROTATOR_EFFORT = 1.2
ROTATOR_VELOCITY = 40.338888721
FINGER_DRIVES = PDActuator(
    joints=rf"{KNUCKLES}|{THUMB_FLEXOR}",
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=FINGER_EFFORT,
    velocity_limit=FINGER_VELOCITY,
    armature=ARMATURE,
)
ROTATOR_DRIVE = PDActuator(
    joints=THUMB_ROTATOR,
    stiffness=STIFFNESS,
    damping=DAMPING,
    effort_limit=ROTATOR_EFFORT,
    velocity_limit=ROTATOR_VELOCITY,
    armature=ARMATURE,
)

#: The thumb's rotator turned to face the fingers across the palm (rad; its range ends
#: at -2.094).
THUMB_OPPOSED = -2.0
#: Open: fingers stretched, the thumb opposed and stretched (standing out of the palm
#: below the grasp's cube).
OPEN = hand_pose(0.0, THUMB_OPPOSED, 0.0)
#: Closed (power grasp, rad): knuckles at 1.4 (the distal joints at 2.205 through the
#: coupling), the thumb's flexor at 1.3: on the cube the joints stop short of these
#: targets and press with kp times the remaining error.
CLOSED = hand_pose(1.4, THUMB_OPPOSED, 1.3)

#: The power grasp's cube: 3 cm, in front of the upper palm (the wrist frame's +y is out
#: of the palm, +z along the fingers), between the opposed thumb below and the curling
#: fingers above (tests/test_ability_hand.py).
GRASP_CUBE_EDGE = 0.03
POWER_GRASP = PowerGrasp(link=WRIST, cube_centre=(0.0, 0.045, 0.09), cube_edge=GRASP_CUBE_EDGE, outward=(0.0, 1.0, 0.0))

ABILITY_HAND = Hand(
    name="hand",
    joints=JOINT_PATTERN,
    open=OPEN,
    closed=CLOSED,
    fingers=FINGERS,
    max_delta=0.1,
    power_grasp=POWER_GRASP,
)

#: The distal links' pads: ManiSkill's front_finger material's dynamic friction.
PAD = FrictionMaterial(sliding=1.5, torsional=0.01, rolling=0.0001)
#: Keyframe: ManiSkill's zeros (the distal joints where the coupling puts them).
REST = hand_qpos(0.0, 0.0, 0.0)


class AbilityHandRight(Agent):
    """The Ability Hand alone (a piece): root body ``base`` (the wrist, z along the
    fingers), palm ``thumb_base``, TCP ``ability_tcp`` (:data:`TCP`), part ``hand``.

    qpos order: :data:`JOINTS`.
    """

    mjcf_path = ASSETS / "ability_hand_right.xml"
    tcp = TCP
    actuators = (FINGER_DRIVES, ROTATOR_DRIVE)
    parts = (ABILITY_HAND,)
    link_materials: ClassVar[Mapping[str, FrictionMaterial]] = {link: PAD for link in PAD_LINKS}
    #: The knuckle links sit in the palm's box at their hinges (as the real links sit in
    #: the palm's shell); only there do the hand's shapes overlap.
    self_collision_exclusions = tuple((PALM, f"{f}_L1") for f in ("thumb", *FINGER_NAMES))
    keyframes = {"rest": Keyframe(qpos=REST)}


#: The hand on the mount: turned -pi/2 about z (ManiSkill's base_joint).
HAND_ON_MOUNT = (math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))


@register_agent()
class FloatingAbilityHandRight(Agent):
    """The Ability Hand on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges).

    qpos order: the six mount joints, then :data:`JOINTS`.
    """

    uid = "floating_ability_hand_right"
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = ASSETS / "floating_mount.xml"
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(AbilityHandRight, at="root", quat=HAND_ON_MOUNT),)
    actuators = (PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2, effort_limit=100.0),)
    parts = (mount_arm(WRIST),)
    keyframes = {"rest": Keyframe(qpos={"root_.*_joint": 0.0, **REST})}
    default_control_mode = "pd_joint_pos"


__all__ = [
    "ABILITY_HAND",
    "COUPLING_OFFSET",
    "COUPLING_RATIO",
    "JOINTS",
    "POWER_GRASP",
    "TIP_LINKS",
    "AbilityHandRight",
    "FloatingAbilityHandRight",
    "distal",
    "hand_pose",
    "hand_qpos",
]
