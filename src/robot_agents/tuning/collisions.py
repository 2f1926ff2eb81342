"""Self-collision pairs that can never touch.

MuJoCo checks every pair of the robot's bodies for contact each physics step, except a
body and its parent, bodies welded together, and the pairs the robot excludes
(``self_collision_exclusions``). Many remaining pairs can never meet: the joints
between the two bodies cannot bring them together. :func:`never_touching_pairs` finds
them by measuring the distance between the two bodies' colliding geoms
(``mujoco.mj_geomDistance``, the convex hulls MuJoCo collides) over the joints of the
kinematic path between the bodies, the only joints that change that distance:

- a path of at most :data:`GRID_MAX_JOINTS` hinge/slide joints is sampled on a dense
  grid (:data:`GRID_POINTS_1` points for one joint, :data:`GRID_POINTS_2` per joint for
  two), and the smallest sampled distance is lowered by an allowance for what lies
  between grid points: half a grid spacing times the largest lever arm of the moved
  geoms about each joint (centre distance from the joint anchor plus bounding radius,
  the largest over the samples; 1 for a slide), summed over the joints;
- a longer path gets :data:`RANDOM_SAMPLES` seeded uniform samples, and the
  :data:`REFINED` closest are refined by a shrinking coordinate search (no allowance:
  the margin covers what sampling may miss).

Joint ranges are widened by how far a joint passes its soft limit in practice
(:data:`HINGE_OVERSHOOT`, :data:`SLIDE_OVERSHOOT`); a hinge without limits is sampled
over a full turn; an unlimited slide, ball or free joint on the path makes the pair
"may touch". Joints coupled by equality constraints or tendons (a gripper's linkage) are
sampled independently: more poses than the robot can reach, so the check errs towards
"may touch".

A pair is never touching when its bound (the smallest distance less the allowance)
stays above :data:`MARGIN` plus the geoms' own contact margins.

Excluding such pairs has not paid on any built-in robot (2026-11-23, within +-3 % of
the physics step; docs/benchmarks.md): in use their geoms stay outside each other's
bounding spheres, so MuJoCo already discards them cheaply, and each exclusion adds to
a list MuJoCo scans per broad-phase pair. Measure before declaring any.

Where a robot's collision time goes: :mod:`robot_agents.tuning.collision_profile`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from robot_agents.agent import Agent
from robot_agents.agent.declaration import build_spec
from robot_agents.errors import ConfigError
from robot_agents.model.compiling import compile_spec
from robot_agents.tuning.claims import OVERSHOOT_BOUND

#: Smallest clearance (m) a never-touching pair keeps at every sampled pose (after the
#: grid allowance). 1 cm, 500 times what sampling missed: over the 124 never-touching
#: pairs of 11 built-in robot models, ten times the random samples (another seed, four
#: times the refined starts) and two to four times the grid points lowered no pair's
#: minimum distance by more than 0.02 mm (2026-11-23, docs/benchmarks.md "Self-collision
#: pairs and the cost of collision detection"); the rest covers what the convex hulls and the sampled ranges leave out (a
#: tolerance of the geometry, not of the sampling).
MARGIN = 0.01
#: How far (rad) a hinge is sampled past each limit: the soft limits let a joint driven
#: into them pass by up to this much (robot_agents.tuning.claims.OVERSHOOT_BOUND).
HINGE_OVERSHOOT = OVERSHOOT_BOUND
#: How far (m) a slide is sampled past each limit (a finger closing at 0.1-0.5 m/s
#: passes its soft limit by a few mm).
SLIDE_OVERSHOOT = 0.01
#: Paths with at most this many joints are sampled on a grid.
GRID_MAX_JOINTS = 2
#: Grid points for a one-joint path, and per joint for a two-joint path.
GRID_POINTS_1 = 721
GRID_POINTS_2 = 61
#: Uniform samples for longer paths, and how many of the closest are refined.
RANDOM_SAMPLES = 3000
REFINED = 8
#: Distances are measured up to this (m); a pair never closer reports this.
DISTMAX = 0.25

_HINGE = int(mujoco.mjtJoint.mjJNT_HINGE)
_SLIDE = int(mujoco.mjtJoint.mjJNT_SLIDE)


@dataclass(frozen=True)
class PairDistance:
    """The closest two of the robot's bodies come over their path's joints.

    Attributes:
        bodies: the two body names, in model order.
        joints: the joints of the kinematic path between them (names).
        method: ``"grid"``, ``"random"``, or ``"unbounded"`` (a joint that cannot be
            sampled: the pair is reported as may-touch).
        samples: poses evaluated.
        min_distance: smallest geom distance found (m; :data:`DISTMAX` when farther).
        allowance: grid allowance subtracted (m; 0 for random sampling).
        margin: clearance required (m): the margin plus the geoms' contact margins.
        closest: the path's joint positions (rad or m) at the closest sampled pose.
    """

    bodies: tuple[str, str]
    joints: tuple[str, ...]
    method: str
    samples: int
    min_distance: float
    allowance: float
    margin: float
    closest: tuple[float, ...]

    @property
    def bound(self) -> float:
        """Lower bound (m) on the pair's distance: the minimum less the allowance."""
        return self.min_distance - self.allowance

    @property
    def never_touching(self) -> bool:
        """Whether the bound stays above the required clearance."""
        return self.method != "unbounded" and self.bound > self.margin


