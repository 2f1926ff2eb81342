"""Joint speeds that position modes command against the drives' rated speeds
(``velocity_limit``): the table in docs/control-modes.md ("Rated speed").

    python benchmarks/rated_speed.py                    # every robot with pd_joint_delta_pos
    python benchmarks/rated_speed.py panda ur_10e --bridge

Per robot (its main part, the first of the mode's parts): the largest
``pd_joint_delta_pos`` step per control period against the rated speed, and the peak
joint speed in ``pd_joint_pos`` over 20 steps after a jump of every joint halfway from
the first keyframe to the far end of its action range, against the rated speed. With
``--bridge``, the same jump through ``RealRobot`` on a ``SimulatedBus`` with
``max_target_step`` = rated speed x control period (inf where none is rated): its peak
and the steps until every joint is within 0.01 of the target (the bus's 20 Hz).
"""

from __future__ import annotations

import argparse

import numpy as np

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.real import RealRobot, SimulatedBus
from robot_agents.sim.scene import Scene


def jump(agent: ra.Agent) -> tuple[np.ndarray, np.ndarray]:
    """The hold action with the main part's joints sent halfway to the far end of their
    action range, and the main part's raw targets."""
    part = next(iter(agent.controller.parts))
    main = agent.controller.parts[part]
    start = agent.qpos[0, [list(agent.index.qpos_adr).index(a) for a in main.binding.qpos_adr]]
    far = np.where(main.raw_high - start > start - main.raw_low, main.raw_high, main.raw_low)
    target = start + 0.5 * (far - start)
    action = hold_action(agent)
    action[agent.controller.slices[part]] = main.from_raw(target[None])[0]
    return action, target


def simulated(uid: str) -> str:
    scene = Scene(uid, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent, dt = scene.agents[0], scene.control_timestep
    main = next(iter(agent.controller.parts.values()))
    names = main.binding.joint_names
    rated = agent.drives.velocity_limit[main.binding.columns]
    if not np.all(np.isfinite(rated)):
        scene.close()
        return f"| `{uid}` | no rated speed on {[n for n, r in zip(names, rated, strict=True) if not np.isfinite(r)]} | | |"
    delta = main.raw_high / dt / rated
    agent.set_control_mode("pd_joint_pos")
    main = next(iter(agent.controller.parts.values()))
    action, _ = jump(agent)
    peak = np.zeros(len(names))
    for _ in range(20):
        agent.set_action(action)
        scene.step()
        peak = np.maximum(peak, np.abs(agent.world.qvel[0, main.binding.dof_adr]))
    scene.close()
    worst = int(np.argmax(peak / rated))
    return (
        f"| `{uid}` | {delta.max():.2f} (`{names[int(np.argmax(delta))]}`) | {peak[worst] / rated[worst]:.2f} "
        f"(`{names[worst]}`: {peak[worst]:.1f} rad/s, rated {rated[worst]:.2f}) |"
    )


def bridged(uid: str) -> str:
    bus = SimulatedBus(uid)
    rated = bus.agent.drives.velocity_limit
    robot = RealRobot(uid, bus, control_mode="pd_joint_pos", max_target_step=rated * bus.scene.control_timestep)
    action, target = jump(robot.agent)
    columns = next(iter(robot.agent.controller.parts.values())).binding.columns
    order = [list(bus.joint_names).index(robot.agent.drives.joint_names[c]) for c in columns]
    peak, reached = np.zeros(len(rated)), 0
    for step in range(1, 201):
        robot.step(action)
        position, velocity = bus.read()
        peak = np.maximum(peak, np.abs(velocity))
        if np.max(np.abs(position[order] - target)) < 0.01:
            reached = step
            break
    robot.close()
    rated_joints = np.isfinite(rated)
    return (
        f"| `{uid}` | {np.max(peak[rated_joints] / rated[rated_joints]):.2f} | "
        f"{reached if reached else 'not within 200'} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("robots", nargs="*", help="robot uids (default: every robot with pd_joint_delta_pos)")
    parser.add_argument("--bridge", action="store_true", help="also the jump through the bridge, bounded")
    args = parser.parse_args()
    robots = args.robots or [uid for uid in ra.list_agents() if "pd_joint_delta_pos" in ra.get_agent(uid).modes()]
    print("| robot | `pd_joint_delta_pos` step / rated (largest) | `pd_joint_pos` jump: peak / rated |")
    print("|---|---|---|")
    for uid in robots:
        print(simulated(uid), flush=True)
    if args.bridge:
        print("\n| robot (bridge, max_target_step = rated x period) | peak / rated | steps to the target |")
        print("|---|---|---|")
        for uid in robots:
            cls = ra.get_agent(uid)
            declared = cls.check()
            in_scope = cls.fix_root_link and not any(isinstance(p, ra.Base) for p in declared.parts)  # the bridge's
            if in_scope and any(np.isfinite(d.velocity_limit) for d in declared.drives):
                print(bridged(uid), flush=True)


if __name__ == "__main__":
    main()
