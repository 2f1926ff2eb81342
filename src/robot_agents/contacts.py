"""Contact forces between bodies, read from a MuJoCo ``MjData`` after a step."""

from __future__ import annotations

import mujoco
import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


def contact_force_between(model: mujoco.MjModel, data: mujoco.MjData, source: int, target: int) -> FloatArray:
    """Total world-frame force (N), shape ``(3,)``, that body ``source`` exerts on body
    ``target`` through their active contacts (normal and friction)."""
    total = np.zeros(3)
    wrench = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        b1, b2 = model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]
        if {b1, b2} != {source, target}:
            continue
        mujoco.mj_contactForce(model, data, i, wrench)  # in the contact frame, acting on geom2
        force = contact.frame.reshape(3, 3).T @ wrench[:3]
        total += force if b1 == source else -force
    return total
