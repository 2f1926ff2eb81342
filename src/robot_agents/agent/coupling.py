"""The range an unlimited joint has through the joints a linear joint equality ties it
to (a URDF mimic, a gear), and whether it is still periodic.

An unlimited hinge alone is periodic: ``q`` and ``q + 2 pi`` are the same pose, and the
controllers take its absolute targets modulo a turn (:mod:`robot_agents.controllers.joint`).
Tied by ``follower = c0 + c1 * leader`` to another joint, it is periodic only when a whole
turn of it is a whole turn of the other (both unlimited hinges; ``c1`` an integer when it
leads, ``1 / c1`` when it follows); tied to a limited joint, it is limited too, to the
range the other's limits give it through the equality. Only direct ties count.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


def _whole(value: float) -> bool:
    """``value`` is a nonzero integer (a whole number of turns)."""
    return value != 0.0 and math.isfinite(value) and value == round(value)


def coupled_range(model: mujoco.MjModel, joint: int) -> tuple[tuple[float, float], bool]:
    """The range (rad or m) and periodicity of the unlimited hinge or slide ``joint``
    (a compiled model's joint id) through its active linear joint equalities:
    ``((-inf, inf), hinge)`` for a joint tied to nothing, the intersection of the ranges
    its limited partners' limits give it (then not periodic), and periodic only when
    every partner turns whole turns with it. A limited joint: its own range, not
    periodic. Ties whose ranges do not overlap leave the range unlimited (the model's
    equality cannot hold them anyway)."""
    hinge = int(model.jnt_type[joint]) == int(mujoco.mjtJoint.mjJNT_HINGE)
    if bool(model.jnt_limited[joint]):
        return (float(model.jnt_range[joint, 0]), float(model.jnt_range[joint, 1])), False
    low, high, periodic = -math.inf, math.inf, hinge
    for eq in range(model.neq):
        if int(model.eq_type[eq]) != int(mujoco.mjtEq.mjEQ_JOINT) or not bool(model.eq_active0[eq]):
            continue
        follower, leader = int(model.eq_obj1id[eq]), int(model.eq_obj2id[eq])
        c0, c1 = float(model.eq_data[eq, 0]), float(model.eq_data[eq, 1])
        if joint not in (follower, leader) or leader < 0 or np.any(model.eq_data[eq, 2:5] != 0.0) or c1 == 0.0:
            continue  # a joint held at a constant, a nonlinear or a degenerate tie: not a mimic
        other = follower if joint == leader else leader
        other_hinge = int(model.jnt_type[other]) == int(mujoco.mjtJoint.mjJNT_HINGE)
        if bool(model.jnt_limited[other]):
            lo, hi = float(model.jnt_range[other, 0]), float(model.jnt_range[other, 1])
            ends = ((lo - c0) / c1, (hi - c0) / c1) if joint == leader else (c0 + c1 * lo, c0 + c1 * hi)
            low, high = max(low, min(ends)), min(high, max(ends))
            periodic = False
        elif not (other_hinge and _whole(c1 if joint == leader else 1.0 / c1)):
            periodic = False
    if low > high:
        return (-math.inf, math.inf), False
    return (low, high), periodic and math.isinf(low) and math.isinf(high)
