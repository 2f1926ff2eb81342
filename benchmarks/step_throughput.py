"""Env step throughput of the Panda in every joint mode, against raw MuJoCo.

For each mode, in one run on one machine, all on the same compiled model with the
same number of physics substeps per control step:

- ``raw const``: ``mujoco.mj_step(model, data, nstep=substeps)`` in a Python loop with
  constant ``ctrl`` (the arm holds still): control steps/s of bare physics;
- ``raw replay``: the same loop replaying the ``ctrl`` sequence our env produced, from
  the same initial state, so it simulates exactly the env's motion (the benchmark
  checks the final states are bit-identical);
- ``env``: ``env.step(action)`` of ``make_env("Empty-v1", robot_uids="panda", ...)``
  at ``num_envs=1`` (validation, controller, substeps, observation) with small
  actions of alternating sign, in env steps/s;
- ``env/replay`` is our overhead on identical physics; ``env/const`` compares with the
  arm at rest (moving costs MuJoCo a little more than holding still);
- ``env xN``: env steps/s of all ``N`` envs together (``num_envs=N`` on all cores)
  and its ratio to the single-env ``raw const`` rate.

End-effector control (``--ee``, on by default): env steps/s of ``pd_ee_delta_pose``
against ``pd_joint_delta_pos`` on the same robot, timed in alternating blocks, and
the IK success rate of ``pd_ee_delta_pose`` on 1000 random deltas over its whole
action range (up to 10 cm and 0.1 rad per axis) applied from the ``rest`` keyframe.

Other robots (``--robots``, default ``xarm6_robotiq so100 fetch spot``): env steps/s at
``num_envs=1`` in ``pd_joint_delta_pos`` and in ``pd_ee_delta_pose`` (``pd_ee_delta_pos``
where the robot has no pose mode), the modes timed in alternating blocks. With
``--peer-python`` (default: ``~/.venvs/maniskill/bin/python`` when it exists; made by
``setup_maniskill.sh``) the same robot and mode of ManiSkill 3 (CPU, ``Empty-v1``,
state observations, its own 20 Hz control) is timed in a worker process in the same
alternating blocks (the worker times its own ``env.step`` loop, so pipe traffic is not
counted); a robot or mode the peer lacks, or cannot load, is reported and skipped.
Nothing here imports ManiSkill.

Env and raw loops run in alternating blocks so that machine noise hits both alike.
Usage: ``python benchmarks/step_throughput.py [--rounds 20] [--block 50] [--num-envs 64] [--no-joint]
[--no-ee] [--robots UID ...] [--peer-python PATH]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from collections.abc import Callable, Sequence

import mujoco
import numpy as np

import robot_agents as ra
from peer import Peer, default_peer_python

#: The robot of the joint-mode table (``--robot``); the end-effector section is the Panda's.
ROBOT = "panda"

JOINT_MODES = (
    "pd_joint_pos",
    "pd_joint_delta_pos",
    "pd_joint_target_delta_pos",
    "pd_joint_vel",
    "pd_joint_pos_vel",
    "pd_joint_delta_pos_vel",
)
STATE = mujoco.mjtState.mjSTATE_INTEGRATION


def small_actions(env: ra.RobotEnv, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Small actions of alternating sign (absolute position modes: about the current
    pose): the arm keeps moving near its rest pose in every mode (no drift into joint
    limits or the floor)."""
    space = env.agent.action_space
    mid, half = (space.low + space.high) / 2, (space.high - space.low) / 2
    actions = [(mid + (-1) ** i * 0.1 * half * rng.uniform(0, 1, space.shape)).astype(np.float32) for i in range(count)]
    controller = env.agent.controller
    for part, config in ((p, c.config) for p, c in controller.parts.items()):
        if isinstance(config, ra.PDJointPosConfig) and not config.use_delta and not config.normalize_action:
            start = controller.slices[part].start
            index = [env.agent.joint_names.index(j) for j in config.joint_names]
            hold = env.agent.qpos[:, index]
            for action in actions:
                action[:, start : start + len(index)] = hold + 0.05 * rng.uniform(-1, 1, hold.shape)
    if env.num_envs > 1:  # different motions per env
        for action in actions:
            rng.shuffle(action, axis=0)
    return actions


