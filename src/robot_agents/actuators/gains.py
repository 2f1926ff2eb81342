"""Suggested PD gains from a model's own inertia: the drives of a robot whose file has
no actuators and whose definition declares none, and a starting point for users
writing their own declarations.

For each joint the effective inertia ``I`` is the diagonal of MuJoCo's joint-space
inertia matrix (armature included) at a pose; a critically damped second-order
response at bandwidth ``f`` gives

    kp = I * (2 pi f)^2,    kv = 2 * zeta * I * (2 pi f)

(N*m/rad and N*m*s/rad for hinges, N/m and N*s/m for slides). The default 10 Hz keeps
``omega * dt`` at 0.13 for the library's 2 ms step (MuJoCo integrates the damping
implicitly; the stiffness term is what limits the step), fast enough to track the
default control rate of 20 Hz. Effort limits come from the file (a URDF's
``<limit effort>``, an MJCF's ``actuatorfrcrange``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError

#: Bandwidth (Hz) and damping ratio of derived gains.
DEFAULT_BANDWIDTH_HZ = 10.0
DEFAULT_DAMPING_RATIO = 1.0


@dataclass(frozen=True)
class SuggestedGains:
    """Gains for some joints (arrays ``(n,)`` in the order of ``joints``)."""

    joints: tuple[str, ...]
    stiffness: npt.NDArray[np.float64]
    damping: npt.NDArray[np.float64]
    effort_limit: npt.NDArray[np.float64]
    inertia: npt.NDArray[np.float64]
    bandwidth_hz: float
    damping_ratio: float

    def as_dict(self) -> dict[str, tuple[float, float]]:
        """``joint -> (stiffness, damping)``."""
        return {j: (float(p), float(d)) for j, p, d in zip(self.joints, self.stiffness, self.damping, strict=True)}


def gains_from_inertia(
    model: mujoco.MjModel,
    joints: Sequence[str],
    qpos: npt.ArrayLike | None = None,
    bandwidth_hz: float = DEFAULT_BANDWIDTH_HZ,
    damping_ratio: float = DEFAULT_DAMPING_RATIO,
) -> SuggestedGains:
    """Critically damped PD gains for hinge and slide ``joints`` of ``model`` at
    configuration ``qpos`` (``(nq,)``; default: the model's reference pose)."""
    if not (isinstance(bandwidth_hz, (int, float)) and math.isfinite(bandwidth_hz) and bandwidth_hz > 0):
        raise ConfigError(f"gains_from_inertia: expected a bandwidth > 0 Hz, got {bandwidth_hz!r}.")
    if not (isinstance(damping_ratio, (int, float)) and math.isfinite(damping_ratio) and damping_ratio >= 0):
        raise ConfigError(f"gains_from_inertia: expected a damping ratio >= 0, got {damping_ratio!r}.")
    data = mujoco.MjData(model)
    if qpos is not None:
        data.qpos[:] = np.asarray(qpos, dtype=np.float64).reshape(model.nq)
    mujoco.mj_forward(model, data)
    inertia_matrix = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, inertia_matrix)  # MuJoCo >= 3.5
    except TypeError:
        mujoco.mj_fullM(model, inertia_matrix, data.qM)
    ids = []
    for name in joints:
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint < 0:
            raise ConfigError(f"gains_from_inertia: no joint {name!r} in the model.")
        if int(model.jnt_type[joint]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            raise ConfigError(f"gains_from_inertia: joint {name!r} is not a hinge or slide joint.")
        ids.append(joint)
    dofs = model.jnt_dofadr[ids]
    inertia = np.maximum(np.diag(inertia_matrix)[dofs], 1e-9)
    omega = 2.0 * math.pi * bandwidth_hz
    limited = model.jnt_actfrclimited[ids].astype(bool)
    effort = np.where(limited, np.abs(model.jnt_actfrcrange[ids]).max(axis=1), np.inf)
    return SuggestedGains(
        joints=tuple(joints),
        stiffness=inertia * omega**2,
        damping=2.0 * damping_ratio * inertia * omega,
        effort_limit=effort,
        inertia=inertia,
        bandwidth_hz=float(bandwidth_hz),
        damping_ratio=float(damping_ratio),
    )
