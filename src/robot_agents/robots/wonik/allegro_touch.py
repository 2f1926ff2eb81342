"""Wonik Robotics Allegro Hand v4, right hand with tactile sensing
(``allegro_hand_right_touch``), as ManiSkill's ``allegro_hand_right_touch``.

The right hand (:mod:`robot_agents.robots.wonik.allegro`, every number its own) with 16
touch sensors where ManiSkill's touch agent has its 16 force-sensing resistors (FSR).

Sources:
- Where the sensors are: ManiSkill 3.0.1's ``agents/robots/allegro_hand/
  allegro_touch.py`` (``AllegroHandRightTouch``: ``palm_fsr_link_names`` then
  ``finger_fsr_link_names``, the order kept here) and its model ``assets/robots/
  allegro/variation/allegro_hand_right_fsr_simple.urdf`` (read as data): a 3 x 22.8 x
  16.8 mm pad on the palm side (+x) of the thumb's medial and distal links and tip and
  of the other fingers' proximal and medial links and tips, and four on the palm: under
  the index (``link_0.0_fsr``), middle (``link_4.0_fsr``) and ring (``link_8.0_fsr``)
  fingers and low on the palm's ring-finger side (``link_base_fsr``).
- What it reports: ManiSkill's ``fsr_impulse``, per FSR link the norm of the summed
  contact impulse on it (N*s per physics step). Here each sensor is MuJoCo's touch
  sensor (:mod:`robot_agents.sensors.touch`): the summed normal force (N) of the
  contacts on the link whose point lies inside the sensor's site, in the
  proprioception as ``touch`` ``(num_envs, 16)`` (:data:`TOUCH_NAMES`).
- How big: our links carry no separate pads (ManiSkill's FSR pads are 3 mm boxes
  standing 1.3-2.5 mm proud of the links' collision boxes), so each site covers the
  palm-side half of its link's collision shape (Menagerie's boxes and fingertip
  capsules, :mod:`robot_agents.robots.wonik.allegro`), 1 mm larger on every outer side
  (contact points lie midway through the penetration): a finger link's box of half
  extents (hx, hy, hz) gets a site from x = 0 to hx + 1 mm, hy + 1 mm and hz + 1 mm;
  a tip's capsule (radius r, half length h) one from x = 0 to r + 1 mm, r + 1 mm wide,
  h + r + 1 mm long. The palm's face (113 x 95 mm) is shared out: its upper half, under
  the fingers, in three equal strips across y (``link_0.0_fsr`` on the index side,
  +y), its lower half as ``link_base_fsr`` (ManiSkill's base pad covers only its
  ring-finger side).
- Physics: the sites are massless and do not collide, so the hand moves as the right
  hand does (its time-step sweep, keyframes and grasp hold unchanged; the sweep of this
  uid is recorded below).
"""

from __future__ import annotations

from typing import ClassVar

from robot_agents.registry import register_agent
from robot_agents.robots.wonik.allegro import AllegroHandRight
from robot_agents.sensors import TouchSensorConfig

#: How far (m) a site reaches past its collision shape's faces.
MARGIN = 0.001

#: The collision boxes' half extents (m): x (palm side), y, and z about their centre.
LINK_HALF_X = 0.0098
LINK_HALF_Y = 0.01375
#: Per sensing finger link: (half length, centre) along z (m).
LINK_BOXES = {
    "link_1.0": (0.027, 0.027),
    "link_2.0": (0.0192, 0.0192),
    "link_5.0": (0.027, 0.027),
    "link_6.0": (0.0192, 0.0192),
    "link_9.0": (0.027, 0.027),
    "link_10.0": (0.0192, 0.0192),
    "link_14.0": (0.0257, 0.0257),
    "link_15.0": (0.0157, 0.0157),
}
#: Fingertip capsules: radius, half length and centre along z (m).
TIP_RADIUS = 0.012
TIP_CAPSULES = {
    "link_3.0_tip": (0.01, -0.0077),
    "link_7.0_tip": (0.01, -0.0077),
    "link_11.0_tip": (0.01, -0.0077),
    "link_15.0_tip": (0.008, -0.0073),
}
#: The palm's collision box: centre x and half extents (m); the face is at x = 0.0111.
PALM_CENTRE_X = -0.0093
PALM_HALF = (0.0204, 0.0565, 0.0475)


