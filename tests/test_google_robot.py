"""The Google Robot checked against numbers: forward kinematics against the URDF's joint
origins chained independently, grasp + lift + hold with contact forces, gripper states,
IK accuracy, the head camera on its link, and base odometry."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.envs.tasks.layout import table_top_layout
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.robots.google_robot.google_robot import GoogleRobot
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.cycles import drive_cycle_bounds
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import (
    ChainJoint,
    assert_camera_on_frame,
    assert_pan_turns_the_view,
    axis_rotation,
    chain,
    index,
    transform,
)
from tests.grasp_check import assert_grasps_lifts_and_holds
from tests.ik_check import assert_ik_reaches_random_targets

ARM = (
    "joint_torso",
    "joint_shoulder",
    "joint_bicep",
    "joint_elbow",
    "joint_forearm",
    "joint_wrist",
    "joint_gripper",
)
X, Y, Z = np.eye(3)
# ManiSkill2_real2sim google_robot_meta_sim_fix_fingertip.urdf: joint origins (in the
# parent link) and axes, from link_base (0.06205 m above the floor) to link_gripper; then
# its gripper_tcp_joint to link_gripper_tcp (xyz, and rpy as URDF's fixed-axis roll,
# pitch, yaw); the head chain to link_camera.
ARM_ORIGINS = [
    ((0.0, 0.0, 0.5945), Z),
    ((0.0, -0.16728852885, 0.113), Y),
    ((0.0, 0.002289, 0.21502852885), Z),
    ((0.0, -0.064, 0.1849715), Y),
    ((0.0, -0.101, 0.0915), Z),
    ((0.0, -0.00604, 0.2735), Y),
    ((0.0, 0.0060384, 0.10911), Z),
]
TCP = (4.3374896e-03, 1.8852949e-03, 1.6353297e-01)
TCP_RPY = (-0.001328879239766479, -0.00443973089771006, -0.0008686511567993004)
TCP_ROTATION = axis_rotation(Z, TCP_RPY[2]) @ axis_rotation(Y, TCP_RPY[1]) @ axis_rotation(X, TCP_RPY[0])
HEAD_ORIGINS = [((0.0, 0.0, 1.16902), Z), ((0.07181, 0.0, 0.11848), Y)]
CAMERA_MOUNT = (0.10488, 0.0, 0.0)
BASE_HEIGHT = 0.06205


def base_chain(base: np.ndarray, joints: list[ChainJoint], q: np.ndarray) -> np.ndarray:
    """link_base pose (x, y, yaw) through the joints' origins and axes."""
    pose = transform(axis_rotation(Z, base[2]), np.array([base[0], base[1], BASE_HEIGHT]))
    return chain(pose, joints, q)


def test_forward_kinematics_match_the_urdf_joint_origins() -> None:
    scene = ra.Scene("google_robot")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    base = index(agent, ["root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint"])
    arm = index(agent, ARM)
    frame = resolve_frame(scene.model, "link_gripper_tcp", agent.prefix)
    rng = np.random.default_rng(0)
    limits = agent.qpos_limits.copy()
    limits = np.where(np.isfinite(limits), limits, np.sign(limits) * math.pi)  # the wheels turn freely
    limits[base] = [[-2.0, 2.0], [-2.0, 2.0], [-math.pi, math.pi]]
    q = rng.uniform(limits[:, 0], limits[:, 1], (20, len(agent.joint_names)))
    configurations = np.repeat(scene.world.qpos, 20, axis=0)
    configurations[:, agent.qpos_adr] = q
    poses = agent.kinematics.pose(configurations, frame)
    for i in range(20):
        expected = base_chain(q[i, base], ARM_ORIGINS, q[i, arm]) @ transform(TCP_ROTATION, np.array(TCP))
        np.testing.assert_allclose(poses[i, :3], expected[:3, 3], atol=1e-6)
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, poses[i, 3:])
        np.testing.assert_allclose(rotation.reshape(3, 3), expected[:3, :3], atol=1e-6)
    scene.close()


