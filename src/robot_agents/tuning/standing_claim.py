"""The standing claim of the time-step sweep (:mod:`.claims`): a robot whose legs carry
a free base stands still, upright, on its feet alone, from each of its keyframes.

From each keyframe the robot repeats its default mode's hold action at the keyframe
(:func:`robot_agents.checks.hold_action`, taken once after the reset) for :data:`STAND_SECONDS` on the floor. The
first :data:`~robot_agents.checks.LOAD_SETTLE_SECONDS` let it settle onto its feet (drives under load give a
little: that static sag is the gains', not the step's); over the rest:

- the base (the root body) moves at most :data:`STAND_DRIFT` (m, any direction: sinking,
  sliding, drifting);
- its up axis stays within :data:`STAND_TILT` (rad) of the keyframe's, over the whole hold;
- only the feet touch anything outside the robot: a foot is the distal link of a leg (a
  body moved by a leg joint that no other leg joint follows) and the bodies fixed to it.

The claim's value is the base's movement; the tilt and the bodies touching the floor
are in its detail and fail it too. Robots with a fixed root or no dynamic ``Legs`` part
(held legs ride a kinematic base: ``spot``) make no standing claim.
"""

from __future__ import annotations

import math

import numpy as np

from robot_agents.agent import Agent
from robot_agents.checks import LOAD_SETTLE_SECONDS, hold_action, standing_leg_joints
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.tuning.claims import ClaimResult, Penetration, claim_scene

#: Seconds each keyframe is held standing; the first
#: :data:`~robot_agents.checks.LOAD_SETTLE_SECONDS` of them are left for settling.
STAND_SECONDS = 5.0
#: Largest movement of the base over the settled part of the hold (m).
STAND_DRIFT = 0.01
#: Largest angle (rad) between the base's up axis and the keyframe's, at any time.
STAND_TILT = math.radians(5.0)


def standing_claim(cls: type[Agent], sim_freq: int, control_freq: int, depth: Penetration) -> ClaimResult | None:
    """Hold each keyframe standing (see the module doc); the base's largest movement over
    the settled hold. ``None``: the robot has no legs carrying a free base."""
    if not standing_leg_joints(cls):
        return None
    mode = cls.default_mode()
    scene = claim_scene(cls, sim_freq, control_freq, mode)
    agent = scene.agents[0]
    model = scene.model
    settle_steps = round(LOAD_SETTLE_SECONDS * control_freq)
    worst_drift, worst_tilt, where = 0.0, 0.0, ""
    touching: set[str] = set()
    for name in cls.keyframe_names():
        scene.reset(keyframes=name)
        up = quat_to_matrix(agent.base_pose[0, 3:])[:, 2]
        settled: np.ndarray | None = None
        hold = hold_action(agent)  # the keyframe's targets, repeated (re-measuring would follow a sag down)
        for step in range(round(STAND_SECONDS * control_freq)):
            agent.set_action(hold)
            scene.step()
            depth.measure(scene)
            pose = agent.base_pose[0]
            tilt = math.acos(float(np.clip(quat_to_matrix(pose[3:])[:, 2] @ up, -1.0, 1.0)))
            worst_tilt = max(worst_tilt, tilt)
            touching |= {f"{model.body(b).name} ({name})" for b in agent.legs.off_feet(0, "standing_claim")}
            if step + 1 == settle_steps:
                settled = pose[:3].copy()
            elif settled is not None:
                drift = float(np.linalg.norm(pose[:3] - settled))
                if drift > worst_drift:
                    worst_drift, where = drift, name
    scene.close()
    passed = worst_drift <= STAND_DRIFT and worst_tilt <= STAND_TILT and not touching
    detail = (
        f"base moved most from {where or cls.keyframe_names()[0]!r}; "
        f"tilt {math.degrees(worst_tilt):.2f} deg (bound {math.degrees(STAND_TILT):.0f}); "
        + (f"touching the floor besides the feet: {sorted(touching)}" if touching else "feet alone on the floor")
    )
    return ClaimResult("standing", passed, worst_drift, STAND_DRIFT, detail)
