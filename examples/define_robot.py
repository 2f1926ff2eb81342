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
    actuators = (  # the drives, declared once: PD servos with the motors' torque limits
        ra.PDActuator(joints="joint_[ab]", stiffness=300.0, damping=30.0, effort_limit=(50.0, 20.0)),
    )
    parts = (  # what the joints are for; control modes are generated from the parts
        ra.Arm(name="arm", joints="joint_[ab]", end_effectors=(ra.EndEffector("tool"),)),
    )
    keyframes = {
        "home": ra.Keyframe(qpos={"joint_a": 0.0, "joint_b": 0.5}),
        "up": ra.Keyframe(qpos={"joint_.": 0.0}),
    }
    default_control_mode = "pd_joint_delta_pos"


if __name__ == "__main__":
    env = ra.make_env("Empty-v1", robot_uids="two_link_arm")
    obs, info = env.reset(seed=0)
    for _ in range(20):
        obs, reward, terminated, truncated, info = env.step(np.array([1.0, -0.5]))  # normalized deltas
    agent = env.unwrapped.agent
    print("qpos", agent.qpos[0].round(3), "tool at", agent.tcp_pose[0, :3].round(3))
