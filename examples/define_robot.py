"""Define a new robot from a URDF in ~20 lines, register it, and drive it in an env."""

from pathlib import Path

import numpy as np

import robot_agents as ra

HERE = Path(__file__).parent


@ra.register_agent()
class TwoLinkArm(ra.Agent):
    uid = "two_link_arm"
    urdf_path = HERE / "two_link_arm.urdf"
    fix_root_link = True  # bolted to the world; gravity compensation is on by default
    keyframes = {"home": ra.Keyframe(qpos=(0.0, 0.5)), "up": ra.Keyframe(qpos=(0.0, 0.0))}
    control_modes = ra.joint_control_modes(
        ra.JointGroup(
            joint_names=("joint_a", "joint_b"),
            stiffness=300.0,  # N*m/rad
            damping=30.0,  # N*m*s/rad
            force_limit=(50.0, 20.0),  # N*m, from the motor datasheet
        )
    )
    tcp_link = "tool"


if __name__ == "__main__":
    env = ra.make_env("Empty-v1", robot_uids="two_link_arm", control_mode="pd_joint_delta_pos")
    obs, info = env.reset(seed=0)
    for _ in range(20):
        obs, reward, terminated, truncated, info = env.step(np.array([1.0, -0.5]))  # normalized deltas
    agent = env.unwrapped.agent
    print("qpos", agent.qpos[0].round(3), "tool at", agent.tcp_pose[0, :3].round(3))
