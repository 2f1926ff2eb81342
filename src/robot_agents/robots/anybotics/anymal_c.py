"""ANYbotics ANYmal C (uid ``anymal_c``): a quadruped on a free (dynamic) base.

(Draft; sources filled in below.)
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import ClassVar

from robot_agents.actuators.config import PDActuator
from robot_agents.agent.agent import Agent
from robot_agents.keyframe import Keyframe
from robot_agents.parts.declaration import Legs
from robot_agents.registry import register_agent

ASSETS = Path(__file__).parent / "assets"

LEGS = ("LF", "RF", "LH", "RH")
#: ManiSkill's joint (action) order: the four HAA, the four HFE, the four KFE.
LEG_JOINTS = tuple(f"{leg}_{joint}" for joint in ("HAA", "HFE", "KFE") for leg in LEGS)
LEG_PATTERNS = ("(LF|RF|LH|RH)_HAA", "(LF|RF|LH|RH)_HFE", "(LF|RF|LH|RH)_KFE")
STANDING_QPOS = (0.03, -0.03, 0.03, -0.03, 0.4, 0.4, -0.4, -0.4, -0.8, -0.8, 0.8, 0.8)
STANDING_HEIGHT = 0.545

ANYMAL_DRIVES = PDActuator(
    joints="(LF|RF|LH|RH)_(HAA|HFE|KFE)", stiffness=400.0, damping=10.0, effort_limit=80.0, velocity_limit=7.5, friction=0.1
)
ANYMAL_LEGS = Legs(name="legs", joints=LEG_PATTERNS, max_delta=0.225)


def _standing() -> Keyframe:
    return Keyframe(qpos=dict(zip(LEG_JOINTS, STANDING_QPOS, strict=True)), base_pos=(0.0, 0.0, STANDING_HEIGHT))


@register_agent()
class AnymalC(Agent):
    """ANYbotics ANYmal C."""

    uid = "anymal_c"
    mjcf_path = ASSETS / "anymal_c.xml"
    fix_root_link = False
    actuators = (ANYMAL_DRIVES,)
    parts = (ANYMAL_LEGS,)
    keyframes: ClassVar[Mapping[str, Keyframe]] = {"standing": _standing(), "rest": _standing()}
    default_control_mode = "pd_joint_target_delta_pos"
    friction_cone = "elliptic"
    impratio = 100.0
