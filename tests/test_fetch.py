"""Fetch checked against numbers: forward kinematics against the URDF's joint origins
chained independently, ManiSkill's mode table and action layout, grasp + lift + hold with
contact forces, gripper states, IK accuracy, the head camera on its link, base odometry
with turning wheels, and pd_ee_delta_pose_align's rotation about the tool's own axes."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.kinematics import IKSolver, resolve_frame
from tests.chain_check import (
    assert_camera_on_frame,
    assert_pan_turns_the_view,
    axis_rotation,
    chain,
    index,
    transform,
)
from tests.grasp_check import assert_grasps_lifts_and_holds
from tests.ik_check import assert_ik_reaches_random_targets
from tests.test_mobile_manipulator import MANISKILL_FETCH_MODES

ARM = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "upperarm_roll_joint",
    "elbow_flex_joint",
    "forearm_roll_joint",
    "wrist_flex_joint",
    "wrist_roll_joint",
)
BASE = ("root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint")
FINGERS = ("l_gripper_finger_joint", "r_gripper_finger_joint")
HEAD = ("head_pan_joint", "head_tilt_joint")
X, Y, Z = np.eye(3)
# fetch_description/robots/fetch.urdf (ZebraDevs/fetch_ros): joint origins in the parent
# link and axes, from base_link (on the floor) through torso_lift_joint (prismatic) and
# the arm to gripper_link (fixed gripper_axis); the head chain to head_camera_link.
TORSO = ((-0.086875, 0.0, 0.37743), Z)
ARM_ORIGINS = [
    ((0.119525, 0.0, 0.34858), Z),
    ((0.117, 0.0, 0.06), Y),
    ((0.219, 0.0, 0.0), X),
    ((0.133, 0.0, 0.0), Y),
    ((0.197, 0.0, 0.0), X),
    ((0.1245, 0.0, 0.0), Y),
    ((0.1385, 0.0, 0.0), X),
]
GRIPPER_AXIS = (0.16645, 0.0, 0.0)
HEAD_ORIGINS = [((0.053125, 0.0, 0.603001), Z), ((0.14253, 0.0, 0.057999), Y)]
HEAD_CAMERA_JOINT = (0.055, 0.0, 0.0225)
WHEEL_RADIUS = 0.055325


def torso_pose(base: np.ndarray, lift: float) -> np.ndarray:
    """torso_lift_link in the world: base_link (x, y, yaw on the floor), then the
    prismatic torso_lift_joint along z."""
    pose = transform(axis_rotation(Z, base[2]), np.array([base[0], base[1], 0.0]))
    origin, axis = TORSO
    return pose @ transform(np.eye(3), np.array(origin) + lift * axis)


def test_forward_kinematics_match_the_urdf_joint_origins() -> None:
    """20 random configurations of base, torso and arm: gripper_link within 1 mm / 1 deg
    of the URDF chain (it matches to 1e-6)."""
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    base, arm, torso = index(agent, BASE), index(agent, ARM), agent.joint_names.index("torso_lift_joint")
    frame = resolve_frame(scene.model, "gripper_link", agent.prefix)
    rng = np.random.default_rng(0)
    limits = agent.qpos_limits.copy()
    limits = np.where(np.isfinite(limits), limits, np.sign(limits) * math.pi)
    limits[base] = [[-2.0, 2.0], [-2.0, 2.0], [-math.pi, math.pi]]
    q = rng.uniform(limits[:, 0], limits[:, 1], (20, len(agent.joint_names)))
    configurations = np.repeat(scene.world.qpos, 20, axis=0)
    configurations[:, agent.qpos_adr] = q
    poses = agent.kinematics.pose(configurations, frame)
    for i in range(20):
        expected = chain(torso_pose(q[i, base], q[i, torso]), ARM_ORIGINS, q[i, arm])
        expected = expected @ transform(np.eye(3), np.array(GRIPPER_AXIS))
        np.testing.assert_allclose(poses[i, :3], expected[:3, 3], atol=1e-6)
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, poses[i, 3:])
        np.testing.assert_allclose(rotation.reshape(3, 3), expected[:3, :3], atol=1e-6)
    scene.close()


def test_limits_masses_and_wheels_from_the_urdf() -> None:
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    np.testing.assert_allclose(
        agent.qpos_limits[index(agent, ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_flex_joint"])],
        [[-1.6056, 1.6056], [-1.221, 1.518], [-2.251, 2.251]],
    )
    np.testing.assert_allclose(agent.qpos_limits[index(agent, ["wrist_flex_joint"])], [[-2.16, 2.16]])
    np.testing.assert_allclose(
        agent.qpos_limits[index(agent, [*HEAD, "torso_lift_joint"])], [[-1.57, 1.57], [-0.76, 1.45], [0.0, 0.38615]]
    )
    np.testing.assert_allclose(agent.qpos_limits[index(agent, FINGERS)], [[0.0, 0.05]] * 2)
    model = scene.model
    links = [n.replace("_joint", "_link") for n in ARM]
    masses = [model.body_mass[model.body(agent.prefix + n).id] for n in links]
    np.testing.assert_allclose(masses, [2.5587, 2.6615, 2.3311, 2.1299, 1.6563, 1.725, 0.1354], rtol=1e-6)
    assert model.body_mass[model.body(agent.prefix + "base_link").id] == pytest.approx(70.1294)
    total = sum(model.body_mass[b] for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix))
    assert total == pytest.approx(120.93, abs=0.01)  # the URDF's links, bellows and sensors aside
    params = agent.params
    assert params.wheel_joints == ("l_wheel_joint", "r_wheel_joint")
    assert params.arm_joints == ARM and params.gripper_joints == FINGERS
    assert params.arm_init_params == (-0.370, -1.032, 0.695, 0.955, -0.1, 2.077, 0.0)
    assert params.gripper_open_state == (0.05, 0.05) and params.gripper_closed_state == (0.0, 0.0)
    scene.close()


#: fetch_description/robots/fetch.urdf's ``<dynamics damping>`` (the same in ManiSkill
#: 3.0.1's copy): arm in ARM order (N*m*s/rad), torso and fingers (N*s/m).
URDF_ARM_DAMPING = (1.0, 1.0, 5.0, 1.0, 5.0, 1.0, 5.0)
URDF_TORSO_DAMPING = 100.0
URDF_FINGER_DAMPING = 100.0


def test_joint_damping_is_the_urdfs_and_the_total_is_maniskills() -> None:
    """Each joint's own damping is the URDF's; the drive adds the rest of ManiSkill's
    kv = 1e2 on the arm and the fingers (its PhysX joints carry the drive's damping only:
    the controller replaces the URDF's), and of our 5e3 N*s/m on the torso."""
    scene = ra.Scene("fetch")
    model, agent = scene.model, scene.agents[0]
    drives = {d.joint: d for d in type(agent).check().drives}
    expected = [
        *((joint, b, 1e3, 1e2) for joint, b in zip(ARM, URDF_ARM_DAMPING, strict=True)),
        ("torso_lift_joint", URDF_TORSO_DAMPING, 1e5, 5e3),
        *((joint, URDF_FINGER_DAMPING, 1e3, 1e2) for joint in FINGERS),
    ]
    for joint, own, stiffness, total in expected:
        dof = model.jnt_dofadr[model.joint(agent.prefix + joint).id]
        assert model.dof_damping[dof] == own, joint
        assert drives[joint].stiffness == stiffness, joint
        assert drives[joint].damping + model.dof_damping[dof] == pytest.approx(total, rel=1e-12), joint
    scene.close()


def test_fingers_close_from_open_at_the_peers_pace() -> None:
    """Open (0.05 m) to the closing command (target -0.01 m, 60 N at the first step) in
    free air, control at the 200 Hz physics rate: the fingers' own damping (100 N*s/m,
    implicit in every step) caps their speed at 60 N / 100 N*s/m = 0.6 m/s (peak 0.565);
    ManiSkill's PhysX fingers under the same gains peak at 0.551 m/s and are at 26.6 mm
    after 0.05 s (0.026 here). With the damping all in the clamped drive the first step
    was explicit: 3.34 m/s, 17 mm in 5 ms. The step is pinned at the 200 Hz these figures
    were measured at (Fetch's own has been 160 Hz since 2026-11-30)."""
    scene = ra.Scene("fetch", control_modes="pd_joint_pos", sim_freq=200, control_freq=200)
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    fingers, arm = index(agent, FINGERS), index(agent, ARM)
    qpos = agent.qpos[0].copy()
    qpos[fingers] = 0.05
    agent.reset(qpos=qpos)
    action = np.concatenate([agent.qpos[0, arm], [-1.0], np.zeros(3), [0.0, 0.0]])
    speeds, positions = [], []
    for _ in range(100):
        agent.set_action(action)
        scene.step()
        speeds.append(float(np.max(np.abs(agent.qvel[0, fingers]))))
        positions.append(agent.qpos[0, fingers].copy())
    assert max(speeds) < 0.6
    assert positions[9] == pytest.approx([0.0266, 0.0266], abs=0.002)  # after 0.05 s
    assert np.all(positions[-1] < 0.0)  # closed, pressing the target past the pads' contact
    scene.close()


# ---------------------------------------------------------------- control modes


def test_maniskill_mode_table_and_action_layout() -> None:
    """ManiSkill's 12 Fetch modes, each with (arm, gripper, body, base) and ManiSkill's
    bounds: 0.1 rad joint deltas, 0.1 m / 0.1 rad EE deltas in torso_lift_link's frame,
    fingers -0.01 .. 0.05 m, base 1 m/s and 3.14 rad/s."""
    cls = ra.get_agent("fetch")
    assert set(cls.modes()) == MANISKILL_FETCH_MODES
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    for mode in MANISKILL_FETCH_MODES:
        controller = agent.controller_for(mode)
        assert list(controller.slices) == ["arm", "gripper", "body", "base"], mode
        widths = [s.stop - s.start for s in controller.slices.values()]
        arm = {"pd_ee_delta_pos": 3, "pd_ee_target_delta_pos": 3}.get(mode, 6 if "ee" in mode else 7)
        if mode.endswith("pos_vel"):
            arm = 14
        assert widths == [arm, 1, 3, 2], mode
        gripper = controller.parts["gripper"]
        assert (gripper.raw_low[0], gripper.raw_high[0]) == pytest.approx((-0.01, 0.05))
        base = controller.parts["base"]
        np.testing.assert_allclose([base.raw_low, base.raw_high], [[-1.0, -3.14], [1.0, 3.14]])
    assert agent.controller_for("pd_joint_delta_pos").parts["body"].config.joint_names == (
        "head_pan_joint",
        "head_tilt_joint",
        "torso_lift_joint",
    )  # ManiSkill's body order, though the model has the torso first
    ee = agent.controller_for("pd_ee_delta_pose").parts["arm"]
    assert scene.model.body(ee.root_frame.id).name == agent.prefix + "torso_lift_link"
    np.testing.assert_allclose([ee.raw_low, ee.raw_high], [[-0.1] * 6, [0.1] * 6])
    scene.close()


def tool_rotation(agent: ra.Agent) -> np.ndarray:
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, agent.tcp_pose[0, 3:])
    return rotation.reshape(3, 3)


