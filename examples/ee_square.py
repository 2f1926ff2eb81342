"""Trace a 10 cm square with the Panda's tool centre point in end-effector control.

Runs offline on the built-in model: ``python examples/ee_square.py``. Prints, per
side, how far the TCP moved (root frame, mm) and whether IK met its tolerance.
"""

from __future__ import annotations

import numpy as np

import robot_agents as ra


def main() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_ee_target_delta_pos", robot_init_qpos_noise=0.0)
    env.reset(seed=0)
    agent = env.unwrapped.agent
    # 5 mm per step (0.05 of the 10 cm bound) for 20 steps = 10 cm per side; the
    # gripper entry (last) keeps the fingers open.
    sides = {"+x": (1, 0), "+y": (0, 1), "-x": (-1, 0), "-y": (0, -1)}
    for name, (dx, dy) in sides.items():
        start = agent.frame_pose("panda_hand_tcp", relative_to="root")[0, :3]
        all_solved = True
        for _ in range(20):
            _, _, _, _, info = env.step(np.array([0.05 * dx, 0.05 * dy, 0.0, 1.0]))
            all_solved &= bool(info["ik_success"].all())
        for _ in range(5):  # let the arm settle on the corner
            env.step(np.array([0.0, 0.0, 0.0, 1.0]))
        moved = agent.frame_pose("panda_hand_tcp", relative_to="root")[0, :3] - start
        millimetres = ", ".join(f"{value:+.1f}" for value in 1000 * moved)
        print(f"side {name}: moved ({millimetres}) mm, IK solved every step: {all_solved}")
    env.close()


if __name__ == "__main__":
    main()
