"""What never-touching self-collision pairs cost per robot: raw ``mj_step`` time per
physics step of a robot's scene (floor included, the robot's default sim_freq) as the
library builds it, and with the pairs
:func:`robot_agents.tuning.collisions.never_touching_pairs` finds excluded; for
comparison, with all self-collision off, without the floor, with MuJoCo's midphase off
and with contacts off altogether (bounds on what collision settings could gain, not
options). Variants are timed in alternating blocks within one run: medians (the gain also from
the fastest block of each, steadier on a loaded machine).

    python benchmarks/collision_pairs.py                 # every registered robot
    python benchmarks/collision_pairs.py panda xarm6_robotiq --rounds 9

Every variant replays the same recorded control sequence (seeded random
``pd_joint_delta_pos`` actions through the library's own controller) from the same
start; "same trajectory" says whether the final state of the excluded variant is
bit-identical to the one as built (it is when the excluded pairs never touched). Also
prints, per robot, the share of the step spent in collision detection and the geom
pairs reaching the narrow phase (:func:`~robot_agents.tuning.collision_profile.collision_profile`).
Not run in CI.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np

from robot_agents.agent import Agent
from robot_agents.agent.declaration import check
from robot_agents.registry import get_agent, list_agents
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene
from robot_agents.tuning.collision_profile import collision_profile
from robot_agents.tuning.collisions import geom_pairs, never_touching_pairs
from sim_options import controls, replay


def scene_model(cls: type[Agent], floor: bool = True) -> mujoco.MjModel:
    """The scene model of ``cls`` (default sim_freq, with or without the floor)."""
    scene = Scene(cls, control_modes="pd_joint_delta_pos", floor=floor)
    model = scene.model
    scene.close()
    return model


def with_exclusions(cls: type[Agent], pairs: Sequence[tuple[str, str]]) -> type[Agent]:
    """A subclass of ``cls`` that also excludes ``pairs`` (keeping the exclusions the
    library derives for a robot that declares none)."""
    kept = tuple(cls.self_collision_exclusions) + tuple(check(cls).derived_exclusions)
    return type(cls.__name__, (cls,), {"self_collision_exclusions": kept + tuple(pairs)})


def move_visual_geoms(spec: mujoco.MjSpec) -> mujoco.MjSpec:
    """Move each body's non-colliding geoms into a new child body without joints (welded
    to it, massless geoms): MuJoCo's broad phase bounds a colliding body by all its
    geoms, visual ones included, so this leaves it fewer to bound. A prototype for the
    measurement (adds bodies named ``<body>_visual``)."""
    for body in list(spec.worldbody.find_all(mujoco.mjtObj.mjOBJ_BODY)):
        visual = [g for g in body.geoms if not (g.contype or g.conaffinity)]
        if not visual or len(visual) == len(body.geoms):
            continue
        child = body.add_body(name=body.name + "_visual")
        for geom in visual:
            child.add_geom(
                type=geom.type,
                size=geom.size,
                pos=geom.pos,
                quat=geom.quat,
                fromto=geom.fromto,
                rgba=geom.rgba,
                group=geom.group,
                material=geom.material,
                meshname=geom.meshname,
                contype=0,
                conaffinity=0,
                mass=0,
            )
            spec.delete(geom)
    return spec


def with_visual_geoms_apart(cls: type[Agent]) -> type[Agent]:
    """A subclass of ``cls`` whose spec has its visual geoms moved (:func:`move_visual_geoms`)."""

    class Apart(cls):  # type: ignore[valid-type,misc]
        @classmethod
        def build_spec(klass, cameras: Sequence[Any] | None = None) -> mujoco.MjSpec:
            return move_visual_geoms(super().build_spec(cameras))

    Apart.__name__ = cls.__name__
    return Apart


def poses(model: mujoco.MjModel, start: np.ndarray, ctrl: np.ndarray, substeps: int) -> np.ndarray:
    """The qpos after every control step of the replay."""
    data = mujoco.MjData(model)
    data.qpos[:] = start
    visited = []
    for row in ctrl:
        data.ctrl[:] = row
        mujoco.mj_step(model, data, nstep=substeps)
        visited.append(data.qpos.copy())
    return np.array(visited)


def collision_us(
    models: dict[str, mujoco.MjModel], visited: np.ndarray, rounds: int, repeat: int = 20
) -> dict[str, float]:
    """Median µs of ``mj_collision`` alone (Python call included) at the replay's poses,
    per model, in alternating blocks."""
    datas = {name: mujoco.MjData(model) for name, model in models.items()}
    times: dict[str, list[float]] = {name: [] for name in models}
    for _ in range(rounds):
        for name, model in models.items():
            data, total = datas[name], 0.0
            for qpos in visited:
                data.qpos[:] = qpos
                mujoco.mj_kinematics(model, data)
                begin = time.perf_counter()
                for _ in range(repeat):
                    mujoco.mj_collision(model, data)
                total += time.perf_counter() - begin
            times[name].append(total / (len(visited) * repeat) * 1e6)
    return {name: float(np.median(values)) for name, values in times.items()}


def sphere_overlaps(model: mujoco.MjModel, visited: np.ndarray, pairs: Sequence[tuple[str, str]]) -> float:
    """Mean number, per pose, of the pairs' collidable geom pairs whose bounding spheres
    overlap (the first test a geom pair must pass in MuJoCo's midphase; pairs that never
    pass it cost only their broad-phase and exclusion checks)."""
    names = {model.body(b).name.split("/")[-1]: b for b in range(1, model.nbody)}
    geoms = [(a, b) for first, second in pairs for a, b in geom_pairs(model, names[first], names[second])]
    if not geoms:
        return 0.0
    first_geoms, second_geoms = np.array(geoms).T
    radius = model.geom_rbound[first_geoms] + model.geom_rbound[second_geoms]
    data = mujoco.MjData(model)
    count = 0
    for qpos in visited:
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        gap = np.linalg.norm(data.geom_xpos[first_geoms] - data.geom_xpos[second_geoms], axis=1)
        count += int(np.sum(gap <= radius))
    return count / len(visited)


def measure(uid: str, rounds: int, steps: int) -> tuple[str, str]:
    """One table row and a detail paragraph for robot ``uid``."""
    cls = get_agent(uid)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pairs = () if cls.disable_self_collisions else never_touching_pairs(cls)
        base, start, ctrl = controls(cls, steps)
        substeps = round(1.0 / (base.opt.timestep * DEFAULT_CONTROL_FREQ))
        models = {"as built": base}
        if pairs:
            models["excluded"] = scene_model(with_exclusions(cls, pairs))
        if not cls.disable_self_collisions:
            models["self off"] = scene_model(type(cls.__name__, (cls,), {"disable_self_collisions": True}))
        models["visual apart"] = scene_model(with_visual_geoms_apart(cls))
        models["no floor"] = scene_model(cls, floor=False)
    for name, flag in (
        ("midphase off", mujoco.mjtDisableBit.mjDSBL_MIDPHASE),
        ("contacts off", mujoco.mjtDisableBit.mjDSBL_CONTACT),
    ):
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
    best = {name: float(np.min(values)) for name, values in times.items()}
    profile = collision_profile(base, start, ctrl, substeps)
    compared = {name: models[name] for name in ("as built", "excluded", "self off") if name in models}
    visited = poses(base, start, ctrl, substeps)
    alone = collision_us(compared, visited, rounds)
    overlaps = sphere_overlaps(base, visited, pairs)
    self_pairs = sum(v for (a, b), v in profile.narrow_pairs.items() if "world" not in (a, b))
    floor_pairs = sum(v for (a, b), v in profile.narrow_pairs.items() if "world" in (a, b))
    same = "-"
    gain = "-"
    if "excluded" in us:
        same = "yes" if np.array_equal(finals["excluded"], finals["as built"]) else "no"
        gain = (
            f"{(1 - us['excluded'] / us['as built']) * 100:+.1f} % "
            f"(min {(1 - best['excluded'] / best['as built']) * 100:+.1f} %)"
        )
    apart_same = "=" if np.array_equal(finals["visual apart"], finals["as built"]) else "differs"
    row = (
        f"| `{uid}` | {round(1 / base.opt.timestep)} | {len(pairs)} | {overlaps:.2f} | {us['as built']:.1f} | "
        f"{us.get('excluded', float('nan')):.1f} | {gain} | {same} | {alone['as built']:.2f} / {alone.get('excluded', float('nan')):.2f} / {alone.get('self off', float('nan')):.2f} | {us.get('self off', float('nan')):.1f} | "
        f"{us['visual apart']:.1f} ({apart_same}) | {us['no floor']:.1f} | {us['midphase off']:.1f} | {us['contacts off']:.1f} | {profile.shares['collision'] * 100:.0f} % | {self_pairs:.1f} / {floor_pairs:.1f} |"
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
    "| robot | Hz | pairs excluded | their sphere overlaps/pose | as built (µs/step) | excluded | gain (median, min) | same trajectory | "
    "mj_collision alone (µs: as built / excluded / self off) | self off | visual geoms apart | "
    "no floor | midphase off | contacts off | collision share | narrow pairs/step (self / floor) |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=None)
    parser.add_argument("--rounds", type=int, default=31)
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