@pytest.mark.parametrize("mode", ["pd_ee_delta_pose_align", "pd_ee_delta_pose"])
def test_align_mode_turns_the_tool_about_the_command_frames_axes(mode: str) -> None:
    """A constant rotation command (0.03 rad per step about z for 10 steps) from the rest
    pose, whose tool z is tilted from torso_lift_link's: in both modes the tool turns
    0.3 rad about torso_lift_link's z through the tool point (axis within 1 deg, angle
    within 5 %) and stays put. ManiSkill 2's ee_align (pd_ee_delta_pose_align) composes
    ``delta * previous`` and then restores ``previous.p + d``: a turn about the base's axes
    through the tool, as pd_ee_delta_pose. (0.42 rad about it reaches wrist_flex_joint's
    limit from rest, hence the small angle.)"""
    scene = ra.Scene("fetch", control_modes=mode)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    torso_z = agent.frame_pose("torso_lift_link")[0]
    torso_axes = np.zeros(9)
    mujoco.mju_quat2Mat(torso_axes, torso_z[3:])
    start_rotation, start_position = tool_rotation(agent), agent.tcp_pose[0, :3].copy()
    assert math.degrees(math.acos(abs(start_rotation[:, 2] @ torso_axes.reshape(3, 3)[:, 2]))) > 30
    action = hold_action(agent)
    action[3:6] = [0.0, 0.0, 0.3]  # 0.03 rad per step about z
    for _ in range(10):
        agent.set_action(action)
        scene.step()
    action[3:6] = 0.0
    for _ in range(10):
        agent.set_action(action)
        scene.step()
    rotation = tool_rotation(agent)
    relative = rotation @ start_rotation.T  # in the world (= torso) axes
    relative = torso_axes.reshape(3, 3).T @ relative @ torso_axes.reshape(3, 3)
    angle_axis = np.zeros(3)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, relative.reshape(-1))
    mujoco.mju_quat2Vel(angle_axis, quat, 1.0)
    angle = float(np.linalg.norm(angle_axis))
    assert angle == pytest.approx(0.3, rel=0.05)
    assert math.degrees(math.acos(min(1.0, angle_axis[2] / angle))) < 1.0
    assert np.linalg.norm(agent.tcp_pose[0, :3] - start_position) < 0.005
    scene.close()