def test_limits_masses_and_drives_from_the_data() -> None:
    scene = ra.Scene("google_robot")
    agent = scene.agents[0]
    limits = agent.qpos_limits[index(agent, ARM)]
    np.testing.assert_allclose(
        limits,
        [[-4.49, 1.35], [-2.66, 3.18], [-2.13, 3.71], [-2.05, 3.79], [-2.92, 2.92], [-1.79, 1.79], [-4.49, 1.35]],
    )
    np.testing.assert_allclose(
        agent.qpos_limits[index(agent, ["joint_head_pan", "joint_head_tilt"])], [[-3.79, 2.22], [-1.17, 1.17]]
    )
    model = scene.model
    masses = [model.body_mass[model.body(agent.prefix + n.replace("joint_", "link_")).id] for n in ARM]
    np.testing.assert_allclose(masses, [2.46883, 2.08054, 1.3989, 0.788999, 0.819369, 0.543658, 0.41474], rtol=1e-5)
    assert model.body_mass[model.body(agent.prefix + "link_base").id] == pytest.approx(52.9101, rel=1e-5)
    scene.close()


# ManiSkill2_real2sim ``GoogleRobotDefaultConfig`` at ef7a4d4f ("force" drive mode, the
# config of google_robot_static): arm stiffness (N*m/rad), damping (N*m*s/rad) and force
# limits (N*m), torso .. gripper joint.
SIMPLER_ENV_STIFFNESS = (
    1700.0,
    1737.0471680861954,
    979.975871856535,
    930.0,
    1212.154500274304,
    432.96500923932535,
    468.0013365498738,
)
SIMPLER_ENV_DAMPING = (
    1059.9791902443303,
    1010.4720585373592,
    767.2803161582076,
    680.0,
    674.9946964336588,
    274.613381336198,
    340.532560578637,
)
SIMPLER_ENV_FORCE_LIMIT = (300.0, 300.0, 100.0, 100.0, 100.0, 100.0, 100.0)


def test_arm_drives_are_simplerenvs_with_a_seventh_of_its_damping() -> None:
    """The built arm drives carry SimplerEnv's stiffness and force limits and a seventh
    of its damping; a seventh is the largest 1/n at which no drive of the robot can
    cycle between its torque limits at the default step (a sixth lets the forearm and
    the bicep, ``robot_agents.tuning.cycles``)."""
    bounds = {b.joint: b for b in drive_cycle_bounds("google_robot")}
    for joint, kp, kv, limit in zip(
        ARM, SIMPLER_ENV_STIFFNESS, SIMPLER_ENV_DAMPING, SIMPLER_ENV_FORCE_LIMIT, strict=True
    ):
        assert bounds[joint].stiffness == pytest.approx(kp, rel=1e-12)
        assert bounds[joint].damping == pytest.approx(kv / 7.0, rel=1e-12)
        assert bounds[joint].effort_limit == limit
    rate = GoogleRobot.sim_freq
    assert rate == 500
    assert max(b.cycle_free_above for b in bounds.values()) < rate  # the forearm's: 465 Hz
    sixth = [dataclasses.replace(bounds[j], damping=bounds[j].damping * 7.0 / 6.0) for j in ARM]
    assert sorted(b.joint for b in sixth if b.cycle_free_above >= rate) == ["joint_bicep", "joint_forearm"]


def run_on_after_a_stop(cls: type[ra.Agent]) -> tuple[float, float]:
    """``pd_ee_delta_pose`` from ``rest``: 10 steps of +x at half the 5 cm bound, then
    zero commands for 2 s. Returns how far the tool travels in those 2 s (m) and the
    fastest arm joint at their end (rad/s)."""
    scene = ra.Scene(cls, control_modes="pd_ee_delta_pose")
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    arm = index(agent, ARM)
    for step in range(10 + 2 * scene.control_freq):
        action = hold_action(agent)
        action[0] = 0.5 if step < 10 else 0.0
        agent.set_action(action)
        scene.step()
        if step == 9:
            stopped = agent.tcp_pose[0, :3].copy()
    travel = float(np.linalg.norm(agent.tcp_pose[0, :3] - stopped))
    speed = float(np.abs(agent.qvel[0, arm]).max())
    scene.close()
    return travel, speed


def test_simplerenvs_full_damping_leaves_the_arm_running_after_a_stop() -> None:
    """With a seventh of SimplerEnv's damping the tool, which lags the command, comes to
    rest 4.5 mm on; with the full damping (every arm drive able to cycle at 2 ms) it runs
    on 200 mm in 2 s with joints at 1.4 rad/s (measured 2026-11-29)."""
    travel, speed = run_on_after_a_stop(GoogleRobot)
    assert travel < 0.01 and speed < 1e-6, (travel, speed)
    drives = tuple(
        dataclasses.replace(d, damping=SIMPLER_ENV_DAMPING) if d.joints == GoogleRobot.actuators[1].joints else d
        for d in GoogleRobot.actuators
    )
    full = type("GoogleRobotFullDamping", (GoogleRobot,), {"uid": "", "actuators": drives})
    travel, speed = run_on_after_a_stop(full)
    assert travel > 0.1 and speed > 0.5, (travel, speed)


