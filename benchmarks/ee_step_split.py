"""Where a one-env end-effector step's time goes, and what a change to the end-effector
code saves, measured in one process.

**Split** (the default). For each robot and mode (``num_envs=1``, ``Empty-v1``, the
robot's default steps, small actions of alternating sign: ``step_throughput.small_actions``),
three loops run in alternating blocks of ``--block`` steps; every figure is a median over
single steps (``time.perf_counter``: on a shared machine a median of short intervals
skips the ones another job interrupted):

1. the env with real physics: the whole ``env.step``, the time inside ``mujoco.mj_step``
   on the env's data, the end-effector controller's one-env call (forward kinematics at
   the seed, the target pose, the IK, the feed-forward targets: what ``overhead_ratio.py``
   counts as ``IK µs``) and, within it, ``IKSolver.solve_one``;
2. a raw replay of the same ``mj_step`` calls (the same controls, from the same start) on
   a plain ``MjData``: the physics without anything between its steps;
3. the env with the physics replaced by stand-ins that only advance time
   (``overhead_ratio.no_physics``): the same Python, its caches not flushed by the physics
   between steps (the arm does not move there, so the IK may take another number of
   iterations).

For a robot with a planar base (Fetch) the replay leaves out the base's joint-state
writes between steps, so its physics only approximates the env's (not checked there).
``mj_step +`` (env minus replay) is what the physics loses to what runs between its steps
(cache effects); ``rest`` is the step's Python outside the controller's call (action
checks and scaling, other parts, drives, the step's own bookkeeping, ``info`` and the
observation), with the physics (1) and without it (3): their difference is what the
Python loses to the physics between its runs.

**Against another checkout** (``--against SRC``: the ``src`` folder of another checkout of
this library). Two envs of the same robot and mode step the same actions in alternating
blocks (CPU clock, ``--rounds`` rounds): one on this tree's code, the other with the
other checkout's ``controllers/ee.py`` (``PDEEController.single_apply``) and
``kinematics/ik.py`` (``IKSolver.solve_one``) loaded in their place and without the
planned one-env step (``envs/single_step.py``; the general path, as before end-effector
modes had one). The median of the per-round differences resolves a few microseconds on a
noisy machine where separate runs spread by tens. Both envs must end in the same physics
state, bit for bit (checked). ``--python-only`` compares them with the physics stubbed
(``no_physics``).

Usage: ``python benchmarks/ee_step_split.py [--robots UID:MODE ...] [--rounds 30]
[--block 10] [--against SRC [--python-only]]``.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import os
import statistics
import sys
import time
import types
from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from overhead_ratio import no_physics
from robot_agents.controllers.ee import PDEEController
from step_throughput import small_actions

DEFAULT = (
    "panda:pd_ee_delta_pose",
    "panda:pd_ee_delta_pos",
    "so100:pd_ee_delta_pos",
    "fetch:pd_ee_delta_pose",
    "widowx250s:pd_ee_delta_pose",
    "ur_10e:pd_ee_delta_pose",
)


def make(uid: str, mode: str) -> Any:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None).unwrapped
    env.reset(seed=0)
    return env


def ee_parts(env: Any) -> list[PDEEController]:
    """The end-effector parts of every mode's controller of the env's robot (built now)."""
    control = env.agent.control
    controllers = [control.controller_for(mode) for mode in control.modes]
    return [part for c in controllers for part in c.parts.values() if isinstance(part, PDEEController)]


def timed_calls(env: Any, seconds: dict[str, float], tag: str) -> None:
    """The active mode's end-effector call and its solver's ``solve_one`` add their time
    to ``seconds[tag + "ee"]`` and ``seconds[tag + "ik"]`` (the one-env plan made again)."""
    combined = env.agent.controller
    for part in combined.parts.values():
        if not isinstance(part, PDEEController):
            continue
        plan_call = part.single_apply
        solve_one = part.solver.solve_one

        def planned(raw: np.ndarray, qpos: np.ndarray, plan_call: Any = plan_call) -> Callable[[], None]:
            call = plan_call(raw, qpos)

            def timed() -> None:
                begin = time.perf_counter()
                call()
                seconds[tag + "ee"] += time.perf_counter() - begin

            return timed

        def timed_solve(*args: Any, solve_one: Any = solve_one) -> None:
            begin = time.perf_counter()
            solve_one(*args)
            seconds[tag + "ik"] += time.perf_counter() - begin

        setattr(part, "single_apply", planned)  # noqa: B010
        setattr(part.solver, "solve_one", timed_solve)  # noqa: B010
    combined._single_sim = None


def split(uid: str, mode: str, rounds: int, block: int) -> dict[str, float]:
    """Per-step medians (µs) of the three loops of the module doc."""
    real, stub = make(uid, mode), make(uid, mode)
    actions = small_actions(real, 64, np.random.default_rng(0))
    seconds = dict.fromkeys(("rmj", "ree", "rik", "see", "sik"), 0.0)
    timed_calls(real, seconds, "r")
    timed_calls(stub, seconds, "s")
    model, data0 = real.model, real.scene.world._data0
    replay = mujoco.MjData(model)
    mujoco.mj_setState(model, replay, real.get_state()["physics"][0], mujoco.mjtState.mjSTATE_INTEGRATION)
    mj_step = mujoco.mj_step
    recorded: list[tuple[np.ndarray, int]] = []

    def recording_step(m: mujoco.MjModel, d: mujoco.MjData, nstep: int = 1) -> None:
        if d is data0:
            recorded.append((d.ctrl.copy(), nstep))
            begin = time.perf_counter()
            mj_step(m, d, nstep)
            seconds["rmj"] += time.perf_counter() - begin
        else:
            mj_step(m, d, nstep)

    series: dict[str, list[float]] = {k: [] for k in ("env", "mj", "ee", "ik", "replay", "stub", "stub_ee", "stub_ik")}
    cursor = {"real": 0, "stub": 0, "replay": 0}
    for _ in range(rounds):
        mujoco.mj_step = recording_step
        try:
            for _ in range(block):
                seconds["rmj"] = seconds["ree"] = seconds["rik"] = 0.0
                begin = time.perf_counter()
                real.step(actions[cursor["real"] % len(actions)])
                series["env"].append(time.perf_counter() - begin)
                series["mj"].append(seconds["rmj"])
                series["ee"].append(seconds["ree"])
                series["ik"].append(seconds["rik"])
                cursor["real"] += 1
        finally:
            mujoco.mj_step = mj_step
        for _ in range(block):
            ctrl, nstep = recorded[cursor["replay"]]
            begin = time.perf_counter()
            replay.ctrl[:] = ctrl
            mj_step(model, replay, nstep)
            series["replay"].append(time.perf_counter() - begin)
            cursor["replay"] += 1
        with no_physics():
            for _ in range(block):
                seconds["see"] = seconds["sik"] = 0.0
                begin = time.perf_counter()
                stub.step(actions[cursor["stub"] % len(actions)])
                series["stub"].append(time.perf_counter() - begin)
                series["stub_ee"].append(seconds["see"])
                series["stub_ik"].append(seconds["sik"])
                cursor["stub"] += 1
    state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_INTEGRATION))
    mujoco.mj_getState(model, replay, state, mujoco.mjtState.mjSTATE_INTEGRATION)
    # (a planar base's joint-state writes between steps are not replayed: there the
    # replay only approximates the env's physics, its mj_step figures too)
    if real.agent.mobile.planar is None and not np.array_equal(state, real.get_state()["physics"][0]):
        raise RuntimeError(f"{uid} {mode}: the replay did not reproduce the env's physics")
    real.close()
    stub.close()
    return {key: 1e6 * statistics.median(values) for key, values in series.items()}


def load_module(name: str, path: str) -> types.ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise FileNotFoundError(path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # (dataclasses look their module up)
    spec.loader.exec_module(module)
    return module


def against(uid: str, mode: str, other_src: str, rounds: int, block: int, python_only: bool) -> tuple[float, ...]:
    """``(this tree's µs/step, the other's, median of per-round differences, its lower
    and upper quartiles, median ratio other / this)``, see the module doc."""
    other_ik = load_module("other_ik", os.path.join(other_src, "robot_agents", "kinematics", "ik.py"))
    other_ee = load_module("other_ee", os.path.join(other_src, "robot_agents", "controllers", "ee.py"))
    other_ee.PDEEController = PDEEController  # (its one-env call tests the type against this one)
    envs = [make(uid, mode), make(uid, mode)]
    other = envs[1]
    other._planned_step = None
    for part in ee_parts(other):
        setattr(part, "single_apply", types.MethodType(other_ee.PDEEController.single_apply, part))  # noqa: B010
        setattr(part.solver, "solve_one", types.MethodType(other_ik.IKSolver.solve_one, part.solver))  # noqa: B010
    other.agent.controller._single_sim = None
    actions = small_actions(envs[0], 64, np.random.default_rng(0))
    cursor, times = [0, 0], ([], [])  # type: tuple[list[int], tuple[list[float], list[float]]]

    def run(k: int) -> float:
        env, begin = envs[k], time.process_time()
        for _ in range(block):
            env.step(actions[cursor[k] % len(actions)])
            cursor[k] += 1
        return time.process_time() - begin

    with no_physics() if python_only else contextlib.nullcontext():
        for i in range(rounds):
            for k in (0, 1) if i % 2 else (1, 0):
                times[k].append(run(k))
    if envs[0].get_state()["physics"].tobytes() != envs[1].get_state()["physics"].tobytes():
        raise RuntimeError(f"{uid} {mode}: the two trees' steps did not end in the same physics state")
    for env in envs:
        env.close()
    differences = [1e6 * (b - a) / block for a, b in zip(*times, strict=True)]
    return (
        1e6 * statistics.median(times[0]) / block,
        1e6 * statistics.median(times[1]) / block,
        statistics.median(differences),
        float(np.percentile(differences, 25)),
        float(np.percentile(differences, 75)),
        statistics.median([b / a for a, b in zip(*times, strict=True)]),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--robots", nargs="*", default=list(DEFAULT), help="UID:MODE pairs")
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--block", type=int, default=10)
    parser.add_argument("--against", default=None, help="the src folder of another checkout (module doc)")
    parser.add_argument("--python-only", action="store_true", help="with --against: the physics stubbed")
    args = parser.parse_args()
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    print(f"# {stamp}, load average {os.getloadavg()[0]:.1f}, {args.rounds} rounds of {args.block} steps")
    if args.against:
        print(
            "| robot | mode | this tree µs/step | other µs/step | other - this, µs (median, quartiles) | other / this |"
        )
        print("|---|---|---|---|---|---|")
        for pair in args.robots:
            uid, mode = pair.split(":")
            this, other, median, low, high, ratio = against(
                uid, mode, args.against, args.rounds, args.block, args.python_only
            )
            print(
                f"| `{uid}` | `{mode}` | {this:.1f} | {other:.1f} | {median:.1f} ({low:.1f}..{high:.1f}) | {ratio:.3f} |",
                flush=True,
            )
        return
    print(
        "| robot | mode | env µs/step | mj_step (replay, +) | end-effector call (solve_one) | rest | "
        "no physics: step | end-effector call (solve_one) | rest |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for pair in args.robots:
        uid, mode = pair.split(":")
        m = split(uid, mode, args.rounds, args.block)
        print(
            f"| `{uid}` | `{mode}` | {m['env']:.1f} | {m['mj']:.1f} ({m['replay']:.1f}, +{m['mj'] - m['replay']:.1f}) | "
            f"{m['ee']:.1f} ({m['ik']:.1f}) | {m['env'] - m['mj'] - m['ee']:.1f} | {m['stub']:.1f} | "
            f"{m['stub_ee']:.1f} ({m['stub_ik']:.1f}) | {m['stub'] - m['stub_ee']:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
