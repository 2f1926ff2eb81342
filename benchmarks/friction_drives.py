"""Derived drives against a model file's dry friction (``frictionloss``): how far short of
its target each frictional joint stops, with plain inertia gains and with the friction
floor (:func:`robot_agents.actuators.gains.friction_gains`).

For a model file defined with the two-line robot (``--floating`` for a free root), each
driven joint with friction is listed with its friction (N*m or N), the inertia gains'
``kp`` and the derived ``kp``, and ``friction / kp`` for both (the error at which the
drive's pull equals the friction). Then, per variant (the floor switched off, and on),
from the default keyframe in ``pd_joint_pos``
every frictional joint is commanded 90 % of the way to the farther end of its range at
once (the others hold): the time until each is within 0.01 rad (m) of its target (``-`` if never within
``--seconds``), and its error at the end.

Usage: ``python benchmarks/friction_drives.py MODEL_FILE [--floating] [--seconds 3]``.
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

import robot_agents as ra
from robot_agents.actuators.gains import gains_from_inertia
from robot_agents.agent import declaration


def robot(path: Path, floating: bool, uid: str) -> type[ra.Agent]:
    attrs: dict[str, object] = {"uid": uid, "mjcf_path" if path.suffix == ".xml" else "urdf_path": path}
    if floating:
        attrs["fix_root_link"] = False
    return type("FrictionRobot", (ra.Agent,), attrs)


def step_response(cls: type[ra.Agent], joints: list[str], seconds: float) -> dict[str, tuple[float, float]]:
    """joint -> (seconds until within 0.01 of the target or nan, final error)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        scene = ra.Scene(cls, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    names = agent.joint_names
    start = agent.qpos[0].copy()
    targets = {}
    for joint in joints:  # 90 % of the way to the farther end of the range
        low, high = (float(v) for v in scene.model.jnt_range[agent.index.joint(joint, "friction_drives").id])
        here = float(start[names.index(joint)])
        end = high if high - here > here - low else low
        targets[joint] = here + 0.9 * (end - here)
    parts = []
    for controller in agent.controller.parts.values():
        raw = np.array([targets.get(j, start[names.index(j)]) for j in controller.config.joint_names])
        raw = raw[: controller.action_dim]
        parts.append(controller.from_raw(raw) if controller.config.normalize_action else raw)
    action = np.concatenate(parts)
    reached = dict.fromkeys(joints, math.nan)
    for step in range(round(seconds * scene.control_freq)):
        agent.set_action(action)
        scene.step()
        for joint in joints:
            if math.isnan(reached[joint]) and abs(agent.qpos[0, names.index(joint)] - targets[joint]) < 0.01:
                reached[joint] = (step + 1) / scene.control_freq
    out = {j: (reached[j], abs(float(agent.qpos[0, names.index(j)]) - targets[j])) for j in joints}
    scene.close()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("model", type=Path)
    parser.add_argument("--floating", action="store_true")
    parser.add_argument("--seconds", type=float, default=3.0)
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cls = robot(args.model.resolve(), args.floating, "friction_floor_on")
        checked = cls.check()
    model = checked.index.model
    derived = checked.derived_gains or {}
    frictional = [j for j in derived if model.dof_frictionloss[model.joint(j).dofadr[0]] > 0]
    if not frictional:
        print(f"{args.model.name}: no derived drive on a joint with frictionloss")
        return
    full = model.qpos0.copy()
    full[checked.index.qpos_adr] = next(iter(checked.keyframes.values())).qpos
    plain = gains_from_inertia(model, frictional, full).as_dict()
    print(f"{args.model.name}: {len(frictional)} frictional joint(s) of {len(derived)} driven\n")
    print("| joint | friction | kp inertia | friction / kp | kp derived | friction / kp |")
    print("|---|---|---|---|---|---|")
    for joint in frictional:
        friction = float(model.dof_frictionloss[model.joint(joint).dofadr[0]])
        kp_plain, kp = plain[joint][0], derived[joint][0]
        print(
            f"| `{joint}` | {friction:.3g} | {kp_plain:.3g} | {friction / kp_plain:.4f} | {kp:.3g} | {friction / kp:.4f} |"
        )
    original = declaration.friction_gains
    try:
        declaration.friction_gains = lambda gains, timestep: (gains, ())  # the floor off
        without = step_response(
            robot(args.model.resolve(), args.floating, "friction_floor_off"), frictional, args.seconds
        )
    finally:
        declaration.friction_gains = original
    with_floor = step_response(cls, frictional, args.seconds)
    print(f"\nStep towards the range end in pd_joint_pos, {args.seconds:g} s: time to within 0.01 / error at the end")
    print("| joint | inertia gains | derived gains |")
    print("|---|---|---|")
    for joint in frictional:
        cells = [f"{'-' if math.isnan(t) else f'{t:.2f} s'} / {e:.4f}" for t, e in (without[joint], with_floor[joint])]
        print(f"| `{joint}` | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