# ---------------------------------------------------------------- IK
def arm_solver(scene: ra.Scene, frame_name: str = "link_gripper_tcp") -> IKSolver:
    agent = scene.agents[0]
    arm = np.array(index(agent, ARM))
    frame = resolve_frame(scene.model, frame_name, agent.prefix)
    return IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], agent.qpos_limits[arm])


def test_ik_reaches_50_random_reachable_targets() -> None:
    """Targets are FK of random arm configurations, the base turned and moved; IK starts
    at ``rest`` and lands within 1 mm and 1 deg."""
    scene = ra.Scene("google_robot")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    agent.set_base_pose(xy=[0.3, -0.2], yaw=0.7)
    assert_ik_reaches_random_targets(scene, ARM, "link_gripper_tcp", 50, seed=2)
    scene.close()


# ---------------------------------------------------------------- gripper
def test_gripper_open_closed_and_half() -> None:
    scene = ra.Scene("google_robot")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    fingers = index(agent, ["joint_finger_right", "joint_finger_left"])
    assert agent.is_gripper_open()[0] and not agent.is_gripper_closed()[0]
    for value, is_open, is_closed in ((1.3, False, True), (0.65, False, False), (0.0, True, False)):
        q = agent.qpos[0].copy()
        q[fingers] = value
        agent.reset(qpos=q)
        assert bool(agent.is_gripper_open()[0]) is is_open and bool(agent.is_gripper_closed()[0]) is is_closed
    scene.close()


#: A 4 cm, 100 g cube on a pedestal in front of the robot, grasped from above with the
#: gripper's grasp frame (``link_gripper_grasp``, 19.6 mm short of the URDF's TCP, which
#: lies near the fingertips' ends) at its centre.
DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # tool z along world -z
CUBE_MASS, CUBE_HALF = 0.1, 0.02
GRASP = (0.6, -0.2, 0.45)
GRASP_FRAME = "link_gripper_grasp"


def solve_down(scene: ra.Scene, position: tuple[float, float, float], seed: np.ndarray) -> np.ndarray:
    target = np.concatenate([position, DOWN])[None]
    solver = arm_solver(scene, GRASP_FRAME)
    result = solver.solve(scene.world.qpos, target, seed[None], max_iterations=200, restarts=10)
    assert result.success[0], (result.position_error, result.rotation_error)
    return result.qpos[0]


def test_gripper_grasps_lifts_and_holds_a_cube() -> None:
    cube_z = GRASP[2]
    props = [
        ra.Prop(
            name="pedestal",
            shape="box",
            size=(0.012, 0.012, (cube_z - CUBE_HALF) / 2),
            pos=(GRASP[0], GRASP[1], (cube_z - CUBE_HALF) / 2),
            mass=None,
        ),
        ra.Prop(
            name="cube", shape="box", size=(CUBE_HALF,) * 3, pos=(GRASP[0], GRASP[1], cube_z + 1e-4), mass=CUBE_MASS
        ),
    ]
    scene = ra.Scene("google_robot", props=props, control_modes="pd_joint_pos")
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    arm = index(agent, ARM)
    grasp = solve_down(scene, GRASP, agent.qpos[0, arm])
    lift = solve_down(scene, (GRASP[0], GRASP[1], GRASP[2] + 0.1), grasp)
    qpos = agent.qpos[0].copy()
    qpos[arm] = grasp
    agent.reset(qpos=qpos)  # fingers open around the cube
    head = agent.qpos[0, index(agent, ["joint_head_pan", "joint_head_tilt"])]

    def act(arm_target: np.ndarray, gripper: float) -> None:
        agent.set_action(np.concatenate([arm_target, [gripper], head, [0.0, 0.0]]))
        scene.step()

    # -1 closes (1.3 rad), +1 opens (0 rad), as every built-in gripper (ManiSkill's Google
    # Robot has the opposite sign).
    fingers = [
        [agent.prefix + "link_finger_right", agent.prefix + "link_finger_tip_right"],
        [agent.prefix + "link_finger_left", agent.prefix + "link_finger_tip_left"],
    ]
    assert_grasps_lifts_and_holds(scene, act, grasp, lift, fingers, CUBE_MASS, min_force=1.0, held_at=GRASP_FRAME)
    scene.close()