def robot_model(cls: type[Agent]) -> mujoco.MjModel:
    """The robot alone (no floor), compiled with every declared option and exclusion."""
    return compile_spec(build_spec(cls), cls.__name__)


def excluded_pairs(model: mujoco.MjModel) -> set[tuple[int, int]]:
    """Body id pairs (smaller first) the model excludes from contact."""
    pairs = set()
    for signature in model.exclude_signature:
        first, second = int(signature) >> 16, int(signature) & 0xFFFF
        pairs.add((min(first, second), max(first, second)))
    return pairs


def can_collide(model: mujoco.MjModel, g1: int, g2: int) -> bool:
    """MuJoCo's contype / conaffinity test: True when geoms ``g1`` and ``g2`` may collide."""
    return bool(
        (model.geom_contype[g1] & model.geom_conaffinity[g2]) or (model.geom_contype[g2] & model.geom_conaffinity[g1])
    )


def _geoms(model: mujoco.MjModel, body: int) -> list[int]:
    start = int(model.body_geomadr[body])
    return list(range(start, start + int(model.body_geomnum[body])))


def geom_pairs(model: mujoco.MjModel, body1: int, body2: int) -> list[tuple[int, int]]:
    """The geom pairs of two bodies whose contype/conaffinity let them collide."""
    return [(a, b) for a in _geoms(model, body1) for b in _geoms(model, body2) if can_collide(model, a, b)]


def _filtered_by_mujoco(model: mujoco.MjModel, body1: int, body2: int) -> bool:
    """MuJoCo's own body-pair filter: same weld body, or weld parent/child."""
    weld1, weld2 = int(model.body_weldid[body1]), int(model.body_weldid[body2])
    if weld1 == weld2:
        return True
    parent1 = int(model.body_weldid[model.body_parentid[weld1]])
    parent2 = int(model.body_weldid[model.body_parentid[weld2]])
    return weld1 != 0 and weld2 != 0 and (weld1 == parent2 or weld2 == parent1)


def candidate_pairs(model: mujoco.MjModel) -> list[tuple[int, int]]:
    """Body id pairs MuJoCo checks for contact in the robot alone: not filtered as
    parent/child or welded, not excluded, and with geoms that can collide."""
    excluded = excluded_pairs(model)
    pairs = []
    for body1, body2 in itertools.combinations(range(1, model.nbody), 2):
        if (body1, body2) in excluded or _filtered_by_mujoco(model, body1, body2):
            continue
        if geom_pairs(model, body1, body2):
            pairs.append((body1, body2))
    return pairs


