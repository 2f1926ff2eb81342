"""Named robot poses used for resets, by joint name.

A keyframe names joints by pattern::

    Keyframe(qpos={"panda_joint[1-7]": (0, 0.39, 0, -1.96, 0, 2.36, 0.79), "panda_finger_joint.*": 0.04})

Each pattern (a regular expression over the robot's joint names, whole-name match)
must match at least one joint; a scalar applies to every matched joint, a tuple gives
the matched joints' positions in model order (4 numbers, a quaternion normalized
``w, x, y, z``, for a ball joint). Joints not named take the model's default (the
file's own keyframe where it has one); followers of joint couplings (mimic fingers,
linkages) that are not named are filled from their leaders. A positional tuple over
every joint's ``qpos`` still works. :func:`resolve_keyframe` turns a keyframe into
the robot's ``qpos`` / ``qvel`` vectors and checks names, sizes, limits and
quaternions; robots resolve every keyframe when they are checked or registered.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.limits import MAX_SPEED
from robot_agents.patterns import as_patterns, match
from robot_agents.validation import ball_angles, check_quat, check_quat_rows, outside_limits

if TYPE_CHECKING:
    import mujoco

    from robot_agents.agent.index import RobotIndex

FloatArray = npt.NDArray[np.float64]
#: Positions (or velocities) by joint pattern, or one positional tuple over the robot's vector.
JointValues = tuple[float, ...] | Mapping[str, float | tuple[float, ...]]


def _as_floats(name: str, values: Any, size: int | None = None) -> tuple[float, ...]:
    try:
        array = np.asarray(values, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(f"Keyframe.{name}: expected numbers, got {values!r}.") from None
    if size is not None and array.size != size:
        raise ConfigError(f"Keyframe.{name}: expected {size} values, got {array.size}: {array.tolist()}.")
    if not np.all(np.isfinite(array)):
        raise ConfigError(f"Keyframe.{name}: expected finite values, got {array.tolist()}.")
    return tuple(float(v) for v in array)


def _as_values(name: str, values: Any) -> JointValues:
    if isinstance(values, Mapping):
        out: dict[str, float | tuple[float, ...]] = {}
        for pattern, value in values.items():
            as_patterns(pattern, f"Keyframe.{name}")
            floats = _as_floats(f"{name}[{pattern!r}]", value)
            if not floats:
                raise ConfigError(f"Keyframe.{name}[{pattern!r}]: expected a number or a tuple, got nothing.")
            out[pattern] = floats[0] if np.ndim(value) == 0 else floats
        return out
    return _as_floats(name, values)


@checked_keywords
@dataclass(frozen=True)
class Keyframe:
    """A named pose of one robot.

    Attributes:
        qpos: joint positions by joint pattern (see the module doc), or a positional
            tuple over the robot's ``qpos`` vector (radians for hinges, metres for
            slides, quaternions for ball joints). The root pose of a free-floating robot
            is not part of it: that is ``base_pos`` / ``base_quat``.
        qvel: joint velocities, by pattern or positional over ``qvel``; zeros when omitted.
        base_pos: root position (m), relative to where the scene mounts the robot.
            For free-root robots; a fixed-root robot stays on its mount (placed with the
            scene's ``robot_poses`` or its ``mount_pose``) and ignores it, with a warning.
        base_quat: root orientation as a unit quaternion ``(w, x, y, z)``, relative to
            the mount's orientation.
        base_vel: root velocity ``(6,)`` as MuJoCo's free joint carries it: linear
            (m/s) in the mount's frame, then angular (rad/s) in the root body's own
            frame; zeros when omitted. A fixed root ignores a non-zero one, with a warning.
    """

    qpos: JointValues = field(default_factory=dict)
    qvel: JointValues | None = None
    base_pos: tuple[float, ...] = (0.0, 0.0, 0.0)
    base_quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)
    base_vel: tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "qpos", _as_values("qpos", self.qpos))
        if self.qvel is not None:
            object.__setattr__(self, "qvel", _as_values("qvel", self.qvel))
        object.__setattr__(self, "base_pos", _as_floats("base_pos", self.base_pos, 3))
        object.__setattr__(self, "base_quat", check_quat(self.base_quat, "Keyframe.base_quat"))
        object.__setattr__(self, "base_vel", _as_floats("base_vel", self.base_vel, 6))

    @property
    def by_name(self) -> bool:
        """True when ``qpos`` names joints by pattern."""
        return isinstance(self.qpos, Mapping)


@dataclass(frozen=True)
class ResolvedKeyframe:
    """A keyframe as the robot's vectors: ``qpos`` ``(nq,)``, ``qvel`` ``(nv,)``, base pose
    ``(7,)`` and base velocity ``(6,)`` (:attr:`Keyframe.base_vel`; zeros for a fixed root)."""

    qpos: FloatArray
    qvel: FloatArray
    base: FloatArray
    base_vel: FloatArray = field(default_factory=lambda: np.zeros(6))


#: How far inside its range (a share of it) a joint whose default value lies outside
#: its limits is set (:func:`default_qpos`).
INSIDE_LIMITS = 0.1


def default_qpos(index: RobotIndex, key: int = 0) -> FloatArray:
    """The robot's default ``qpos`` ``(nq,)``: the file's first keyframe if it has one,
    else the model's reference pose (``qpos0``; identity quaternions for ball joints).
    A value outside its joint's limits (a model's zero pose may lie outside them) is
    moved :data:`INSIDE_LIMITS` of the range inside the nearer limit: resting on a stop,
    a drive would press into it, and an arm with its elbow at a stop is stretched
    straight (a singular pose, where IK and end-effector modes stall).

    ``key``: which of the file's keyframes (its place in the file, from 0) to read, moved
    inside the limits the same way (the derived keyframes: :func:`file_keyframe_names`).

    Raises:
        ConfigError: ``key`` is not one of the model's keyframes.
    """
    model = index.model
    if key != 0 and not 0 <= key < model.nkey:
        raise ConfigError(
            f"default_qpos: expected a keyframe number from 0 to {model.nkey - 1} (the file's keyframes), got {key!r}."
        )
    source = model.key_qpos[key] if model.nkey > 0 else model.qpos0
    values = np.array(source[index.qpos_adr], dtype=np.float64)
    low, high = index.qpos_limits[:, 0], index.qpos_limits[:, 1]
    inside = INSIDE_LIMITS * np.where(np.isfinite(high - low), high - low, 0.0)
    default: FloatArray = np.where(values < low, low + inside, np.where(values > high, high - inside, values))
    return default


#: The name of a robot's first keyframe when it declares none: the file's first
#: keyframe (or its reference pose); the file's own name of that keyframe is an alias of it.
DEFAULT_KEYFRAME = "default"


def file_keyframe_names(model: mujoco.MjModel) -> list[str]:
    """The names a robot declaring no keyframes gives its file's keyframes, in the file's
    order: the first is :data:`DEFAULT_KEYFRAME` (``"default"``: a model without
    keyframes has that one alone; its own name in the file is another name of it,
    :func:`file_keyframe_aliases`), each other its own ``name``, an unnamed one
    ``"key<i>"`` (``i`` its place among the file's keyframes, from 0: the third is
    ``"key2"``), and a name already taken (``"default"``, the first keyframe's own name,
    or ``"key2"`` written on another keyframe) gets ``"_<i>"`` added."""
    names = [DEFAULT_KEYFRAME]
    taken = {DEFAULT_KEYFRAME, *file_keyframe_aliases(model)}
    for key in range(1, model.nkey):
        name = model.key(key).name or f"key{key}"
        while name in taken:
            name += f"_{key}"
        names.append(name)
        taken.add(name)
    return names


def file_keyframe_aliases(model: mujoco.MjModel) -> dict[str, str]:
    """Other names of a robot's file keyframes, alias -> keyframe name: the file's own
    name of its first keyframe (``<key name="home">``) names :data:`DEFAULT_KEYFRAME`
    too, so both ``reset(keyframes="home")`` and ``"default"`` reach it. Empty when the
    file has no keyframes or its first is unnamed or named ``"default"``."""
    first = model.key(0).name if model.nkey > 0 else ""
    return {first: DEFAULT_KEYFRAME} if first and first != DEFAULT_KEYFRAME else {}


def file_keyframe(model: mujoco.MjModel, index: RobotIndex, key: int) -> Keyframe:
    """The file's keyframe at place ``key`` (from 0) as the :class:`Keyframe` a robot
    declaring none resolves: its joint velocities ``qvel`` (the robot's joints, in model
    order), its positions left to the default the caller gives (:func:`default_qpos`),
    and for a floating robot its root's velocity (:attr:`Keyframe.base_vel`). A model
    without keyframes (``key`` 0): all zero. The file key's ``act`` (actuator
    activations; the robot's check notes it) and mocap poses are not read (see
    docs/defining-a-robot.md, "Keyframes by joint name")."""
    if key >= model.nkey:
        return Keyframe()
    qvel = np.asarray(model.key_qvel[key], dtype=np.float64)
    free = index.free_joint
    base_vel = (0.0,) * 6 if free is None else tuple(float(v) for v in qvel[free.dof_adr : free.dof_adr + 6])
    return Keyframe(qvel=tuple(float(v) for v in qvel[index.dof_adr]), base_vel=base_vel)


#: How far (rad or m) a keyframe may put a follower from where its coupling puts it.
COUPLING_TOLERANCE = 1e-6

#: A keyframe's base pose when it sets none: at the mount, unturned.
IDENTITY_BASE = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])


def resolve_keyframe(
    frame: Keyframe, index: RobotIndex, where: str, default: FloatArray | None = None
) -> ResolvedKeyframe:
    """``frame`` as the robot's ``qpos`` / ``qvel`` vectors, checked. Joints it does not
    name take ``default`` (``(nq,)``; :func:`default_qpos` when ``None``).

    Raises:
        ConfigError / UnknownNameError: a pattern matches no joint, two patterns name one
            joint, a value has the wrong size, a position is outside its joint's limits,
            a speed passes :data:`~robot_agents.limits.MAX_SPEED`, or a ball joint's
            quaternion is zero or turned beyond its range (a non-zero one is
            normalized, in the returned ``qpos``). The message names
            ``where`` (the keyframe).
    """
    if not isinstance(frame, Keyframe):
        raise ConfigError(f"{where}: expected a Keyframe, got {frame!r}.")
    named: set[str] = set()
    base_qpos = default_qpos(index) if default is None else default
    qpos = _fill(frame.qpos, index, base_qpos, "qpos", where, named)
    _fill_couplings(qpos, index, named, where)
    qvel = (
        np.zeros(index.nv) if frame.qvel is None else _fill(frame.qvel, index, np.zeros(index.nv), "qvel", where, set())
    )
    _check_limits(qpos, index, where)
    base = np.array([*frame.base_pos, *frame.base_quat], dtype=np.float64)
    base_vel = np.array(frame.base_vel, dtype=np.float64)
    fastest = float(np.max(np.abs(np.concatenate([qvel, base_vel]))))
    if fastest > MAX_SPEED:  # a reset would refuse it (limits.check_speeds)
        raise ConfigError(
            f"{where}: expected speeds below {MAX_SPEED:g} (rad/s or m/s) in qvel and base_vel, got up to {fastest:.3g}."
        )
    if index.free_joint is None and np.any(base_vel):
        warnings.warn(
            f"{where}: base_vel {frame.base_vel} moves a free root; this robot's root is fixed: it is ignored.",
            RuntimeWarning,
            stacklevel=2,
        )
        base_vel = np.zeros(6)
    if index.free_joint is None and not np.array_equal(base, IDENTITY_BASE):
        # not an error: a legged robot's variant with its root fixed (hung up to test its
        # legs) keeps the keyframes written for it standing
        warnings.warn(
            f"{where}: base_pos {frame.base_pos} / base_quat {frame.base_quat} place a free root; this robot's root "
            "is fixed and stays where the scene mounts it (robot_poses, mount_pose): they are ignored.",
            RuntimeWarning,
            stacklevel=2,
        )
    return ResolvedKeyframe(qpos, qvel, base, base_vel)


def _fill(
    values: JointValues, index: RobotIndex, default: FloatArray, what: str, where: str, named: set[str]
) -> FloatArray:
    positions = what == "qpos"
    size = index.nq if positions else index.nv
    if not isinstance(values, Mapping):
        if len(values) != size:
            layout = ", ".join(index.joint_names)
            raise ConfigError(
                f"{where}: expected {size} joint {'positions' if positions else 'velocities'} ({layout}), got {len(values)}."
            )
        named.update(index.joint_names)
        return np.array(values, dtype=np.float64)
    out: FloatArray = default.copy()
    owner: dict[str, str] = {}
    for pattern, value in values.items():
        hits = [index.joints[i] for i in match(pattern, index.joint_names, f"{where}.{what}")]
        for joint in hits:
            if joint.name in owner:
                raise ConfigError(
                    f"{where}.{what}: joint {joint.name!r} is named by both {owner[joint.name]!r} and {pattern!r}."
                )
            owner[joint.name] = pattern
        widths = [joint.nq if positions else joint.nv for joint in hits]
        scalar = not isinstance(value, tuple)
        if scalar and any(w != 1 for w in widths):
            odd = next(j.name for j, w in zip(hits, widths, strict=True) if w != 1)
            raise ConfigError(
                f"{where}.{what}[{pattern!r}]: joint {odd!r} is a ball joint; give its "
                f"{'quaternion (w, x, y, z)' if positions else 'angular velocity (3 values)'} as a tuple."
            )
        flat = np.full(sum(widths), value) if scalar else np.asarray(value, dtype=np.float64)
        if flat.size != sum(widths):
            names = ", ".join(j.name for j in hits)
            raise ConfigError(
                f"{where}.{what}[{pattern!r}]: matches {len(hits)} joint(s) ({names}) with {sum(widths)} values; got {flat.size}."
            )
        cursor = 0
        for joint, width in zip(hits, widths, strict=True):
            start = joint.qpos_start if positions else joint.dof_start
            out[start : start + width] = flat[cursor : cursor + width]
            cursor += width
            named.add(joint.name)
    return out


def _fill_couplings(qpos: FloatArray, index: RobotIndex, named: set[str], where: str) -> None:
    """Followers the keyframe did not name follow their leaders (twice, for chains); a
    follower it names must agree with its leader (within :data:`COUPLING_TOLERANCE`), or
    the coupling would snap it there at the first step."""
    pairs = [(c, index.joint(c.leader, "coupling"), index.joint(c.follower, "coupling")) for c in index.couplings]
    pairs = [(c, leader, follower) for c, leader, follower in pairs if leader.nq == 1 and follower.nq == 1]
    for _ in range(2):
        for coupling, leader, follower in pairs:
            if coupling.follower not in named:
                qpos[follower.qpos_start] = coupling.follow(float(qpos[leader.qpos_start]))
    for coupling, leader, follower in pairs:
        expected = coupling.follow(float(qpos[leader.qpos_start]))
        if coupling.follower in named and abs(float(qpos[follower.qpos_start]) - expected) > COUPLING_TOLERANCE:
            raise ConfigError(
                f"{where}: joint {follower.name!r} follows {leader.name!r} (a joint coupling), which puts it at "
                f"{expected:.6g}, but the keyframe gives {float(qpos[follower.qpos_start]):.6g}; name only "
                f"{leader.name!r}."
            )


def _check_limits(qpos: FloatArray, index: RobotIndex, where: str) -> None:
    for joint in index.joints:
        start = joint.qpos_start
        if joint.kind.value == "ball":
            # any non-zero length, normalized (as a reset's qpos and a keyframe's base_quat)
            quat = qpos[start : start + 4]
            quat /= check_quat_rows(quat[None], f"ball joint {joint.name!r} (w, x, y, z)", where, ConfigError)[0]
            angle = float(ball_angles(quat[None])[0])
            if joint.limited and angle > joint.range[1] + 1e-9:
                raise ConfigError(
                    f"{where}: ball joint {joint.name!r} turned {angle:.6g} rad from its reference, beyond its "
                    f"limit {joint.range[1]:.6g} rad."
                )
            continue
        low, high = index.qpos_limits[start]
        value = float(qpos[start])
        if outside_limits(value, low, high):
            raise ConfigError(
                f"{where}: joint {joint.name!r} at {value:.6g} is outside its limits [{low:.6g}, {high:.6g}]."
            )