# ---------------------------------------------------------------- head camera
def test_head_camera_follows_its_link_and_pans() -> None:
    """The camera sits on link_camera (chained from the URDF's head joints), looks along
    the tilt link's x with z up, and turns with head pan."""
    scene = ra.Scene("google_robot")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    camera = scene.model.camera(agent.prefix + "overhead_camera").id
    base = index(agent, ["root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint"])
    head = index(agent, ["joint_head_pan", "joint_head_tilt"])
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = agent.qpos[0].copy()
        q[base] = rng.uniform([-1.0, -1.0, -math.pi], [1.0, 1.0, math.pi])
        q[head] = rng.uniform(agent.qpos_limits[head, 0], agent.qpos_limits[head, 1])
        agent.reset(qpos=q)
        tilt = base_chain(q[base], HEAD_ORIGINS, q[head])
        mount = tilt @ transform(np.eye(3), np.array(CAMERA_MOUNT))
        assert_camera_on_frame(scene.world.camera_poses(camera)[0], mount)
    assert_pan_turns_the_view(scene, camera, base, head)  # about world z by the pan angle
    scene.close()


# ---------------------------------------------------------------- base
def test_differential_base_odometry() -> None:
    """pd_base_forward_vel: 0.2 m/s for 2 s travels 0.4 m (+-5 %) along the robot's
    heading; 0.5 rad/s for 2 s turns 1 rad (+-5 %); the arm holds meanwhile."""
    scene = ra.Scene("google_robot", control_modes="pd_joint_delta_pos")
    agent = scene.agents[0]
    assert agent.controller.slices["base"] == slice(10, 12)
    scene.reset(keyframes="rest")
    agent.set_base_pose(xy=[0.0, 0.0], yaw=math.pi / 2)
    for _ in range(2 * scene.control_freq):
        action = hold_action(agent)
        action[..., 10:12] = [0.4, 0.0]  # 0.4 of 0.5 m/s
        agent.set_action(action)
        scene.step()
    assert agent.base_pos[0, 1] == pytest.approx(0.4, rel=0.05) and abs(agent.base_pos[0, 0]) < 0.01
    for _ in range(2 * scene.control_freq):
        action = hold_action(agent)
        action[..., 10:12] = [0.0, 0.5]
        agent.set_action(action)
        scene.step()
    assert agent.base_rot[0] - math.pi / 2 == pytest.approx(1.0, rel=0.05)
    scene.close()


# ---------------------------------------------------------------- grasp frame
def test_layout_measures_the_gripper_at_its_grasp_frame() -> None:
    """The URDF's TCP lies near the fingertips' ends, where the open fingers are 19 cm
    apart: the layout measures the gripper at ``link_gripper_grasp`` instead (its grasp
    point is that frame's position in the TCP's frame, its cube half the opening
    there: 77.9 mm), and the sweep's grasp claim holds at the default step. Measured at
    the TCP (the same robot without ``grasp_frame``), the cube is 95.8 mm: wider than
    the fingertips, 75.2 mm apart where they stand parallel, so the fingers close on it
    at their knuckles, and the claim fails (7.4 mm at 500 Hz: the cube swings on the
    knuckles' edges; 0.21 mm at the grasp frame; 2026-11-29, SimplerEnv's current arm
    gains)."""
    layout = table_top_layout(GoogleRobot)
    assert layout.gripper is not None
    scene = ra.Scene("google_robot")
    scene.reset(keyframes="rest")
    grasp_in_tcp = scene.agents[0].frame_pose(GRASP_FRAME, relative_to="tcp")[0, :3]
    scene.close()
    np.testing.assert_allclose(layout.gripper.grasp_point, grasp_in_tcp, atol=2e-4)  # the gap's middle: 0.1 mm off
    assert 2 * layout.cube_half_size == pytest.approx(0.0779, abs=5e-4)
    held = grasp_claim(GoogleRobot, 500, 20, Penetration())
    assert held is not None and held.passed, held

    gripper = dataclasses.replace(GoogleRobot.parts[1], grasp_frame=None)
    at_tcp = type(
        "GoogleRobotGraspAtTcp",
        (GoogleRobot,),
        {"uid": "", "parts": (*GoogleRobot.parts[:1], gripper, *GoogleRobot.parts[2:])},
    )
    assert 2 * table_top_layout(at_tcp).cube_half_size == pytest.approx(0.0958, abs=5e-4)
    lost = grasp_claim(at_tcp, 500, 20, Penetration())
    assert lost is not None and not lost.passed, lost
