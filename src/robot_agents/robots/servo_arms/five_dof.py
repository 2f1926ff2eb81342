"""End-effector position control of a 5-DoF arm.

The library's position modes (``pd_ee_delta_pos``, ``pd_ee_target_delta_pos``) hold the
tool's orientation: their IK solves for position and orientation together. A 5-DoF
arm cannot hold a full orientation while its tool moves (turning the base turns the
tool), so that solve fails whenever the base must turn. For these arms the held
orientation is made a soft preference instead: IK weighs it 0.01 m per rad (a 1 mm
position error outweighs a 0.1 rad orientation error) and does not require it
(tolerance pi), so a solve succeeds when the position is within 1 mm and, among the
postures that reach it, prefers the one that keeps the jaw's orientation.
"""

from __future__ import annotations

import math

from robot_agents.kinematics.ik_config import IKConfig

#: IK settings of the end-effector position modes of a 5-DoF arm (see the module doc).
POSITION_IK = IKConfig(rotation_weight=0.01, rotation_tolerance=math.pi)

__all__ = ["POSITION_IK"]
