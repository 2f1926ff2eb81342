"""Robotiq 2F-85 adaptive gripper: a piece to mount on arms, and the gripper alone on a
floating mount (``floating_robotiq_2f_85_gripper``).

Sources of the numbers:
- Datasheet (Robotiq 2F-85 & 2F-140 instruction manual, section 6.1 "Specifications";
  robotiq.com 2F-85 product page): stroke 85 mm, grip force 20-235 N, closing speed
  20-150 mm/s, gripper mass 925 g.
- Linkage geometry, joint ranges, masses and inertias: MuJoCo Menagerie's
  ``robotiq_2f85/2f85.xml`` (google-deepmind/mujoco_menagerie), read as data, which in
  turn comes from Robotiq's public ROS description
  (``robotiq_2f_85_gripper_visualization``, ros-industrial). Per side, in the base
  frame (x along the hinge axes, y across the fingers, z along them): driver hinge
  at (0, +-0.0306011, 0.054904), coupler fixed on it at (0, 0.0315, -0.0041), spring
  link hinge at (0, +-0.0132, 0.0609), follower at (0, 0.055, 0.0375) on the spring
  link, pad at (0, -0.0189, 0.01352) on the follower; pad faces 85.4 mm apart open.
  Driver range 0-0.8 rad; spring link -0.2967..0.8; follower +-0.8727 (Menagerie's
  signs, ours too). Masses: base 0.777 kg; driver 9.0 g, coupler
  14.1 g, spring link 22.2 g, follower 12.5 g, pad 3.5 g per side; the coupling plate
  takes the rest of the datasheet's 925 g (25.0 g).
- Link shapes: boxes and cylinders fitted to the extents of the ROS description's
  link meshes (housing 75 mm across and 90 mm tall; coupling 75 x 14 mm; outer knuckle
  24 mm wide, outer finger 27 mm, inner knuckle 39 mm, inner finger 15 mm; pads
  22 x 8 x 37.5 mm, as Menagerie's two pad boxes).
- Parallel grip: the follower's hinge sits at (0, -0.0174011, 0.005996) in its frame
  (Menagerie: (0, -0.018, 0.0065)), 0.8 mm away, so that the linkage is an exact
  parallelogram as the ROS model's mimic joints (inner knuckle = +q, inner finger =
  -q) state: the pads stay parallel to the palm over the whole stroke. With
  Menagerie's point they turn 1.85 deg by full closure and, pressed flat on an object,
  would stretch the loop.
- Pad friction 2.0: ManiSkill's floating_robotiq_2f_85_gripper pad material.
- Floating mount: ManiSkill's ``floating_robotiq_2f_85_gripper`` (joint names, 0.5 m
  height, keyframes ``open_facing_down`` / ``open_facing_up`` / ``open_facing_side``
  with the same gripper orientations: turned pi about x, unturned, and turned pi/2
  about y), kp = 1000, kv = 100, 100 N on the mount as there.

The mechanism: per side a four-bar linkage (base, driver + coupler, follower, spring
link) closed by a ``connect`` equality at the follower's origin; the left driver
follows the right one through a joint equality, as the real gripper's single motor
drives both sides. Only the two drivers are actuated, each with half of the motor
(Menagerie splits its one actuator over both drivers the same way); the spring links
and followers are passive and follow through the loop. The real gripper's coupler
leaves its spring-loaded stop when an object meets the proximal phalanges first
(encompassing grip); here the coupler is fixed on that stop (the parallel grip).

Sign: all linkage hinges turn about +x as in Menagerie and the ROS description, so
closing is positive (driver 0 open .. 0.8 rad closed); the gripper action's -1 still
closes (the generated gripper control maps -1 onto the closed end, whichever it is).

The drive (one position servo with a force limit, split over the two drivers):
- effort_limit 6 N*m per driver: grip force 6 / (0.0575 m * sin(49.16 deg + |q|))
  = 138 N open .. 105 N closed, inside the datasheet's 20-235 N (the real gripper's
  force setting near the middle of its range).
- Speed: the drive saturates at 6 N*m while closing and the driver joints' passive
  damping (4.6 N*m*s/rad in the model file, the motor's back-EMF and the lead screw's
  drag) caps the driver at 6 / 4.6 = 1.30 rad/s: the pads close on each other at
  2 * 0.0575 m * 1.30 rad/s = 150 mm/s at most (the datasheet's full speed, read as
  the rate at which the gap between the pads closes), a full stroke in about 0.6 s.
- kp = 100 N*m/rad, kv = 0 (the passive damping damps it; overdamped, 46 ms time
  constant near the target): 0.06 rad of error saturates the drive, and the gripper
  action squeezes 0.1 rad past closed, so a grasp always presses with the full force.
- armature 0.01 kg*m^2 per driver: an estimate of the motor's rotor inertia reflected
  through the lead screw and linkage; the driver reaches its speed within 2 ms, and
  the links' own inertias (~1e-6 kg*m^2) stay stable under the stiff loop constraints
  at a 2 ms step.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Gripper
from robot_agents.registry import register_agent
from robot_agents.robots.floating_mount import MOUNT_JOINTS, mount_arm

ASSETS = Path(__file__).parent / "assets"

#: Every hinge of the two linkages, in model order: right driver, spring link,
#: follower, then the left ones.
LINKAGE_JOINTS = "(right|left)_(driver|spring_link|follower)_joint"
#: The two actuated hinges (one motor, split over both sides).
DRIVER_JOINTS = "(right|left)_driver_joint"
#: The tool centre point: a body on the gripper's axis, 0.1553 m from the coupling's
#: mounting face, where the pad centres meet when the gripper is closed.
TCP = "robotiq_tcp"

#: Driver angle when open and when closed (rad; Menagerie's 0..0.8).
OPEN = 0.0
CLOSED = 0.8
#: How far past closed the gripper action commands the drivers (rad).
SQUEEZE = 0.1

#: One position servo with a force limit, half of it on each driver (see the module
#: docstring for how the numbers follow from the datasheet).
ROBOTIQ_DRIVES = PDActuator(joints=DRIVER_JOINTS, stiffness=100.0, damping=0.0, effort_limit=6.0, armature=0.01)


def linkage_qpos(driver: float, prefix: str = "") -> dict[str, float]:
    """Keyframe entries for both linkages with the drivers at ``driver`` (rad): the
    parallelogram turns each spring link with its driver and each follower back by
    the same angle. ``prefix``: the piece's name prefix where it is attached with one.

    A keyframe that closes the gripper must name every linkage joint: the loops are
    closed by ``connect`` equalities, which keyframes do not fill in."""
    p = re.escape(prefix)
    return {f"{p}(right|left)_(driver|spring_link)_joint": driver, f"{p}(right|left)_follower_joint": 0.0 - driver}


#: The gripper part: one normalized action for both drivers (-1 closes 0.1 rad past
#: closed and squeezes, +1 opens); the passive hinges follow through the loop.
ROBOTIQ_GRIPPER = Gripper(
    name="gripper",
    joints=LINKAGE_JOINTS,
    open=OPEN,
    closed=(CLOSED, CLOSED, -CLOSED, CLOSED, CLOSED, -CLOSED),
    squeeze=SQUEEZE,
    fingers=(("right_driver", "right_spring_link"), ("left_driver", "left_spring_link")),
)

#: Silicone pads (ManiSkill's pad friction for this gripper).
PAD = FrictionMaterial(sliding=2.0, torsional=0.01, rolling=0.0001)


class Robotiq2F85(Agent):
    """The Robotiq 2F-85 alone (a piece): root body ``base_mount`` (the coupling
    plate, origin on the flange), TCP body ``robotiq_tcp``, part ``gripper``.

    qpos order: ``right_driver_joint``, ``right_spring_link_joint``,
    ``right_follower_joint``, then the same on the left.
    """

    mjcf_path = ASSETS / "robotiq_2f85.xml"
    tcp = TCP
    actuators = (ROBOTIQ_DRIVES,)
    parts = (ROBOTIQ_GRIPPER,)
    link_materials = {"right_pad": PAD, "left_pad": PAD}
    keyframes = {"open": Keyframe(qpos=linkage_qpos(OPEN))}


HALF_PI = math.pi / 2
#: The gripper on the mount: turned -pi/2 about x, so it points along +y with the
#: mount's joints at 0 (see floating_mount.xml).
GRIPPER_ON_MOUNT = (math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0)


def facing(x_rot: float, z_rot: float) -> Keyframe:
    """The mount at its origin turned ``x_rot`` about x then ``z_rot`` about z (rad), gripper open."""
    return Keyframe(
        qpos={
            "root_[xyz]_axis_joint": 0.0,
            "root_x_rot_joint": x_rot,
            "root_y_rot_joint": 0.0,
            "root_z_rot_joint": z_rot,
            **linkage_qpos(OPEN),
        }
    )


@register_agent()
class FloatingRobotiq2F85Gripper(Agent):
    """The Robotiq 2F-85 on a 6-DoF floating mount (x, y, z slides, then x, y, z hinges).

    Keyframes: ``open_facing_down`` (default; approach -z), ``open_facing_up`` (+z) and
    ``open_facing_side`` (+x); in all three the fingers close along world y.
    qpos order: the six mount joints, then the gripper's six linkage hinges.
    """

    uid = "floating_robotiq_2f_85_gripper"
    #: Time-step sweep (2026-11-23, 20 Hz control): with the pads' near-rigid contact
    #: (robotiq_2f85.xml) the gripper's claims hold from 160 Hz (contact depth 0.17 mm,
    #: grasp slip 0.2 mm). The mount's hinges limit the step: with ManiSkill's 100 N*m
    #: limit and kv 100 on 0.1 kg*m^2 of armature they could cycle between their torque
    #: limits below 498 Hz (seen at 200 Hz, 2.8 rad/s; the default was 500 Hz). The
    #: mount is a fixture, so its hinge armature is ours to choose: 0.3 kg*m^2 puts that
    #: bound at 166 Hz (``robot_agents.tuning.cycles``) and leaves the hinges' response
    #: as it was (a 1 rad step in ``pd_joint_pos``: 0.31 of it after one control step
    #: against 0.37, 90 % after five either way). Every claim then holds from 160 Hz
    #: (2026-11-23 21:37 UTC, ``python benchmarks/timestep_sweep.py
    #: floating_robotiq_2f_85_gripper``); default one tried step finer, 200 Hz, above
    #: the bound. (Without the effort limit, as the Franka Hand's mount, random actions
    #: fling the 2F-85's linkage apart: 2e5 rad/s at 200 Hz, 0.004 at 800.)
    sim_freq: ClassVar[int | None] = 200
    mjcf_path = ASSETS / "floating_mount.xml"
    attachments: ClassVar[Sequence[Attachment]] = (Attachment(Robotiq2F85, at="root", quat=GRIPPER_ON_MOUNT),)
    actuators = (PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2, effort_limit=100.0),)
    #: pd_ee_pose's box is computed on the model at build: the TCP is 0.1553 m from the
    #: hinges' common point, so +-1.1553 m.
    parts = (mount_arm(TCP),)
    keyframes = {
        "open_facing_down": facing(-HALF_PI, 0.0),
        "open_facing_up": facing(HALF_PI, 0.0),
        "open_facing_side": facing(HALF_PI, -HALF_PI),
        # the name every built-in robot has, for tasks that reset to it: facing down
        "rest": facing(-HALF_PI, 0.0),
    }
    default_control_mode = "pd_joint_delta_pos"


__all__ = [
    "DRIVER_JOINTS",
    "LINKAGE_JOINTS",
    "ROBOTIQ_DRIVES",
    "ROBOTIQ_GRIPPER",
    "TCP",
    "FloatingRobotiq2F85Gripper",
    "Robotiq2F85",
    "linkage_qpos",
]
