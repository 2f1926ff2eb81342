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

A joint its file gives dry friction (``frictionloss``) stops where the drive's pull
falls below it, ``friction / kp`` from the target: :func:`friction_gains` raises ``kp``
to ``friction / FRICTION_STALL`` (capped by the stability bound below; a derived robot's
class check gives a note for each joint so capped) and ``kv`` to critical for it.

A floating robot standing on its legs needs more: its legs' own inertia is small (the
body is free), and gains from it let the body's weight fold the legs. With the static
torque ``tau`` each joint carries standing at its keyframe
(:func:`robot_agents.agent.stance.find_stance`), :func:`stance_gains` raises

    kp = max(kp_inertia, |tau| / STANCE_SAG + sum_i F_i r_i)

so that the joint gives at most :data:`STANCE_SAG` under its load, the load's own
softening included (a load ``F_i`` at distance ``r_i`` from the axis grows its torque by
at most ``F_i r_i`` per radian given), and damps it critically against the share of the
body it carries, ``I_load = sum_i F_i r_i^2 / g``:

    kv = max(kv_inertia, min(2 * zeta * sqrt(kp * max(I, I_load)), 2 I_free / dt - b))

``kp`` stays below :data:`STANCE_STABLE_SHARE` of the explicit-stiffness bound
``4 I / dt^2`` (``I`` the leg's own inertia: a swinging leg carries no body), so the
physics check passes with a factor 2 to spare; where that caps it, the joint sags more.
``kv`` stays below :data:`STANCE_DAMPING_SHARE` of the explicit-damping bound
``2 I_free / dt``, less the file's own joint damping ``b`` (``I_free = 1 / (M^-1)_ii``, the
inertia the joint presents with everything else free): MuJoCo's constraint solver sizes
contact and equality forces for ``M``, not for the ``M + dt D`` its implicit damping
integrates, and far beyond that bound a stance bounces on its feet.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.validation import check_real

#: Bandwidth (Hz) and damping ratio of derived gains.
DEFAULT_BANDWIDTH_HZ = 10.0
DEFAULT_DAMPING_RATIO = 1.0


#: Static sag (rad, or m for slides) a derived drive allows under the load it carries
#: standing: half of :data:`robot_agents.checks.HOLD_TOLERANCE`. A four-legged stance
#: is statically indeterminate: when the legs give, load moves between them (a diagonal
#: pair can take more), so a joint's load may change by its whole static value after
#: settling, which then moves it by half the tolerance. (A quarter made solo12, whose
#: file gives 1000 N*m efforts over +-10 rad ranges, blow up under random absolute targets.)
STANCE_SAG = 0.005
#: How far from its target a derived drive may leave a joint that its file gives dry
#: friction (``frictionloss``), rad or m: as far as a standing leg may sag
#: (:data:`STANCE_SAG`), half the keyframe-hold tolerance.
FRICTION_STALL = STANCE_SAG
#: Bandwidth (Hz) of a gripper joint that its file gives no effort limit (the
#: mani-skill wheel's SO-100 and Koch URDFs write ``effort="0"``): stiffer than the
#: drives' 10 Hz, which on a light jaw (the SO-100's 20 g) pressed a cube with 0.08 N*m
#: and let it pivot and drop as the carry set off, but far below the step's stability
#: bound, whose squeeze on the cube shoved the light arm and pressed the cube out of
#: the jaw. Scripted PickCube-v1, 20 seeds, at 10 / 14 / 25 / 44 / 80 Hz: the SO-100
#: file 4 / 17 / 19 / - / 0, the Koch file 6 / 12 / 17 / 6 / 0, damped over 0.05 s (2026-11-29; see
#: docs/using-a-model-file.md, "Two-line robots in the tasks").
GRIP_BANDWIDTH_HZ = 25.0
GRIP_OMEGA = 2.0 * math.pi * GRIP_BANDWIDTH_HZ
#: Time constant (s) of such a joint's drive: damped ``kv = kp * GRIP_TIME_CONSTANT``
#: (overdamped; MuJoCo's ``implicitfast`` integrates an unclamped drive's damping
#: implicitly), it closes as a first-order lag, at first the distance over 0.1 s (two
#: 20 Hz control steps), slower than its 10 Hz spring's fastest (the distance over
#: ``e / omega``, 0.043 s): a light jaw stopped by nothing but what it closes on. At the
#: stability bound, critically damped, the SO-100 file's jaw shot through the cube in
#: one 2 ms step. Scripted, 20 seeds, at 0.02 / 0.05 / 0.1 s: the Koch file's
#: PickCube-v1 16 / 18 / 19, PushCube-v1 20 / 18 / 20 (20 before); the SO-100 file's
#: PickCube-v1 - / 19 / 20.
GRIP_TIME_CONSTANT = 0.1
#: Share of the explicit-stiffness bound ``4 I / dt^2`` that stance gains stay below:
#: half of :data:`robot_agents.checks.STABLE_SHARE`, the share the physics check passes below.
STANCE_STABLE_SHARE = 0.25
#: The share of the clamped-damping bound ``kv dt / I < 2`` (at a joint's smallest
#: inertia) that gains derived over configurations keep to, for joints with an effort
#: limit (:func:`gains_over_configurations`).
CLAMPED_DAMPING_SHARE = 0.5
#: Share of the explicit-damping bound ``2 I_free / dt`` that a joint's whole damping in a
#: stance (its drive's ``kv`` and the file's own ``b``) stays below: ``dt (kv + b) <= 2 I_free``.
#: MuJoCo integrates damping implicitly, but its constraint solver sizes contact and
#: equality forces for ``M``, before that update: a joint damped by ``D`` answers a force
#: ``1 + dt D / I_free`` times more weakly than the solver expects (``I_free = 1 / (M^-1)_ii``;
#: Sherman-Morrison), here at most 3 times. Far beyond, a standing robot bounces:
#: dm_control's quadruped (tendon equalities coupling each leg's joints) hopped 15 cm,
#: its dog rocked on its front feet and walked back 5 cm in 5 s. Half the bound (at most
#: twice) also stood them, but left example-robot-data's Solo12 too little damping for
#: random absolute targets (MuJoCo reset it in ``pd_joint_pos`` after 1.5 s); the whole
#: bound stands them and keeps Solo12 stable.
STANCE_DAMPING_SHARE = 1.0