# ---------------------------------------------------------------- IK
def test_ik_reaches_50_random_reachable_targets() -> None:
    """Targets are FK of random arm configurations (base moved and turned, torso half
    up); IK starts at ``rest`` and lands within 1 mm and 1 deg inside the limits."""
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    q = agent.qpos[0].copy()
    q[agent.joint_names.index("torso_lift_joint")] = 0.2
    agent.reset(qpos=q)
    agent.set_base_pose(xy=[0.3, -0.2], yaw=0.7)
    assert_ik_reaches_random_targets(scene, ARM, "gripper_link", 50, seed=2)
    scene.close()


# ---------------------------------------------------------------- gripper
def test_gripper_open_closed_and_half() -> None:
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    fingers = index(agent, FINGERS)
    assert not agent.is_gripper_open()[0] and not agent.is_gripper_closed()[0]  # rest: 0.015 m
    for value, is_open, is_closed in ((0.0, False, True), (0.025, False, False), (0.05, True, False)):
        q = agent.qpos[0].copy()
        q[fingers] = value
        agent.reset(qpos=q)
        assert bool(agent.is_gripper_open()[0]) is is_open and bool(agent.is_gripper_closed()[0]) is is_closed
    scene.reset(keyframes="habitat_arm_init")
    assert agent.is_gripper_closed()[0]
    scene.close()


