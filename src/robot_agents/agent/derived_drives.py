"""What a robot's derived drives learn from its file at check time, beyond its
inertia: the configurations a fixed robot's gains are derived over
(:func:`drive_configurations`), the load note for joints whose dry-friction floor the stability bound capped
(:func:`note_friction_cap`), and a floating robot's stance (:func:`stand`), which
stiffens the legs that carry its weight. Called by
:func:`robot_agents.agent.declaration.check` (their warnings' ``stacklevel`` counts that
call: they point at its caller)."""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.actuators.gains import FRICTION_STALL, SuggestedGains, stance_gains
from robot_agents.agent.derived import random_configurations
from robot_agents.agent.index import JointKind, RobotIndex
from robot_agents.agent.stance import find_stance

#: Configurations a fixed robot's derived gains are taken over, besides its default
#: keyframe (fixed seed: the gains are deterministic).
DRIVE_SAMPLES = 256


def drive_configurations(
    model: mujoco.MjModel, index: RobotIndex, joints: Sequence[str], reference: np.ndarray
) -> np.ndarray:
    """``(DRIVE_SAMPLES + 1, nq)`` configurations: ``reference`` (the robot's default
    keyframe in the model's ``qpos``) first, then :data:`DRIVE_SAMPLES` of
    :func:`~robot_agents.agent.derived.random_configurations` over ``joints``
    (:func:`robot_agents.actuators.gains.gains_over_configurations`)."""
    samples = random_configurations(model, index, joints, reference, DRIVE_SAMPLES, "drive_configurations")
    return np.vstack([reference, samples])


def note_friction_cap(
    name: str, index: RobotIndex, gains: SuggestedGains, capped: Sequence[str], timestep: float
) -> None:
    """A load note for derived drives whose friction floor (:func:`friction_gains`) the
    stability bound at ``timestep`` (s) capped: per joint of ``capped``, its dry friction,
    the ``kp`` that friction asks for, the ``kp`` given, and how far friction may stop it."""
    friction = gains.passive_friction if gains.passive_friction is not None else np.zeros(len(gains.joints))
    lines = []
    for joint in capped:
        i = gains.joints.index(joint)
        slide = index.joint(joint, name).kind is JointKind.SLIDE
        force, stiffness, length = ("N", "N/m", "m") if slide else ("N*m", "N*m/rad", "rad")
        wanted, given = friction[i] / FRICTION_STALL, gains.stiffness[i]
        lines.append(
            f"{joint} (frictionloss {friction[i]:.3g} {force}: kp {wanted:.3g} {stiffness} wanted, {given:.3g} given; "
            f"friction may stop it up to {friction[i] / given:.3g} {length} from its target)"
        )
    warnings.warn(
        f"{name}: its derived drives cannot hold every joint within {FRICTION_STALL:g} rad (m) of its target against "
        f"the file's dry friction: the stability bound at the {timestep:g} s step caps kp for {', '.join(lines)}. "
        "Add armature to light joints, or raise sim_freq.",
        RuntimeWarning,
        stacklevel=4,
    )


def stand(
    name: str,
    spec: mujoco.MjSpec,
    index: RobotIndex,
    gains: SuggestedGains,
    qpos: np.ndarray,
    timestep: float,
    cone: str,
    mount_quat: np.ndarray | None = None,
) -> tuple[SuggestedGains, tuple[str, ...]]:
    """Derived ``gains`` of a floating robot stiffened to carry its weight where it stands
    at ``qpos`` (:func:`robot_agents.agent.stance.find_stance`,
    :func:`robot_agents.actuators.gains.stance_gains`), and the joints that carry it (its
    legs; empty, with the gains unchanged, for a robot that does not stand on its joints'
    bodies: a floating arm rests on its base). A note says when its locked body does not
    come to rest, when a joint's static torque exceeds its effort limit (it cannot stand)
    and when the stability bound caps a stiffness. ``spec``: the robot's, with its
    self-collision filtering; ``timestep`` (s) and friction ``cone``: its scene's.
    Warnings point at the caller of :func:`~robot_agents.agent.declaration.check`."""
    found = find_stance(spec, index, gains.joints, qpos, timestep, cone, name, mount_quat)
    if isinstance(found, str):
        if "not at rest" in found or "diverged" in found:
            warnings.warn(
                f"{name}: {found}; its derived drives keep the gains of its legs' own inertia, which may not carry "
                "its weight (declare actuators, or a keyframe it stands in).",
                RuntimeWarning,
                stacklevel=4,
            )
        return gains, ()
    stiff, capped = stance_gains(gains, found.torque, found.lever, found.reflected, timestep)
    over = [
        f"{j} {abs(t):.3g} > {e:.3g}"
        for j, t, e in zip(found.joints, found.torque, gains.effort_limit, strict=True)
        if abs(t) > e
    ]
    if over:
        warnings.warn(
            f"{name}: standing at its default keyframe, joints carry more torque than their effort limits "
            f"({', '.join(over)}): it cannot stand there (the limits are the file's and stay).",
            RuntimeWarning,
            stacklevel=4,
        )
    if capped:
        warnings.warn(
            f"{name}: the stiffness that would carry its weight is capped by the stability bound at the "
            f"{timestep:g} s step for {', '.join(capped)}: they give more under the load (add armature to light "
            "joints, or raise sim_freq).",
            RuntimeWarning,
            stacklevel=4,
        )
    return stiff, found.legs