def make(mode: str, num_envs: int) -> ra.RobotEnv:
    env = ra.make_env("Empty-v1", robot_uids=ROBOT, control_mode=mode, num_envs=num_envs, max_episode_steps=None)
    env.reset(seed=0)
    return env.unwrapped  # type: ignore[return-value]


def interleaved(loops: list[Callable[[int], None]], rounds: int, block: int) -> list[float]:
    """Calls/s of each loop, timed in alternating blocks of ``block`` calls after a warm-up."""
    for loop in loops:
        loop(block)
    totals = [0.0] * len(loops)
    for _ in range(rounds):
        for i, loop in enumerate(loops):
            start = time.perf_counter()
            loop(block)
            totals[i] += time.perf_counter() - start
    return [rounds * block / total for total in totals]


def single_env(mode: str, rounds: int, block: int, rng: np.random.Generator) -> tuple[float, float, float]:
    """(raw const, raw replay, env) control steps/s at num_envs=1."""
    env = make(mode, 1)
    model, substeps = env.model, env.scene.substeps
    actions = small_actions(env, 64, rng)
    steps = (rounds + 1) * block
    start = env.get_state()
    controls = []
    for i in range(steps):  # record the ctrl sequence the env produces
        env.step(actions[i % len(actions)])
        controls.append(env.data.ctrl.copy())
    final = env.get_state()["physics"][0]
    env.set_state(start)
    replay_data, const_data = mujoco.MjData(model), mujoco.MjData(model)
    for data in (replay_data, const_data):
        mujoco.mj_setState(model, data, start["physics"][0], STATE)
    cursor = {"env": 0, "replay": 0}

    def env_loop(count: int) -> None:
        for _ in range(count):
            env.step(actions[cursor["env"] % len(actions)])
            cursor["env"] += 1

    def replay_loop(count: int) -> None:
        for _ in range(count):
            replay_data.ctrl[:] = controls[cursor["replay"]]
            mujoco.mj_step(model, replay_data, substeps)
            cursor["replay"] += 1

    def const_loop(count: int) -> None:
        for _ in range(count):
            mujoco.mj_step(model, const_data, substeps)

    const, replay, env_rate = interleaved([const_loop, replay_loop, env_loop], rounds, block)
    replay_state = np.empty(mujoco.mj_stateSize(model, STATE))
    mujoco.mj_getState(model, replay_data, replay_state, STATE)
    if not (np.array_equal(replay_state, final) and np.array_equal(env.get_state()["physics"][0], final)):
        raise RuntimeError(f"{mode}: the replay did not reproduce the env's trajectory")
    env.close()
    return const, replay, env_rate


def batched_env(mode: str, num_envs: int, rounds: int, block: int, rng: np.random.Generator) -> tuple[float, float]:
    """(raw const single-env, env steps/s of all envs together)."""
    env = make(mode, num_envs)
    actions = small_actions(env, 16, rng)
    data = mujoco.MjData(env.model)
    mujoco.mj_setState(env.model, data, env.get_state()["physics"][0], STATE)
    counter = [0]

    def env_loop(count: int) -> None:
        for _ in range(count):
            env.step(actions[counter[0] % len(actions)])
            counter[0] += 1

    def const_loop(count: int) -> None:
        for _ in range(count):
            mujoco.mj_step(env.model, data, env.scene.substeps)

    const, rate = interleaved([const_loop, env_loop], rounds, block)
    env.close()
    return const, rate * num_envs