def _ancestors(model: mujoco.MjModel, body: int) -> list[int]:
    chain = [body]
    while chain[-1] != 0:
        chain.append(int(model.body_parentid[chain[-1]]))
    return chain


def path_joints(model: mujoco.MjModel, body1: int, body2: int) -> tuple[list[int], list[int]]:
    """The joints between two bodies and their common ancestor: those moving ``body1``
    relative to it, and those moving ``body2`` (joint ids)."""
    up1, up2 = _ancestors(model, body1), _ancestors(model, body2)
    common = next(b for b in up1 if b in up2)
    sides = []
    for chain in (up1, up2):
        joints: list[int] = []
        for body in chain[: chain.index(common)]:
            start = int(model.body_jntadr[body])
            joints += list(range(start, start + int(model.body_jntnum[body])))
        sides.append(sorted(joints))
    return sides[0], sides[1]


def joint_interval(model: mujoco.MjModel, joint: int) -> tuple[float, float] | None:
    """The sampled interval of a hinge or slide joint (rad or m): its range widened by
    the overshoot; a full turn for an unlimited hinge; ``None`` when it cannot be
    sampled (an unlimited slide, a ball or free joint)."""
    kind = int(model.jnt_type[joint])
    limited = bool(model.jnt_limited[joint])
    low, high = (float(v) for v in model.jnt_range[joint])
    if kind == _HINGE:
        if not limited or high - low + 2 * HINGE_OVERSHOOT >= 2 * math.pi:
            middle = (low + high) / 2 if limited else 0.0
            return middle - math.pi, middle + math.pi
        return low - HINGE_OVERSHOOT, high + HINGE_OVERSHOOT
    if kind == _SLIDE and limited:
        return low - SLIDE_OVERSHOOT, high + SLIDE_OVERSHOOT
    return None


class _PairProbe:
    """Poses a pair's path joints and measures the distance of its geoms."""

    def __init__(self, model: mujoco.MjModel, body1: int, body2: int, joints: Sequence[int]) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.pairs = geom_pairs(model, body1, body2)
        self.qpos_adr = [int(model.jnt_qposadr[j]) for j in joints]
        self.evaluations = 0

    def distance(self, q: np.ndarray) -> float:
        """Smallest geom distance (m) with the path joints at ``q``."""
        self.data.qpos[self.qpos_adr] = q
        mujoco.mj_kinematics(self.model, self.data)
        self.evaluations += 1
        return min(float(mujoco.mj_geomDistance(self.model, self.data, a, b, DISTMAX, None)) for a, b in self.pairs)


def _lever(model: mujoco.MjModel, data: mujoco.MjData, joint: int, geoms: Sequence[int]) -> float:
    """Largest speed (m per rad, or m per m) of a point of ``geoms`` under ``joint``."""
    if int(model.jnt_type[joint]) == _SLIDE:
        return 1.0
    anchor = data.xanchor[joint]
    return max(float(np.linalg.norm(data.geom_xpos[g] - anchor)) + float(model.geom_rbound[g]) for g in geoms)


def _grid(
    probe: _PairProbe, intervals: Sequence[tuple[float, float]], moved: Sequence[list[int]], joints: Sequence[int]
) -> tuple[float, float, np.ndarray, int]:
    points = GRID_POINTS_1 if len(intervals) == 1 else GRID_POINTS_2
    axes = [np.linspace(low, high, points) for low, high in intervals]
    levers = np.zeros(len(joints))
    best, closest = math.inf, np.zeros(len(joints))
    for q in itertools.product(*axes):
        value = probe.distance(np.array(q))
        for i, joint in enumerate(joints):
            levers[i] = max(levers[i], _lever(probe.model, probe.data, joint, moved[i]))
        if value < best:
            best, closest = value, np.array(q)
    spacing = np.array([(high - low) / (points - 1) for low, high in intervals])
    return best, float(levers @ spacing / 2), closest, probe.evaluations


