"""Universal Robots UR10e.

Sources of the numbers:
- Kinematics: Universal Robots' published DH parameters of the UR10e (d1 0.1807, a2
  -0.6127, a3 -0.57155, d4 0.17415, d5 0.11985, d6 0.11655 m; alpha pi/2, 0, 0, pi/2,
  -pi/2, 0), in the body frames and with the joint and body names of MuJoCo Menagerie's
  ``universal_robots_ur10e`` model (read as data; its lengths are rounded to the mm and
  its flange sits at 0.1 instead of 0.11655 m). ``base`` is the UR controller's base
  frame; ``tool0`` is DH frame 6, the flange (z out of it), as in ``ur_description``.
  ManiSkill's ``ur_10e`` (haosulab/ManiSkill-UR10e v0.1.0, commit 734bc91, Menagerie's
  model) has the same joint and link names but Menagerie's base frame, turned 90 deg
  about z from UR's: the same joint angles put its links where ours are after a -90 deg
  turn about z (tests/test_peer_assets.py).
- Joint ranges: UR10e user manual (+-360 deg; elbow +-180 deg as in ``ur_description``).
  Maximum joint speeds: 120 deg/s (base, shoulder), 180 deg/s (elbow, wrists).
  Maximum joint torques: 330, 330, 150, 54, 54, 54 N*m, Universal Robots' own
  ``Universal_Robots_ROS2_Description`` ``config/ur10e/joint_limits.yaml`` (commit
  60e6974, 2024-09-20, "Update dynamic properties", co-authored by UR: the wrists went
  from 56 to 54 N*m; 56 N*m, the older figure, is still Menagerie's and was ours until
  2026-11-29, docs/notes/robot-facts-audit.md).
- Link inertials: UR's published dynamics parameters ("DH Parameters for calculations
  of kinematics and dynamics", universal-robots.com): masses 7.369, 13.051, 3.989, 2.1,
  1.98, 0.615 kg and centres of mass in DH frames 1-6 (0.021, 0, 0.027), (0.38, 0, 0.158),
  (0.24, 0, 0.068), (0, 0.007, 0.018), (0, 0.007, 0.018), (0, 0, -0.026) m; full inertia
  tensors about the centres of mass in the DH frames' axes from the same UR commit of
  ``config/ur10e/physical_parameters.yaml``. ``ur10e.xml`` writes them in our body
  frames (``tests/test_ur_xarm.py`` checks them against the DH chain). Until 2026-11-29
  the masses were spread over the collision primitives by volume, which put the centres
  of mass up to 0.12 m (forearm) from UR's and the elbow's gravity load at 34.9 N*m
  instead of 39.3 with the arm stretched level. Base 4.0 kg (``ur_description``, "might
  be incorrect"; UR publishes none), spread over its primitives: 33.1 kg in all
  (datasheet: 33.5 kg).
- Armature: 0.1 kg*m^2 per joint, as in Menagerie's UR10e (UR publishes no gear ratios
  or rotor inertias).
- Gains: MuJoCo Menagerie's ``universal_robots_ur10e/ur10e.xml`` per joint size (read
  as data): size 4 (shoulder pan and lift) kp 4000, damping 350; size 3 (elbow) kp 3500,
  damping 200; size 2 (wrists) kp 3200, damping 30 (N*m/rad, N*m*s/rad), Menagerie's
  joint damping taken as the drives' kv. They hold every keyframe to < 1e-6 rad with
  exact gravity compensation and settle a 0.1 rad step within 0.3 s without overshoot
  (tests/test_ur_xarm.py). ManiSkill's ur_10e uses kp 1000, kv 100 (absolute targets) and
  kp 1e4, kv 1e3 (delta targets). (Before 2026-11-23 every joint had kp 5000, kv 500:
  with the wrists' 56 N*m limit (then) and 0.1 kg*m^2 armature, kv * dt / I was 10 at 2 ms, so
  a wrist drive clamped at its limit overshot its damping band every step and was left
  in a bang-bang cycle after random actions, at every step down to 1 ms; at kv 30 it is
  0.6 at 2 ms. See docs/timestep.md.)
- Keyframe ``rest``: ManiSkill's (and Menagerie's ``home``) (-pi/2, -pi/2, pi/2, -pi/2,
  -pi/2, 0): upper arm up, forearm level, flange facing down.
- Composition: :class:`UR10e` ends at its flange body ``tool0``; a tool is attached there
  and the arm part re-pointed to its TCP with :func:`with_tool`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.controllers.task_space import TaskSpace, WorkspaceBox
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Arm, EndEffector
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

ARM_JOINTS = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)
ARM_PATTERN = "|".join(ARM_JOINTS)
#: The flange body: tools are attached here (DH frame 6, z out of the flange face).
FLANGE = "tool0"

#: PD servos (kp N*m/rad, kv N*m*s/rad) with the published torque and speed limits.
UR10E_DRIVES = PDActuator(
    joints=ARM_PATTERN,
    stiffness=(4000.0, 4000.0, 3500.0, 3200.0, 3200.0, 3200.0),
    damping=(350.0, 350.0, 200.0, 30.0, 30.0, 30.0),
    effort_limit=(330.0, 330.0, 150.0, 54.0, 54.0, 54.0),
    velocity_limit=tuple(math.radians(v) for v in (120.0, 120.0, 180.0, 180.0, 180.0, 180.0)),
    armature=0.1,
)

#: End-effector commands: ManiSkill's delta bounds (10 cm, 0.1 rad per step); absolute
#: positions bounded by a box around the flange's reach (1.36 m from the shoulder at
#: z = 0.1807 m; datasheet reach 1300 mm).
UR10E_TASK_SPACE = TaskSpace(
    position_bounds=WorkspaceBox(lower=(-1.4, -1.4, -1.2), upper=(1.4, 1.4, 1.6)),
    max_translation=0.1,
    max_rotation=0.1,
)
#: The arm part; its end effector is the flange until a tool is attached.
UR10E_ARM = Arm(
    name="arm",
    joints=ARM_PATTERN,
    end_effectors=(EndEffector(FLANGE, name="flange"),),
    task_space=UR10E_TASK_SPACE,
    max_delta=0.1,
)

REST = (-math.pi / 2, -math.pi / 2, math.pi / 2, -math.pi / 2, -math.pi / 2, 0.0)


def with_tool(tcp: str, pos: Sequence[float] = (0.0, 0.0, 0.0)) -> tuple[Arm]:
    """The arm part with its end effector moved to a tool's TCP (a body or site of the
    tool, with an optional offset ``pos`` in its frame, m)."""
    tool = EndEffector(tcp, name="tcp", pos=(float(pos[0]), float(pos[1]), float(pos[2])))
    return (dataclasses.replace(UR10E_ARM, end_effectors=(tool,)),)


@register_agent()
class UR10e(Agent):
    """Universal Robots UR10e with a bare flange; its end effector ``flange`` is ``tool0``.

    qpos order: shoulder pan, shoulder lift, elbow, wrist 1, wrist 2, wrist 3.
    """

    uid = "ur_10e"
    #: Time-step sweep (benchmarks/timestep_sweep.py, 2026-11-23, 20 Hz control; see
    #: docs/timestep.md): with Menagerie's gains and stiff joint limits (ur10e.xml) every
    #: claim holds from 3.125 ms (320 Hz) down to 1 ms (random-action overshoot 0.12 rad
    #: at 320 Hz, bound 0.25); at 200 Hz the limits, whose stiffness MuJoCo bounds by
    #: the step, let the wrists 0.26 rad past. With three random-action seeds
    #: (2026-11-23 14:00 UTC rerun) wrist 3 settles at 0.076 rad/s at 320 Hz (bound
    #: 0.05) and every claim holds from 400 Hz; the shoulder pan (kv 350, 330 N*m,
    #: 0.40 kg*m^2 at its lightest) can cycle between its torque limits below 441 Hz
    #: (``robot_agents.tuning.cycles``): default one tried step finer, 500 Hz (was 400).
    #: (With MuJoCo's soft default limits the random-action claim failed at every
    #: step: 0.42-0.69 rad past +-2 pi.) With UR's link inertials and 54 N*m wrists
    #: (2026-11-29 09:22 UTC rerun, docs/timestep-sweep.md) every claim holds from
    #: 200 Hz (random 0.199 rad there, 0.316 at 160 Hz) and the shoulder pan's cycle
    #: bound is 412 Hz: the default stays 500 Hz.
    sim_freq: ClassVar[int | None] = 500
    mjcf_path = ASSETS / "ur10e.xml"
    actuators = (UR10E_DRIVES,)
    parts = (UR10E_ARM,)
    keyframes = {"rest": Keyframe(qpos={ARM_PATTERN: REST})}
    default_control_mode = "pd_joint_delta_pos"


__all__ = ["ARM_JOINTS", "FLANGE", "UR10e", "with_tool"]
