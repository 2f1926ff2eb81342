"""Grasp detection for any gripper or hand: opposing contact forces from two fingers.

A finger is a group of links. An object is grasped when at least two fingers each
press on it with a contact force of at least ``min_force`` (N) and two of those forces
oppose each other: the angle between them is at least ``180 - max_angle`` degrees.
This holds for parallel jaws (two pads pressing from opposite sides), linkage grippers
and multi-finger hands (thumb against fingers), and rejects an object that merely
rests on one finger or is pushed from one side.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]


def grasped(finger_forces: FloatArray, min_force: float, max_angle: float) -> BoolArray:
    """Per env, whether the finger forces ``(num_envs, fingers, 3)`` (N, each the total
    force one finger exerts on the object) make a grasp."""
    magnitude = np.linalg.norm(finger_forces, axis=2)  # (N, F)
    pressing = magnitude >= min_force
    unit = np.divide(
        finger_forces, magnitude[..., None], out=np.zeros_like(finger_forces), where=magnitude[..., None] > 0
    )
    cosines = np.einsum("nfi,ngi->nfg", unit, unit)  # (N, F, F)
    limit = math.cos(math.radians(180.0 - max_angle))
    both = pressing[:, :, None] & pressing[:, None, :]
    opposing = both & (cosines <= limit + 1e-12)
    return np.asarray(np.any(opposing, axis=(1, 2)))