@dataclass(frozen=True)
class SuggestedGains:
    """Gains for some joints (arrays ``(n,)`` in the order of ``joints``).

    ``inertia`` is each joint's effective inertia, the diagonal of the joint-space inertia
    matrix ``M`` (kg*m^2, or kg for slides: every other joint held). ``free_inertia`` is
    ``1 / (M^-1)_ii``, the inertia the joint presents with every other degree of freedom
    free (a floating base's too): what a force at the joint meets in MuJoCo's constraint
    solver. ``passive_damping`` is the file's own joint damping (N*m*s/rad or N*s/m),
    ``passive_friction`` its dry friction (``frictionloss``, N*m or N).
    ``least_inertia`` is the smallest ``inertia`` over the configurations gains were
    derived over (:func:`gains_over_configurations`), the one the explicit-stiffness
    bound is taken at. ``None``: not computed; ``inertia`` and no damping stand in for
    them."""

    joints: tuple[str, ...]
    stiffness: npt.NDArray[np.float64]
    damping: npt.NDArray[np.float64]
    effort_limit: npt.NDArray[np.float64]
    inertia: npt.NDArray[np.float64]
    bandwidth_hz: float
    damping_ratio: float
    free_inertia: npt.NDArray[np.float64] | None = None
    passive_damping: npt.NDArray[np.float64] | None = None
    passive_friction: npt.NDArray[np.float64] | None = None
    least_inertia: npt.NDArray[np.float64] | None = None

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
    if check_real(bandwidth_hz, "bandwidth_hz", "gains_from_inertia", minimum=0.0) <= 0.0:
        raise ConfigError(f"gains_from_inertia: expected a bandwidth > 0 Hz, got {bandwidth_hz!r}.")
    check_real(damping_ratio, "damping_ratio", "gains_from_inertia", minimum=0.0)
    data = mujoco.MjData(model)
    if qpos is not None:
        try:
            data.qpos[:] = np.asarray(qpos, dtype=np.float64).reshape(model.nq)
        except (TypeError, ValueError):
            raise ConfigError(f"gains_from_inertia: expected qpos as {model.nq} numbers, got {qpos!r:.80}.") from None
    mass = inertia_matrix(model, data)
    ids = []
    for name in joints:
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint < 0:
            raise ConfigError(f"gains_from_inertia: no joint {name!r} in the model.")
        if int(model.jnt_type[joint]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            raise ConfigError(f"gains_from_inertia: joint {name!r} is not a hinge or slide joint.")
        ids.append(joint)
    dofs = model.jnt_dofadr[ids]
    inertia = np.maximum(np.diag(mass)[dofs], 1e-9)
    # (M^-1)_ii >= 1 / M_ii for a positive-definite M: the free inertia is at most the held one
    mobility = np.diag(np.linalg.inv(mass))[dofs]
    free_inertia = np.clip(1.0 / np.maximum(mobility, 1e-300), 1e-9, inertia)
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
        free_inertia=free_inertia,
        passive_damping=np.array(model.dof_damping[dofs], dtype=np.float64),
        passive_friction=np.array(model.dof_frictionloss[dofs], dtype=np.float64),
    )