def ee_against_joint(rounds: int, block: int, rng: np.random.Generator) -> dict[str, float]:
    """Env steps/s of pd_ee_delta_pose and pd_joint_delta_pos (num_envs=1), interleaved."""
    rates: dict[str, float] = {}
    envs = {mode: make(mode, 1) for mode in ("pd_joint_delta_pos", "pd_ee_delta_pose", "pd_ee_target_delta_pose")}
    loops = []
    for env in envs.values():
        # Pairs of opposite small actions: target variants oscillate instead of drifting.
        pairs = [action for action in small_actions(env, 32, rng) for action in (action, -action)]
        actions = [action.copy() for action in pairs]
        counter = [0]

        def loop(
            count: int, env: ra.RobotEnv = env, actions: list[np.ndarray] = actions, counter: list[int] = counter
        ) -> None:
            for _ in range(count):
                env.step(actions[counter[0] % len(actions)])
                counter[0] += 1

        loops.append(loop)
    for mode, rate in zip(envs, interleaved(loops, rounds, block), strict=True):
        rates[mode] = rate
    for mode, env in envs.items():
        if not np.all(env.agent.controller.step_info().get("ik_success", True)):
            raise RuntimeError(f"{mode}: IK failed during the timing run; the actions are not small")
        env.close()
    return rates


def ik_success_rate(count: int = 1000) -> tuple[float, float, float, float]:
    """(success rate, mean DLS iterations, 99th-percentile position error (m), rotation
    error (rad)) of one pd_ee_delta_pose step from ``rest`` for ``count`` random actions."""
    env = ra.make_env(
        "Empty-v1", robot_uids="panda", control_mode="pd_ee_delta_pose", num_envs=count, robot_init_qpos_noise=0.0
    ).unwrapped
    env.reset(seed=0, options={"keyframe": "rest"})
    actions = np.random.default_rng(1).uniform(-1.0, 1.0, (count, env.agent.controller.action_dim))
    _, _, _, _, info = env.step(actions)
    iterations = env.agent.controller.parts["arm"]._result.iterations  # type: ignore[attr-defined]
    env.close()
    return (
        float(np.mean(info["ik_success"])),
        float(np.mean(iterations)),
        float(np.percentile(info["ik_position_error"], 99)),
        float(np.percentile(info["ik_rotation_error"], 99)),
    )


def ee_mode(uid: str) -> str:
    modes = ra.get_agent(uid).modes()
    return "pd_ee_delta_pose" if "pd_ee_delta_pose" in modes else "pd_ee_delta_pos"


