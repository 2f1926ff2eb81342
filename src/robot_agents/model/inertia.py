"""Several rigid bodies' mass properties as one body's."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


def combine_inertias(
    masses: Sequence[float], centres: Sequence[FloatArray], tensors: Sequence[FloatArray]
) -> tuple[float, FloatArray, FloatArray]:
    """Bodies of ``masses`` (kg) with centres of mass ``centres`` (``(3,)``, m) and inertia
    tensors ``tensors`` (``(3, 3)``, kg*m^2, about their own centres, in the same axes) as
    one body: its total mass, its centre of mass and its tensor about that centre
    (parallel-axis theorem). Without mass, the centre is the first body's."""
    total = float(sum(masses))
    centre: FloatArray = (
        np.asarray(masses) @ np.asarray(centres) / total if total > 0 else np.asarray(centres[0], dtype=np.float64)
    )
    combined = np.zeros((3, 3))
    for mass, position, tensor in zip(masses, centres, tensors, strict=True):
        offset = position - centre
        combined += tensor + mass * (float(offset @ offset) * np.eye(3) - np.outer(offset, offset))
    return total, centre, combined
