"""Physics checks of a robot, for the one someone is writing (``robot-agents check``):
each check has a number and a pass / fail, and says what to change when it fails."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.gains import gains_from_inertia
from robot_agents.actuators.spec import DriveKind
from robot_agents.agent import Agent
from robot_agents.agent.derived import joint_actuator
from robot_agents.agent.legs import standing_legs
from robot_agents.controllers.ee import PDEEController
from robot_agents.errors import ConfigError, RobotAgentsError
from robot_agents.model.inertia import combine_inertias
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene, default_sim_freq

FloatArray = npt.NDArray[np.float64]

#: A keyframe is held when no joint drifts more than this over the hold (rad or m).
HOLD_TOLERANCE = 0.01
#: Seconds a robot standing on its legs is given to settle onto them before its hold is
#: measured: legs carrying the body give under the load by load / stiffness (the drives'
#: static sag, set by the gains, not by the step), and then must stay put.
LOAD_SETTLE_SECONDS = 1.0
#: Plausible masses of a moving body (kg).
MASS_RANGE = (1e-4, 1e4)
#: A PD drive is stable when kp stays below this share of the explicit-stiffness bound 4 I / dt^2.
STABLE_SHARE = 0.5


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, whether it passed, and what was measured."""

    name: str
    passed: bool
    detail: str

    def line(self) -> str:
        return f"[{'PASS' if self.passed else 'FAIL'}] {self.name}: {self.detail}"


def hold_action(agent: Agent, env: int = 0) -> np.ndarray:
    """The action that asks the robot to stay where it is (env ``env``), in any mode:
    absolute joint targets at the measured pose, the end effector's current target for
    absolute end-effector modes, zero deltas, velocities and efforts otherwise (each
    normalized where its mode is, whatever its bounds).

    To hold a pose, take it once and repeat it: taken again at every step, absolute
    targets would follow a joint that gives under its load (a leg carrying the body)
    all the way down."""
    parts = []
    for controller in agent.controller.parts.values():
        raw = controller.hold_raw(agent.world)[env]  # each controller's hold, raw (m, rad, ...)
        # The action that commands ``raw``: with symmetric bounds a raw zero is a normalized
        # zero (exactly); with asymmetric ones, or a normalized absolute mode, it is not.
        parts.append(controller.from_raw(raw) if controller.config.normalize_action else raw)
    return np.concatenate(parts) if parts else np.zeros(0)


def raw_hold(controller: PDEEController, hold: np.ndarray) -> np.ndarray:
    """The raw command (m, rad; not normalized) of an end-effector controller's slice
    ``hold`` of :func:`hold_action`, a new array of shape ``(action_dim,)``: zero for
    delta modes, the held pose for absolute ones (un-normalized where the mode is)."""
    if controller.config.use_delta:
        return np.zeros(controller.action_dim)
    if controller.config.normalize_action:
        raw: np.ndarray = controller.to_raw(np.asarray(hold, dtype=float)[None])[0]
        return raw
    return np.array(hold, dtype=float)


def standing_leg_joints(cls: type[Agent]) -> tuple[str, ...]:
    """The joints of legs that carry the robot (:func:`robot_agents.agent.legs.standing_legs`):
    empty for a fixed root and for held legs."""
    checked = cls.check()
    return standing_legs(checked.parts, checked.part_joints, cls.fix_root_link)


def load_settle_steps(cls: type[Agent], control_freq: int) -> int:
    """Control steps a hold is given to settle before its drift counts:
    :data:`LOAD_SETTLE_SECONDS` for a robot standing on its legs, none for others."""
    return round(LOAD_SETTLE_SECONDS * control_freq) if standing_leg_joints(cls) else 0


def keeps_targets(agent: Agent) -> bool:
    """Whether the active mode's hold action keeps every joint target where it was taken:
    absolute and target-delta joint modes, end-effector modes. A delta from the measured
    pose, or a zero velocity, lets a joint under a load it carries (a leg under the body)
    give without end: in such modes a robot standing on its legs cannot hold a pose."""
    return all(controller.config.keeps_targets for controller in agent.controller.parts.values())


