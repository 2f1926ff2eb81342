"""xarm6_robotiq and xarm6_robotiq_wristcam checked against numbers: the 2F-85 composed
on the xArm6's flange grasps, lifts and holds a cube (contact forces carrying its
weight), IK reaches 100 random TCP poses, the gripper keeps one convention in every
control mode, and the wrist camera sits on UFactory's camera stand."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.kinematics.rotations import quat_to_matrix, relative_pose
from robot_agents.robots.robotiq.robotiq import CLOSED, SQUEEZE, TCP
from robot_agents.robots.ufactory.xarm6 import UFACTORY_STAND_CAMERA
from tests.ik_check import assert_ik_reaches_random_targets

UIDS = ("xarm6_robotiq", "xarm6_robotiq_wristcam")
CUBE_MASS, CUBE_HALF = 0.15, 0.02
GRIP_FORCE = (20.0, 235.0)  # the 2F-85 datasheet's grip force range (N)


def arm_solver(scene: ra.Scene) -> IKSolver:
    agent = scene.agents[0]
    arm = np.arange(6)
    frame = resolve_frame(scene.model, TCP, agent.prefix)
    return IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], agent.qpos_limits[arm])


def settle(scene: ra.Scene, action: np.ndarray, steps: int) -> None:
    for _ in range(steps):
        scene.agents[0].set_action(action)
        scene.step()


@pytest.mark.parametrize("uid", UIDS)
def test_grasps_lifts_and_holds_a_cube(uid: str) -> None:
    """A 4 cm, 150 g cube on the floor, grasped from above at the rest keyframe's tool
    orientation: lifted 10 cm and held 2 s, the pads' contact forces squeezing it within
    the datasheet's grip force and carrying its weight; not grasped once open."""
    cube = ra.Prop(name="cube", shape="box", size=(CUBE_HALF,) * 3, pos=(0.45, 0.05, CUBE_HALF + 1e-4), mass=CUBE_MASS)
    scene = ra.Scene(uid, props=[cube], control_modes="pd_joint_pos")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    down = agent.tcp_pose[0, 3:].copy()
    solver = arm_solver(scene)
    rest = agent.qpos[0, :6].copy()

    def arm_at(z: float, seed: np.ndarray) -> np.ndarray:
        target = np.r_[0.45, 0.05, z, down][None]
        result = solver.solve(scene.world.qpos, target, seed[None], max_iterations=200, restarts=10)
        assert result.success[0], (result.position_error, result.rotation_error)
        return result.qpos[0]

    above, grasp, lifted = arm_at(0.15, rest), arm_at(0.03, rest), arm_at(0.13, rest)
    for i in range(30):  # to 15 cm above the cube, then down, the gripper open
        settle(scene, np.r_[rest + min(1.0, (i + 1) / 20) * (above - rest), 1.0], 1)
    for i in range(30):
        settle(scene, np.r_[above + min(1.0, (i + 1) / 20) * (grasp - above), 1.0], 1)
    assert not agent.is_grasping("cube")[0]
    settle(scene, np.r_[grasp, -1.0], 20)
    assert agent.is_grasping("cube")[0]

    body = lambda name: mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_BODY, name)  # noqa: E731
    fingers = [[body(f"{agent.prefix}{side}_{link}") for link in ("follower", "pad")] for side in ("right", "left")]
    cube_z0 = scene.body_pose("cube")[0, 2]
    for i in range(60):  # lift 10 cm over 1 s, hold 2 s
        settle(scene, np.r_[grasp + min(1.0, (i + 1) / 20) * (lifted - grasp), -1.0], 1)
        if i >= 20:
            assert agent.is_grasping("cube")[0]
    assert scene.body_pose("cube")[0, 2] - cube_z0 > 0.095
    right, left = scene.world.contact_forces(fingers, body("cube"))[0]
    closing = quat_to_matrix(agent.tcp_pose[0, 3:])[:, 1]  # the fingers close along the TCP's y
    for force in (right, left):
        assert GRIP_FORCE[0] < abs(force @ closing) < GRIP_FORCE[1]
    assert abs((right + left) @ closing) < 0.5
    np.testing.assert_allclose((right + left)[2], CUBE_MASS * 9.81, rtol=0.05)  # the pads carry the weight
    settle(scene, np.r_[lifted, 1.0], 10)
    assert not agent.is_grasping("cube")[0]
    scene.close()


def test_ik_solves_100_random_reachable_targets() -> None:
    """Targets: the TCP pose at 100 random arm configurations within the joint limits
    (the gripper open); solutions within 1 mm and 1 deg, inside the limits."""
    scene = ra.Scene("xarm6_robotiq")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    assert_ik_reaches_random_targets(scene, agent.joint_names[:6], TCP, 100, seed=5)
    scene.close()


