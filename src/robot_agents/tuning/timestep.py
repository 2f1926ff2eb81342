"""The time-step sweep: the largest physics step at which all of a robot's physics
claims hold.

For a robot, :func:`sweep_timestep` tries physics steps from large to small among the
divisors of the control period (``1 / control_freq`` split into ``n`` substeps) and
measures, at each step, every claim the robot makes:

- ``hold``: each keyframe held for :data:`HOLD_SECONDS` in the default mode, no joint
  drifting more than :data:`~robot_agents.checks.HOLD_TOLERANCE` (rad or m);
- ``random``: :data:`RANDOM_SECONDS` of uniformly random actions in every mode without
  instability (MuJoCo warnings, non-finite state) and without a joint passing its limit
  by more than :data:`OVERSHOOT_BOUND`;
- ``settle``: after the random actions, :data:`SETTLE_SECONDS` of the hold action (joint
  modes that command positions or velocities) leaves every joint slower than
  :data:`SETTLE_SPEED` (catches limit cycles such as a drive bang-banging between its
  torque limits every physics step);
- ``ee_tracking``: where the robot has an end effector, a commanded 2 cm move of the
  tool (``pd_ee_target_delta_pos``, else an absolute end-effector mode) reached within
  :data:`EE_TOLERANCE` of the commanded distance after :data:`EE_SECONDS`;
- ``penetration``: the deepest contact while holding and tracking at most
  :data:`PENETRATION_BOUND` (the depth random actions press is reported beside it).

Grasp holding (no slip of a grasped cube) is measured by the scripted PickCube solver's
tests (``tests/test_scripted_solvers.py``), which run at each robot's default step.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from robot_agents.agent import Agent
from robot_agents.checks import HOLD_TOLERANCE, hold_action
from robot_agents.controllers.ee import PDEEController
from robot_agents.errors import ConfigError, RobotAgentsError
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.registry import get_agent
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene

#: Seconds each keyframe is held.
HOLD_SECONDS = 2.0
#: Seconds of random actions per mode.
RANDOM_SECONDS = 10.0
#: How far (rad or m) a joint may pass its limit under random actions. MuJoCo's joint
#: limits are soft constraints (time constant 0.02 s, whatever the step), so a joint
#: driven into its limit at speed passes it by about speed x 0.02 s x a few, at any
#: step: at every step from 1 ms to 10 ms the Panda's velocity-feedforward modes push
#: joint 1 0.08-0.16 rad past, the WidowX 250 S's elbow 0.15-0.23 rad, the Koch's
#: joints 0.08-0.19 rad (2026-11-23 sweep). This bound catches a step too coarse to
#: stop a joint at all (0.3-2 rad at 25 ms).
OVERSHOOT_BOUND = 0.25
#: Seconds of the hold action after the random actions.
SETTLE_SECONDS = 1.0
#: Fastest joint speed (rad/s or m/s) allowed at the end of the settle phase.
SETTLE_SPEED = 0.05
#: The end-effector move commanded (m) and the seconds it is given.
EE_MOVE = 0.02
EE_SECONDS = 1.0
#: Largest end-effector tracking error, as a share of the commanded move.
EE_TOLERANCE = 0.05
#: Deepest contact penetration allowed (m) while holding keyframes and tracking the
#: end-effector move. (Random actions press links into the floor with the drives' full
#: torque, 1-8 cm at any step; that depth is reported, not judged.)
PENETRATION_BOUND = 0.005
#: Substeps per control step tried by default (control period / n), large steps first.
DEFAULT_SUBSTEPS = (2, 4, 5, 8, 10, 16, 20, 25, 40, 50)
#: The claims, in the order they are reported.
CLAIMS = ("hold", "random", "settle", "ee_tracking", "penetration")


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

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.claims)

    def claim(self, name: str) -> ClaimResult | None:
        return next((c for c in self.claims if c.name == name), None)


@dataclass(frozen=True)
class SweepResult:
    """A robot's sweep: per step (largest first) its claims, and the largest step at
    which all held (``None``: none did)."""

    uid: str
    control_freq: int
    steps: tuple[StepResult, ...] = field(default_factory=tuple)

    @property
    def largest_passing(self) -> int | None:
        """The lowest ``sim_freq`` (largest step) at which every claim held, provided
        every smaller step tried also passed (a pass below a failure is not trusted)."""
        best = None
        for step in sorted(self.steps, key=lambda s: -s.sim_freq):  # small steps first
            if not step.passed:
                break
            best = step.sim_freq
        return best

    def table(self) -> str:
        """A markdown table: one row per step, one column per claim (value, pass)."""
        header = "| sim_freq (Hz) | step (ms) | " + " | ".join(CLAIMS) + " | all | random-action press (m) |"
        rows = [header, "|" + "---|" * (len(CLAIMS) + 4)]
        for step in self.steps:
            cells = []
            for name in CLAIMS:
                claim = step.claim(name)
                if claim is None:
                    cells.append("n/a")
                else:
                    cells.append(f"{claim.value:.3g}{'' if claim.passed else ' FAIL'}")
            ok = "yes" if step.passed else "no"
            rows.append(
                f"| {step.sim_freq} | {1000 / step.sim_freq:.3g} | "
                + " | ".join(cells)
                + f" | {ok} | {step.random_press_depth:.3g} |"
            )
        return "\n".join(rows)


class _Penetration:
    """The deepest contact penetration (m) seen in env 0 of a scene."""

    def __init__(self) -> None:
        self.depth = 0.0
        self.where = ""

    def measure(self, scene: Scene) -> None:
        data = scene.world.render_sources([0])[0]
        if data.ncon:
            dist = data.contact.dist[: data.ncon]
            deepest = int(np.argmin(dist))
            if -float(dist[deepest]) > self.depth:
                self.depth = -float(dist[deepest])
                g1, g2 = data.contact.geom1[deepest], data.contact.geom2[deepest]
                self.where = f"{scene.model.geom(g1).name} / {scene.model.geom(g2).name}"


def _commands_motion(agent: Agent) -> bool:
    return any(
        kind in ("position", "velocity") for c in agent.controller.parts.values() for kind in c.config.target_kinds()
    )


def _hold(cls: type[Agent], sim_freq: int, control_freq: int, depth: _Penetration) -> ClaimResult:
    mode = cls.default_mode()
    scene = Scene(cls, sim_freq=sim_freq, control_freq=control_freq, control_modes=mode)
    agent = scene.agents[0]
    if not _commands_motion(agent):
        scene.close()
        return ClaimResult("hold", True, 0.0, HOLD_TOLERANCE, f"{mode} commands efforts")
    worst, where = 0.0, ""
    for name in cls.keyframe_names():
        scene.reset(keyframes=name)
        start = agent.qpos
        for _ in range(round(HOLD_SECONDS * control_freq)):
            agent.set_action(hold_action(agent))
            scene.step()
            depth.measure(scene)
            drift = float(np.max(np.abs(agent.qpos - start), initial=0.0))
            if drift > worst:
                worst, where = drift, name
    scene.close()
    return ClaimResult("hold", worst < HOLD_TOLERANCE, worst, HOLD_TOLERANCE, where)


def _random(
    cls: type[Agent], sim_freq: int, control_freq: int, seed: int, depth: _Penetration
) -> tuple[ClaimResult, ClaimResult]:
    """Random actions in every mode; ``depth`` collects how deep they press links into
    the floor or each other (reported, not judged: that depth is set by the drives'
    torque against MuJoCo's soft contacts, not by the step)."""
    unstable: list[str] = []
    overshoot, over_where = 0.0, ""
    speed, speed_where = 0.0, ""
    for mode in cls.modes():
        try:
            scene = Scene(cls, sim_freq=sim_freq, control_freq=control_freq, control_modes=mode)
        except RobotAgentsError as err:
            unstable.append(f"{mode} ({err})")
            continue
        scene.reset()
        agent = scene.agents[0]
        limits = agent.qpos_limits
        rng = np.random.default_rng(seed)
        space = agent.action_space
        for _ in range(round(RANDOM_SECONDS * control_freq)):
            agent.set_action(rng.uniform(space.low, space.high))
            scene.step()
            depth.measure(scene)
            q = agent.qpos[0]
            beyond = np.maximum(q - limits[:, 1], limits[:, 0] - q)
            past = float(np.max(beyond, initial=0.0))
            if past > overshoot:
                overshoot, over_where = past, f"{mode}: {agent.joint_names[int(np.argmax(beyond))]}"
        if _commands_motion(agent) and not any(isinstance(c, PDEEController) for c in agent.controller.parts.values()):
            for _ in range(round(SETTLE_SECONDS * control_freq)):
                agent.set_action(hold_action(agent))
                scene.step()
                depth.measure(scene)
            fastest = float(np.max(np.abs(agent.qvel[0]), initial=0.0))
            if fastest > speed:
                speed, speed_where = fastest, f"{mode}: {agent.joint_names[int(np.argmax(np.abs(agent.qvel[0])))]}"
        if scene.world.unstable_steps.any() or not np.all(np.isfinite(scene.world.get_state())):
            unstable.append(mode)
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


def _ee_mode(cls: type[Agent]) -> str | None:
    modes = cls.modes()
    for name in ("pd_ee_target_delta_pos", "pd_ee_pose", "pd_ee_target_delta_pose"):
        if name in modes:
            return name
    return None


def _ee_tracking(cls: type[Agent], sim_freq: int, control_freq: int, depth: _Penetration) -> ClaimResult | None:
    mode = _ee_mode(cls)
    if mode is None:
        return None
    scene = Scene(cls, sim_freq=sim_freq, control_freq=control_freq, control_modes=mode)
    scene.reset()
    agent = scene.agents[0]
    if not agent.has_end_effector:
        scene.close()
        return None
    controllers = list(agent.controller.parts.values())
    start_tcp = agent.tcp_pose[0, :3].copy()
    start_target = next(c for c in controllers if isinstance(c, PDEEController)).target_pose[0, :3].copy()
    rotation = quat_to_matrix(agent.base_pose[0, 3:])
    first = []
    for controller in controllers:
        hold = hold_action_of(agent, controller)
        if isinstance(controller, PDEEController):
            raw = hold.copy() if not controller.config.use_delta else np.zeros(controller.action_dim)
            raw[0] += EE_MOVE
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
    return ClaimResult("ee_tracking", error <= EE_TOLERANCE, error, EE_TOLERANCE, f"{mode}, {distance * 1000:.1f} mm")


def hold_action_of(agent: Agent, controller: object) -> np.ndarray:
    """The hold action's slice belonging to one part's controller."""
    action = hold_action(agent)
    start = 0
    for part in agent.controller.parts.values():
        if part is controller:
            return np.asarray(action[start : start + part.action_dim])
        start += part.action_dim
    raise ConfigError(f"hold_action_of: the controller is not one of {type(agent).__name__}'s parts.")


def measure_step(
    cls: type[Agent], sim_freq: int, control_freq: int = DEFAULT_CONTROL_FREQ, seed: int = 0
) -> StepResult:
    """Every claim of ``cls`` at ``sim_freq``."""
    depth, pressed = _Penetration(), _Penetration()
    claims = [_hold(cls, sim_freq, control_freq, depth), *_random(cls, sim_freq, control_freq, seed, pressed)]
    tracking = _ee_tracking(cls, sim_freq, control_freq, depth)
    if tracking is not None:
        claims.append(tracking)
    claims.append(
        ClaimResult("penetration", depth.depth <= PENETRATION_BOUND, depth.depth, PENETRATION_BOUND, depth.where)
    )
    return StepResult(sim_freq, tuple(claims), pressed.depth)


def sweep_timestep(
    robot: str | type[Agent],
    control_freq: int = DEFAULT_CONTROL_FREQ,
    substeps: Sequence[int] = DEFAULT_SUBSTEPS,
    seed: int = 0,
    stop_after: int | None = 2,
    progress: Callable[[StepResult], None] | None = None,
) -> SweepResult:
    """Measure every claim of ``robot`` at ``sim_freq = control_freq * n`` for each
    ``n`` in ``substeps``, largest step first.

    ``stop_after``: stop once this many steps in a row have passed (the sweep's answer
    is then settled: smaller steps are not expected to fail); ``None`` tries them all.
    ``progress`` is called with each step's result as it is measured.
    """
    cls = get_agent(robot) if isinstance(robot, str) else robot
    if not (isinstance(cls, type) and issubclass(cls, Agent)):
        raise ConfigError(f"sweep_timestep: expected a robot uid or an Agent subclass, got {robot!r}.")
    counts = sorted({int(n) for n in substeps})
    if not counts or counts[0] < 1:
        raise ConfigError(f"sweep_timestep: expected positive substep counts, got {list(substeps)!r}.")
    results: list[StepResult] = []
    passes = 0
    for n in counts:
        step = measure_step(cls, control_freq * n, control_freq, seed)
        results.append(step)
        if progress is not None:
            progress(step)
        passes = passes + 1 if step.passed else 0
        if stop_after is not None and passes >= stop_after:
            break
    return SweepResult(cls.uid or cls.__name__, control_freq, tuple(results))