def _palm_side(half_x: float) -> tuple[float, float]:
    """Centre and half extent along x of a site from x = 0 to ``half_x`` + margin."""
    half = 0.5 * (half_x + MARGIN)
    return half, half


def _link_site(link: str) -> TouchSensorConfig:
    half_z, centre_z = LINK_BOXES[link]
    centre_x, half_x = _palm_side(LINK_HALF_X)
    return TouchSensorConfig(
        f"{link}_fsr",
        link=link,
        pos=(centre_x, 0.0, centre_z),
        size=(half_x, LINK_HALF_Y + MARGIN, half_z + MARGIN),
    )


def _tip_site(link: str) -> TouchSensorConfig:
    half_length, centre_z = TIP_CAPSULES[link]
    centre_x, half_x = _palm_side(TIP_RADIUS)
    return TouchSensorConfig(
        f"{link}_fsr",
        link=link,
        pos=(centre_x, 0.0, centre_z),
        size=(half_x, TIP_RADIUS + MARGIN, half_length + TIP_RADIUS + MARGIN),
    )


def _palm_sites() -> tuple[TouchSensorConfig, ...]:
    """The palm's face shared out: lower half (``link_base_fsr``), then the upper half in
    three strips across y: index (+y), middle, ring."""
    low_x = PALM_CENTRE_X
    high_x = PALM_CENTRE_X + PALM_HALF[0] + MARGIN
    centre_x, half_x = 0.5 * (low_x + high_x), 0.5 * (high_x - low_x)
    half_z = 0.5 * (PALM_HALF[2] + MARGIN)  # each half of the face, the outer edge 1 mm out
    upper_z, lower_z = MARGIN - half_z, -2.0 * PALM_HALF[2] - MARGIN + half_z
    width = 2.0 * (PALM_HALF[1] + MARGIN)
    strip = width / 3.0
    base = TouchSensorConfig(
        "link_base_fsr", link="base_link", pos=(centre_x, 0.0, lower_z), size=(half_x, 0.5 * width, half_z)
    )
    strips = tuple(
        TouchSensorConfig(
            f"link_{finger}.0_fsr", link="base_link", pos=(centre_x, y, upper_z), size=(half_x, 0.5 * strip, half_z)
        )
        for finger, y in ((0, strip), (4, 0.0), (8, -strip))
    )
    return (base, *strips)


#: ManiSkill's order: the palm's four, then thumb, index, middle, ring from root to tip.
FSR_TOUCH = (
    *_palm_sites(),
    _link_site("link_14.0"),
    _link_site("link_15.0"),
    _tip_site("link_15.0_tip"),
    _link_site("link_1.0"),
    _link_site("link_2.0"),
    _tip_site("link_3.0_tip"),
    _link_site("link_5.0"),
    _link_site("link_6.0"),
    _tip_site("link_7.0_tip"),
    _link_site("link_9.0"),
    _link_site("link_10.0"),
    _tip_site("link_11.0_tip"),
)
#: The sensors' names: ManiSkill's FSR link names, in its order.
TOUCH_NAMES = tuple(sensor.uid for sensor in FSR_TOUCH)


@register_agent()
class AllegroHandRightTouch(AllegroHandRight):
    """The right Allegro Hand with 16 touch sensors where ManiSkill's has its FSRs:
    ``touch`` ``(num_envs, 16)`` in the proprioception, the normal force (N) on each, in
    the order of :data:`TOUCH_NAMES`."""

    uid = "allegro_hand_right_touch"
    #: Time-step sweep: see the module's record.
    sim_freq: ClassVar[int | None] = 200
    touch_sensors = FSR_TOUCH


__all__ = ["FSR_TOUCH", "TOUCH_NAMES", "AllegroHandRightTouch"]
