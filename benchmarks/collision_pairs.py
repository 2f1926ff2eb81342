"""What never-touching self-collision pairs cost per robot: raw ``mj_step`` time per
physics step of a robot's scene (floor included, the robot's default sim_freq) as the
library builds it, with the pairs :func:`robot_agents.tuning.collisions.never_touching_pairs`
finds excluded, with all self-collision off, and with contacts off altogether (the last
two are ceilings, not options), timed in alternating blocks within one run.

    python benchmarks/collision_pairs.py                 # every registered robot
    python benchmarks/collision_pairs.py panda xarm6_robotiq --rounds 9

Every variant replays the same recorded control sequence (seeded random
``pd_joint_delta_pos`` actions through the library's own controller) from the same
start; "same trajectory" says whether the final state of the excluded variant is
bit-identical to the one as built (it is when the excluded pairs never touched). Also
prints, per robot, the share of the step spent in collision detection and the geom
pairs reaching the narrow phase (:func:`~robot_agents.tuning.collisions.collision_profile`).
Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.agent import Agent
from robot_agents.agent.declaration import check
from robot_agents.registry import get_agent, list_agents
from robot_agents.sim.scene import Scene
from robot_agents.tuning.collisions import collision_profile, never_touching_pairs


def controls(cls: type[Agent], steps: int, seed: int = 0) -> tuple[mujoco.MjModel, np.ndarray, np.ndarray, int]:
    """The scene's model, its start qpos, the ctrl sequence the library's controller
    produced for seeded random delta actions, and the physics steps per control step."""
    scene = Scene(cls, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    start = scene.world.render_sources([0])[0].qpos.copy()
    rng = np.random.default_rng(seed)
    space = agent.action_space
    sequence = []
    for _ in range(steps):
        agent.set_action(rng.uniform(space.low, space.high) * 0.3)
        scene.step()
        sequence.append(scene.world.render_sources([0])[0].ctrl.copy())
    model = scene.model
    substeps = round(1.0 / (model.opt.timestep * scene.control_freq))
    scene.close()
    return model, start, np.array(sequence), substeps


def scene_model(cls: type[Agent]) -> mujoco.MjModel:
    """The scene model of ``cls`` (default sim_freq, floor)."""
    scene = Scene(cls, control_modes="pd_joint_delta_pos")
    model = scene.model
    scene.close()
    return model


def with_exclusions(cls: type[Agent], pairs: Sequence[tuple[str, str]]) -> type[Agent]:
    """A subclass of ``cls`` that also excludes ``pairs`` (keeping the exclusions the
    library derives for a robot that declares none)."""
    kept = tuple(cls.self_collision_exclusions) + tuple(check(cls).derived_exclusions)
    return type(cls.__name__, (cls,), {"self_collision_exclusions": kept + tuple(pairs)})


def replay(model: mujoco.MjModel, start: np.ndarray, ctrl: np.ndarray, substeps: int) -> tuple[float, np.ndarray]:
    """Seconds for the replay and the final qpos."""
    data = mujoco.MjData(model)
    data.qpos[:] = start
    begin = time.perf_counter()
    for row in ctrl:
        data.ctrl[:] = row
        mujoco.mj_step(model, data, nstep=substeps)
    return time.perf_counter() - begin, data.qpos.copy()


def measure(uid: str, rounds: int, steps: int) -> tuple[str, str]:
    """One table row and a detail paragraph for robot ``uid``."""
    cls = get_agent(uid)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pairs = () if cls.disable_self_collisions else never_touching_pairs(cls)
        base, start, ctrl, substeps = controls(cls, steps)
        models = {"as built": base}
        if pairs:
            models["excluded"] = scene_model(with_exclusions(cls, pairs))
        if not cls.disable_self_collisions:
            models["self off"] = scene_model(type(cls.__name__, (cls,), {"disable_self_collisions": True}))
    for name, flag in (("midphase off", mujoco.mjtDisableBit.mjDSBL_MIDPHASE), ("contacts off", mujoco.mjtDisableBit.mjDSBL_CONTACT)):
        changed = _copy(base)
        changed.opt.disableflags |= int(flag)
        models[name] = changed
    times: dict[str, list[float]] = {name: [] for name in models}
    finals: dict[str, np.ndarray] = {}
    for _ in range(rounds):
        for name, model in models.items():
            seconds, finals[name] = replay(model, start, ctrl, substeps)
            times[name].append(seconds / (len(ctrl) * substeps) * 1e6)
    us = {name: float(np.median(values)) for name, values in times.items()}
    profile = collision_profile(base, start, ctrl, substeps)
    self_pairs = sum(v for (a, b), v in profile.narrow_pairs.items() if "world" not in (a, b))
    floor_pairs = sum(v for (a, b), v in profile.narrow_pairs.items() if "world" in (a, b))
    same = "-"
    gain = "-"
    if "excluded" in us:
        same = "yes" if np.array_equal(finals["excluded"], finals["as built"]) else "no"
        gain = f"{(1 - us['excluded'] / us['as built']) * 100:+.1f} %"
    row = (
        f"| `{uid}` | {round(1 / base.opt.timestep)} | {len(pairs)} | {us['as built']:.1f} | "
        f"{us.get('excluded', float('nan')):.1f} | {gain} | {same} | {us.get('self off', float('nan')):.1f} | "
        f"{us['midphase off']:.1f} | {us['contacts off']:.1f} | {profile.shares['collision'] * 100:.0f} % | {self_pairs:.1f} / {floor_pairs:.1f} |"
    )
    top = ", ".join(f"{a}-{b} {v:.2f}" for (a, b), v in list(profile.narrow_pairs.items())[:8])
    detail = (
        f"- `{uid}`: excluded {list(pairs)}; collision {profile.shares['collision'] * 100:.0f} % of the step "
        f"(broad {profile.shares['broad'] * 100:.0f} %, narrow {profile.shares['narrow'] * 100:.0f} %), "
        f"{profile.contacts:.1f} contacts per step; narrow-phase pairs per step: {top}"
    )
    return row, detail


def _copy(model: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.copy(model)


HEADER = (
    "| robot | Hz | pairs excluded | as built (µs/step) | excluded | gain | same trajectory | self off | "
    "midphase off | contacts off | collision share | narrow pairs/step (self / floor) |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=None)
    parser.add_argument("--rounds", type=int, default=21)
    parser.add_argument("--steps", type=int, default=50, help="control steps (20 Hz) per replay")
    args = parser.parse_args(argv)
    uids = args.uids or list_agents()
    print(f"load average {os.getloadavg()[0]:.2f}, rounds {args.rounds}, {args.steps} control steps\n")
    print(HEADER)
    details = []
    for uid in uids:
        row, detail = measure(uid, args.rounds, args.steps)
        print(row, flush=True)
        details.append(detail)
    print()
    print("\n".join(details))
    print(f"\nload average {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
