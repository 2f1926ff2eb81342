"""Per-step overhead of the env against a raw MuJoCo replay of identical physics, for
every registered robot in a joint mode and an end-effector mode, at its default step.

For each robot and mode (``num_envs=1``, ``Empty-v1``, ``obs_mode="state"``, the robot's
default ``sim_freq``, control 20 Hz):

1. **Record.** From a seeded reset, the env steps small actions of alternating sign
   (``step_throughput.small_actions``) while the script records, per control step,
   every MuJoCo call the world made on its behalf: each ``mj_step`` with the ``ctrl``
   it ran with and its number of substeps (one call of ``substeps`` steps, or one per
   substep in modes with substep hooks: interpolated targets, explicit PD drives), and
   each joint-state write after the physics (kinematic bases and wheels move by the
   commanded velocity; MuJoCo's ``mj_forward`` follows each write, or only
   ``mj_kinematics`` and ``mj_camlight`` for writes that only move bodies: wheels, held legs).
2. **Raw replay** (the denominator): from the same start state, a bare Python loop on a
   plain ``MjData`` of the same model redoes exactly those calls: ``data.ctrl[:] = u``,
   ``mj_step(model, data, n)``, the recorded joint-state writes with the same MuJoCo calls,
   then the minimum that reading the same observation needs: ``mj_kinematics`` (body
   poses at the stepped ``qpos``; ``mj_step`` leaves them one substep behind; not after a
   step that ends with a joint-state write, which recomputed them) and one
   ``np.concatenate`` of ``qpos``, ``qvel``, ``ctrl`` and the tool body's position and
   quaternion into a float32 vector. The script checks that the replay ends in the
   env's exact integration state (bit for bit), so both loops simulate the same thing.
3. **Env**: ``env.step(action)`` on the same action sequence from the same start
   (validation, clipping and scaling, controllers, drive stage, stepping, instability
   test, ``info``, observation).
4. **Python floor**: the raw replay plus the least Python any env step must add to it
   with the same action: convert it and test it finite, clip and scale it, add it to the
   measured joint positions and clip those to bounds (``numpy`` on the same small arrays,
   in its cheapest forms: in-place ``maximum`` / ``minimum`` into preallocated buffers;
   the targets go to a scratch buffer, the recorded ``ctrl`` drives the physics, so the
   physics stays identical). ``floor ratio`` = replay time / floor time is the most any
   Python env step could reach here; the gap between it and ``ratio`` is the part of
   the overhead this library's code adds (``python_floor.py`` writes such a loop out in
   full for the Panda).

The loops run in alternating blocks of ``--block`` control steps; per round the
ratio is replay time / env time over the same steps, and the table gives the median
over ``--rounds`` rounds (the machine is shared, so noise hits both loops of a round
alike). Times are this process's CPU time by default (``--clock cpu``): on a shared
machine, time spent waiting for a core is not the step's cost. ``overhead`` is env
minus replay per step in microseconds.

End-effector modes solve inverse kinematics every step. That is control (the work a
user asks for by choosing the mode, which a raw replay of the resulting ``ctrl`` does
not do), not per-step overhead: the script times each end-effector controller's
``apply`` (forward kinematics at the seed, target pose, IK solve, target write; in a
one-env step, the same work in the call its ``single_apply`` made) inside
the env loop and reports ``env/replay`` both with it (``ratio``) and without it
(``ratio excl. IK``: replay time / (env time - IK time)).

``--num-envs N`` (N > 1) measures the batched path instead (``measure_batched``): one
world of N envs stepped on one thread against N plain ``MjData`` replayed in a Python
loop, figures per env-step (the overhead a policy pays per sample when it steps many
envs at once); no Python floor there.

``--python-only`` reports instead the step's own cost with the physics calls replaced
by stand-ins that only advance simulated time (``python_cost``, ``no_physics``; the
time advance's own cost taken off, ``stand_in_surplus``), so the step takes a real
step's path: the part of the overhead this library's Python owns.

Usage: ``python benchmarks/overhead_ratio.py [--robots UID ...] [--modes joint ee] [--rounds 40]
[--block 10] [--clock cpu|wall] [--num-envs 1] [--python-only]``.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.controllers.ee import PDEEController
from robot_agents.kinematics.forward import FrameKind
from step_throughput import small_actions

STATE = mujoco.mjtState.mjSTATE_INTEGRATION
JOINT_MODE = "pd_joint_delta_pos"
EE_MODES = ("pd_ee_delta_pose", "pd_ee_delta_pos")


@dataclass
class Result:
    robot: str
    mode: str
    sim_freq: int
    substeps: int
    env_us: float
    replay_us: float
    ratio: float
    floor_us: float = float("nan")
    floor_ratio: float = float("nan")
    ik_us: float = 0.0
    ratio_excl_ik: float = float("nan")
    ratios: list[float] = field(default_factory=list)


def mode_of(uid: str, kind: str) -> str | None:
    modes = ra.get_agent(uid).modes()
    if kind == "joint":
        return JOINT_MODE if JOINT_MODE in modes else None
    return next((m for m in EE_MODES if m in modes), None)


def record(env: Any, actions: list[np.ndarray], steps: int) -> list[list[tuple[Any, ...]]]:
    """The MuJoCo calls of ``steps`` env steps: per step a list of ``("step", ctrl, n)``
    and ``("write", qpos_adr, qpos, dof_adr, qvel, forward)`` in order (one env: from
    ``write_joint_state`` and ``write_joint_row``)."""
    world = env.scene.world
    calls: list[tuple[Any, ...]] = []
    step_single = getattr(world, "_step_single", None)  # the one-env path, where the world has one
    step_all, write = world._step_all, world.write_joint_state

    def recording_step_single() -> None:
        calls.append(("step", world.ctrl[0].copy(), world.substeps))
        step_single()

    def recording_step_all(nstep: int) -> None:
        calls.append(("step", world.ctrl[0].copy(), nstep))
        step_all(nstep)

    def recording_write(env_ids: Any, qpos_adr: Any, qpos: Any, dof_adr: Any, qvel: Any, forward: bool = True) -> None:
        calls.append(
            ("write", np.asarray(qpos_adr), np.array(qpos)[0], np.asarray(dof_adr), np.array(qvel)[0], forward)
        )
        write(env_ids, qpos_adr, qpos, dof_adr, qvel, forward)

    patches: dict[str, Callable[..., None]] = {"_step_all": recording_step_all, "write_joint_state": recording_write}
    if step_single is not None:
        patches["_step_single"] = recording_step_single
    write_row = getattr(world, "write_joint_row", None)  # the one-env per-step writes, where the world has them
    if write_row is not None:

        def recording_write_row(qpos_adr: Any, qpos: Any, dof_adr: Any, qvel: Any, forward: bool = True) -> None:
            calls.append(("write", np.asarray(qpos_adr), np.array(qpos), np.asarray(dof_adr), np.array(qvel), forward))
            write_row(qpos_adr, qpos, dof_adr, qvel, forward)

        patches["write_joint_row"] = recording_write_row
    return recorded_steps(env, actions, steps, calls, patches)


def recorded_steps(
    env: Any,
    actions: list[np.ndarray],
    steps: int,
    calls: list[tuple[Any, ...]],
    patches: dict[str, Callable[..., None]],
) -> list[list[tuple[Any, ...]]]:
    """``steps`` env steps with the world's methods in ``patches`` replaced by recording
    ones (which append to ``calls``); the calls of each step, in order."""
    world = env.scene.world
    for name, method in patches.items():
        setattr(world, name, method)
    try:
        per_step = []
        for i in range(steps):
            calls.clear()
            env.step(actions[i % len(actions)])
            per_step.append(list(calls))
    finally:
        for name in patches:
            delattr(world, name)
    return per_step


def timed_single_apply(
    single_apply: Callable[..., Callable[[], None] | None], seconds: list[float], clock: Callable[[], float]
) -> Callable[..., Callable[[], None] | None]:
    """An end-effector controller's ``single_apply`` whose one-env call adds its time to
    ``seconds[0]`` (the one-env step's share of ``ratio excl. IK``, as ``apply``'s)."""

    def planned(raw: np.ndarray, qpos: np.ndarray) -> Callable[[], None] | None:
        call = single_apply(raw, qpos)
        if call is None:
            return None

        def timed() -> None:
            begin = clock()
            call()
            seconds[0] += clock() - begin

        return timed

    return planned


def measure(
    uid: str, mode: str, rounds: int, block: int, rng: np.random.Generator, clock: Callable[[], float]
) -> Result:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None).unwrapped
    env.reset(seed=0)
    model, agent = env.model, env.agent
    actions = small_actions(env, 64, rng)
    steps = (rounds + 1) * block
    start = env.get_state()
    per_step = record(env, actions, steps)
    final = env.get_state()["physics"][0]
    env.set_state(start)

    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, start["physics"][0], STATE)
    tool = agent.frames.end_effector(None, "overhead_ratio") if agent.has_end_effector else None
    body = tool.id if tool is not None and tool.kind is FrameKind.BODY else agent.root_body_id

    # End-effector controllers' apply, timed inside the env loop (see the docstring).
    ik_seconds = [0.0]
    combined = agent.controller
    wrapped = []
    for (apply, part_slice), controller in zip(combined._apply, combined.parts.values(), strict=True):
        if isinstance(controller, PDEEController):

            def timed(raw: np.ndarray, sim: Any, apply: Callable[..., None] = apply) -> None:
                begin = clock()
                apply(raw, sim)
                ik_seconds[0] += clock() - begin

            wrapped.append((timed, part_slice))
            setattr(controller, "single_apply", timed_single_apply(controller.single_apply, ik_seconds, clock))  # noqa: B010
        else:
            wrapped.append((apply, part_slice))
    combined._apply = wrapped
    combined._single_sim = None  # the one-env plan made again, with the timed calls

    cursor = {"env": 0, "replay": 0}

    def env_loop(count: int) -> None:
        for _ in range(count):
            env.step(actions[cursor["env"] % len(actions)])
            cursor["env"] += 1

    def replay_calls(data: mujoco.MjData, step: int) -> None:
        for call in per_step[step]:
            if call[0] == "step":
                data.ctrl[:] = call[1]
                mujoco.mj_step(model, data, call[2])
            else:
                data.qpos[call[1]] = call[2]
                data.qvel[call[3]] = call[4]
                data.qacc_warmstart[:] = 0.0
                if call[5]:
                    mujoco.mj_forward(model, data)
                else:
                    mujoco.mj_kinematics(model, data)
                    mujoco.mj_camlight(model, data)
        if per_step[step][-1][0] == "step":  # (a write last recomputed the poses)
            mujoco.mj_kinematics(model, data)
        np.concatenate((data.qpos, data.qvel, data.ctrl, data.xpos[body], data.xquat[body]), dtype=np.float32)

    def replay_loop(count: int) -> None:
        for _ in range(count):
            replay_calls(data, cursor["replay"])
            cursor["replay"] += 1

    # The Python floor's action arithmetic (module doc, item 4): the action's bounds and
    # scale, and the first joints the robot drives (as many as the action has numbers).
    floor_data = mujoco.MjData(model)
    mujoco.mj_setState(model, floor_data, start["physics"][0], STATE)
    # The cheapest NumPy forms: in-place maximum / minimum (np.clip costs ~2 µs a call
    # on arrays this small, three times the pair), preallocated buffers.
    low, high = combined.action_low.reshape(-1), combined.action_high.reshape(-1)
    scale = np.ones_like(low)
    joints = agent.drives.qpos_adr[: len(low)]
    joint_low, joint_high = np.full(len(joints), -10.0), np.full(len(joints), 10.0)
    raw, scratch = np.empty(len(low)), np.empty(len(joints))
    cursor["floor"] = 0

    def floor_loop(count: int) -> None:
        for _ in range(count):
            step = cursor["floor"]
            action = np.asarray(actions[step % len(actions)], dtype=np.float64).reshape(-1)
            if not math.isfinite(action.sum()):
                raise ValueError("non-finite action")
            np.maximum(action, low, out=raw)
            np.minimum(raw, high, out=raw)
            np.multiply(raw, scale, out=raw)
            np.add(floor_data.qpos[joints], raw[: len(joints)], out=scratch)
            np.maximum(scratch, joint_low, out=scratch)
            np.minimum(scratch, joint_high, out=scratch)
            replay_calls(floor_data, step)
            cursor["floor"] += 1

    env_loop(block)  # warm-up, every loop
    replay_loop(block)
    floor_loop(block)
    ik_seconds[0] = 0.0
    env_times, replay_times, floor_times, ik_times = [], [], [], []
    for _ in range(rounds):
        ik_before = ik_seconds[0]
        begin = clock()
        env_loop(block)
        env_times.append(clock() - begin)
        ik_times.append(ik_seconds[0] - ik_before)
        begin = clock()
        replay_loop(block)
        replay_times.append(clock() - begin)
        begin = clock()
        floor_loop(block)
        floor_times.append(clock() - begin)
    for name, replayed in (("replay", data), ("Python floor", floor_data)):
        replay_state = np.empty(mujoco.mj_stateSize(model, STATE))
        mujoco.mj_getState(model, replayed, replay_state, STATE)
        if not np.array_equal(replay_state, final):
            raise RuntimeError(f"{uid} {mode}: the {name} did not reproduce the env's trajectory")
    if not np.array_equal(env.get_state()["physics"][0], final):
        raise RuntimeError(f"{uid} {mode}: the env did not repeat its recorded trajectory")
    substeps, sim_freq = env.scene.substeps, env.sim_freq
    env.close()
    ratios = [r / e for r, e in zip(replay_times, env_times, strict=True)]
    result = Result(
        uid,
        mode,
        sim_freq,
        substeps,
        env_us=1e6 * statistics.median(env_times) / block,
        replay_us=1e6 * statistics.median(replay_times) / block,
        ratio=statistics.median(ratios),
        floor_us=1e6 * statistics.median(floor_times) / block,
        floor_ratio=statistics.median([r / f for r, f in zip(replay_times, floor_times, strict=True)]),
        ratios=ratios,
    )
    if any(ik_times):
        result.ik_us = 1e6 * statistics.median(ik_times) / block
        result.ratio_excl_ik = statistics.median(
            [r / (e - k) for r, e, k in zip(replay_times, env_times, ik_times, strict=True)]
        )
    return result


def record_batched(env: Any, actions: list[np.ndarray], steps: int) -> list[list[tuple[Any, ...]]]:
    """:func:`record` for ``num_envs > 1``: per step ``("step", ctrl (N, nu), n, sync)``
    (``sync``: poses updated after it) and ``("write", env_ids, qpos_adr, qpos, dof_adr,
    qvel, forward)`` with a row per env id."""
    world = env.scene.world
    calls: list[tuple[Any, ...]] = []
    step_all, write = world._step_all, world.write_joint_state

    def recording_step_all(nstep: int) -> None:
        calls.append(("step", world.ctrl.copy(), nstep, world._sync_after_step))
        step_all(nstep)

    def recording_write(env_ids: Any, qpos_adr: Any, qpos: Any, dof_adr: Any, qvel: Any, forward: bool = True) -> None:
        ids = np.asarray(env_ids, dtype=np.int64).reshape(-1).copy()
        calls.append(("write", ids, np.asarray(qpos_adr), np.array(qpos), np.asarray(dof_adr), np.array(qvel), forward))
        write(env_ids, qpos_adr, qpos, dof_adr, qvel, forward)

    return recorded_steps(
        env, actions, steps, calls, {"_step_all": recording_step_all, "write_joint_state": recording_write}
    )


def measure_batched(
    uid: str,
    mode: str,
    num_envs: int,
    rounds: int,
    block: int,
    rng: np.random.Generator,
    clock: Callable[[], float],
) -> Result:
    """``env / raw replay`` for ``num_envs`` envs in one batched world stepped on one
    thread (``num_threads=1``), against a raw replay of the same calls on ``num_envs``
    plain ``MjData`` in a Python loop (each: ``ctrl``, ``mj_step``, the recorded joint
    writes, ``mj_kinematics`` and ``mj_camlight`` after the control step's physics, as
    the world does), then one ``np.concatenate`` per env of ``qpos``, ``qvel``,
    ``ctrl`` and the tool body's pose stacked into the ``(N, D)`` float32 observation.
    Checked bit for bit: every replayed env ends in its env's integration state. No
    Python floor is measured here."""
    env = ra.make_env(
        "Empty-v1", robot_uids=uid, control_mode=mode, num_envs=num_envs, num_threads=1, max_episode_steps=None
    ).unwrapped
    env.reset(seed=0)
    model, agent = env.model, env.agent
    actions = small_actions(env, 64, rng)
    steps = (rounds + 1) * block
    start = env.get_state()
    per_step = record_batched(env, actions, steps)
    final = [np.array(row) for row in env.get_state()["physics"]]
    env.set_state(start)
    datas = []
    for row in start["physics"]:
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, row, STATE)
        datas.append(data)
    tool = agent.frames.end_effector(None, "overhead_ratio") if agent.has_end_effector else None
    body = tool.id if tool is not None and tool.kind is FrameKind.BODY else agent.root_body_id
    cursor = {"env": 0, "replay": 0}

    def env_loop(count: int) -> None:
        for _ in range(count):
            env.step(actions[cursor["env"] % len(actions)])
            cursor["env"] += 1

    def replay_loop(count: int) -> None:
        for _ in range(count):
            for call in per_step[cursor["replay"]]:
                if call[0] == "step":
                    ctrl, nstep, sync = call[1], call[2], call[3]
                    for i, data in enumerate(datas):
                        data.ctrl[:] = ctrl[i]
                        mujoco.mj_step(model, data, nstep)
                        if sync:
                            mujoco.mj_kinematics(model, data)
                            mujoco.mj_camlight(model, data)
                else:
                    _, ids, qa, qpos, da, qvel, forward = call
                    for row, i in enumerate(ids):
                        data = datas[i]
                        data.qpos[qa] = qpos[row]
                        data.qvel[da] = qvel[row]
                        data.qacc_warmstart[:] = 0.0
                        if forward:
                            mujoco.mj_forward(model, data)
                        else:
                            mujoco.mj_kinematics(model, data)
                            mujoco.mj_camlight(model, data)
            np.stack(
                [np.concatenate((d.qpos, d.qvel, d.ctrl, d.xpos[body], d.xquat[body]), dtype=np.float32) for d in datas]
            )
            cursor["replay"] += 1

    env_loop(block)  # warm-up
    replay_loop(block)
    env_times, replay_times = [], []
    for _ in range(rounds):
        begin = clock()
        env_loop(block)
        env_times.append(clock() - begin)
        begin = clock()
        replay_loop(block)
        replay_times.append(clock() - begin)
    state = np.empty(mujoco.mj_stateSize(model, STATE))
    for i, data in enumerate(datas):
        mujoco.mj_getState(model, data, state, STATE)
        if not np.array_equal(state, final[i]):
            raise RuntimeError(f"{uid} {mode}: the replay of env {i} did not reproduce the env's trajectory")
    substeps, sim_freq = env.scene.substeps, env.sim_freq
    env.close()
    ratios = [r / e for r, e in zip(replay_times, env_times, strict=True)]
    per_env = block * num_envs
    return Result(
        uid,
        mode,
        sim_freq,
        substeps,
        env_us=1e6 * statistics.median(env_times) / per_env,
        replay_us=1e6 * statistics.median(replay_times) / per_env,
        ratio=statistics.median(ratios),
        ratios=ratios,
    )


def stand_in_step(model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
    """:func:`python_cost`'s ``mj_step``: no physics, but simulated time advances by
    ``nstep`` time steps (s) as a real step's does; ``qpos``, ``qvel`` and everything
    else stay as they are. The world's instability test reads the time (a step that did
    not advance it counts as MuJoCo's reset of a blown-up env): with time standing still
    every step was flagged unstable, which skipped the one-env step's speed test
    (``or`` short-circuits) and added the flag's bookkeeping (``unstable_steps``) to
    both paths, so the no-physics step took another path than a real one."""
    data.time += nstep * model.opt.timestep


def stand_in_forward(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """:func:`python_cost`'s ``mj_forward``: nothing (a forward pass moves no time)."""


