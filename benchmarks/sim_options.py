"""What MuJoCo's physics options cost per robot: raw ``mj_step`` throughput of a
robot's scene with one option changed, as a ratio to the scene as the library builds
it, timed in alternating blocks within one run (machine noise hits all alike).

    python benchmarks/sim_options.py                # panda so100 ur_10e
    python benchmarks/sim_options.py widowxai --blocks 10
    python benchmarks/sim_options.py --all --clock cpu --variants "as built,midphase off"
    python benchmarks/sim_options.py panda so100 --variants "midphase off,islands off" --task-identity

The arm replays the same recorded control sequence (random pd_joint_delta_pos actions
from the library's own controller) in every variant. The table also says whether each
variant ends in the same state as the scene as built, bit for bit (``same``): an option
that only skips work (MuJoCo's midphase) must, one that changes the physics will not.
The ratio is the median over blocks of each block's ratio (the variants of a block run
back to back, in alternating order). ``visual geoms simulated`` is the scene as it was
before the simulated twin (``Scene(render_only_visuals=False)``: the visual-only geoms
simulated too), against the twin the library now simulates.
Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable, Sequence

import mujoco
import numpy as np

from robot_agents import list_agents
from robot_agents.agent import Agent
from robot_agents.sim.scene import Scene

Variant = Callable[[mujoco.MjModel], None]
VISUALS_SIMULATED = "visual geoms simulated"


def _set(field: str, value: object) -> Variant:
    def apply(model: mujoco.MjModel) -> None:
        setattr(model.opt, field, value)

    return apply


def _flag(flag: int, enable: bool) -> Variant:
    def apply(model: mujoco.MjModel) -> None:
        if enable:
            model.opt.enableflags |= flag
        else:
            model.opt.disableflags |= flag

    return apply


VARIANTS: dict[str, Variant | None] = {
    "as built": None,
    "integrator implicit": _set("integrator", int(mujoco.mjtIntegrator.mjINT_IMPLICIT)),
    "integrator euler": _set("integrator", int(mujoco.mjtIntegrator.mjINT_EULER)),
    # MuJoCo 3.13+: the constraint solve and the implicit update in one metric
    "integrator discrete": _set("integrator", int(mujoco.mjtIntegrator.mjINT_DISCRETE)),
    "solver iterations 20": _set("iterations", 20),
    "solver tolerance 1e-6": _set("tolerance", 1e-6),
    # MuJoCo's default, for a robot that declares a tighter one (``solver_tolerance``)
    "solver tolerance 1e-8": _set("tolerance", 1e-8),
    # the XLeRobot's declared one, for a robot at MuJoCo's default (benchmarks/solver_tolerance.py)
    "solver tolerance 1e-11": _set("tolerance", 1e-11),
    "cone elliptic": _set("cone", int(mujoco.mjtCone.mjCONE_ELLIPTIC)),
    "jacobian dense": _set("jacobian", int(mujoco.mjtJacobian.mjJAC_DENSE)),
    "jacobian sparse": _set("jacobian", int(mujoco.mjtJacobian.mjJAC_SPARSE)),
    "warmstart off": _flag(int(mujoco.mjtDisableBit.mjDSBL_WARMSTART), False),
    # MuJoCo's midphase: a bounding-volume tree over each body's geoms, walked for every
    # body pair the broadphase passes; off, every geom pair of the two bodies goes to
    # the bounding-sphere filter instead (contacts and their order are the same).
    "midphase off": _flag(int(mujoco.mjtDisableBit.mjDSBL_MIDPHASE), False),
    # Constraint islands: the solver works on each group of coupled trees separately.
    "islands off": _flag(int(mujoco.mjtDisableBit.mjDSBL_ISLAND), False),
    # The scene as it was before the simulated twin: the visual-only geoms in the
    # simulated model too (``Scene(render_only_visuals=False)``; a model of its own,
    # built in ``run``, not a change to the twin).
    VISUALS_SIMULATED: None,
}
CLOCKS: dict[str, Callable[[], float]] = {"wall": time.perf_counter, "cpu": time.process_time}


def controls(
    uid: str | type[Agent], steps: int, seed: int = 0, render_only_visuals: bool = True
) -> tuple[mujoco.MjModel, np.ndarray, np.ndarray]:
    """The scene's simulated model, its start state (qpos) and the ctrl sequence the
    library's controller produced for random delta actions (also used by
    ``collision_pairs.py``)."""
    scene = Scene(uid, control_modes="pd_joint_delta_pos", render_only_visuals=render_only_visuals)
    scene.reset()
    agent = scene.agents[0]
    data = scene.world.physics_sources([0])[0]
    start = data.qpos.copy()
    rng = np.random.default_rng(seed)
    space = agent.action_space
    sequence = []
    for _ in range(steps):
        agent.set_action(rng.uniform(space.low, space.high) * 0.3)
        scene.step()
        sequence.append(scene.world.physics_sources([0])[0].ctrl.copy())
    model = scene.model
    scene.close()
    return model, start, np.array(sequence)


def replay(
    model: mujoco.MjModel,
    start: np.ndarray,
    ctrl: np.ndarray,
    substeps: int,
    clock: Callable[[], float] = time.perf_counter,
) -> tuple[float, np.ndarray]:
    """Seconds (of ``clock``) for replaying ``ctrl`` (one row per control step) from
    ``start``, and the final qpos (also used by ``collision_pairs.py``)."""
    data = mujoco.MjData(model)
    data.qpos[:] = start
    begin = clock()
    for row in ctrl:
        data.ctrl[:] = row
        mujoco.mj_step(model, data, nstep=substeps)
    return clock() - begin, data.qpos.copy()


def copy_model(model: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.copy(model)


def run(
    uid: str, blocks: int, steps: int, variants: Sequence[str] = tuple(VARIANTS), clock: str = "wall"
) -> tuple[str, dict[str, float]]:
    """The markdown table of one robot and each variant's ratio to the scene as built."""
    base, start, ctrl = controls(uid, steps)
    substeps = round(1.0 / (base.opt.timestep * 20))
    models = {}
    for name in ["as built", *(v for v in variants if v != "as built")]:
        if name == VISUALS_SIMULATED:
            models[name] = controls(uid, 1, render_only_visuals=False)[0]
            continue
        copy = copy_model(base)
        variant = VARIANTS[name]
        if variant is not None:
            variant(copy)
        models[name] = copy
    rates: dict[str, list[float]] = {name: [] for name in models}
    finals: dict[str, np.ndarray] = {}
    order = list(models)
    for block in range(blocks):
        # alternate the order, so that no variant always runs right after another
        for name in order if block % 2 == 0 else order[::-1]:
            seconds, finals[name] = replay(models[name], start, ctrl, substeps, CLOCKS[clock])
            rates[name].append(len(ctrl) / seconds)
    lines = [f"### `{uid}` ({1 / base.opt.timestep:.0f} Hz, {substeps} substeps per control step)", ""]
    lines += ["| variant | control steps/s (median) | ratio to as built | same final state |", "|---|---|---|---|"]
    ratios = {}
    for name, values in rates.items():
        median = float(np.median(values))
        # the median of the per-block ratios: each block's variants ran back to back,
        # so a slow spell of the machine hits both sides of a ratio alike
        ratios[name] = float(np.median(np.array(values) / np.array(rates["as built"])))
        same = "yes" if np.array_equal(finals[name], finals["as built"]) else "no"
        lines.append(f"| {name} | {median:.0f} | {ratios[name]:.2f} | {same} |")
    return "\n".join(lines), ratios