def test_the_gripper_keeps_one_convention_in_every_mode() -> None:
    """The gripper slice is the same absolute command in all 11 modes (the peer's
    pd_ee_delta_pose is absolute and its pd_ee_delta_pos a delta): held at 0 it goes to
    the middle of its commanded range (0 .. closed - squeeze) in both EE delta modes."""
    cls = ra.get_agent("xarm6_robotiq")
    reference = cls.mode_parts("pd_joint_pos")["gripper"]
    assert not reference.use_delta
    assert len(cls.modes()) == 11
    for mode in cls.modes():
        assert cls.mode_parts(mode)["gripper"] == reference, mode
    middle = (CLOSED + SQUEEZE) / 2
    for mode, arm_dim in (("pd_ee_delta_pos", 3), ("pd_ee_delta_pose", 6), ("pd_joint_delta_pos", 6)):
        scene = ra.Scene("xarm6_robotiq", control_modes=mode)
        agent = scene.agents[0]
        scene.reset(keyframes="rest")
        settle(scene, np.zeros(arm_dim + 1), 30)  # the arm holds, the gripper goes to 0
        drivers = agent.qpos[0, [6, 9]]
        np.testing.assert_allclose(drivers, middle, atol=0.01, err_msg=mode)
        settle(scene, np.zeros(arm_dim + 1), 10)  # repeating 0 is not "move further"
        np.testing.assert_allclose(agent.qpos[0, [6, 9]], drivers, atol=2e-3, err_msg=mode)
        scene.close()


def test_wrist_camera_sits_on_ufactorys_stand_and_sees_the_fingers() -> None:
    """camera_link where UFactory's realsense_d435i.urdf.xacro puts it on link_eef
    (xyz (0.06746, -0.0175, 0.0237), rpy (pi, -pi/2, 0)); the camera looks along the
    flange's +z with its image up along the flange's +x; the gripper's fingers are in
    the lower part of its image."""
    env = ra.make_env(
        "Empty-v1",
        robot_uids="xarm6_robotiq_wristcam",
        obs_mode="rgbd",
        sensor_configs={"hand_camera": {"width": 64, "height": 64}, "base_camera": None},
    ).unwrapped
    obs, _ = env.reset(seed=0)

    def matrix(name: str) -> np.ndarray:
        body = env.agent.index.body_id(name, "test")
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = env.data.xmat[body].reshape(3, 3), env.data.xpos[body]
        return pose

    flange = matrix("link_eef")
    camera_link = np.linalg.inv(flange) @ matrix("camera_link")
    rpy = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])  # Ry(-pi/2) Rx(pi)
    np.testing.assert_allclose(camera_link[:3, 3], [0.06746, -0.0175, 0.0237], atol=1e-9)
    np.testing.assert_allclose(camera_link[:3, :3], rpy, atol=1e-9)
    pose = obs["sensor_param"]["hand_camera"]["cam2world_gl"][0].astype(np.float64)
    np.testing.assert_allclose(pose[:3, 3], matrix("camera_link")[:3, 3], atol=1e-6)
    np.testing.assert_allclose(pose[:3, :3] @ [0, 0, -1], flange[:3, 2], atol=1e-6)
    np.testing.assert_allclose(pose[:3, :3] @ [0, 1, 0], flange[:3, 0], atol=1e-6)
    assert UFACTORY_STAND_CAMERA.mount == "camera_link"
    # Depth: the fingers (< 0.2 m away) fill part of the lower image rows only; the
    # floor beyond them (the camera ~0.19 m up at rest, looking down) is farther away.
    depth = obs["sensor_data"]["hand_camera"]["depth"][0, ..., 0].astype(np.float64)
    near = depth < 0.17
    assert near[48:].mean() > 0.05 and near[:16].mean() == 0.0
    env.close()


@pytest.mark.parametrize("uid", ["xarm6_robotiq", "xarm6_robotiq_wristcam"])
def test_pd_ee_pose_bounds_cover_every_reachable_tcp_position(uid: str) -> None:
    """The absolute end-effector mode's position bounds are the flange's box grown by the
    Robotiq's length: the TCP of 2000 random arm configurations lies inside them (before,
    the flange's box clipped 3 % of them, out to 0.88 m and up to 1.16 m), and a command
    at the far edge of the reach is taken as it is."""
    scene = ra.Scene(uid, control_modes="pd_ee_pose")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    low, high = agent.single_action_space.low[:3], agent.single_action_space.high[:3]
    arm = np.arange(6)
    rng = np.random.default_rng(0)
    limits = agent.qpos_limits[arm]
    configurations = np.repeat(scene.world.qpos, 2000, axis=0)
    configurations[:, agent.qpos_adr[arm]] = rng.uniform(limits[:, 0], limits[:, 1], (2000, 6))
    tcp = agent.kinematics.pose(configurations, agent.frames.end_effector("tcp", "test"))
    points = relative_pose(tcp, agent.kinematics.pose(configurations, agent.root_frame))[:, :3]
    assert np.all((points >= low) & (points <= high))
    far = points[np.argmax(points[:, 0])]
    assert far[0] > 0.85
    action = np.concatenate([far, np.zeros(agent.single_action_space.shape[0] - 3)])
    agent.set_action(action)
    scene.step()
    controller = next(c for c in agent.controller.parts.values() if hasattr(c, "target_pose"))
    np.testing.assert_array_equal(controller.target_pose[0, :3], far)
    scene.close()