def inertia_matrix(model: mujoco.MjModel, data: mujoco.MjData) -> npt.NDArray[np.float64]:
    """The joint-space inertia matrix ``(nv, nv)`` at ``data``'s ``qpos``."""
    mujoco.mj_forward(model, data)
    matrix = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, matrix)  # MuJoCo >= 3.5
    except TypeError:
        mujoco.mj_fullM(model, matrix, data.qM)
    return matrix


def gains_over_configurations(
    model: mujoco.MjModel,
    joints: Sequence[str],
    configurations: npt.ArrayLike,
    timestep: float,
    bandwidth_hz: float = DEFAULT_BANDWIDTH_HZ,
    damping_ratio: float = DEFAULT_DAMPING_RATIO,
) -> SuggestedGains:
    """PD gains for hinge and slide ``joints`` that reach ``bandwidth_hz``, at least
    critically damped, in every one of ``configurations`` (``(k, nq)``): a joint's
    effective inertia changes with the pose (an arm's first joint carries little when
    the arm points up, much when it is stretched out), so the stiffness is taken at its
    largest inertia over them, ``I_max * omega^2``, with damping critical there
    (``2 zeta sqrt(kp I_max)``: overdamped where the inertia is smaller; MuJoCo's
    ``implicitfast`` integrates it implicitly), but at most :data:`STANCE_STABLE_SHARE`
    of the explicit-stiffness bound ``4 I_min / dt^2`` at the smallest inertia
    (``timestep`` in s). The first configuration is the reference: its gains are
    :func:`gains_from_inertia`'s (files' damping and friction, free inertia), and the
    stiffness never falls below them."""
    rows = np.atleast_2d(np.asarray(configurations, dtype=np.float64))
    first = gains_from_inertia(model, joints, rows[0], bandwidth_hz, damping_ratio)  # checks the joints
    dofs = model.jnt_dofadr[[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) for name in joints]]
    data = mujoco.MjData(model)  # one scratch for the others: only their inertias are needed
    inertias = [first.inertia]
    for row in rows[1:]:
        data.qpos[:] = row
        inertias.append(np.maximum(np.diag(inertia_matrix(model, data))[dofs], 1e-9))
    largest = np.max(inertias, axis=0)
    least = np.min(inertias, axis=0)
    omega = 2.0 * math.pi * bandwidth_hz
    cap = STANCE_STABLE_SHARE * 4.0 * least / timestep**2
    # a joint with an effort limit: while its force is clamped MuJoCo integrates the
    # damping explicitly, stable only for kv dt / I < 2 at its smallest inertia; keep
    # kv within half that, and kp low enough to stay critically damped at the largest
    damping_cap = np.where(np.isfinite(first.effort_limit), CLAMPED_DAMPING_SHARE * 2.0 * least / timestep, np.inf)
    cap = np.minimum(cap, damping_cap**2 / (4.0 * damping_ratio**2 * largest))
    free = largest * omega**2 <= cap  # uncapped: the formulas of gains_from_inertia, at the largest inertia
    stiffness = np.where(free, largest * omega**2, cap)
    damping = np.where(free, 2.0 * damping_ratio * largest * omega, 2.0 * damping_ratio * np.sqrt(cap * largest))
    stiffness, damping = np.maximum(stiffness, first.stiffness), np.maximum(damping, first.damping)
    return replace(first, stiffness=stiffness, damping=damping, inertia=largest, least_inertia=least)


def grip_gains(
    gains: SuggestedGains, strokes: Mapping[str, float], timestep: float, unbounded: Iterable[str] = ()
) -> tuple[SuggestedGains, tuple[str, ...]]:
    """``gains`` with each gripper joint of ``strokes`` (joint -> its open-to-closed
    travel, rad or m) stiff enough to press with its whole effort limit when commanded
    a full stroke past where it stands: ``kp >= effort / stroke``, so a grasp holds
    with the force the file's motor gives, not with what a 10 Hz spring on a light
    finger gives (a Panda finger of 15 g: 59 N/m, 1.4 N on a 4 cm cube); at most
    :data:`STANCE_STABLE_SHARE` of the explicit-stiffness bound (``timestep`` in s),
    damping critical for the new stiffness. Each joint of ``unbounded`` (a gripper
    joint whose file gives it no effort limit: the SO-100's and the Koch's jaws, whose
    URDFs write ``effort="0"``) that has none gets a :data:`GRIP_BANDWIDTH_HZ` spring
    on its inertia (within that bound), damped over :data:`GRIP_TIME_CONSTANT`: nothing
    states its force, and a 10 Hz spring on a 20 g jaw pressed with 0.08 N*m. Other
    joints without an effort limit keep their gains. Returns the gains and the joints
    stiffened."""
    cap = _stiffness_cap(gains, timestep)
    stiffness, damping = gains.stiffness.copy(), gains.damping.copy()
    raised = []
    free = set(unbounded)
    for i, joint in enumerate(gains.joints):
        stroke, effort = strokes.get(joint), gains.effort_limit[i]
        if joint in free and not math.isfinite(effort):
            stiffness[i] = max(stiffness[i], min(float(gains.inertia[i]) * GRIP_OMEGA**2, float(cap[i])))
            damping[i] = max(damping[i], stiffness[i] * GRIP_TIME_CONSTANT)
            raised.append(joint)
            continue
        if stroke is None or not stroke > 0.0 or not math.isfinite(effort):
            continue
        wanted = min(effort / stroke, cap[i])
        if wanted > stiffness[i]:
            stiffness[i] = wanted
            damping[i] = max(damping[i], 2.0 * gains.damping_ratio * math.sqrt(wanted * gains.inertia[i]))
            raised.append(joint)
    return replace(gains, stiffness=stiffness, damping=damping), tuple(raised)