@contextmanager
def no_physics() -> Iterator[None]:
    """``mujoco.mj_step`` and ``mujoco.mj_forward`` replaced by :func:`stand_in_step` and
    :func:`stand_in_forward` inside the block (the library looks them up at each call)."""
    step, forward = mujoco.mj_step, mujoco.mj_forward
    mujoco.mj_step, mujoco.mj_forward = stand_in_step, stand_in_forward
    try:
        yield
    finally:
        mujoco.mj_step, mujoco.mj_forward = step, forward


def _nothing(model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
    """The stand-in ``mj_step`` before 2026-11-29 (a call that does nothing)."""


def stand_in_surplus(model: mujoco.MjModel, calls: int, clock: Callable[[], float], repeats: int = 7) -> float:
    """Seconds ``calls`` calls of :func:`stand_in_step` take beyond as many calls of a
    function that does nothing (best of ``repeats`` loops of at least 20,000 calls each,
    scaled): the time advance's own cost (a few hundred ns a call: ``model.opt`` and
    ``data.time`` through the bindings), which is not the library's, so
    :func:`python_cost` takes it off; the call itself stays counted, as before."""
    data = mujoco.MjData(model)
    count = max(calls, 20_000)
    best = {}
    for function in (stand_in_step, _nothing):
        best[function] = math.inf
        for _ in range(repeats):
            begin = clock()
            for _ in range(count):
                function(model, data, 1)
            best[function] = min(best[function], clock() - begin)
    return max(0.0, best[stand_in_step] - best[_nothing]) * calls / count


def python_cost(
    uid: str,
    mode: str,
    rng: np.random.Generator,
    steps: int = 300,
    repeats: int = 7,
    clock: Callable[[], float] = time.perf_counter,
    num_envs: int = 1,
) -> float:
    """Microseconds of one ``env.step`` with MuJoCo's ``mj_step`` and ``mj_forward``
    replaced by :func:`no_physics`'s stand-ins (the physics does not move, simulated time
    advances as in a real step, so the step takes a real step's path): what the step
    costs in Python and in the small MuJoCo calls around it (pose sync), best of
    ``repeats`` loops of ``steps`` steps (the minimum is the least disturbed by other
    jobs on the machine), less the time advance's own cost (:func:`stand_in_surplus`);
    with ``num_envs > 1``, per env-step of one batched world on one thread. Raises
    ``RuntimeError`` if the env flagged a step unstable or its time did not advance by
    the control steps' (then the figure would not be a real step's). End-effector modes:
    the arm does not move, so the IK may take another number of iterations than in a real
    step (6 of the 22 built-in robots with such a mode at one env, docs/notes/speed-log.md)."""
    env = ra.make_env(
        "Empty-v1", robot_uids=uid, control_mode=mode, num_envs=num_envs, num_threads=1, max_episode_steps=None
    ).unwrapped
    env.reset(seed=0)
    actions = small_actions(env, 64, rng)
    world = env.scene.world
    started, flagged = world.time, world.unstable_steps.copy()
    calls = [0]

    def counted(model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
        calls[0] += 1
        stand_in_step(model, data, nstep)

    with no_physics():
        best = math.inf
        for _ in range(repeats):
            begin = clock()
            for i in range(steps):
                env.step(actions[i % len(actions)])
            best = min(best, clock() - begin)
        mujoco.mj_step = counted  # one loop more, untimed: how many mj_step calls a loop makes
        for i in range(steps):
            env.step(actions[i % len(actions)])
    advanced = world.time - started
    expected = (repeats + 1) * steps * env.scene.substeps * float(env.model.opt.timestep)
    unstable = world.unstable_steps - flagged
    model = env.model
    env.close()
    if unstable.any() or not np.allclose(advanced, expected, rtol=1e-9, atol=0.0):
        raise RuntimeError(
            f"python_cost({uid!r}, {mode!r}): the no-physics step is not a real step's path: "
            f"{unstable.tolist()} steps flagged unstable per env, time advanced {advanced.tolist()} s "
            f"(expected {expected} s)"
        )
    best -= stand_in_surplus(model, calls[0], clock)
    return 1e6 * best / (steps * num_envs)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--robots", nargs="*", default=None, help="robot uids (default: every registered robot)")
    parser.add_argument("--modes", nargs="*", default=["joint", "ee"], choices=["joint", "ee"])
    parser.add_argument("--rounds", type=int, default=40)
    parser.add_argument("--block", type=int, default=10)
    parser.add_argument(
        "--num-envs",
        type=int,
        default=1,
        help="N > 1: one batched world of N envs on one thread against N plain MjData in a loop "
        "(measure_batched, or with --python-only the step's Python per env-step; no Python floor, end-effector modes without the IK split)",
    )
    parser.add_argument(
        "--python-only",
        action="store_true",
        help="instead of the ratio: the step's own cost with mj_step and mj_forward replaced by stand-ins that only "
        "advance simulated time (python_cost)",
    )
    parser.add_argument(
        "--clock",
        default="cpu",
        choices=["cpu", "wall"],
        help="cpu: this process's CPU time (time.process_time; time spent waiting for a core on a shared "
        "machine is not counted); wall: time.perf_counter",
    )
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    robots = args.robots or ra.list_agents()
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    if args.python_only:
        print(
            f"| robot | mode | env step without physics, µs{' per env-step' if args.num_envs > 1 else ''} "
            f"(best of 7 x 300 steps, {args.clock} clock, num_envs {args.num_envs}) |\n|---|---|---|"
        )
        for uid in robots:
            for kind in args.modes:
                mode = mode_of(uid, kind)
                if mode is not None:
                    print(
                        f"| `{uid}` | `{mode}` | {python_cost(uid, mode, rng, clock=clock, num_envs=args.num_envs):.1f} |",
                        flush=True,
                    )
        return
    print(
        f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.processor() or platform.machine()}, "
        f"Python {platform.python_version()}, MuJoCo {mujoco.__version__}, {args.rounds} rounds of {args.block} steps, "
        f"num_envs {args.num_envs}{' (one thread; µs per env-step)' if args.num_envs > 1 else ''}, "
        f"{args.clock} clock, load average {os.getloadavg()[0]:.1f}"
    )
    print(
        "| robot | mode | sim_freq (substeps) | env µs/step | raw replay µs/step | overhead µs | IK µs | ratio | "
        "ratio excl. IK | Python floor µs/step | floor ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for uid in robots:
        for kind in args.modes:
            mode = mode_of(uid, kind)
            if mode is None:
                continue
            if args.num_envs > 1:
                r = measure_batched(uid, mode, args.num_envs, args.rounds, args.block, rng, clock)
            else:
                r = measure(uid, mode, args.rounds, args.block, rng, clock)
            excl = "-" if np.isnan(r.ratio_excl_ik) else f"{r.ratio_excl_ik:.2f}"
            ik = "-" if not r.ik_us else f"{r.ik_us:.0f}"
            floor = "- | -" if np.isnan(r.floor_us) else f"{r.floor_us:.0f} | {r.floor_ratio:.2f}"
            print(
                f"| `{uid}` | `{mode}` | {r.sim_freq} ({r.substeps}) | {r.env_us:.0f} | {r.replay_us:.0f} | "
                f"{r.env_us - r.replay_us:.0f} | {ik} | {r.ratio:.2f} | {excl} | {floor} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