def robot_rates(
    uids: Sequence[str], rounds: int, block: int, peer_python: str | None, rng: np.random.Generator
) -> None:
    """Env steps/s of each robot in a joint and an end-effector delta mode (num_envs=1),
    and of the peer's same robot and mode where it has them: per robot, all its loops
    (ours and the peer's) timed in one set of alternating blocks."""
    print("\nother robots, num_envs=1, control_freq 20 Hz (env steps/s, interleaved; higher is better)")
    print(f"{'robot':<16} {'mode':<20} {'ours':>6} {'peer':>6} {'ours/peer':>9}  notes")
    for uid in uids:
        modes = ("pd_joint_delta_pos", ee_mode(uid))
        envs, actions, peers = [], [], []
        loops: list[Callable[[int], None]] = []
        for mode in modes:
            env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None).unwrapped
            env.reset(seed=0)
            # Pairs of opposite small actions: target variants oscillate instead of drifting.
            pairs = [action for action in small_actions(env, 32, rng) for action in (action, -action)]
            counter = [0]

            def ours(
                count: int, env: ra.RobotEnv = env, pairs: list[np.ndarray] = pairs, counter: list[int] = counter
            ) -> None:
                for _ in range(count):
                    env.step(pairs[counter[0] % len(pairs)])
                    counter[0] += 1

            envs.append(env)
            actions.append(pairs)
            loops.append(ours)
            peer = Peer(peer_python, uid, mode) if peer_python else None
            peers.append(peer)
            if peer is not None and peer.ready:
                loops.append(peer.loop)
        rates = iter(interleaved(loops, rounds, block))
        for mode, env, pairs, peer in zip(modes, envs, actions, peers, strict=True):
            ours_rate = next(rates)
            solved = []  # untimed: how often IK met these actions' targets (EE modes)
            for action in pairs:
                env.step(action)
                solved.append(bool(np.all(env.agent.controller.step_info().get("ik_success", True))))
            env.close()
            note = "" if mode.startswith("pd_joint") else f"IK {100 * np.mean(solved):.0f}% of steps; "
            if peer is not None and peer.ready:
                next(rates)
                peer_rate = rounds * block / sum(peer.blocks[1:])  # the timed rounds, after the warm-up block
                peer.close()
                print(
                    f"{uid:<16} {mode:<20} {ours_rate:>6.0f} {peer_rate:>6.0f} {ours_rate / peer_rate:>8.2f}x  "
                    f"{note}peer: ManiSkill {peer.status.split()[1]} (its own {peer.status.split()[3]} Hz physics)",
                    flush=True,
                )
            else:
                status = peer.status if peer is not None else "no peer python"
                print(f"{uid:<16} {mode:<20} {ours_rate:>6.0f} {'-':>6} {'-':>9}  {note}peer: {status}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--block", type=int, default=50, help="control steps per timed block")
    parser.add_argument("--num-envs", type=int, default=64)
    parser.add_argument("--no-joint", action="store_true", help="skip the joint-mode table")
    parser.add_argument("--no-ee", action="store_true", help="skip the end-effector comparison")
    parser.add_argument("--robot", default="panda", help="robot of the joint-mode table (at its default sim_freq)")
    parser.add_argument(
        "--robots", nargs="*", default=["xarm6_robotiq", "so100", "fetch", "spot"], help="other robots to time"
    )
    parser.add_argument(
        "--peer-python",
        default=default_peer_python(),
        help="a Python with ManiSkill 3 installed (default: ~/.venvs/maniskill/bin/python if present)",
    )
    args = parser.parse_args()
    global ROBOT
    ROBOT = args.robot
    probe = make("pd_joint_pos", 1)
    scene = probe.scene
    print(
        f"robot_agents {ra.__version__}, mujoco {mujoco.__version__}, python {platform.python_version()}, {os.cpu_count()} cores"
    )
    print(
        f"{ROBOT}, Empty-v1, sim_freq {scene.sim_freq} Hz, control_freq {scene.control_freq} Hz, {scene.substeps} substeps/step\n"
    )
    probe.close()
    n = args.num_envs
    header = (
        f"{'mode':<26} {'raw const':>9} {'raw replay':>10} {'env':>6} {'env/replay':>10} {'env/const':>9}"
        f" {f'env x{n}':>9} {'x' + str(n) + '/const':>9}"
    )
    rng = np.random.default_rng(0)
    if not args.no_joint:
        print("control steps/s" + " " * 12 + "(higher is better)")
        print(header)
        print("-" * len(header))
    for mode in () if args.no_joint else JOINT_MODES:
        const, replay, env_rate = single_env(mode, args.rounds, args.block, rng)
        const_b, batch = batched_env(mode, n, max(2, args.rounds // 2), max(2, args.block // 5), rng)
        print(
            f"{mode:<26} {const:>9.0f} {replay:>10.0f} {env_rate:>6.0f} {env_rate / replay:>10.2f} {env_rate / const:>9.2f}"
            f" {batch:>9.0f} {batch / const_b:>8.2f}x",
            flush=True,
        )
    if args.robots:
        robot_rates(args.robots, args.rounds, args.block, args.peer_python, rng)
    if args.no_ee:
        return
    rates = ee_against_joint(args.rounds, args.block, rng)
    joint = rates["pd_joint_delta_pos"]
    print("\nend-effector vs joint control, num_envs=1 (env steps/s, interleaved)")
    for mode, rate in rates.items():
        print(f"{mode:<26} {rate:>6.0f}  {rate / joint:.2f}x of pd_joint_delta_pos")
    success, iterations, position, rotation = ik_success_rate()
    print(
        f"\npd_ee_delta_pose IK from rest, 1000 random actions over the full range: success {100 * success:.1f}%, "
        f"mean {iterations:.2f} DLS iterations, 99th percentile error {1000 * position:.3f} mm / "
        f"{np.degrees(rotation):.3f} deg"
    )


if __name__ == "__main__":
    main()
