"""Where a robot's collision time goes: :func:`collision_profile` measures, over a
replayed control sequence, the share of the physics step spent in collision detection
(``MjData.timer``) and which geom pairs reach the narrow phase (pass the broad phase,
the contype/conaffinity filter and the bounding spheres) per physics step."""

from __future__ import annotations

import ctypes
import ctypes.util
import time
from collections import Counter
from dataclasses import dataclass

import mujoco
import numpy as np

from robot_agents.notes import mujoco_messages
from robot_agents.tuning.collisions import can_collide


@dataclass(frozen=True)
class CollisionProfile:
    """Collision detection's share of the physics step over a replay.

    Attributes:
        step_us: mean physics step (µs) with MuJoCo's timers on (slightly slower than
            without).
        shares: share of the step per stage: ``"collision"`` (``"broad"`` and
            ``"narrow"`` phase within it), ``"constraint"``, ``"kinematics"``.
        narrow_pairs: body-name pairs of the geom pairs reaching the narrow phase, with
            the mean number per physics step (most frequent first; ``"world"`` is the
            floor's body).
        contacts: mean contacts per physics step.
    """

    step_us: float
    shares: dict[str, float]
    narrow_pairs: dict[tuple[str, str], float]
    contacts: float


def _clock() -> object:
    """A timer for ``mjcb_time``: OpenMP's C wall clock when present (no Python in the
    step), else ``time.perf_counter``."""
    path = ctypes.util.find_library("gomp")
    if path is None:
        return time.perf_counter
    function = ctypes.CDLL(path).omp_get_wtime
    function.restype = ctypes.c_double
    function.argtypes = []
    return function


def _sphere_overlap(model: mujoco.MjModel, data: mujoco.MjData, g1: int, g2: int) -> bool:
    """MuJoCo's bounding-sphere test (``mj_filterSphere``): True when the pair goes on."""
    margin = float(model.geom_margin[g1] + model.geom_margin[g2] + model.geom_gap[g1] + model.geom_gap[g2])
    r1, r2 = float(model.geom_rbound[g1]), float(model.geom_rbound[g2])
    if r1 > 0 and r2 > 0:
        return float(np.linalg.norm(data.geom_xpos[g1] - data.geom_xpos[g2])) <= r1 + r2 + margin
    plane, other, radius = (g1, g2, r2) if r1 == 0 else (g2, g1, r1)
    normal = data.geom_xmat[plane].reshape(3, 3)[:, 2]
    return float(normal @ (data.geom_xpos[other] - data.geom_xpos[plane])) <= margin + radius


def _pair_names(model: mujoco.MjModel, g1: int, g2: int) -> tuple[str, str]:
    names = [model.body(int(model.geom_bodyid[g])).name or "world" for g in (g1, g2)]
    return (names[0], names[1])


def collision_profile(model: mujoco.MjModel, qpos: np.ndarray, ctrl: np.ndarray, substeps: int) -> CollisionProfile:
    """Replay ``ctrl`` (one row per control step, ``substeps`` physics steps each) from
    ``qpos`` twice: once with MuJoCo's timers on, once recording the narrow-phase pairs
    (a contact filter callback; the contype/conaffinity and bounding-sphere tests
    reproduced). Sets and clears MuJoCo's global ``mjcb_time`` and
    ``mjcb_contactfilter``; not thread-safe."""
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.set_mjcb_time(_clock())
    contacts = 0
    try:
        with mujoco_messages("collision_profile"):
            for row in ctrl:
                data.ctrl[:] = row
                for _ in range(substeps):
                    mujoco.mj_step(model, data)
                    contacts += data.ncon
    finally:
        mujoco.set_mjcb_time(None)
    timers = mujoco.mjtTimer
    total = float(data.timer[int(timers.mjTIMER_STEP)].duration)
    steps = len(ctrl) * substeps

    def share(*which: mujoco.mjtTimer) -> float:
        return sum(float(data.timer[int(t)].duration) for t in which) / total

    shares = {
        "collision": share(timers.mjTIMER_POS_COLLISION),
        "broad": share(timers.mjTIMER_COL_BROAD),
        "narrow": share(timers.mjTIMER_COL_NARROW),
        "constraint": share(timers.mjTIMER_CONSTRAINT, timers.mjTIMER_POS_MAKE),
        "kinematics": share(timers.mjTIMER_POS_KINEMATICS),
    }
    seen: Counter[tuple[str, str]] = Counter()

    def record(m: mujoco.MjModel, d: mujoco.MjData, g1: int, g2: int) -> int:
        if not can_collide(m, g1, g2):
            return 1
        if _sphere_overlap(m, d, g1, g2):
            seen[_pair_names(m, g1, g2)] += 1
        return 0

    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.set_mjcb_contactfilter(record)
    try:
        with mujoco_messages("collision_profile"):
            for row in ctrl:
                data.ctrl[:] = row
                mujoco.mj_step(model, data, nstep=substeps)
    finally:
        mujoco.set_mjcb_contactfilter(None)
    narrow = {pair: count / steps for pair, count in seen.most_common()}
    return CollisionProfile(total / steps * 1e6, shares, narrow, contacts / steps)
