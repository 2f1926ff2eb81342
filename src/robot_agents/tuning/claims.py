"""The physics claims of a robot at one physics step (what the time-step sweep of
:mod:`robot_agents.tuning.timestep` measures at each step it tries).

:func:`measure_step` measures, at one ``sim_freq``, every claim the robot makes:

- ``hold``: each keyframe held for :data:`HOLD_SECONDS` in the default mode, no joint
  drifting more than :data:`~robot_agents.checks.HOLD_TOLERANCE` (rad or m);
- ``random``: :data:`RANDOM_SECONDS` of uniformly random actions in every mode, for each
  of :data:`RANDOM_SEEDS`, without instability (MuJoCo warnings, non-finite state) and
  without a joint passing its limit by more than :data:`OVERSHOOT_BOUND`;
- ``settle``: after the random actions, the robot asked to stay where they left it
  (joint modes that command positions or velocities: targets set to the measured pose
  once, then one hold command repeated; :func:`settle_hold`) has every joint slower than
  :data:`SETTLE_SPEED` over the last :data:`SETTLE_WINDOW` of :data:`SETTLE_SECONDS`
  (catches limit cycles such as a drive bang-banging between its torque limits every
  physics step, or a contact that bounces); a robot standing on its legs is given
  :data:`LEGGED_SETTLE_SECONDS` and judged on the joints that cycle over that window
  (:data:`CYCLE_SHARE`), in the modes whose hold keeps its targets
  (:func:`~robot_agents.checks.keeps_targets`: elsewhere its loaded legs creep);
- ``ee_tracking``: where the robot has an end effector, a commanded 2 cm move of the
  tool (``pd_ee_target_delta_pos``, else an absolute end-effector mode) along the x
  axis of its command frame (another axis where the arm cannot move the tool along x)
  reached within :data:`EE_TOLERANCE` of the commanded distance after :data:`EE_SECONDS`;
- ``grasp``: where the robot has a gripper (a Gripper part with two fingers), a cube of
  the table-top tasks' size for that gripper (half its opening, water's density; see
  :mod:`robot_agents.envs.tasks.table_top`) is placed between the open fingers where the
  scripted PickCube solver grasps it (the gripper's grasp point, a fifth of an edge
  towards the wrist; 0.4 and 0.6 edges deeper when it does not hold there; faces square
  to the closing axis), weightless while the fingers close (no floor: the cube meets
  only the robot); then its weight is on, the tool is lifted and the cube held
  (:mod:`.grasp_claim` has the times, the lift and the bound): the cube may move at most
  :data:`~.grasp_claim.SLIP_BOUND`
  relative to the tool frame over the hold (a cube that falls or slides out moves more;
  a movement of more than the cube's edge is reported as the edge: the cube is lost);
  a hand that declares its power grasp (``Hand.power_grasp``) closes to ``closed`` on
  the declared cube instead and holds it against a pull of 1 g away from the palm (its
  movement relative to the palm counts; a hand without one makes no grasp claim);
- ``standing``: where the robot's legs carry a free base (a ``Legs`` part that is not
  held, a free root), from each keyframe it holds its pose on the floor and stays still,
  upright and on its feet alone (:mod:`.standing_claim` has the times and bounds);
  ``spot``'s legs are held and its base kinematic (Habitat's navmesh-style base): it makes
  no standing claim;
- ``penetration``: the deepest contact while holding keyframes, tracking, holding
  the grasped cube and standing at most :data:`PENETRATION_BOUND` (the depth random
  actions press is reported beside it; the fingers' impact while closing on the cube is
  not judged).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from robot_agents.agent import Agent
from robot_agents.checks import (
    HOLD_TOLERANCE,
    LOAD_SETTLE_SECONDS,
    contact_label,
    hold_action,
    hold_drift,
    keeps_targets,
    load_settle_steps,
    raw_hold,
    run_random_actions,
    standing_leg_joints,
)
from robot_agents.controllers.ee import PDEEController
from robot_agents.errors import ConfigError, RobotAgentsError
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene
from robot_agents.validation import is_whole

#: Seconds each keyframe is held.
HOLD_SECONDS = 2.0
#: Seconds of random actions per mode (and per seed).
RANDOM_SECONDS = 10.0
#: Seeds of the random action sequences; the claim holds only if it holds for each.
#: One seed let a rare event decide a step: a random ``pd_ee_pose`` target that pries
#: Spot's jaw into its own leg appeared with seed 0 at 800 Hz only (2026-11-23 sweep),
#: so a step could pass by luck of the one sequence tried.
RANDOM_SEEDS = (0, 1, 2)
#: How far (rad or m) a joint may pass its limit under random actions. MuJoCo's joint
#: limits are soft constraints (time constant 0.02 s, whatever the step), so a joint
#: driven into its limit at speed passes it by about speed x 0.02 s x a few, at any
#: step: at every step from 1 ms to 10 ms the Panda's velocity-feedforward modes push
#: joint 1 0.08-0.16 rad past, the WidowX 250 S's elbow 0.15-0.23 rad, the Koch's
#: joints 0.08-0.19 rad (2026-11-23 sweep). This bound catches a step too coarse to
#: stop a joint at all (0.3-2 rad at 25 ms).
OVERSHOOT_BOUND = 0.25
#: Seconds of one repeated hold command after the random actions: long enough for an
#: underdamped drive to recover from a large swing (the WidowX 250 S's waist, thrown
#: 1.2 rad past its target, rings down within 1.5 s; Fetch's shoulder pan, swinging
#: 1.2 rad, within 2.4 s), and a limit cycle never decays, so it is still caught. The
#: hold starts from targets at the measured pose: kept where the random actions left
#: them, a target-delta mode's targets can lie far off (the Bridge WidowX's tuned,
#: overdamped forearm roll was still closing a 0.39 rad gap after 3 s; the Stretch's
#: telescope 9 cm), or inside the robot's own body (the WidowX AI folded onto its base,
#: its jammed links slipping at 0.05-0.26 rad/s for seconds): travel and jams, not the
#: step's doing (2026-11-28).
SETTLE_SECONDS = 3.0
#: How long (s) every joint must have stayed below :data:`SETTLE_SPEED`, on end, when
#: the settle claim is judged: sampled at the control rate, one instant can fall on a
#: slow phase of a cycle (a fingertip of the Allegro hand chattering on another finger
#: showed 0.003-0.09 rad/s from one control step to the next, 2026-11-28).
SETTLE_WINDOW = 0.5
#: The settle phase of a robot standing on its legs: random actions may have thrown it
#: over, and a body still rolling or sliding to rest moves its joints (the Unitree H1,
#: seed 0 at 500 Hz: its torso turns at 0.29 rad/s 3 s into the hold, everything is
#: still by 3.5 s); a limit cycle never decays, so it is still caught.
LEGGED_SETTLE_SECONDS = 5.0
#: A robot standing on its legs is judged on cycling joints only: thrown over by the
#: random actions, it lies on its links, which rock and slip under its weight long after
#: the drives are still (2026-11-28: the ANYmal on its back rocking until about 9 s,
#: a hip at up to 0.36 rad/s; the H1's arm under its body creeping at 0.12 rad/s for 12 s),
#: and that motion, not a drive's, decided the claim by the chance of the instant read.
#: A joint cycles when, at every control step of the last :data:`SETTLE_WINDOW`, it is
#: faster than :data:`SETTLE_SPEED` and moved less than this share of the distance its
#: speed covers in one control step: a drive flipping between its torque limits every
#: physics step barely moves (the Go2 with ManiSkill's kp 1000 / kv 100 at 400 Hz: 3 rad/s,
#: 0.01 of that distance), a rocking or creeping body does (0.25-2.7, and 1.0).
CYCLE_SHARE = 0.1
#: Fastest joint speed (rad/s or m/s) allowed at the end of the settle phase.
SETTLE_SPEED = 0.05
#: The end-effector move commanded (m) and the seconds it is given.
EE_MOVE = 0.02
EE_SECONDS = 1.0
#: Largest end-effector tracking error, as a share of the commanded move.
EE_TOLERANCE = 0.05
#: Deepest contact penetration allowed (m) while holding keyframes and tracking the
#: end-effector move. (Random actions press links into the floor and into each other
#: with the drives' full torque, 0.3-25 cm at the built-in robots' defaults; that depth
#: and where it is are reported, not judged: docs/timestep.md, "Where random actions
#: press".)
PENETRATION_BOUND = 0.005
#: The claims, in the order they are reported.
CLAIMS = ("hold", "random", "settle", "ee_tracking", "grasp", "standing", "penetration")


@dataclass(frozen=True)
class ClaimResult:
    """One claim at one step: whether it held, the measured value and its bound."""

    name: str
    passed: bool
    value: float
    bound: float
    detail: str = ""


@dataclass(frozen=True)
class StepResult:
    """Every claim at one physics rate."""

    sim_freq: int
    claims: tuple[ClaimResult, ...]
    #: Deepest contact under random actions (m), for information (see :func:`_random`).
    random_press_depth: float = 0.0
    #: Where it was: the two geoms (:func:`contact_label`), ``""`` when nothing touched.
    random_press_where: str = ""

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.claims)

    def claim(self, name: str) -> ClaimResult | None:
        return next((c for c in self.claims if c.name == name), None)


class Penetration:
    """The deepest contact penetration (m) seen in env 0 of a scene."""

    def __init__(self) -> None:
        self.depth = 0.0
        self.where = ""

    def measure(self, scene: Scene) -> None:
        data = scene.world.physics_sources([0])[0]
        if data.ncon:
            dist = data.contact.dist[: data.ncon]
            deepest = int(np.argmin(dist))
            if -float(dist[deepest]) > self.depth:
                self.depth = -float(dist[deepest])
                g1, g2 = data.contact.geom1[deepest], data.contact.geom2[deepest]
                self.where = f"{contact_label(scene.model, g1)} / {contact_label(scene.model, g2)}"


def _commands_motion(agent: Agent) -> bool:
    return any(
        kind in ("position", "velocity") for c in agent.controller.parts.values() for kind in c.config.target_kinds()
    )


def _hold(cls: type[Agent], sim_freq: int, control_freq: int, depth: Penetration) -> ClaimResult:
    mode = cls.default_mode()
    scene = claim_scene(cls, sim_freq, control_freq, mode)
    agent = scene.agents[0]
    if not _commands_motion(agent):
        scene.close()
        return ClaimResult("hold", True, 0.0, HOLD_TOLERANCE, f"{mode} commands efforts")
    worst, where, sag = 0.0, "", 0.0
    settle_steps = load_settle_steps(cls, control_freq)
    for name in cls.keyframe_names():
        scene.reset(keyframes=name)
        drift, settling = hold_drift(scene, agent, HOLD_SECONDS, settle_steps, lambda: depth.measure(scene))
        sag = max(sag, settling)
        if drift > worst or not where:
            worst, where = drift, name
    scene.close()
    if settle_steps:
        where += f" (after {LOAD_SETTLE_SECONDS:g} s on its legs; sag meanwhile {sag:.4f})"
    return ClaimResult("hold", worst < HOLD_TOLERANCE, worst, HOLD_TOLERANCE, where)


def _random(
    cls: type[Agent], sim_freq: int, control_freq: int, seeds: Sequence[int], depth: Penetration
) -> tuple[ClaimResult, ClaimResult]:
    """Random actions in every mode, one sequence per seed (the worst counts); ``depth``
    collects how deep they press links into the floor or each other (reported, not
    judged: that depth is set by the drives' torque against MuJoCo's soft contacts, not
    by the step)."""
    unstable: list[str] = []
    overshoot, over_where = 0.0, ""
    speed, speed_where = 0.0, ""
    legged = bool(standing_leg_joints(cls))
    settle_seconds = LEGGED_SETTLE_SECONDS if legged else SETTLE_SECONDS
    for mode, seed in [(mode, seed) for mode in cls.modes() for seed in seeds]:
        where = f"{mode} (seed {seed})" if len(seeds) > 1 else mode
        try:
            scene = claim_scene(cls, sim_freq, control_freq, mode)
        except RobotAgentsError as err:
            unstable.append(f"{where} ({err})")
            continue
        scene.reset()
        agent = scene.agents[0]
        limits = agent.qpos_limits

        def measure(
            scene: Scene = scene, agent: Agent = agent, limits: np.ndarray = limits, where: str = where
        ) -> None:
            nonlocal overshoot, over_where
            depth.measure(scene)
            q = agent.qpos[0]
            beyond = np.maximum(q - limits[:, 1], limits[:, 0] - q)
            past = float(np.max(beyond, initial=0.0))
            if past > overshoot:
                overshoot, over_where = past, f"{where}: {agent.joint_names[int(np.argmax(beyond))]}"

        run_random_actions(scene, RANDOM_SECONDS, seed, measure)
        settles = _commands_motion(agent) and not any(
            isinstance(c, PDEEController) for c in agent.controller.parts.values()
        )
        if settles and legged and not keeps_targets(agent):
            # legs under the body's weight give at load / damping in a mode whose hold
            # keeps no target (a zero delta from the measured pose, a zero velocity):
            # creep, not a cycle, and not the step's doing
            settles = False
        if settles:
            fastest, joint = settle_hold(scene, agent, settle_seconds, partial(depth.measure, scene), legged)
            if fastest > speed or not speed_where:
                speed, speed_where = fastest, f"{where}: {joint or 'no joint cycling'}"
        if scene.world.unstable_steps.any() or not np.all(np.isfinite(scene.world.get_state())):
            unstable.append(where)
        scene.close()
    random = ClaimResult(
        "random",
        not unstable and overshoot <= OVERSHOOT_BOUND,
        overshoot,
        OVERSHOOT_BOUND,
        (f"unstable: {unstable}; " if unstable else "") + f"largest overshoot at {over_where}",
    )
    settle = ClaimResult("settle", speed <= SETTLE_SPEED, speed, SETTLE_SPEED, speed_where)
    return random, settle


def settle_hold(
    scene: Scene,
    agent: Agent,
    seconds: float = SETTLE_SECONDS,
    on_step: Callable[[], None] | None = None,
    cycles_only: bool = False,
) -> tuple[float, str]:
    """The settle claim's hold in env 0 of ``scene``: the controllers' targets set to the
    measured pose once (as a reset does: the robot is asked to stay where the random
    actions left it, not to finish travelling to their last targets), then one hold
    command (:func:`~robot_agents.checks.hold_action`, taken once and repeated, so that
    a joint sagging under its load cannot drag its own target along) for ``seconds``.

    Returns the fastest joint speed over the last :data:`SETTLE_WINDOW` (rad/s or m/s;
    passive wheels left out: they turn with the base, whose joints count) and that
    joint's name; with ``cycles_only``, the fastest among the joints that cycled over that
    window (:data:`CYCLE_SHARE`; 0 and ``""`` when none did). ``on_step`` is called after
    each control step."""
    agent.controller.reset(np.zeros(1, dtype=np.int64), agent.world)
    hold = hold_action(agent)
    control_freq = scene.control_freq
    steps = max(1, round(seconds * control_freq))
    last_steps = min(steps, max(1, round(SETTLE_WINDOW * control_freq)))
    wheels = [w.dof_start for w in agent.mobile.wheels]
    fastest = np.zeros(len(agent.joint_names))  # per joint, over the window
    cycling = np.ones(len(agent.joint_names), dtype=bool)  # fast and barely moving at every step of it
    qpos = agent.qpos[0]
    for step in range(steps):
        agent.set_action(hold)
        scene.step()
        if on_step is not None:
            on_step()
        moved, qpos = np.abs(agent.qpos[0] - qpos), agent.qpos[0]
        if step >= steps - last_steps:
            speeds = np.abs(agent.qvel[0])
            speeds[wheels] = 0.0
            np.maximum(fastest, speeds, out=fastest)
            cycling &= (speeds > SETTLE_SPEED) & (moved < CYCLE_SHARE * speeds / control_freq)
    if cycles_only:
        fastest = np.where(cycling, fastest, 0.0)
    if not fastest.size or not fastest.any():
        return 0.0, "" if cycles_only or not agent.joint_names else agent.joint_names[0]
    joint = int(np.argmax(fastest))
    return float(fastest[joint]), agent.joint_names[joint]


def ee_mode(cls: type[Agent]) -> str | None:
    modes = cls.modes()
    for name in ("pd_ee_target_delta_pos", "pd_ee_pose", "pd_ee_target_delta_pose"):
        if name in modes:
            return name
    return None


def _ee_tracking(cls: type[Agent], sim_freq: int, control_freq: int, depth: Penetration) -> ClaimResult | None:
    mode = ee_mode(cls)
    if mode is None:
        return None
    scene = claim_scene(cls, sim_freq, control_freq, mode)
    scene.reset()
    agent = scene.agents[0]
    if not agent.has_end_effector:
        scene.close()
        return None
    from robot_agents.envs.tasks.layout import tool_arm

    controllers = list(agent.controller.parts.values())
    start_tcp = agent.tcp_pose[0, :3].copy()
    start_target = next(c for c in controllers if isinstance(c, PDEEController)).target_pose[0, :3].copy()
    # The axes commands are expressed in (the end effector's command frame), and the axis
    # moved along: x, unless the arm moves the tool along x less than half as readily as
    # along its best axis (a Stretch's arm cannot move its tool forward: its base does).
    arm = tool_arm(agent, "sweep_timestep")
    tool_ee = arm.end_effectors[0]
    frame = tool_ee.command_frame or "root"
    tool, tool_in_frame = agent.frame_pose(tool_ee.name)[0], agent.frame_pose(tool_ee.name, relative_to=frame)[0]
    rotation = quat_to_matrix(tool[3:]) @ quat_to_matrix(tool_in_frame[3:]).T
    dofs = [agent.index.joint(j, "sweep_timestep").dof_start for j in agent.part_joints[arm.name]]
    reach = np.linalg.norm(agent.frame_jacobian(tool_ee.name, relative_to=frame)[0, :3][:, dofs], axis=1)
    axis = 0 if reach[0] >= 0.5 * reach.max() else int(np.argmax(reach))
    first = []
    for controller in controllers:
        hold = hold_action_of(agent, controller)
        if isinstance(controller, PDEEController):
            raw = raw_hold(controller, hold)
            raw[axis] += EE_MOVE
            first.append(controller.from_raw(raw))
        else:
            first.append(hold)
    ee = next(c for c in controllers if isinstance(c, PDEEController))
    agent.set_action(np.concatenate(first))
    scene.step()
    commanded = ee.target_pose[0, :3] - start_target
    for _ in range(round(EE_SECONDS * control_freq) - 1):
        agent.set_action(hold_action(agent))
        scene.step()
        depth.measure(scene)
    moved = agent.tcp_pose[0, :3] - start_tcp
    distance = float(np.linalg.norm(commanded))
    error = float(np.linalg.norm(moved - rotation @ commanded)) / max(distance, 1e-9)
    scene.close()
    detail = f"{mode}, {distance * 1000:.1f} mm along {'xyz'[axis]}"
    return ClaimResult("ee_tracking", error <= EE_TOLERANCE, error, EE_TOLERANCE, detail)


def hold_action_of(agent: Agent, controller: object) -> np.ndarray:
    """The hold action's slice belonging to one part's controller."""
    for name, part in agent.controller.parts.items():
        if part is controller:
            return np.asarray(hold_action(agent)[agent.controller.slices[name]])
    raise ConfigError(f"hold_action_of: the controller is not one of {type(agent).__name__}'s parts.")


def checked_seeds(seeds: Sequence[int], where: str) -> tuple[int, ...]:
    """``seeds`` as a tuple of ints, or a :class:`ConfigError` naming what was given."""
    if isinstance(seeds, (str, bytes)) or not isinstance(seeds, Sequence):
        raise ConfigError(f"{where}: expected a sequence of int seeds (e.g. (0, 1, 2)), got {seeds!r}.")
    if not seeds or not all(is_whole(s) and s >= 0 for s in seeds):
        raise ConfigError(f"{where}: expected one or more int seeds >= 0, got {list(seeds)!r}.")
    return tuple(int(s) for s in seeds)


#: What every claim's scene is handed to right after it is made (:func:`scene_setup`).
_SCENE_SETUP: ContextVar[Callable[[Scene], None] | None] = ContextVar("claim_scene_setup", default=None)


def claim_scene(cls: type[Agent], sim_freq: int, control_freq: int, mode: str | None, **options: Any) -> Scene:
    """The scene a claim runs in, ``Scene(cls, sim_freq=..., control_freq=...,
    control_modes=mode, **options)``, handed to the active :func:`scene_setup`, if any,
    before the claim resets it."""
    scene = Scene(cls, sim_freq=sim_freq, control_freq=control_freq, control_modes=mode, **options)
    setup = _SCENE_SETUP.get()
    if setup is not None:
        setup(scene)
    return scene


@contextmanager
def scene_setup(setup: Callable[[Scene], None]) -> Iterator[None]:
    """Within the block, every claim's scene is handed to ``setup`` once made (before its
    reset): a benchmark measuring the claims with a variant of the scene, e.g. another
    floor contact (``benchmarks/random_press.py --claims``). The setup is a context
    variable: it applies to claims run in this thread (and in contexts copied from it)."""
    token = _SCENE_SETUP.set(setup)
    try:
        yield
    finally:
        _SCENE_SETUP.reset(token)


def measure_step(
    cls: type[Agent],
    sim_freq: int,
    control_freq: int = DEFAULT_CONTROL_FREQ,
    seeds: Sequence[int] = RANDOM_SEEDS,
) -> StepResult:
    """Every claim of ``cls`` at ``sim_freq``; ``seeds``: the random claim's action
    sequences (each must pass)."""
    seeds = checked_seeds(seeds, "measure_step")
    depth, pressed = Penetration(), Penetration()
    claims = [_hold(cls, sim_freq, control_freq, depth), *_random(cls, sim_freq, control_freq, seeds, pressed)]
    tracking = _ee_tracking(cls, sim_freq, control_freq, depth)
    if tracking is not None:
        claims.append(tracking)
    from robot_agents.tuning.grasp_claim import grasp_claim  # (imports this module)

    grasp = grasp_claim(cls, sim_freq, control_freq, depth)
    if grasp is not None:
        claims.append(grasp)
    from robot_agents.tuning.standing_claim import standing_claim  # (imports this module)

    standing = standing_claim(cls, sim_freq, control_freq, depth)
    if standing is not None:
        claims.append(standing)
    claims.append(
        ClaimResult("penetration", depth.depth <= PENETRATION_BOUND, depth.depth, PENETRATION_BOUND, depth.where)
    )
    return StepResult(sim_freq, tuple(claims), pressed.depth, pressed.where)
