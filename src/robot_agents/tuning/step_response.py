"""Step responses of a robot's drives: how each joint answers a step of its target,
with the gains it declares or with gains to try.

A joint's target is stepped by ``step`` (rad or m) from a keyframe held until settled,
the other joints held where they are, and the joint is recorded at every physics
step: rise time (10-90 % of the step), overshoot, the time after which it stays within
2 % of the step, the error left at the end, the largest drive effort against the
effort limit and the largest speed against the rated speed. A second-order model of
the joint gives what the gains should do: with ``kp`` the stiffness, ``kv`` the drive's
damping plus the joint's own (``dof_damping``) and ``I`` the joint's inertia at the pose
(the diagonal of MuJoCo's joint-space inertia matrix, armature included: the other
joints held stiffly),

    natural frequency  f = sqrt(kp / I) / (2 pi),   damping ratio  zeta = kv / (2 sqrt(kp I)),

overshoot ``exp(-pi zeta / sqrt(1 - zeta^2))`` for ``zeta < 1``; ``kp / (4 I / dt^2)``
is the share of the explicit stability bound at the physics step ``dt`` (as
:func:`robot_agents.checks.check_pd_stability`). A measured response that departs from
the model shows what the model leaves out: the effort limit (a saturated drive ramps
instead of ringing), coupling to the other joints, gravity, contacts.

The same measurement runs from the command line: ``robot-agents tune UID --joints
PATTERN [--stiffness KP] [--damping KV] [--effort-limit L]``.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.gains import inertia_matrix
from robot_agents.agent import Agent
from robot_agents.agent.index import RobotIndex
from robot_agents.checks import hold_action
from robot_agents.controllers.base import Controller
from robot_agents.controllers.joint import PDJointPosConfig, PDJointPosMimicConfig
from robot_agents.errors import ConfigError, MediaError, PhysicsError, UnknownNameError
from robot_agents.patterns import Patterns, match
from robot_agents.registry import agent_class
from robot_agents.sim.scene import Scene, default_sim_freq
from robot_agents.validation import check_real

FloatArray = npt.NDArray[np.float64]

#: The control mode the steps are commanded in: absolute joint targets.
STEP_MODE = "pd_joint_pos"
#: Default steps: rad for a hinge, m for a slide.
HINGE_STEP = 0.1
SLIDE_STEP = 0.01
#: The range of ``seconds`` recorded after each step (s): at least one physics step of
#: any rate up to 1 kHz, at most a minute.
MIN_SECONDS = 1e-3
MAX_SECONDS = 60.0
#: The band a settled joint stays in, as a share of the step.
SETTLE_BAND = 0.02


@dataclass(frozen=True)
class StepResponse:
    """One joint's answer to a step of its target, recorded at every physics step.

    Attributes:
        joint: the joint (its name in the robot's definition).
        start: its settled position before the step (rad or m); target: the target after it.
        stiffness, damping: of the drives moving the joint, in effect (joint units;
            ``damping`` includes the joints' own ``dof_damping``); effort_limit,
            velocity_limit: the joint's drive's (``inf``: none).
        inertia: what the joint moves at the start, armature included (kg*m^2 or kg).
        coupled: the joints moving with it through joint equalities (mimic fingers, a
            telescope's segments), itself included, where there are others; ``stiffness``,
            ``damping`` and ``inertia`` are then the coupled set's seen from the joint,
            the equalities taken as rigid: with ``c`` each joint's motion per unit of
            this one's, ``I = c^T M c``, ``kp = sum c_i^2 kp_i``, ``kv = sum c_i^2 kv_i``.
        physics_step: the step ``dt`` (s).
        times: ``(T,)`` s after the step; positions ``(T,)`` rad or m; velocities ``(T,)``;
        efforts: ``(T,)`` the drive's force on the joint (N*m or N).
        unstable: MuJoCo found the state diverging and reset it during the record.
    """

    joint: str
    start: float
    target: float
    stiffness: float
    damping: float
    effort_limit: float
    velocity_limit: float
    inertia: float
    physics_step: float
    times: FloatArray
    positions: FloatArray
    velocities: FloatArray
    efforts: FloatArray
    unstable: bool
    coupled: tuple[str, ...] = ()

    @property
    def step(self) -> float:
        """The commanded change, ``target - start`` (rad or m)."""
        return self.target - self.start

    @property
    def progress(self) -> FloatArray:
        """``(T,)`` the share of the step covered: 0 at the start, 1 at the target."""
        progress: FloatArray = (self.positions - self.start) / self.step
        return progress

    # -- what the second-order model predicts ------------------------------------------
    @property
    def natural_frequency(self) -> float:
        """Hz, ``sqrt(kp / I) / (2 pi)``."""
        return math.sqrt(self.stiffness / self.inertia) / (2 * math.pi)

    @property
    def damping_ratio(self) -> float:
        """``kv / (2 sqrt(kp I))``; ``inf`` without stiffness."""
        if self.stiffness <= 0:
            return math.inf
        return self.damping / (2 * math.sqrt(self.stiffness * self.inertia))

    @property
    def predicted_overshoot(self) -> float:
        """Share of the step, ``exp(-pi zeta / sqrt(1 - zeta^2))``; 0 when critically
        damped or more."""
        zeta = self.damping_ratio
        return math.exp(-math.pi * zeta / math.sqrt(1 - zeta**2)) if zeta < 1 else 0.0

    @property
    def stability_share(self) -> float:
        """``kp / (4 I / dt^2)``: the stiffness's share of the explicit stability bound."""
        return self.stiffness * self.physics_step**2 / (4 * self.inertia)

    # -- what was measured ---------------------------------------------------------------
    @property
    def rise_time(self) -> float | None:
        """s from 10 % to 90 % of the step; ``None`` when 90 % is never reached."""
        progress = self.progress
        low, high = np.flatnonzero(progress >= 0.1), np.flatnonzero(progress >= 0.9)
        if not len(high):
            return None
        return float(self.times[high[0]] - self.times[low[0]])

    @property
    def overshoot(self) -> float:
        """Share of the step travelled past the target (0 when it never gets past)."""
        return max(float(np.max(self.progress)) - 1.0, 0.0)

    @property
    def settling_time(self) -> float | None:
        """s after which the joint stays within :data:`SETTLE_BAND` of the step from
        the target; ``None`` when it is outside at the end."""
        outside = np.flatnonzero(np.abs(self.progress - 1.0) > SETTLE_BAND)
        if not len(outside):
            return 0.0
        if outside[-1] == len(self.times) - 1:
            return None
        return float(self.times[outside[-1] + 1])

    @property
    def final_error(self) -> float:
        """``target - position`` at the end (rad or m)."""
        return self.target - float(self.positions[-1])

    @property
    def peak_effort(self) -> float:
        """The largest drive force on the joint (N*m or N)."""
        return float(np.max(np.abs(self.efforts)))

    @property
    def saturated_share(self) -> float:
        """Share of the record with the drive at its effort limit (0 without one)."""
        if not math.isfinite(self.effort_limit):
            return 0.0
        return float(np.mean(np.abs(self.efforts) >= self.effort_limit * (1 - 1e-6)))

    @property
    def peak_speed(self) -> float:
        """The largest joint speed (rad/s or m/s)."""
        return float(np.max(np.abs(self.velocities)))

    def line(self) -> str:
        """One line for the command line's table."""

        def seconds(value: float | None) -> str:
            return f"{value * 1000:.0f} ms" if value is not None else "never"

        limit = f"/{self.effort_limit:.4g}" if math.isfinite(self.effort_limit) else ""
        speed = f"/{self.velocity_limit:.3g}" if math.isfinite(self.velocity_limit) else ""
        zeta = self.damping_ratio
        moving = f" (with {', '.join(j for j in self.coupled if j != self.joint)})" if self.coupled else ""
        return (
            f"{self.joint}{moving}: kp {self.stiffness:.4g} kv {self.damping:.4g} I {self.inertia:.3g} "
            f"(f {self.natural_frequency:.3g} Hz, zeta {zeta:.2f}, stability {self.stability_share:.2f}) | "
            f"step {self.step:+.3g}: rise {seconds(self.rise_time)}, overshoot {self.overshoot * 100:.1f}% "
            f"(model {self.predicted_overshoot * 100:.1f}%), settled {seconds(self.settling_time)}, "
            f"error {self.final_error:+.2e}, effort {self.peak_effort:.3g}{limit} "
            f"(saturated {self.saturated_share * 100:.0f}%), speed {self.peak_speed:.3g}{speed}"
            + (" | UNSTABLE: MuJoCo reset the state" if self.unstable else "")
        )


def write_csv(responses: Sequence[StepResponse], path: str | Path) -> Path:
    """Write ``responses`` as one CSV table for plotting: a row per joint and physics
    step with ``joint``, ``time_s`` (after the step), ``target``, ``position``,
    ``velocity``, ``effort`` (joint units). Returns the path.

    Raises:
        MediaError: the file cannot be written (the message names it and why).
    """
    target = Path(path)
    try:
        with target.open("w", newline="") as stream:
            writer = csv.writer(stream)
            writer.writerow(("joint", "time_s", "target", "position", "velocity", "effort"))
            for r in responses:
                for row in zip(r.times, r.positions, r.velocities, r.efforts, strict=True):
                    writer.writerow((r.joint, f"{row[0]:.6g}", repr(r.target), *(repr(float(v)) for v in row[1:])))
    except OSError as err:
        raise MediaError(f"write_csv: cannot write {str(target)!r}: {err.strerror or err}.") from None
    return target


def step_responses(
    robot: str | type[Agent],
    joints: Patterns | Sequence[str] | None = None,
    *,
    step: float | None = None,
    keyframe: str | None = None,
    seconds: float = 1.0,
    settle_seconds: float = 0.5,
    sim_freq: int | None = None,
    stiffness: float | None = None,
    damping: float | None = None,
    effort_limit: float | None = None,
) -> list[StepResponse]:
    """Step each of ``joints``' targets in turn and record the answer.

    Args:
        robot: a uid, a model file, ``module:Class`` or an Agent class.
        joints: name patterns of driven joints (default: every joint its
            ``pd_joint_pos`` mode commands); a mimic follower is stepped through its leader.
        step: the change of the target, rad for a hinge and m for a slide (default
            0.1 rad / 0.01 m); taken the other way where the joint's range or its action
            bounds leave no room.
        keyframe: the pose stepped from (default: the robot's first).
        seconds: how long the answer is recorded (s); settle_seconds: how long the pose
            is held before the step.
        sim_freq: physics rate (Hz; default: the robot's own).
        stiffness, damping, effort_limit: gains to try on the stepped joints instead of
            the declared ones (N*m/rad, N*m*s/rad, N*m; N/m, N*s/m, N for slides).

    Raises:
        ConfigError: bad arguments, a robot without a ``pd_joint_pos`` mode, a joint with
            no room for the step.
        UnknownNameError: a pattern or keyframe matching nothing (close names listed).
    """
    where = "step_responses"
    cls = agent_class(robot, where)
    if step is not None:
        check_real(step, "step", where, unit=" (rad or m)")
        if step == 0:
            raise ConfigError(f"{where}: expected a non-zero step, got {step!r}.")
    seconds = check_real(seconds, "seconds", where, minimum=MIN_SECONDS, maximum=MAX_SECONDS, unit=" (s)")
    settle_seconds = check_real(settle_seconds, "settle_seconds", where, minimum=0.0, maximum=MAX_SECONDS, unit=" (s)")
    modes = cls.modes()
    if STEP_MODE not in modes:
        raise ConfigError(
            f"{where}: {cls.__name__} has no {STEP_MODE!r} mode to step joint targets in; "
            f"its modes: {', '.join(modes)}."
        )
    checked = cls.check()
    if keyframe is not None and checked.keyframe_name(keyframe) is None:
        raise UnknownNameError(where, "keyframe", keyframe, checked.keyframes, checked.keyframe_aliases)
    rate = int(sim_freq) if sim_freq is not None else default_sim_freq([cls])
    # one physics step per control step: every step recorded
    scene = Scene(cls, sim_freq=rate, control_freq=rate, control_modes=STEP_MODE)
    try:
        agent = scene.agents[0]
        steppable = _steppable_joints(agent)
        names = list(steppable)
        chosen = (
            [names[i] for i in match(joints, names, f"{where} ({STEP_MODE}: its joints by absolute position)")]
            if joints is not None
            else names
        )
        columns = agent.drives.columns(chosen, where)
        # the gains are checked before anything runs: a bad one raises here
        agent.drives.retune(columns, stiffness, damping, effort_limit)
        return [
            _record(scene, agent, steppable[joint], joint, step, keyframe, seconds, settle_seconds, columns[k])
            for k, joint in enumerate(chosen)
        ]
    finally:
        scene.close()


def coupled_joints(index: RobotIndex, joint: str) -> dict[str, float]:
    """Joint name -> how far it moves per unit of ``joint``'s motion, for ``joint`` (1)
    and every joint tied to it through the robot's joint couplings (``index.couplings``,
    MuJoCo's joint equalities: their linear term; transitively, both ways)."""
    ratios = {joint: 1.0}
    grown = True
    while grown:
        grown = False
        for coupling in index.couplings:  # follower = c0 + c1 * leader + ...
            slope = coupling.coef[1]
            if coupling.leader in ratios and coupling.follower not in ratios:
                ratios[coupling.follower] = slope * ratios[coupling.leader]
                grown = True
            elif coupling.follower in ratios and coupling.leader not in ratios and slope != 0.0:
                ratios[coupling.leader] = ratios[coupling.follower] / slope
                grown = True
    return ratios


def _steppable_joints(agent: Agent) -> dict[str, tuple[str, Controller, int, str]]:
    """Joint -> (part, its controller, the action column commanding it, the joint that
    column sets) for every joint the step mode commands by absolute position (a mimic
    follower: its leader's column and the leader)."""
    found: dict[str, tuple[str, Controller, int, str]] = {}
    for part, controller in agent.controller.parts.items():
        config = controller.config
        if not isinstance(config, PDJointPosConfig) or config.use_delta:
            continue
        names = config.joint_names
        per_joint = not isinstance(config, PDJointPosMimicConfig)
        for k, joint in enumerate(names):
            found[joint] = (part, controller, k, joint) if per_joint else (part, controller, 0, names[0])
    return found


def _record(
    scene: Scene,
    agent: Agent,
    steppable: tuple[str, Controller, int, str],
    joint: str,
    step: float | None,
    keyframe: str | None,
    seconds: float,
    settle_seconds: float,
    column: int,
) -> StepResponse:
    part, controller, action_column, commanded = steppable
    drives, model = agent.drives, scene.world.model
    data = scene.world.datas[0]
    qadr, dadr = int(drives.qpos_adr[column]), int(drives.dof_adr[column])
    # the joint the action column sets: the stepped one, or its leader
    joint_id = int(drives.joint_ids[drives.columns([commanded], "step_responses")[0]])
    slide = int(model.jnt_type[joint_id]) == int(mujoco.mjtJoint.mjJNT_SLIDE)
    size = float(step) if step is not None else (SLIDE_STEP if slide else HINGE_STEP)
    scene.reset(keyframes=keyframe)
    settle = hold_action(agent)
    for _ in range(round(settle_seconds * scene.control_freq)):
        agent.set_action(settle)
        scene.step()
    start = float(data.qpos[qadr])
    raw = controller.hold_raw(agent.world)[0].copy()
    before = float(raw[action_column])
    low, high = float(controller.raw_low[action_column]), float(controller.raw_high[action_column])
    if model.jnt_limited[joint_id]:
        low, high = max(low, float(model.jnt_range[joint_id, 0])), min(high, float(model.jnt_range[joint_id, 1]))
    for signed in (size, -size):
        if low <= before + signed <= high:
            break
    else:
        raise ConfigError(
            f"step_responses: {commanded}'s target {before:.4g} has no room for a step of {abs(size):g} either way "
            f"within [{low:.4g}, {high:.4g}] (its range and its action bounds in {STEP_MODE}); pass a smaller step."
        )
    raw[action_column] = before + signed
    action = settle.copy()
    piece = agent.controller.slices[part]
    action[piece] = controller.from_raw(raw[None])[0] if controller.config.normalize_action else raw
    mass = inertia_matrix(model, data)
    count = round(seconds * scene.control_freq)
    positions, velocities, efforts = np.empty(count), np.empty(count), np.empty(count)
    unstable = False
    target = math.nan
    for i in range(count):
        agent.set_action(action)
        if i == 0:  # the joint's target as the mode writes it (a mimic follower's through its leader)
            target = float(drives.targets.position[0, column])
        scene.step()
        unstable |= bool(scene.world.last_step_unstable[0])
        positions[i], velocities[i], efforts[i] = data.qpos[qadr], data.qvel[dadr], data.qfrc_actuator[dadr]
    if not np.all(np.isfinite(positions)):
        raise PhysicsError(f"step_responses: {joint}'s record is not finite at {scene.sim_freq} Hz.")
    dt = float(model.opt.timestep)
    # the joints moving with this one through joint equalities (mimic fingers, a telescope)
    coupling = coupled_joints(agent.index, joint)
    ratios = np.zeros(model.nv)  # each dof's motion per unit of this joint's
    for name, ratio in coupling.items():
        ratios[agent.index.joint(name, "step_responses").dof_adr] = ratio
    coupled_drive = ratios[drives.dof_adr] ** 2  # (n,) weights of the robot's drives
    return StepResponse(
        joint=joint,
        start=start,
        target=target,
        stiffness=float(coupled_drive @ drives.stiffness),
        damping=float(coupled_drive @ drives.damping + ratios**2 @ model.dof_damping),
        effort_limit=float(drives.effort_limit[column]),
        velocity_limit=float(drives.velocity_limit[column]),
        inertia=float(ratios @ mass @ ratios),
        coupled=tuple(j for j in agent.index.joint_names if j in coupling) if len(coupling) > 1 else (),
        physics_step=dt,
        times=np.arange(1, count + 1, dtype=np.float64) * dt,
        positions=positions,
        velocities=velocities,
        efforts=efforts,
        unstable=unstable,
    )
