"""Wonik Robotics Allegro Hand v4, left hand (``allegro_hand_left``): the right hand
(:mod:`robot_agents.robots.wonik.allegro`) mirrored, as ManiSkill's ``allegro_hand_left``.

One model for both hands: the left one is the right hand's file mirrored across its xz
plane (y -> -y) through MjSpec when it is read (:func:`robot_agents.model.mirror.
mirror_spec`, in :meth:`AllegroHandLeft.edit_model`), so every number (links, masses,
ranges, drives, pads, the power grasp) is the right hand's and a fix to one is a fix to
both.

Sources of the numbers:
- Kinematics: Wonik's left descriptions, read as data: ``simlabrobotics/allegro_hand_ros``
  ``allegro_hand_description/allegro_hand_description_left.urdf`` (commit 5dbee2a) and
  ``Wonikrobotics-git/allegro_hand_ros2`` ``allegro_hand_hardwares/v4/description/urdf/
  allegro_hand_description_left.xacro`` (commit e6b9cbf), which agree with each other
  and with MuJoCo Menagerie's ``wonik_allegro/left_hand.xml`` (commit 1b3b0c6): the
  right hand's numbers with y negated: the index finger (``joint_0.0``-``3.0``) at
  (0, -0.0435, -0.001542) turned +5 deg about x, next to the thumb, the ring finger
  (``joint_8.0``-``11.0``) at +0.0435 turned -5 deg; the thumb's base at (-0.0182,
  -0.019333, -0.045987), rpy (0, -1.658063, +1.570796) (quaternion (0.477714, 0.521334,
  -0.521334, 0.477714)), axis +x; its proximal joint at (-0.027, -0.005, 0.0399), axis
  -z. That is the right hand mirrored, with one exception the mirror alone would not
  give: the fingers' spread joints (``joint_0.0``, ``4.0``, ``8.0``) keep the right
  hand's axis +z (a mirror turns a hinge's axis to -z), so a positive spread turns
  every finger towards +y on both hands (:data:`SPREAD_JOINTS`). Ranges are the right
  hand's in all three sources.
- Where ManiSkill's left URDF differs (``assets/robots/allegro/allegro_hand_left.urdf``
  of ManiSkill 3.0.1, read as data): it mirrors only the thumb's base frame, its two
  first axes and the palm's collision boxes; its fingers keep the right hand's places
  (``joint_0.0`` at +0.0435, the side away from the thumb), and its thumb's proximal
  joint the right hand's (-0.027, +0.005, 0.0399). We follow Wonik: ManiSkill's thumb
  tip is 10 mm from ours (along the thumb's base y), and its fingers 0-3 and 8-11
  swap places with ours (tests/test_allegro_left.py checks both).
- Everything else is the right hand's (:mod:`robot_agents.robots.wonik.allegro`):
  masses, collision shapes, pads, drives (kp 10 N*m/rad, kv 1 N*m*s/rad), armature,
  gravity compensation, the keyframes ``palm_side`` / ``palm_up`` (ManiSkill's left
  hand has the right hand's: the same joint zeros and root poses), control modes and
  the power grasp (the cube lies on the palm's centre line, y = 0, mirrored onto
  itself).
"""

from __future__ import annotations

from typing import ClassVar

import mujoco
import numpy as np

from robot_agents.model.mirror import mirror_spec
from robot_agents.registry import register_agent
from robot_agents.robots.wonik.allegro import AllegroHandRight

#: The fingers' spread joints, whose axis Wonik's left descriptions keep at +z.
SPREAD_JOINTS = ("joint_0.0", "joint_4.0", "joint_8.0")


@register_agent()
class AllegroHandLeft(AllegroHandRight):
    """Wonik Allegro Hand v4, left hand, on a fixed mount 0.5 m up (``palm_side``): the
    right hand mirrored (y -> -y, the thumb at -y).

    qpos order: ``joint_0.0`` .. ``joint_15.0`` (index, middle, ring, thumb; base,
    proximal, medial, distal each), as the right hand's.
    """

    uid = "allegro_hand_left"
    #: Time-step sweep (``python benchmarks/timestep_sweep.py --jobs 1 allegro_hand_right
    #: allegro_hand_left allegro_hand_right_touch``, 2026-11-29 18:48-18:49 UTC, 20 Hz
    #: control): every claim holds from 6.25 ms (160 Hz) down to 1 ms (random-action
    #: overshoot 0.151 rad at 160 Hz, 0.103 at 200 Hz, bound 0.25; settle at most 1.5e-4
    #: rad/s, bound 0.05; the power grasp's slip 0.13-0.16 mm; deepest contact 4.5 mm,
    #: bound 5), as the right hand's. Default one tried step finer: 200 Hz (5 ms), the
    #: right hand's. It was 320 Hz while the fingertip pads had a near-rigid contact
    #: (allegro.py): random actions then pressed ``joint_3.0`` 0.257 rad past its limit at
    #: 160 Hz (the right hand 0.150; 2026-11-29 18:15 UTC).
    sim_freq: ClassVar[int | None] = 200

    @classmethod
    def edit_model(cls, spec: mujoco.MjSpec, where: str) -> None:
        """The right hand's file mirrored across its xz plane, the spread joints'
        axes kept (Wonik's left descriptions)."""
        mirror_spec(spec, where)
        spec.modelname = "allegro_hand_left"
        for name in SPREAD_JOINTS:
            joint = spec.joint(name)
            joint.axis = -np.asarray(joint.axis)


__all__ = ["SPREAD_JOINTS", "AllegroHandLeft"]
