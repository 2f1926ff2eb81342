"""Drive a real robot with its simulation definition: the same control modes, the same
controllers, joint targets sent to the hardware.

:class:`RealRobot` keeps a one-env scene of the robot that is never stepped. Each
control step it reads the robot's measured joint positions and velocities from a
:class:`JointBus` (the hardware's interface: motors, a vendor SDK, a ROS topic), writes
them into that scene, lets the mode's controllers turn the action into joint targets
exactly as in simulation (end-effector modes solve their IK on the model at the
measured pose), and sends the targets to the bus. The drives themselves (the PD loops)
run on the hardware.

Scope: robots whose root is fixed and which have no ``Base`` part (arms, grippers,
hands, arm + gripper); a mobile base has no joints to command. The bus carries the
robot's driven joints (``Agent.drives.joint_names``); joints that follow one of them
through a linear joint equality (a mimic finger) are set with it; passive joints (a
linkage) keep their keyframe values in the controllers' model. Substep interpolation
of targets is a simulation feature: the bus receives each step's final targets.

:class:`~robot_agents.real.simulated_bus.SimulatedBus` stands in for hardware.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.envs.state_obs import StateObservation
from robot_agents.errors import ConfigError, StateError, close_names
from robot_agents.kinematics import LinearFollowers
from robot_agents.real.bus import JointBus
from robot_agents.registry import agent_class
from robot_agents.sim.scene import Scene
from robot_agents.validation import check_open, check_whole

FloatArray = npt.NDArray[np.float64]

#: How close (rad or m, every driven joint) :meth:`RealRobot.move_to` brings the robot to
#: a keyframe before holding it: the keyframe hold tolerance of the robot checks.
MOVE_TOLERANCE = 0.01


def bus_columns(driven: list[str], names: list[str], robot: str) -> npt.NDArray[np.int64]:
    """The drive column of each of a bus's joints ``names``; :class:`ConfigError` unless
    they are the ``driven`` joints (any order, each once), with close-name hints."""
    if sorted(names) == sorted(driven) and len(set(names)) == len(names):
        return np.array([driven.index(n) for n in names], dtype=np.int64)
    missing = sorted(set(driven) - set(names))
    extra = sorted(set(names) - set(driven))
    hints = [f"{n!r} (did you mean {close_names(n, missing)[0]!r}?)" for n in extra if close_names(n, missing)]
    raise ConfigError(
        f"RealRobot: the bus must carry {robot}'s driven joints {driven}, got {names}"
        + (f"; missing {missing}" if missing else "")
        + (f"; not driven {extra}" if extra else "")
        + (f"; {', '.join(hints)}" if hints else "")
        + ("; repeated names" if len(set(names)) != len(names) else "")
        + "."
    )


class RealRobot:
    """A real robot driven through ``bus`` with the control modes of its definition.

    Args:
        robot: registered uid or Agent subclass (fixed root, no ``Base`` part).
        bus: the hardware's :class:`JointBus`; its ``joint_names`` must be the robot's
            driven joints (any order).
        control_mode: the mode to start in (default: the robot's default mode).
        max_target_step: the farthest (rad or m, one number or one per bus joint) a
            position target may lie from the measured position; targets beyond are
            clipped towards it (a safety limit for hardware; ``None``: no limit; ``inf``
            for a joint: none on it). Rated speed times the control period keeps the
            joints under their rated speeds, which position modes do not respect. The
            velocity and effort targets sent with a clipped position target (the
            feed-forward of end-effector modes, ``pd_joint_pos_vel``'s velocities, an
            effort mode's efforts on drives that keep their stiffness) are scaled by the
            same fraction, ``(clipped - measured) / (target - measured)``, on joints
            whose drive has position stiffness in the mode (see :meth:`step`).

    Raises:
        ConfigError: the robot has a free root or a mobile base, the bus's joints are
            not the robot's driven joints, or ``max_target_step`` is not positive (or
            ``inf`` for every joint).
    """

    def __init__(
        self,
        robot: str | type[Agent],
        bus: JointBus,
        control_mode: str | None = None,
        max_target_step: float | Sequence[float] | None = None,
    ) -> None:
        where = "RealRobot"
        cls = agent_class(robot, where)
        if not cls.fix_root_link:
            raise ConfigError(f"{where}: {cls.__name__} has a free root; the bridge drives fixed-root robots only.")
        if not isinstance(bus, JointBus):
            raise ConfigError(
                f"{where}: expected a JointBus (joint_names, read, write, set_gains, close), got {bus!r}."
            )
        self.scene = Scene(cls, control_modes=control_mode, floor=False, render_only_visuals=False)
        self.agent = self.scene.agents[0]
        self.bus = bus
        self._closed = False
        try:  # on any failure the scene is closed (the bus stays the caller's)
            if self.agent.mobile.planar is not None:
                raise ConfigError(
                    f"{where}: {cls.__name__} has a mobile base; the bridge drives fixed-root robots only."
                )
            drives = self.agent.drives
            #: the drive column of each bus joint
            self._columns = bus_columns(list(drives.joint_names), [str(n) for n in bus.joint_names], cls.__name__)
            self._qpos_adr = drives.qpos_adr[self._columns]  # scene addresses, bus order
            # joints that follow a bus joint through a linear equality (a mimic finger):
            # written with it, as the equality holds them on the real robot
            dof_adr = drives.dof_adr[self._columns]
            self._followers = LinearFollowers.of(self.scene.model, dof_adr)
            #: where :meth:`sync` writes: the bus joints, then their followers
            self._write_qpos_adr = np.concatenate([self._qpos_adr, self._followers.qpos_adr])
            self._write_dof_adr = np.concatenate([dof_adr, self._followers.dof_adr])
            self._observation = StateObservation(self.scene, True, None, None, where)
            self._max_step = self._checked_step(max_target_step, len(self._columns), where)
            self._measured = np.zeros(len(self._columns))
            if cls.keyframe_names():  # joints the bus does not carry start at the default keyframe
                self.scene.reset()
            self.set_control_mode(self.agent.control_mode)  # holding the measured pose
        except Exception:
            self.scene.close()
            raise

    @staticmethod
    def _checked_step(value: float | Sequence[float] | None, n: int, where: str) -> FloatArray | None:
        if value is None:
            return None
        step: FloatArray
        try:
            raw = np.asarray(value)
            if raw.dtype.kind not in "fiu":  # bools, strings, objects: not distances
                raise TypeError
            step = np.broadcast_to(raw.astype(np.float64), (n,)).copy()
        except Exception:  # also whatever the input's own __array__ raises
            step = np.full(n, np.nan)
        if np.any(np.isnan(step)) or np.any(step <= 0) or np.all(np.isinf(step)):
            raise ConfigError(
                f"{where}: expected max_target_step > 0 (one number or {n}; inf for a joint without a bound, "
                f"not for all), got {value!r}."
            )
        return step

    # -- state -----------------------------------------------------------------------------
    def sync(self) -> None:
        """Read the measured state from the bus into the controllers' model."""
        self._check_open("RealRobot.sync")
        reading = self.bus.read()
        n = len(self._columns)
        try:
            qpos, qvel = (np.asarray(a, dtype=np.float64) for a in reading)
        except (TypeError, ValueError):  # not a pair, or not numbers
            raise StateError(
                f"RealRobot.sync: expected the bus to read (positions, velocities), finite ({n},) each; "
                f"got {reading!r}."
            ) from None
        if qpos.shape != (n,) or qvel.shape != (n,) or not (np.all(np.isfinite(qpos)) and np.all(np.isfinite(qvel))):
            raise StateError(
                f"RealRobot.sync: the bus read positions {qpos.shape} and velocities {qvel.shape}; "
                f"expected finite ({n},) each."
            )
        self._measured = qpos.copy()
        qpos = np.concatenate([qpos, self._followers.positions(qpos)])
        qvel = np.concatenate([qvel, self._followers.velocities(qvel)])
        self.scene.world.write_joint_state(
            np.array([0]), self._write_qpos_adr, qpos[None], self._write_dof_adr, qvel[None]
        )

    @property
    def control_mode(self) -> str:
        return self.agent.control_mode

    def set_control_mode(self, mode: str) -> None:
        """Switch modes: the new mode holds the measured pose (read from the bus) and
        its drive settings go to the bus (:meth:`JointBus.set_gains`). An unknown mode
        raises :class:`UnknownNameError` before the bus is read (nothing changes)."""
        where = "RealRobot.set_control_mode"
        self._check_open(where)
        self.agent.controller_for(mode, where)  # the name checked (and the mode built) first
        self.sync()
        self.agent.set_control_mode(mode)
        drives, columns = self.agent.drives, self._columns
        self.bus.set_gains(drives.stiffness[columns], drives.damping[columns], drives.effort_limit[columns])

    @property
    def action_space(self) -> Any:
        """The mode's action space of one robot, ``(action_dim,)``."""
        return self.agent.single_action_space

    def get_proprioception(self) -> dict[str, Any]:
        """As in simulation (:meth:`Agent.get_proprioception`), from the last read."""
        self._check_open("RealRobot.get_proprioception")
        return self.agent.get_proprioception()

    def get_obs(self) -> npt.NDArray[np.float32]:
        """The robot's part of a simulated env's ``obs_mode="state"`` observation,
        ``(1, D)`` float32, from the last read (:meth:`sync`): the same entries in the
        same order (``Empty-v1``'s whole observation; a task appends its own), so a
        policy trained on it reads the real robot unchanged. Joints the bus does not
        carry and no linear equality ties to one (a passive linkage) read their keyframe
        values and zero speed."""
        self._check_open("RealRobot.get_obs")
        obs: npt.NDArray[np.float32] = self._observation.observe()
        return obs

    def camera_params(self) -> dict[str, dict[str, FloatArray]]:
        """The robot's own cameras (its definition's mounts) at the last read, as a
        simulated env's ``obs["sensor_param"]``: per camera ``intrinsic_cv`` ``(1, 3, 3)``,
        ``extrinsic_cv`` ``(1, 3, 4)`` and ``cam2world_gl`` ``(1, 4, 4)``, float64
        (:mod:`robot_agents.sensors.camera_params`): where the real camera on that mount
        looks from, to project its images."""
        self._check_open("RealRobot.camera_params")
        return self.scene.cameras.params(self.scene.world)

    # -- control ---------------------------------------------------------------------------
    def step(self, action: npt.ArrayLike) -> FloatArray:
        """Read the state, turn ``action`` into joint targets with the mode's controllers
        and send them; returns the position targets sent ``(n,)``, bus order. A rejected
        action (:class:`ActionError`) sends nothing and changes no controller state; a
        ``bus.write`` that raises leaves the controllers and targets as they were before
        the call (the exception propagates; the bus's reading stays in the model), so a
        retry sends the same command: a target-delta mode does not add its step twice.

        With ``max_target_step``, a position target ``p`` farther than the bound from the
        measured position ``q`` is sent as ``p'`` on the bound, and the velocity target
        ``v`` and effort ``tau`` sent with it as ``f v`` and ``f tau``, ``f = (p' - q) /
        (p - q)``: the command shrunk as a whole, on joints whose drive has position
        stiffness in the mode. (The bridge sends efforts only from a mode's effort
        targets, ``JointEffortConfig``; no gravity compensation: simulation cancels
        gravity on a fixed-root robot's bodies, the hardware does its own.) An effort
        sent in full against a spring cut to the bound ran a joint away where the
        simulation's rests at ``p + tau / kp``; shrunk, ``f (kp (p - q) + tau)`` is
        zero where it rests. End-effector modes send the
        midpoint of the step's joint path with the speed that covers it, ``(q + s) / 2``
        and ``(s - q) / dt``; the scaled pair is the same path cut to the bound, and the
        unscaled speed (up to 13 rad/s on the Panda with a bound of 0.01 rad) drove a
        joint 0.5 rad in one step. Zero would cut the feed-forward off wherever the bound
        is reached, a jump in the command each time a steady motion crosses it; scaling
        is continuous there (the fraction is 1 at the bound). A velocity mode's position
        targets (stiffness 0) pull on nothing: its velocities go as they are."""
        self._check_open("RealRobot.step")
        agent = self.agent
        checked = agent.validate_action(action)  # before anything moves (raises ActionError)
        self.sync()
        targets, ctrl = agent.drives.targets, self.scene.world.ctrl
        before = (
            agent.controller.get_state(),
            [a.copy() for a in (targets.position, targets.velocity, targets.effort)],
        )
        before_ctrl = np.array(ctrl)
        agent.set_action(checked)
        wanted = targets.position[0, self._columns].copy()
        position = self._limited(wanted.copy())
        velocity = targets.velocity[0, self._columns].copy()
        effort = targets.effort[0, self._columns].copy()
        if self._max_step is not None:
            self._scale_held_back((velocity, effort), wanted, position)
        try:
            self.bus.write(position, velocity, effort)
        except BaseException:  # the command did not go (or not for sure): as before the call
            agent.controller.set_state(before[0])
            for target, saved in zip((targets.position, targets.velocity, targets.effort), before[1], strict=True):
                target[...] = saved
            ctrl[...] = before_ctrl
            raise
        return position

    def _scale_held_back(self, feed_forward: tuple[FloatArray, ...], wanted: FloatArray, sent: FloatArray) -> None:
        """Scale in place the feed-forward targets (velocity and effort, ``(n,)`` each,
        bus order) of the joints whose position target ``wanted`` was held back to
        ``sent`` by ``max_target_step``, by the fraction of the step that is sent,
        ``(sent - measured) / (wanted - measured)`` (in ``(0, 1)``), where the mode's
        drive has position stiffness; other entries keep their bits."""
        held = (sent != wanted) & (self.agent.drives.stiffness[self._columns] > 0.0)
        if np.any(held):
            measured = self._measured[held]
            fraction = (sent[held] - measured) / (wanted[held] - measured)
            for target in feed_forward:
                target[held] *= fraction

    def move_to(self, keyframe: str, steps: int = 40) -> float:
        """Bring the robot to ``keyframe`` (its driven joints) along a smooth ramp of
        position commands from the measured pose (one per control step of the caller's
        timing: the bus decides how long each takes), then command the keyframe itself
        until every joint is within :data:`MOVE_TOLERANCE` of it (at most as many
        commands again), and hold the measured pose in the active mode.

        The ramp runs under the declared drives' position gains (a velocity mode's
        stiffness is 0, which would not follow it) and the active mode's are sent again
        after it. It takes ``steps`` commands, or more where ``max_target_step`` needs
        them (the smoothstep ramp's largest step is 1.5 times the mean); each command
        is within ``max_target_step`` of the measured pose. Returns the largest distance
        (rad or m) left between the measured joints and the keyframe at the end (a
        robot that lags or is blocked stops short: check it against your tolerance)."""
        where = "RealRobot.move_to"
        self._check_open(where)
        agent = self.agent
        robot_qpos = agent.keyframe_qpos(keyframe)  # raises UnknownNameError
        steps = check_whole(steps, "steps", where, minimum=1)
        drives, columns = agent.drives, self._columns
        stiffness = drives.declared_stiffness[columns]
        if np.any(stiffness <= 0.0):
            limp = [str(self.bus.joint_names[int(i)]) for i in np.flatnonzero(stiffness <= 0.0)]
            raise ConfigError(
                f"{where}: joints {limp} have no position stiffness in their declared drives, so a ramp of "
                "position commands would not move them; move them in a velocity mode instead."
            )
        local = {int(adr): i for i, adr in enumerate(agent.index.qpos_adr)}
        target = robot_qpos[[local[int(adr)] for adr in self._qpos_adr]]
        self.sync()
        start = self._measured.copy()
        if self._max_step is not None:
            # (max_target_step: a bound per joint, or one for all)
            share = float(np.max(np.abs(target - start) / self._max_step, initial=0.0))
            steps = max(steps, math.ceil(1.5 * share))
        self.bus.set_gains(stiffness, drives.declared_damping[columns], drives.declared_effort_limit[columns])
        zeros = np.zeros_like(start)
        for step in range(1, steps + 1):
            s = step / steps
            position = start + (target - start) * (s * s * (3.0 - 2.0 * s))  # smoothstep: no jump in speed
            if self._max_step is not None:
                self.sync()
            self.bus.write(self._limited(position), zeros, zeros)
        # then the keyframe itself, until the joints are there (a lagging drive, commands
        # held back by max_target_step), for as many commands again at most
        for _ in range(steps):
            self.sync()
            if np.max(np.abs(self._measured - target), initial=0.0) <= MOVE_TOLERANCE:
                break
            self.bus.write(self._limited(target.copy()), zeros, zeros)
        self.set_control_mode(agent.control_mode)  # reads the bus: the measured end pose
        return float(np.max(np.abs(self._measured - target), initial=0.0))

    def _limited(self, position: FloatArray) -> FloatArray:
        """``position`` (bus order) clipped in place to ``max_target_step`` from the
        last measured position (unchanged without a limit)."""
        if self._max_step is not None:
            np.clip(position, self._measured - self._max_step, self._measured + self._max_step, out=position)
        return position

    def _check_open(self, where: str) -> None:
        check_open(self._closed, "this RealRobot", where)

    def close(self) -> None:
        """Close the bus and the controllers' scene (the scene also when the bus's
        ``close`` raises, which then propagates)."""
        if not self._closed:
            self._closed = True
            try:
                self.bus.close()
            finally:
                self.scene.close()
