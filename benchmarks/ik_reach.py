"""IK reach and Jacobians of the registered robots, checked against numbers
(docs/control-modes.md, "IK reach, measured").

IK: for each arm with end-effector modes, ``--count`` targets that are the tool's pose
(in the frame IK works in) at random arm configurations 5 % inside the joint limits
(seeded), solved with the arm's own end-effector IK settings (those of ``pd_ee_pose``,
else ``pd_ee_delta_pose``, else ``pd_ee_delta_pos``) from the robot's first keyframe:
with 10 iterations (a controller's budget per step), 100, and 100 with 20 random
restarts. Solved: within the settings' tolerances (1 mm, 1 deg; the position-only arms
1 mm). Then a target 5 m out of reach along x: the answer must be finite and failed.

Jacobians (``--jacobians``): ``Agent.frame_jacobian`` of every end effector, the last
two bodies and the last two sites of each robot, against central differences (1e-6) of
``Agent.frame_pose``, relative to the world, the root and a mid-chain body, in three
envs: one random configuration, one 1e-4 of the range inside every lower limit, one
inside every upper limit (unlimited joints: +-pi).

Usage: ``python benchmarks/ik_reach.py [--robots panda so100] [--count 20] [--jacobians]``
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import robot_agents as ra
from robot_agents.controllers import PDEEController
from robot_agents.kinematics import finite_difference_jacobian

#: A yawed, raised mount: root and world frames differ in the Jacobian check.
MOUNT = (0.3, -0.2, 0.5, math.cos(math.pi / 6), 0.0, 0.0, math.sin(math.pi / 6))


def ee_controller(agent: ra.Agent) -> PDEEController | None:
    for mode in ("pd_ee_pose", "pd_ee_delta_pose", "pd_ee_delta_pos"):
        if mode in agent.control.modes:
            for part in agent.controller_for(mode).parts.values():
                if isinstance(part, PDEEController):
                    return part
    return None


def ik_row(uid: str, count: int) -> str | None:
    scene = ra.Scene(uid)
    agent = scene.agents[0]
    scene.reset()
    controller = ee_controller(agent)
    if controller is None:
        scene.close()
        return None
    solver = controller.solver
    position_only = not controller.rotation and not controller.config.hold_orientation
    low = np.where(np.isfinite(solver.lower), solver.lower, -np.pi)
    high = np.where(np.isfinite(solver.upper), solver.upper, np.pi)
    rng = np.random.default_rng(0)
    context = np.repeat(scene.world.qpos, count, axis=0)
    configurations = context.copy()
    configurations[:, solver.qpos_adr] = rng.uniform(
        low + 0.05 * (high - low), high - 0.05 * (high - low), (count, solver.size)
    )
    for qpos_adr, _, column, offset, slope in solver._followers:  # Stretch's telescope
        configurations[:, qpos_adr] = offset + slope * configurations[:, solver.qpos_adr[column]]
    targets = agent.kinematics.pose(configurations, controller.ee_frame)
    seed = np.repeat(scene.world.qpos[:, solver.qpos_adr], count, axis=0)
    cells = []
    for iterations, restarts in ((10, 0), (100, 0), (100, 20)):
        result = solver.solve(context, targets, seed, position_only, iterations, restarts)
        inside = np.all((result.qpos >= solver.lower) & (result.qpos <= solver.upper))
        assert inside and np.all(np.isfinite(result.qpos)), uid
        cells.append(f"{int(result.success.sum())} / {count}")
    far = targets.copy()
    far[:, 0] += 5.0
    result = solver.solve(context, far, seed, position_only, 10)
    assert np.all(np.isfinite(result.qpos)) and not result.success.any(), uid
    kind = " (position)" if position_only or controller.solver.config.rotation_tolerance >= math.pi else ""
    scene.close()
    return f"| `{uid}`{kind} | {solver.size} | " + " | ".join(cells) + " |"


def numeric_jacobian(agent: ra.Agent, frame: str, qpos: np.ndarray, relative_to: str) -> np.ndarray:
    return finite_difference_jacobian(lambda q: agent.frame_pose(frame, q, relative_to=relative_to), qpos)


def jacobian_row(uid: str) -> str:
    scene = ra.Scene(uid, num_envs=3, robot_poses=[MOUNT])
    agent = scene.agents[0]
    scene.reset()
    model, prefix = scene.model, agent.prefix
    limits = agent.qpos_limits
    low = np.where(np.isfinite(limits[:, 0]), limits[:, 0], -np.pi)
    high = np.where(np.isfinite(limits[:, 1]), limits[:, 1], np.pi)
    rng = np.random.default_rng(0)
    qpos = np.stack([rng.uniform(low, high), low + 1e-4 * (high - low), high - 1e-4 * (high - low)])
    bodies = [
        model.body(b).name[len(prefix) :]
        for b in range(model.nbody)
        if model.body(b).name.startswith(prefix) and model.body(b).name
    ]
    sites = [model.site(s).name[len(prefix) :] for s in range(model.nsite) if model.site(s).name.startswith(prefix)]
    frames = [*agent.frames.end_effectors, *bodies[-2:], *sites[-2:]]
    references = ["world", "root", *([bodies[len(bodies) // 2]] if bodies else [])]
    worst = max(
        float(np.abs(agent.frame_jacobian(f, qpos, relative_to=r) - numeric_jacobian(agent, f, qpos, r)).max())
        for f in frames
        for r in references
    )
    scene.close()
    return f"| `{uid}` | {len(frames)} | {worst:.1e} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", nargs="*", default=None, help="registered uids (default: all)")
    parser.add_argument("--count", type=int, default=20, help="IK targets per arm")
    parser.add_argument("--jacobians", action="store_true", help="also check the Jacobians")
    args = parser.parse_args()
    uids = args.robots or list(ra.registry.list_agents())
    print(f"IK: {args.count} random reachable targets per arm, solved from the first keyframe")
    print("| arm | joints | 10 iterations | 100 | 100 + 20 restarts |")
    print("|---|---|---|---|---|")
    for uid in uids:
        row = ik_row(uid, args.count)
        if row is not None:
            print(row, flush=True)
    if args.jacobians:
        print("\nJacobians against central differences (largest difference)")
        print("| robot | frames | worst |")
        print("|---|---|---|")
        for uid in uids:
            print(jacobian_row(uid), flush=True)


if __name__ == "__main__":
    main()
