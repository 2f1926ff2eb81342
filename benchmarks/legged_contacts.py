"""What a legged robot's contact options cost and buy: for each friction-cone setting,
how far the standing robot's base creeps (m) between 1 s and 5 s of holding its default
keyframe in its default mode; how many control steps per second it runs standing while
its legs move (small deltas of alternating sign in ``pd_joint_target_delta_pos``, the
loop of ``benchmarks/vs_maniskill.py --our-mode pd_joint_target_delta_pos``); and how
many after its legs have folded under small random deltas in ``pd_joint_delta_pos`` (the
mode ``benchmarks/vs_maniskill.py`` compares; deltas from the measured pose let loaded
legs give), lying on the floor in a heap of contacts. For that folded run it also reports
the share of MuJoCo's step spent in its constraint stage (``mjTIMER_CONSTRAINT`` over
``mjTIMER_STEP``) and the mean Newton iterations of the last substep of each control step,
and, besides the contact variants, solver settings on the declared contacts
(:data:`SOLVER_VARIANTS`, set on the compiled model's ``opt``).

Usage: ``python benchmarks/legged_contacts.py [UID ...] [--steps 200]`` (default
``anymal_c``, whose declared contacts are Menagerie's elliptic cone with impratio 100).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.agent.legs import foot_bodies
from robot_agents.checks import hold_action, standing_leg_joints

#: Variants: name -> class attributes overriding the robot's.
VARIANTS: dict[str, dict[str, Any]] = {
    "as declared": {},
    "pyramidal, impratio 1 (MuJoCo's default)": {"friction_cone": "pyramidal", "impratio": 1.0},
    "elliptic, impratio 10": {"friction_cone": "elliptic", "impratio": 10.0},
}

#: Contact dimensionality of the feet (the sphere geoms of the legs' distal links, set
#: on the compiled model): name -> condim. MuJoCo Menagerie's ANYmal and Go2 feet take 6
#: (sliding, torsional 0.02 and rolling 0.01 friction); our ANYmal's 3, our Go2's 6.
FOOT_CONDIM_VARIANTS: dict[str, int] = {"feet condim 3 (sliding friction only)": 3, "feet condim 6 (Menagerie's)": 6}

#: Solver settings tried on the declared contacts: name -> ``MjOption`` fields.
SOLVER_VARIANTS: dict[str, dict[str, float]] = {
    "as declared, solver tolerance 1e-6 (from 1e-8)": {"tolerance": 1e-6},
    "as declared, solver tolerance 1e-5": {"tolerance": 1e-5},
    "as declared, 20 solver iterations (from 100)": {"iterations": 20},
}


@dataclass(frozen=True)
class Folded:
    """The folded run: control steps per second (CPU time), the constraint stage's share
    of MuJoCo's step time, mean Newton iterations (last substep of each control step)."""

    rate: float
    constraint_share: float
    iterations: float


def _set_options(scene: ra.Scene, options: dict[str, float]) -> None:
    """``MjOption`` fields, and ``foot_condim``: the contact dimensionality of the feet
    (the sphere geoms of the legs' distal links)."""
    model = scene.model
    for field, value in options.items():
        if field == "foot_condim":
            agent = scene.agents[0]
            ids = [agent.index.joint(j, "legged_contacts").id for j in standing_leg_joints(type(agent))]
            feet = np.isin(model.geom_bodyid, sorted(foot_bodies(model, ids)))
            model.geom_condim[feet & (model.geom_type == int(mujoco.mjtGeom.mjGEOM_SPHERE))] = int(value)
        else:
            setattr(model.opt, field, value)


def standing_rate(cls: type[ra.Agent], steps: int, options: dict[str, float] | None = None) -> float:
    """Control steps per second (CPU time) standing in ``pd_joint_target_delta_pos`` while
    small deltas of alternating sign move the legs (the loop of ``vs_maniskill.py
    --our-mode pd_joint_target_delta_pos``), after a second of it."""
    scene = ra.Scene(cls, control_modes="pd_joint_target_delta_pos")
    _set_options(scene, options or {})
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    deltas = [rng.uniform(-0.05, 0.05, agent.controller.action_dim) for _ in range(16)]
    pairs = [delta for pair in deltas for delta in (pair, -pair)]
    for k in range(scene.control_freq):
        agent.set_action(pairs[k % len(pairs)])
        scene.step()
    begin = time.process_time()
    for k in range(steps):
        agent.set_action(pairs[k % len(pairs)])
        scene.step()
    elapsed = time.process_time() - begin
    scene.close()
    return steps / elapsed


def creep(cls: type[ra.Agent], options: dict[str, float] | None = None) -> float:
    """The base's movement (m) from 1 s to 5 s of holding the default keyframe."""
    scene = ra.Scene(cls)
    _set_options(scene, options or {})
    scene.reset()
    agent = scene.agents[0]
    hold = hold_action(agent)
    positions = []
    for _ in range(5 * scene.control_freq):
        agent.set_action(hold)
        scene.step()
        positions.append(agent.base_pose[0, :3].copy())
    scene.close()
    return float(np.linalg.norm(positions[-1] - positions[scene.control_freq - 1]))


def folded_run(cls: type[ra.Agent], steps: int, options: dict[str, float] | None = None) -> Folded:
    """``steps`` small random deltas in ``pd_joint_delta_pos`` from the default keyframe."""
    scene = ra.Scene(cls, control_modes="pd_joint_delta_pos")
    _set_options(scene, options or {})
    scene.reset()
    agent = scene.agents[0]
    data = scene.world.physics_sources([0])[0]
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-0.05, 0.05, agent.controller.action_dim) for _ in range(steps)]
    iterations = []
    begin = time.process_time()
    for action in actions:
        agent.set_action(action)
        scene.step()
        iterations.append(int(data.solver_niter[0]))
    elapsed = time.process_time() - begin
    step_time = data.timer[int(mujoco.mjtTimer.mjTIMER_STEP)].duration
    constraint_time = data.timer[int(mujoco.mjtTimer.mjTIMER_CONSTRAINT)].duration
    scene.close()
    return Folded(steps / elapsed, constraint_time / step_time, float(np.mean(iterations)))


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=["anymal_c"])
    parser.add_argument("--steps", type=int, default=200)
    args = parser.parse_args()
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(
        "| robot | contacts | creep 1-5 s standing (mm) | standing, legs moving: control steps/s | folded: control "
        "steps/s | folded: constraint stage share of mj_step | folded: Newton iterations |\n|---|---|---|---|---|---|---|"
    )
    for uid in args.uids:
        base = ra.get_agent(uid)
        runs = [(name, attributes, {}) for name, attributes in VARIANTS.items()]
        runs += [(name, {}, {"foot_condim": float(condim)}) for name, condim in FOOT_CONDIM_VARIANTS.items()]
        runs += [(name, {}, options) for name, options in SOLVER_VARIANTS.items()]
        for name, attributes, options in runs:
            cls = type(base.__name__, (base,), {"uid": "", **attributes})
            folded = folded_run(cls, args.steps, options)
            print(
                f"| `{uid}` | {name} | {1000 * creep(cls, options):.2f} | {standing_rate(cls, args.steps, options):.0f} "
                f"| {folded.rate:.0f} | "
                f"{folded.constraint_share:.2f} | {folded.iterations:.1f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