def _refine(probe: _PairProbe, start: np.ndarray, value: float, intervals: np.ndarray) -> tuple[float, np.ndarray]:
    """Shrinking coordinate search from ``start`` for a smaller distance."""
    q = start.copy()
    step = (intervals[:, 1] - intervals[:, 0]) / 20
    for _ in range(6):
        improved = True
        while improved:
            improved = False
            for i in range(len(q)):
                for sign in (-1.0, 1.0):
                    trial = q.copy()
                    trial[i] = np.clip(trial[i] + sign * step[i], intervals[i, 0], intervals[i, 1])
                    trial_value = probe.distance(trial)
                    if trial_value < value:
                        q, value, improved = trial, trial_value, True
        step /= 4
    return value, q


def _random(probe: _PairProbe, intervals: Sequence[tuple[float, float]], seed: int) -> tuple[float, np.ndarray, int]:
    bounds = np.array(intervals)
    rng = np.random.default_rng(seed)
    poses = rng.uniform(bounds[:, 0], bounds[:, 1], size=(RANDOM_SAMPLES, len(intervals)))
    values = np.array([probe.distance(q) for q in poses])
    best, closest = math.inf, poses[0]
    for i in np.argsort(values)[:REFINED]:
        value, q = _refine(probe, poses[i], float(values[i]), bounds)
        if value < best:
            best, closest = value, q
    return best, closest, probe.evaluations


def pair_distance(model: mujoco.MjModel, body1: int, body2: int, seed: int = 0) -> PairDistance:
    """How close two of the robot's bodies come (see the module docstring)."""
    side1, side2 = path_joints(model, body1, body2)
    joints = side1 + side2
    names = (model.body(body1).name, model.body(body2).name)
    pairs = geom_pairs(model, body1, body2)
    if not pairs:
        raise ConfigError(f"pair_distance: bodies {names} have no geoms that can collide with each other.")
    margin = MARGIN + max(float(model.geom_margin[a] + model.geom_margin[b]) for a, b in pairs)
    joint_names = tuple(model.joint(j).name for j in joints)
    intervals = [joint_interval(model, j) for j in joints]
    if any(interval is None for interval in intervals):
        return PairDistance(names, joint_names, "unbounded", 0, 0.0, 0.0, margin, ())
    bounded = [i for i in intervals if i is not None]
    probe = _PairProbe(model, body1, body2, joints)
    if len(joints) <= GRID_MAX_JOINTS:
        moved = [[a for a, _ in pairs] if j in side1 else [b for _, b in pairs] for j in joints]
        best, allowance, closest, samples = _grid(probe, bounded, moved, joints)
        method = "grid"
    else:
        best, closest, samples = _random(probe, bounded, seed)
        allowance, method = 0.0, "random"
    return PairDistance(names, joint_names, method, samples, best, allowance, margin, tuple(float(v) for v in closest))


def pair_distances(
    cls: type[Agent], pairs: Iterable[tuple[str, str]] | None = None, seed: int = 0
) -> list[PairDistance]:
    """The distance check of the given body pairs (names), or of every pair MuJoCo
    checks for contact in the robot as declared (:func:`candidate_pairs`)."""
    model = robot_model(cls)
    if pairs is None:
        ids = candidate_pairs(model)
    else:
        ids = []
        for first, second in pairs:
            found = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, n) for n in (first, second)]
            if min(found) < 0:
                raise ConfigError(f"pair_distances({cls.__name__}): no body named {first!r} or {second!r}.")
            ids.append((min(found), max(found)))
    return [pair_distance(model, a, b, seed) for a, b in ids]


def never_touching_pairs(cls: type[Agent], seed: int = 0) -> tuple[tuple[str, str], ...]:
    """The body pairs (names) of ``cls`` MuJoCo checks for contact that can never touch."""
    return tuple(p.bodies for p in pair_distances(cls, seed=seed) if p.never_touching)