def _stiffness_cap(gains: SuggestedGains, timestep: float) -> npt.NDArray[np.float64]:
    """The stiffness (N*m/rad or N/m) derived gains may raise each joint to: a
    :data:`STANCE_STABLE_SHARE` of the explicit-stiffness bound ``4 I / dt^2`` at the
    physics step ``timestep`` (s)."""
    inertia = gains.inertia if gains.least_inertia is None else gains.least_inertia
    cap: npt.NDArray[np.float64] = STANCE_STABLE_SHARE * 4.0 * inertia / timestep**2
    return cap


def friction_gains(
    gains: SuggestedGains, timestep: float, stall: float = FRICTION_STALL
) -> tuple[SuggestedGains, tuple[str, ...]]:
    """``gains`` stiffened so that each joint's dry friction (``gains.passive_friction``,
    the file's ``frictionloss``) stops it at most ``stall`` (rad or m) from its target:
    ``kp >= friction / stall``, below :data:`STANCE_STABLE_SHARE` of the explicit-stiffness
    bound ``4 I / dt^2`` (``timestep`` in s), with ``kv`` critical for the new ``kp``
    (``2 zeta sqrt(kp I)``; the file's own damping adds to it). Inertia gains stiff
    enough already are kept. Returns the gains and the joints whose stiffness the bound
    capped (friction stops them up to ``friction / kp`` from their targets; a derived
    robot's class check reports them in a load note)."""
    if gains.passive_friction is None:
        return gains, ()
    need = gains.passive_friction / stall
    cap = _stiffness_cap(gains, timestep)
    stiffness = np.maximum(gains.stiffness, np.minimum(need, cap))
    raised = stiffness > gains.stiffness  # other joints keep their gains bit for bit
    critical = 2.0 * gains.damping_ratio * np.sqrt(stiffness * gains.inertia)
    damping = np.where(raised, np.maximum(gains.damping, critical), gains.damping)
    capped = tuple(j for j, n, c, k in zip(gains.joints, need, cap, gains.stiffness, strict=True) if n > c and n > k)
    return replace(gains, stiffness=stiffness, damping=damping), capped


def stance_gains(
    gains: SuggestedGains,
    torque: npt.ArrayLike,
    lever: npt.ArrayLike,
    reflected: npt.ArrayLike,
    timestep: float,
    sag: float = STANCE_SAG,
) -> tuple[SuggestedGains, tuple[str, ...]]:
    """``gains`` (from :func:`gains_from_inertia`) stiffened to carry a standing robot's
    weight (see the module doc): ``torque``, ``lever`` and ``reflected`` are ``(n,)``
    in the order of ``gains.joints`` (:class:`robot_agents.agent.stance.Stance`), the
    physics step ``timestep`` in s. Returns the gains and the joints whose stiffness the
    stability bound capped (they sag more than ``sag``)."""
    tau = np.abs(np.asarray(torque, dtype=np.float64))
    need = tau / sag + np.asarray(lever, dtype=np.float64)
    cap = _stiffness_cap(gains, timestep)
    stiffness = np.maximum(gains.stiffness, np.minimum(need, cap))
    load_inertia = np.maximum(gains.inertia, np.asarray(reflected, dtype=np.float64))
    critical = 2.0 * gains.damping_ratio * np.sqrt(stiffness * load_inertia)
    free = gains.inertia if gains.free_inertia is None else gains.free_inertia
    passive = np.zeros(len(gains.joints)) if gains.passive_damping is None else gains.passive_damping
    damping_cap = STANCE_DAMPING_SHARE * 2.0 * free / timestep - passive
    damping = np.maximum(gains.damping, np.minimum(critical, damping_cap))
    capped = tuple(j for j, n, c in zip(gains.joints, need, cap, strict=True) if n > c)
    return replace(gains, stiffness=stiffness, damping=damping), capped