def hold_drift(
    scene: Scene, agent: Agent, seconds: float, settle_steps: int, after_step: Callable[[], object] | None = None
) -> tuple[float, float]:
    """Repeat the hold action taken at the current (just reset) pose for ``seconds``
    after ``settle_steps`` control steps of it; ``(largest drift from the pose after
    settling, largest drift from the reset pose during settling)`` (rad or m).
    ``after_step`` is called after every control step."""
    hold = hold_action(agent)  # the keyframe's own targets, repeated (see hold_action)
    start = agent.qpos
    sag = worst = 0.0
    for step in range(settle_steps + round(seconds * scene.control_freq)):
        if step == settle_steps:
            start = agent.qpos  # settled: drift counts from here
        agent.set_action(hold)
        scene.step()
        if after_step is not None:
            after_step()
        moved = float(np.max(np.abs(agent.qpos - start), initial=0.0))
        if step < settle_steps:
            sag = max(sag, moved)
        else:
            worst = max(worst, moved)
    return worst, sag


def contact_label(model: mujoco.MjModel, geom: int) -> str:
    """A geom's name, or for an unnamed geom its body's name and its index there
    (``"panda-0/panda_link6 geom 2"``): enough to tell a link pressed into the floor
    from two links pressed into each other."""
    name = model.geom(geom).name
    if name:
        return str(name)
    body = int(model.geom_bodyid[geom])
    return f"{model.body(body).name} geom {geom - int(model.body_geomadr[body])}"


def check_keyframes(cls: type[Agent]) -> CheckResult:
    """Every keyframe within limits (checked with the class) and free of penetrating contacts."""
    scene = Scene(cls)
    worst, where = 0.0, ""
    for name in cls.keyframe_names():
        scene.reset(keyframes=name)
        data = scene.world.physics_sources([0])[0]
        for i in range(data.ncon):
            depth = -float(data.contact[i].dist)
            if depth > worst:
                c = data.contact[i]
                pair = f"{contact_label(scene.model, c.geom1)} / {contact_label(scene.model, c.geom2)}"
                worst, where = depth, f" ({name}: {pair})"
    scene.close()
    count = len(cls.keyframe_names())
    return CheckResult(
        "keyframes within limits and free of contacts",
        worst <= 1e-4,
        f"{count} keyframe(s), deepest penetration {worst * 1000:.2f} mm{where}",
    )


def check_holds(cls: type[Agent], seconds: float = 2.0) -> CheckResult:
    """Each keyframe held for ``seconds`` under the default mode."""
    mode = cls.default_mode()
    scene = Scene(cls, control_modes=mode)
    agent = scene.agents[0]
    if not any(
        kind in ("position", "velocity") for c in agent.controller.parts.values() for kind in c.config.target_kinds()
    ):
        scene.close()
        return CheckResult(f"keyframes held {seconds:g} s in {mode}", True, "not applicable: the mode commands efforts")
    drifts, sags = {}, {}
    settle_steps = load_settle_steps(cls, scene.control_freq)
    for name in cls.keyframe_names():
        scene.reset(keyframes=name)
        drifts[name], sags[name] = hold_drift(scene, agent, seconds, settle_steps)
    scene.close()
    name, worst = max(drifts.items(), key=lambda item: item[1])
    return CheckResult(
        f"keyframes held {seconds:g} s in {mode}",
        worst < HOLD_TOLERANCE,
        f"largest drift {worst:.4f} rad/m ({name}); tolerance {HOLD_TOLERANCE}"
        + (
            f"; measured after {LOAD_SETTLE_SECONDS:g} s on its legs (sag meanwhile: {max(sags.values()):.4f})"
            if settle_steps
            else ""
        ),
    )


