"""A pad pressed on a fixed block, traced at every physics step: why a pad chatters.

The press of tests/test_pad_press.py (the same block, joint and target; the action held
from the keyframe for ``--seconds``), stepped with the control rate equal to the physics
rate (the action is constant, so the physics is the test's), with the pads' contact
optionally replaced in the compiled model: ``--solref TIMECONST DAMPRATIO`` and
``--solimp DMIN DMAX WIDTH`` go to every near-rigid pad geom of the robot
(``near_rigid_pads``). Printed: a summary of the last second (the block's normal force,
N; the pressed pad's distance to the block, µm, negative inside, at the steps with a
contact; the physics steps without one) and, with ``--trace FROM TO`` (s), every physics
step in that window: the force, the distance and its change since the step before. The
force is that of the contacts MuJoCo found at the step's start, the distance the pad's
after it (``mj_step`` detects collisions before it integrates): a distance above zero
is a contact the next step will not find.

Usage: ``python benchmarks/pad_press_trace.py stretch [--sim-freq 200] [--solref 0.01 1]
[--solimp 0.9999 0.9999 0.01] [--trace 2.0 2.1]``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests.test_pad_press import CASES, SECONDS, action_for, block_at_contact, near_rigid_pads

import robot_agents as ra


def press_trace(
    uid: str, sim_freq: int, solref: list[float] | None, solimp: list[float] | None, seconds: float
) -> tuple[np.ndarray, np.ndarray]:
    """Per physics step: the block's total normal force (N) and the pressed pad's signed
    distance to the block (m; ``mj_geomDistance``, the nearest of the pad body's
    near-rigid geoms, looked for up to 1 cm), each of shape (steps,)."""
    prop, joint, target = block_at_contact(uid)
    scene = ra.Scene(
        ra.get_agent(uid), props=[prop], control_modes="pd_joint_pos", sim_freq=sim_freq, control_freq=sim_freq
    )
    scene.reset(keyframes=CASES[uid][1])
    agent, model, data = scene.agents[0], scene.model, scene.world.datas[0]
    pads = near_rigid_pads(model)
    for geom in pads:
        if solref is not None:
            model.geom_solref[geom] = solref
        if solimp is not None:
            model.geom_solimp[geom][:3] = solimp
    body = model.body(agent.prefix + CASES[uid][0]).id
    pressed = [g for g in pads if model.geom_bodyid[g] == body]
    block, block_geom = model.body("block").id, model.geom("block").id
    action = action_for(agent, model, {joint: target})
    wrench = np.zeros(6)
    forces, distances = [], []
    for _ in range(round(seconds * sim_freq)):
        agent.set_action(action)
        scene.step()
        force = 0.0
        for i in range(data.ncon):
            contact = data.contact[i]
            if block in (model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]):
                mujoco.mj_contactForce(model, data, i, wrench)
                force += wrench[0]
        forces.append(force)
        distances.append(min(mujoco.mj_geomDistance(model, data, g, block_geom, 0.01, None) for g in pressed))
    scene.close()
    return np.array(forces), np.array(distances)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robot", choices=sorted(CASES))
    parser.add_argument("--sim-freq", type=int, default=None, help="physics Hz (default: the robot's declared step)")
    parser.add_argument("--solref", type=float, nargs=2, metavar=("TIMECONST", "DAMPRATIO"))
    parser.add_argument("--solimp", type=float, nargs=3, metavar=("DMIN", "DMAX", "WIDTH"))
    parser.add_argument("--seconds", type=float, default=SECONDS)
    parser.add_argument(
        "--trace", type=float, nargs=2, metavar=("FROM", "TO"), help="print every step in this window (s)"
    )
    args = parser.parse_args()
    sim_freq = args.sim_freq or ra.get_agent(args.robot).sim_freq or 200
    forces, distances = press_trace(args.robot, sim_freq, args.solref, args.solimp, args.seconds)
    last = slice(len(forces) - sim_freq, None)
    touching = forces[last] > 0.0
    inside = distances[last][touching] * 1e6
    print(
        f"{args.robot} at {sim_freq} Hz, solref {args.solref or 'as declared'}, solimp {args.solimp or 'as declared'}; "
        f"last second: {forces[last].min():.2f}-{forces[last].max():.2f} N, "
        f"in contact {inside.min() if inside.size else float('nan'):.3f} .. {inside.max() if inside.size else float('nan'):.3f} um, "
        f"{int((~touching).sum())} of {sim_freq} steps without contact"
    )
    if args.trace:
        print("| t (s) | force (N) | distance (um) | change (um) |")
        print("|---|---|---|---|")
        for step in range(len(forces)):
            t = (step + 1) / sim_freq
            if args.trace[0] <= t <= args.trace[1]:
                change = (distances[step] - distances[step - 1]) * 1e6 if step else 0.0
                print(f"| {t:.3f} | {forces[step]:.3f} | {distances[step] * 1e6:.4f} | {change:.4f} |")


if __name__ == "__main__":
    main()