#: A 4 cm, 150 g cube on a pedestal in front of the robot, grasped from above.
DOWN = np.array([math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0])  # gripper x along world -z
CUBE_MASS, CUBE_HALF = 0.15, 0.02
TOOL = (0.65, 0.1, 0.7)


def arm_solver(scene: ra.Scene) -> IKSolver:
    agent = scene.agents[0]
    arm = np.array(index(agent, ARM))
    frame = resolve_frame(scene.model, "gripper_link", agent.prefix)
    return IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], agent.qpos_limits[arm])


def solve_down(scene: ra.Scene, position: tuple[float, float, float], seed: np.ndarray) -> np.ndarray:
    target = np.concatenate([position, DOWN])[None]
    result = arm_solver(scene).solve(scene.world.qpos, target, seed[None], max_iterations=200, restarts=10)
    assert result.success[0], (result.position_error, result.rotation_error)
    return result.qpos[0]


def test_gripper_grasps_lifts_and_holds_a_cube() -> None:
    """Close on the cube: is_grasping, the pads' forces opposed and the sum with the
    pedestal's balancing the weight; lift 10 cm over 1 s and hold 2 s: the pads alone
    carry the weight; open: not grasping."""
    props = [
        ra.Prop(
            name="pedestal",
            shape="box",
            size=(0.012, 0.012, (TOOL[2] - CUBE_HALF) / 2),
            pos=(TOOL[0], TOOL[1], (TOOL[2] - CUBE_HALF) / 2),
            mass=None,
        ),
        ra.Prop(
            name="cube", shape="box", size=(CUBE_HALF,) * 3, pos=(TOOL[0], TOOL[1], TOOL[2] + 1e-4), mass=CUBE_MASS
        ),
    ]
    scene = ra.Scene("fetch", props=props, control_modes="pd_joint_pos")
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    arm = index(agent, ARM)
    grasp = solve_down(scene, TOOL, agent.qpos[0, arm])
    lift = solve_down(scene, (TOOL[0], TOOL[1], TOOL[2] + 0.1), grasp)
    qpos = agent.qpos[0].copy()
    qpos[arm] = grasp
    qpos[index(agent, FINGERS)] = 0.05
    agent.reset(qpos=qpos)  # fingers open around the cube

    def act(arm_target: np.ndarray, gripper: float) -> None:
        agent.set_action(np.concatenate([arm_target, [gripper], np.zeros(3), [0.0, 0.0]]))
        scene.step()

    def pads_press_less_than_1_5_mm() -> None:  # inner faces at +-q from the grasp point
        assert np.all(agent.qpos[0, index(agent, FINGERS)] > CUBE_HALF - 0.0015)

    fingers = [[agent.prefix + "l_gripper_finger_link"], [agent.prefix + "r_gripper_finger_link"]]
    assert_grasps_lifts_and_holds(
        scene, act, grasp, lift, fingers, CUBE_MASS, min_force=5.0, after_close=pads_press_less_than_1_5_mm
    )
    scene.close()