def random_action(low: npt.NDArray[Any], high: npt.NDArray[Any], rng: np.random.Generator) -> FloatArray:
    """A uniformly random action within ``[low, high]``; entries without a bound (``inf``)
    drawn as Gymnasium's ``Box.sample`` draws them: a standard normal where both are
    unbounded, the bound plus or minus an exponential where one is."""
    if np.isfinite(low).all() and np.isfinite(high).all():
        drawn: FloatArray = rng.uniform(low, high)
        return drawn
    lower, upper = np.isfinite(low), np.isfinite(high)
    action = rng.standard_normal(np.shape(low))
    both = lower & upper
    action[both] = rng.uniform(low[both], high[both])
    only_low, only_high = lower & ~upper, upper & ~lower
    action[only_low] = low[only_low] + rng.exponential(size=int(only_low.sum()))
    action[only_high] = high[only_high] - rng.exponential(size=int(only_high.sum()))
    return action


def run_random_actions(
    scene: Scene, seconds: float, seed: int = 0, after_step: Callable[[], None] | None = None
) -> None:
    """Step ``scene`` for ``seconds`` with uniformly random actions of its first robot
    (drawn from ``np.random.default_rng(seed)`` within its action space; an unbounded
    entry, efforts a file's motor does not limit, as Gymnasium's ``Box.sample`` draws
    it: see :func:`random_action`), calling ``after_step`` after each control step."""
    agent = scene.agents[0]
    rng = np.random.default_rng(seed)
    space = agent.action_space
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(random_action(space.low, space.high, rng))
        scene.step()
        if after_step is not None:
            after_step()


def check_random_actions(cls: type[Agent], seconds: float = 5.0, seed: int = 0) -> CheckResult:
    """``seconds`` of uniformly random actions in every mode without instability;
    :class:`ConfigError` unless ``seconds`` covers at least one control step (0.05 s at
    the scenes' 20 Hz control: fewer ran no action and passed)."""
    if not (math.isfinite(seconds) and seconds * DEFAULT_CONTROL_FREQ >= 1.0):
        raise ConfigError(
            f"check_random_actions: expected seconds covering at least one control step "
            f"(>= {1.0 / DEFAULT_CONTROL_FREQ:g} s at {DEFAULT_CONTROL_FREQ} Hz control), got {seconds!r}."
        )
    failed: list[str] = []
    for mode in cls.modes():
        try:
            scene = Scene(cls, control_modes=mode)
        except RobotAgentsError as err:
            failed.append(f"{mode} ({err})")
            continue
        scene.reset()
        run_random_actions(scene, seconds, seed)
        if scene.world.unstable_steps.any() or not np.all(np.isfinite(scene.world.get_state())):
            failed.append(mode)
        scene.close()
    count = len(cls.modes())
    detail = f"{count - len(failed)}/{count} modes stable"
    if failed:
        detail += f"; unstable: {failed} (lower the gains, add armature to light joints, or raise sim_freq)"
    return CheckResult(f"{seconds:g} s of random actions in every mode", not failed, detail)


def check_inertia(cls: type[Agent]) -> CheckResult:
    """Moving bodies have plausible masses and physically valid inertias. A moving body
    is judged with the bodies welded to it (a frame, a housing: robosuite's mobile bases
    put their joints on a massless frame whose welded children carry the mass): their
    total mass, and the inertia of the body itself, or theirs combined where the body
    itself has no mass."""
    checked = cls.check()
    model = checked.index.model
    weld = model.body_weldid
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    bad = []
    for body in range(1, model.nbody):
        if weld[body] != body:
            continue
        group = np.flatnonzero(weld == body)
        mass = float(model.body_mass[group].sum())
        if not (MASS_RANGE[0] <= mass <= MASS_RANGE[1]):
            bad.append(f"{model.body(body).name} mass {mass:.3g} kg")
            continue
        own = model.body_mass[body] > 0
        inertia = np.sort(model.body_inertia[body]) if own else _combined_inertia(model, data, group)
        if inertia[0] + inertia[1] < inertia[2] * (1 - 1e-6) or inertia[0] <= 0:
            label = "inertia" if own else "inertia (with its welded bodies)"
            bad.append(f"{model.body(body).name} {label} {inertia.round(6).tolist()}")
    detail = "all moving bodies plausible" if not bad else "; ".join(bad[:5]) + (" ..." if len(bad) > 5 else "")
    return CheckResult(f"masses in [{MASS_RANGE[0]:g}, {MASS_RANGE[1]:g}] kg and valid inertias", not bad, detail)