def same_task_trajectory(uid: str, variant: str, steps: int = 150) -> tuple[bool, int]:
    """Whether ``PickCube-v1`` with random actions gives the same observations and
    rewards bit for bit with ``variant`` applied to its model, and the most contacts seen."""
    import hashlib

    from robot_agents.envs import make_env

    digests, most = [], 0
    for second, apply in enumerate((None, VARIANTS[variant])):
        full = bool(second) and variant == VISUALS_SIMULATED
        env = make_env("PickCube-v1", robot_uids=uid, render_only_visuals=not full)
        world = env.unwrapped.scene.world  # type: ignore[attr-defined]
        if apply is not None:
            apply(world.model)
        obs, _ = env.reset(seed=3)
        rng = np.random.default_rng(0)
        digest = hashlib.sha256()
        for _ in range(steps):
            obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
            digest.update(np.asarray(obs).tobytes() + np.asarray(reward).tobytes())
            most = max(most, int(world.datas[0].ncon))
        env.close()
        digests.append(digest.hexdigest())
    return digests[0] == digests[1], most


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("uids", nargs="*", default=["panda", "so100", "ur_10e"])
    parser.add_argument("--all", action="store_true", help="every registered robot")
    parser.add_argument("--blocks", type=int, default=5)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--variants", default=",".join(VARIANTS), help=f"comma-separated, of: {', '.join(VARIANTS)}")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="wall", help="cpu: this process's CPU time")
    parser.add_argument(
        "--task-identity",
        action="store_true",
        help="instead: does each variant leave PickCube-v1 with random actions bit-identical (contacts included)?",
    )
    args = parser.parse_args(argv)
    variants = [v.strip() for v in args.variants.split(",")]
    unknown = [v for v in variants if v not in VARIANTS]
    if unknown:
        parser.error(f"unknown variants {unknown}; available: {list(VARIANTS)}")
    uids = list_agents() if args.all else args.uids
    if args.task_identity:
        for uid in uids:
            for variant in (v for v in variants if v != "as built"):
                same, contacts = same_task_trajectory(uid, variant)
                print(f"{uid} {variant}: PickCube-v1 bit-identical {same} (up to {contacts} contacts)", flush=True)
        return 0
    print(f"load average {os.getloadavg()[0]:.2f}, clock {args.clock}, {args.blocks} blocks\n")
    summary = []
    for uid in uids:
        table, ratios = run(uid, args.blocks, args.steps, variants, args.clock)
        print(table + "\n", flush=True)
        summary.append(f"| `{uid}` | " + " | ".join(f"{ratios[v]:.2f}" for v in ratios if v != "as built") + " |")
    shown = [v for v in ["as built", *variants] if v != "as built"]
    print("| robot | " + " | ".join(shown) + " |\n|---|" + "---|" * len(shown))
    print("\n".join(summary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