# ---------------------------------------------------------------- head camera
def test_head_camera_follows_its_link_and_pans() -> None:
    """fetch_head sits on head_camera_link (chained from the URDF's torso and head
    joints, 1e-6), looks along its x with z up, and turns with head pan."""
    scene = ra.Scene("fetch")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    camera = scene.model.camera(agent.prefix + "fetch_head").id
    base, head, torso = index(agent, BASE), index(agent, HEAD), agent.joint_names.index("torso_lift_joint")
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = agent.qpos[0].copy()
        q[base] = rng.uniform([-1.0, -1.0, -math.pi], [1.0, 1.0, math.pi])
        q[head] = rng.uniform(agent.qpos_limits[head, 0], agent.qpos_limits[head, 1])
        q[torso] = rng.uniform(0.0, 0.38615)
        agent.reset(qpos=q)
        link = chain(torso_pose(q[base], q[torso]), HEAD_ORIGINS, q[head]) @ transform(
            np.eye(3), np.array(HEAD_CAMERA_JOINT)
        )
        assert_camera_on_frame(scene.world.camera_poses(camera)[0], link)
        np.testing.assert_allclose(agent.frame_pose("head_camera_link")[0, :3], link[:3, 3], atol=1e-6)
    assert_pan_turns_the_view(scene, camera, base, head)
    scene.close()


