"""Edge values for a joint-position part's one-env calls: the part's measured positions,
previous targets and action entries at ``-0.0``, ``0.0``, the smallest subnormals, on
its bounds, past them and where a sum cancels to zero (shared by the tests of the
one-env clip and of the fused call)."""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import Any

import numpy as np

#: Values each of a part's measured positions and action entries takes in turn.
SPECIAL = (-0.0, 0.0, 0.05, -0.05, 5e-324, -5e-324, 0.5, -0.5, 1.0, -1.0, 3.0, -3.0)
#: Values the part's previous targets take in turn.
PREVIOUS = (-0.0, 0.0, 0.05)


def edge_cases(world: Any, combined: Any, name: str, seed: int = 7) -> Iterator[tuple[Any, ...]]:
    """For each combination of :data:`SPECIAL` (measured), :data:`SPECIAL` (entry) and
    :data:`PREVIOUS`: part ``name``'s joints put at the measured value (70 % of them;
    the rest random in [-1, 1]) in the world's one env, its action entries at the entry
    value scaled back through the part's action scale (70 %; the rest unscaled), the rest
    of the action random, and its ``target_qpos`` set to the previous value. Yields
    ``(k, measured, entry, previous, action (1, action_dim), the start targets)``; the
    start targets are the caller's to restore between two calls."""
    part = combined.parts[name]
    part_slice = combined.slices[name]
    data = world.physics_sources()[0]
    qpos_adr = np.asarray(part.binding.qpos_adr)
    rng = np.random.default_rng(seed)
    scale = combined._scale_row[0, part_slice]
    for k, (measured, entry, previous) in enumerate(itertools.product(SPECIAL, SPECIAL, PREVIOUS)):
        data.qpos[qpos_adr] = np.where(rng.random(len(qpos_adr)) < 0.7, measured, rng.uniform(-1, 1, len(qpos_adr)))
        world.invalidate()
        action = rng.uniform(-1.0, 1.0, (1, combined.action_dim))
        action[0, part_slice] = np.where(rng.random(scale.shape) < 0.7, entry / scale, entry)
        start_target = np.full(part.target_qpos.shape, previous)
        part.target_qpos = start_target.copy()
        yield k, measured, entry, previous, action, start_target