def _combined_inertia(model: mujoco.MjModel, data: mujoco.MjData, bodies: npt.NDArray[np.intp]) -> FloatArray:
    """Principal moments (kg*m^2, ascending) of ``bodies`` as one rigid body about their
    common centre of mass, from their poses in ``data``: each body's inertia turned into
    the world frame and moved by the parallel-axis theorem."""
    turns = [data.ximat[b].reshape(3, 3) for b in bodies]
    tensors = [turn @ np.diag(model.body_inertia[b]) @ turn.T for b, turn in zip(bodies, turns, strict=True)]
    _, _, total = combine_inertias(list(model.body_mass[bodies]), list(data.xipos[bodies]), tensors)
    moments: FloatArray = np.linalg.eigvalsh(total).astype(np.float64)
    return moments


def check_pd_stability(cls: type[Agent], timestep: float | None = None) -> CheckResult:
    """Every PD drive's stiffness below half the explicit bound ``4 I / dt^2`` at the
    physics step ``timestep`` (s; default: the robot's own, ``1 / sim_freq``). MuJoCo
    integrates damping implicitly; stiffness limits the step."""
    if timestep is None:
        timestep = 1.0 / default_sim_freq([cls])
    checked = cls.check()
    model = checked.index.model
    affine = [d for d in checked.drives if d.kind in (DriveKind.AFFINE, DriveKind.EXPLICIT)]
    full = model.qpos0.copy()
    full[checked.index.qpos_adr] = next(iter(checked.keyframes.values())).qpos
    gains = gains_from_inertia(model, [d.joint for d in affine], full)
    stiffness = []
    for drive in affine:
        actuator = joint_actuator(model, drive.joint)  # an affine or explicit drive always has one
        kp = (
            -float(model.actuator_biasprm[actuator, 1]) * float(model.actuator_gear[actuator, 0]) ** 2
            if actuator is not None
            else 0.0
        )
        stiffness.append(drive.stiffness if drive.stiffness > 0 or drive.kind is DriveKind.EXPLICIT else kp)
    if not any(k > 0 for k in stiffness):
        return CheckResult("PD drives stable at the physics step", True, "no PD drives (motors take efforts)")
    bound = 4.0 * gains.inertia / timestep**2
    share = np.asarray(stiffness) / bound
    worst = int(np.argmax(share))
    detail = (
        f"largest kp / (4 I / dt^2) = {share[worst]:.3f} at {gains.joints[worst]} "
        f"(kp {stiffness[worst]:.4g}; the check passes below {STABLE_SHARE:g} of that bound, "
        f"kp < {STABLE_SHARE * bound[worst]:.4g}; dt {timestep:g} s)"
    )
    return CheckResult("PD drives stable at the physics step", bool(share[worst] < STABLE_SHARE), detail)


def check_standing(cls: type[Agent]) -> CheckResult | None:
    """A robot whose legs carry a free base stands from each keyframe at its physics
    step (the sweep's standing claim, :mod:`robot_agents.tuning.standing_claim`);
    ``None`` for other robots."""
    from robot_agents.tuning.claims import Penetration
    from robot_agents.tuning.standing_claim import STAND_SECONDS, standing_claim

    claim = standing_claim(cls, default_sim_freq([cls]), DEFAULT_CONTROL_FREQ, Penetration())
    if claim is None:
        return None
    name = f"stands {STAND_SECONDS:g} s on its legs from each keyframe"
    detail = f"base moved {claim.value * 1000:.1f} mm after settling (bound {claim.bound * 1000:g} mm); {claim.detail}"
    return CheckResult(name, claim.passed, detail)


def run_checks(cls: type[Agent], random_seconds: float = 5.0) -> list[CheckResult]:
    """Every check that applies to the robot, in order."""
    checks = [
        check_keyframes(cls),
        check_holds(cls),
        check_random_actions(cls, random_seconds),
        check_inertia(cls),
        check_pd_stability(cls),
    ]
    standing = check_standing(cls)
    return checks if standing is None else [*checks[:2], standing, *checks[2:]]