# ---------------------------------------------------------------- base
def test_differential_base_odometry_and_wheels() -> None:
    """pd_base_forward_vel: 0.2 m/s for 2 s travels 0.4 m (+-5 %) along the robot's
    heading and turns both wheels by distance / radius; 0.5 rad/s for 2 s turns 1 rad
    (+-5 %) with the wheels turning opposite ways; the arm holds meanwhile."""
    scene = ra.Scene("fetch", control_modes="pd_joint_delta_pos")
    agent = scene.agents[0]
    base = agent.controller.slices["base"]
    assert base == slice(11, 13)
    scene.reset(keyframes="rest")
    agent.set_base_pose(xy=[0.0, 0.0], yaw=math.pi / 2)
    wheels = index(agent, ["l_wheel_joint", "r_wheel_joint"])
    arm = index(agent, ARM)
    arm_start = agent.qpos[0, arm].copy()
    wheel_start = agent.qpos[0, wheels].copy()
    for _ in range(2 * scene.control_freq):
        action = hold_action(agent)
        action[..., base] = [0.2, 0.0]  # 0.2 of 1 m/s
        agent.set_action(action)
        scene.step()
    travelled = float(agent.base_pos[0, 1])
    assert travelled == pytest.approx(0.4, rel=0.05) and abs(agent.base_pos[0, 0]) < 0.01
    np.testing.assert_allclose(agent.qpos[0, wheels] - wheel_start, [travelled / WHEEL_RADIUS] * 2, rtol=0.01)
    wheel_start = agent.qpos[0, wheels].copy()
    for _ in range(2 * scene.control_freq):
        action = hold_action(agent)
        action[..., base] = [0.0, 0.5 / 3.14]
        agent.set_action(action)
        scene.step()
    assert agent.base_rot[0] - math.pi / 2 == pytest.approx(1.0, rel=0.05)
    turned = agent.qpos[0, wheels] - wheel_start
    arc = (agent.base_rot[0] - math.pi / 2) * 0.18738 / WHEEL_RADIUS
    assert (turned[1] - turned[0]) / 2 == pytest.approx(arc, rel=0.01)  # opposite ways, by the arc
    assert np.max(np.abs(agent.qpos[0, arm] - arm_start)) < 0.01
    scene.close()


def test_align_is_an_optional_rule_mode() -> None:
    """Not generated unless a TaskSpace lists it; then the same config as
    pd_ee_delta_pose (ManiSkill 2's ee_align); an unknown name lists it among the
    choices."""
    from robot_agents.controllers.ee import CommandFrame
    from robot_agents.controllers.rules import JointGroup, ee_control_modes
    from robot_agents.errors import UnknownNameError

    group = JointGroup(ARM)
    task = ra.TaskSpace(position_bounds=ra.WorkspaceBox(lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0)))
    assert "pd_ee_delta_pose_align" not in ee_control_modes(group, task)
    modes = ee_control_modes(group, task, ("pd_ee_delta_pose", "pd_ee_delta_pose_align"))
    align, pose = modes["pd_ee_delta_pose_align"], modes["pd_ee_delta_pose"]
    assert align == pose and align.rotation_frame is CommandFrame.ROOT
    with pytest.raises(UnknownNameError, match="pd_ee_delta_pose_align"):
        ee_control_modes(group, task, ("pd_ee_align",))


@pytest.mark.parametrize("mode", ["pd_ee_target_delta_pos", "pd_ee_delta_pos"])
def test_ee_delta_moves_the_tool_in_the_torso_frame_while_the_base_turns(mode: str) -> None:
    """A constant end-effector delta (0.5 cm per step forward and left, 1 cm per step
    down, in torso_lift_link's axes) for 1 s from rest while the base turns at 0.5 rad/s:
    the tool moves by the commanded displacement in the turning torso frame (5 %).
    (Straight forward from rest, wrist_flex_joint reaches its limit after ~7 cm.)"""
    scene = ra.Scene("fetch", control_modes=mode)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    step = np.array([0.005, 0.005, -0.01])

    def in_torso() -> np.ndarray:
        torso = agent.frame_pose("torso_lift_link")[0]
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, torso[3:])
        return rotation.reshape(3, 3).T @ (agent.tcp_pose[0, :3] - torso[:3])

    start = in_torso()
    action = np.zeros(agent.single_action_space.shape)
    action[:3] = step / 0.1
    base = agent.controller.slices["base"]
    action[base.start + 1] = 0.5 / 3.14  # yaw rate 0.5 rad/s
    for _ in range(20):
        agent.set_action(action)
        scene.step()
    action[base.start + 1] = 0.0
    if mode == "pd_ee_target_delta_pos":  # let the tool reach the last target, base still
        action[:3] = 0.0
        for _ in range(10):
            agent.set_action(action)
            scene.step()
    moved = in_torso() - start
    assert agent.base_rot[0] > 0.4  # the base turned
    np.testing.assert_allclose(moved, 20 * step, atol=0.05 * np.linalg.norm(20 * step))
    scene.close()
