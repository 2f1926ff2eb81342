"""Habitat's mobile-manipulator API on a small test robot (planar base with wheels,
torso slide, 6-joint arm, parallel gripper): params derived from the parts, FK with no
side effects that matches the simulation, IK to random reachable targets."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics.rotations import quat_angle

MM_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base_link" pos="0 0 0.12">
      <joint name="root_x_axis_joint" type="slide" axis="1 0 0"/>
      <joint name="root_y_axis_joint" type="slide" axis="0 1 0"/>
      <joint name="root_z_rotation_joint" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.3 0.15 0.1" mass="20"/>
      <body name="l_wheel_link" pos="0 0.2 -0.02">
        <joint name="l_wheel_joint" axis="0 1 0" damping="0.01"/>
        <geom type="cylinder" size="0.1 0.02" euler="1.5708 0 0" mass="1"/>
      </body>
      <body name="r_wheel_link" pos="0 -0.2 -0.02">
        <joint name="r_wheel_joint" axis="0 1 0" damping="0.01"/>
        <geom type="cylinder" size="0.1 0.02" euler="1.5708 0 0" mass="1"/>
      </body>
      <body name="torso_lift_link" pos="0 0 0.1">
        <joint name="torso_lift_joint" type="slide" axis="0 0 1" range="0 0.3"/>
        <geom type="box" size="0.08 0.08 0.2" pos="0 0 0.2" mass="5"/>
        <body name="shoulder_link" pos="0.1 0 0.35">
          <joint name="j1" axis="0 0 1" range="-3 3"/>
          <geom type="capsule" fromto="0 0 0 0 0 0.08" size="0.04" mass="1"/>
          <body name="upper_arm_link" pos="0 0 0.08">
            <joint name="j2" axis="0 1 0" range="-2 2"/>
            <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.035" mass="1"/>
            <body name="forearm_link" pos="0.3 0 0">
              <joint name="j3" axis="0 1 0" range="-2.5 2.5"/>
              <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.03" mass="0.8"/>
              <body name="wrist_1_link" pos="0.25 0 0">
                <joint name="j4" axis="1 0 0" range="-3 3"/>
                <geom type="capsule" fromto="0.01 0 0 0.05 0 0" size="0.025" mass="0.3"/>
                <body name="wrist_2_link" pos="0.06 0 0">
                  <joint name="j5" axis="0 1 0" range="-2 2"/>
                  <geom type="capsule" fromto="0.01 0 0 0.05 0 0" size="0.025" mass="0.3"/>
                  <body name="gripper_link" pos="0.06 0 0">
                    <joint name="j6" axis="1 0 0" range="-3 3"/>
                    <geom type="box" size="0.02 0.05 0.02" pos="0.02 0 0" mass="0.2"/>
                    <site name="grip_site" pos="0.1 0 0"/>
                    <body name="l_finger_link" pos="0.06 0.02 0">
                      <joint name="l_finger_joint" type="slide" axis="0 1 0" range="0 0.04"/>
                      <geom type="box" size="0.03 0.005 0.01" pos="0.03 0 0" mass="0.05"/>
                    </body>
                    <body name="r_finger_link" pos="0.06 -0.02 0">
                      <joint name="r_finger_joint" type="slide" axis="0 -1 0" range="0 0.04"/>
                      <geom type="box" size="0.03 0.005 0.01" pos="0.03 0 0" mass="0.05"/>
                    </body>
                  </body>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

ARM = "j[1-6]"


def manipulator(path: Path) -> type[ra.Agent]:
    return type(
        "TestMobileManipulator",
        (ra.Agent,),
        {
            "uid": "test_mobile_manipulator",
            "mjcf_path": path,
            "actuators": (
                ra.VelocityActuator(joints="root_.*", damping=(4000.0, 4000.0, 400.0)),
                ra.PDActuator(joints="torso_lift_joint", stiffness=20000.0, damping=2000.0),
                ra.PDActuator(joints=ARM, stiffness=5000.0, damping=300.0),
                ra.PDActuator(joints=".*_finger_joint", stiffness=200.0, damping=10.0),
            ),
            "parts": (
                ra.Arm(
                    name="arm",
                    joints=ARM,
                    end_effectors=(
                        ra.EndEffector(
                            "gripper_link", name="tool", pos=(0.1, 0.0, 0.0), command_frame="torso_lift_link"
                        ),
                    ),
                    task_space=ra.TaskSpace(
                        position_bounds=ra.WorkspaceBox(lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0)),
                        max_translation=0.01,
                    ),
                ),
                ra.Gripper(name="gripper", joints=".*_finger_joint", open=0.04, closed=0.0),
                ra.Torso(name="torso", joints="torso_lift_joint"),
                ra.Base(
                    name="base",
                    joints="root_.*",
                    holonomic=False,
                    wheels=("l_wheel_joint", "r_wheel_joint"),
                    wheel_radius=0.1,
                    wheel_separation=0.4,
                ),
            ),
            "cameras": (
                ra.CameraConfig.look_at(
                    "head_camera", eye=(0.1, 0.0, 0.5), target=(0.8, 0.0, 0.1), mount="torso_lift_link"
                ),
            ),
            "keyframes": {"home": ra.Keyframe(qpos={"torso_lift_joint": 0.1, "j2": -0.5, "j3": 1.0, "j5": 0.5})},
        },
    )


@pytest.fixture
def mm_cls(tmp_path: Path) -> type[ra.Agent]:
    path = tmp_path / "mm.xml"
    path.write_text(MM_MJCF)
    return manipulator(path)


def test_params_are_derived_from_the_parts(mm_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    p = agent.params
    assert p.arm_joints == tuple(f"j{k}" for k in range(1, 7))
    assert p.gripper_joints == ("l_finger_joint", "r_finger_joint")
    assert p.wheel_joints == ("l_wheel_joint", "r_wheel_joint")
    assert p.arm_init_params == (0.0, -0.5, 1.0, 0.0, 0.5, 0.0)
    assert p.gripper_open_state == (0.04, 0.04) and p.gripper_closed_state == (0.0, 0.0)
    assert p.ee_links == ("gripper_link",) and p.ee_offsets == ((0.1, 0.0, 0.0),)
    assert p.base_link == "base_link" and p.base_dynamics == "dynamic"  # the robot's name, as ee_links
    box = np.array(p.ee_constraint[0])
    assert box.shape == (3, 2) and np.all(box[:, 1] - box[:, 0] > 0.3)  # reach ~0.77 m
    np.testing.assert_allclose(agent.ee_local_offset(0), [0.1, 0.0, 0.0])
    inside = agent.clip_ee_to_workspace([[10.0, 0.0, -10.0]] * 2)
    np.testing.assert_allclose(inside[0], [box[0, 1], 0.0, box[2, 0]])
    with pytest.raises(ra.ConfigError, match="end-effector index"):
        agent.ee_transform(3)
    with pytest.raises(AttributeError):
        p.arm_joints = ()  # type: ignore[misc]
    # The params do not depend on the state the robot is in when they are first read.
    other = ra.Scene(mm_cls, num_envs=2)
    other.reset()
    moved = other.agents[0]
    moved.set_base_pose(xy=[1.0, 2.0], yaw=2.0)
    q = moved.keyframe_qpos(moved.default_keyframe())
    q[moved.joint_names.index("torso_lift_joint")] += 0.2  # the torso lifts the arm's workspace
    moved.reset(qpos=q)
    assert moved.params == p
    other.close()
    scene.close()


def test_params_report_the_base_dynamics_after_a_switch(mm_cls: type[ra.Agent]) -> None:
    """params.base_dynamics follows set_base_dynamics (it kept the value of the first read)."""
    scene = ra.Scene(mm_cls)
    scene.reset()
    agent = scene.agents[0]
    first = agent.params
    agent.set_base_dynamics("kinematic")
    assert agent.params.base_dynamics == agent.mobile.dynamics == "kinematic"
    assert agent.params == dataclasses.replace(first, base_dynamics="kinematic")
    agent.set_base_dynamics("dynamic")
    assert agent.params == first
    scene.close()


def test_forward_kinematics_has_no_side_effects_and_matches_the_simulation(mm_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    agent.set_base_pose(xy=[0.3, -0.2], yaw=0.7)
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, (2, 6))
        before = scene.get_state()
        fk = agent.calculate_ee_forward_kinematics(q)
        after = scene.get_state()
        assert np.array_equal(before["physics"], after["physics"])  # bit-identical
        agent.arm_joint_pos = q
        np.testing.assert_allclose(agent.arm_joint_pos, q, atol=0)
        np.testing.assert_allclose(fk, agent.ee_transform(0), atol=1e-9)


def test_inverse_kinematics_reaches_random_reachable_targets(mm_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(mm_cls, num_envs=50)
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(7)
    limits = np.array([[-3, 3], [-2, 2], [-2.5, 2.5], [-3, 3], [-2, 2], [-3, 3]]) * 0.8
    goal_q = rng.uniform(limits[:, 0], limits[:, 1], (50, 6))
    goal = agent.calculate_ee_forward_kinematics(goal_q)
    pose = np.concatenate([goal[:, :3, 3], matrix_to_quat(goal[:, :3, :3])], axis=1)
    state = scene.get_state()["physics"].copy()
    q, ok = agent.calculate_ee_inverse_kinematics(pose)
    assert np.array_equal(state, scene.get_state()["physics"])
    reached = agent.calculate_ee_forward_kinematics(q)
    got = np.concatenate([reached[:, :3, 3], matrix_to_quat(reached[:, :3, :3])], axis=1)
    position = np.linalg.norm(got[:, :3] - pose[:, :3], axis=1)
    angle = quat_angle(got[:, 3:], pose[:, 3:])
    assert ok.all(), f"{(~ok).sum()} targets missed"
    assert position.max() < 1e-3 and np.degrees(angle).max() < 1.0


def matrix_to_quat(rotations: np.ndarray) -> np.ndarray:
    import mujoco

    out = np.empty((len(rotations), 4))
    for row, rotation in enumerate(rotations):
        mujoco.mju_mat2Quat(out[row], rotation.reshape(-1))
    return out


def test_gripper_open_close_and_targets(mm_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    agent.close_gripper()
    np.testing.assert_allclose(agent.gripper_joint_pos, 0.0, atol=1e-12)
    assert agent.is_gripper_closed().all()
    agent.open_gripper(env_ids=[1])
    assert agent.is_gripper_open()[1] and agent.is_gripper_closed()[0]
    agent.set_gripper_target_state([0.0, 0.5])
    for _ in range(20):
        scene.step()
    np.testing.assert_allclose(agent.gripper_joint_pos[:, 0], [0.04, 0.02], atol=2e-3)
    assert not agent.is_gripper_open()[1] and not agent.is_gripper_closed()[1]
    np.testing.assert_allclose(agent.arm_motor_pos, agent.arm_joint_pos, atol=0.02)
    with pytest.raises(ra.StateError, match=r"\[0, 1\]"):
        agent.set_gripper_target_state(2.0)


def tool_in_torso(agent: ra.Agent) -> np.ndarray:
    return agent.frame_pose("tool", relative_to="torso_lift_link")[0, :3]


def test_ee_delta_commands_move_the_tool_in_the_turning_base_frame(mm_cls: type[ra.Agent]) -> None:
    """A constant pd_ee_delta_pos command while the base turns at 0.5 rad/s: the tool
    moves by the commanded displacement in the torso frame (which turns with the base)."""
    scene = ra.Scene(mm_cls, control_modes="pd_ee_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    start, start_yaw = tool_in_torso(agent), agent.base_rot[0]
    steps = 20
    command = np.array([-0.5, 0.5, 0.3])  # normalized: 5 mm back, 5 mm left, 3 mm up per step
    for _ in range(steps):
        agent.set_action([*command, 0.0, 0.0, 0.0, 1.0])  # arm, gripper, torso, base (v, wz)
        scene.step()
    turned = agent.base_rot[0] - start_yaw
    for _ in range(10):  # settle with zero commands, base still
        agent.set_action(np.zeros(7))
        scene.step()
    moved = tool_in_torso(agent) - start
    expected = steps * 0.01 * command
    assert turned == pytest.approx(steps * scene.control_timestep, rel=0.05)  # 1 rad/s
    np.testing.assert_allclose(moved, expected, atol=0.05 * np.linalg.norm(expected))


#: ManiSkill 3.0.1's Fetch control modes (mani_skill/agents/robots/fetch/fetch.py, read
#: as data): each is (arm, gripper, body, base).
MANISKILL_FETCH_MODES = {
    "pd_joint_delta_pos",
    "pd_joint_pos",
    "pd_ee_delta_pos",
    "pd_ee_delta_pose",
    "pd_ee_delta_pose_align",
    "pd_joint_target_delta_pos",
    "pd_ee_target_delta_pos",
    "pd_ee_target_delta_pose",
    "pd_joint_vel",
    "pd_joint_pos_vel",
    "pd_joint_delta_pos_vel",
    "pd_joint_delta_pos_stiff_body",
}


def test_rules_generate_the_fetch_mode_table_and_action_layout(mm_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(mm_cls)
    scene.reset()
    agent = scene.agents[0]
    modes = set(agent.modes())
    # Not generated: ManiSkill's pd_ee_delta_pose_align (rotation about the tool with a
    # root-aligned frame); extra: pd_ee_pose (absolute pose in the command frame).
    assert MANISKILL_FETCH_MODES - modes == {"pd_ee_delta_pose_align"}
    assert modes - MANISKILL_FETCH_MODES == {"pd_ee_pose"}
    for mode in modes:
        controller = agent.controller_for(mode)
        assert list(controller.slices) == ["arm", "gripper", "torso", "base"], mode
        assert controller.slices["gripper"].stop - controller.slices["gripper"].start == 1
        assert controller.slices["base"].stop - controller.slices["base"].start == 2  # (v, wz)
    stiff = agent.controller_for("pd_joint_delta_pos_stiff_body")
    assert not stiff.parts["torso"].config.use_delta and stiff.parts["arm"].config.use_delta
    agent.set_control_mode("pd_joint_delta_pos_stiff_body")
    for _ in range(20):
        agent.set_action([0.0] * 6 + [0.0, 0.25, 0.0, 0.0])  # torso to 0.25 m (absolute)
        scene.step()
    assert agent.qpos[0, agent.joint_names.index("torso_lift_joint")] == pytest.approx(0.25, abs=5e-3)


def test_a_camera_placement_follows_its_link(mm_cls: type[ra.Agent]) -> None:
    import mujoco

    scene = ra.Scene(mm_cls, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    camera = next(c for c in range(scene.model.ncam) if scene.model.camera(c).name.endswith("head_camera"))
    config = mm_cls.cameras[0]
    for yaw, lift in ((0.0, 0.0), (2.5, 0.2), (-3.0, 0.3)):
        agent.set_base_pose(xy=[yaw, -lift], yaw=yaw)
        q = agent.qpos[0].copy()
        q[agent.joint_names.index("torso_lift_joint")] = lift
        agent.reset(qpos=q)
        link = agent.frame_pose("torso_lift_link")[0]
        expected = np.empty(3)
        mujoco.mju_rotVecQuat(expected, np.array(config.pos), link[3:])
        pose = scene.world.camera_poses(camera)[0]
        np.testing.assert_allclose(pose[:3, 3], link[:3] + expected, atol=1e-6)
        turned = np.empty(4)
        mujoco.mju_mulQuat(turned, link[3:], np.array(config.quat))
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, turned)
        np.testing.assert_allclose(pose[:3, :3], rotation.reshape(3, 3), atol=1e-6)


def test_base_pos_and_base_rot_are_settable_as_habitats(mm_cls: type[ra.Agent]) -> None:
    """``agent.base_pos = p`` and ``agent.base_rot = yaw`` (Habitat's property setters)
    teleport every env's base and read back; they raised AttributeError (no setter)."""
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    for dynamics in ("dynamic", "kinematic"):
        agent.set_base_dynamics(dynamics)
        agent.base_rot = 0.5
        np.testing.assert_allclose(agent.base_rot, [0.5, 0.5], atol=1e-15)
        agent.base_pos = [1.0, 2.0, 0.0]  # x, y, z (z: the base's own)
        np.testing.assert_array_equal(agent.base_pos, [[1.0, 2.0, 0.0]] * 2)
        np.testing.assert_allclose(agent.base_rot, [0.5, 0.5], atol=1e-15)  # the yaw kept
        agent.base_pos = [[0.3, -0.2], [-1.0, 0.5]]  # x, y per env
        agent.base_rot = [0.1, -3.0]
        np.testing.assert_array_equal(agent.base_pos[:, :2], [[0.3, -0.2], [-1.0, 0.5]])
        np.testing.assert_allclose(agent.base_rot, [0.1, -3.0], atol=1e-15)
        before = agent.qpos
        agent.base_pos = agent.base_pos  # a round trip holds
        np.testing.assert_array_equal(agent.qpos, before)
        agent.set_action(np.zeros(agent.action_space.shape))  # a zero base velocity holds it
        scene.step()
        np.testing.assert_allclose(agent.base_pos[:, :2], [[0.3, -0.2], [-1.0, 0.5]], atol=1e-4)
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.base_pos: the base moves in its plane at z = 0"):
        agent.base_pos = [1.0, 2.0, 0.5]
    with pytest.raises(ra.StateError, match=r"base_pos: expected the base position \(x, y\) or \(x, y, z\)"):
        agent.base_pos = [1.0]
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.base_rot: expected yaw"):
        agent.base_rot = float("nan")
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.base_rot: expected yaw .* got True"):
        agent.base_rot = True  # not an angle (it turned the base to 1 rad)
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.set_base_pose: expected yaw"):
        agent.set_base_pose(None, [False, True])
    np.testing.assert_allclose(agent.base_rot, [0.1, -3.0], atol=1e-15)  # refused: unchanged
    scene.close()


def test_workspace_box_is_in_the_base_frame_whatever_the_keyframe_base_pose(mm_cls: type[ra.Agent]) -> None:
    """``ee_constraint`` is a box in the base link's frame: a first keyframe that starts
    the base turned (and away from the mount) gives the same box. It was sampled in the
    mount's frame, so a keyframe yaw of 90 deg swapped its x and y ranges, and
    ``clip_ee_to_workspace`` moved a base-frame point the arm was at."""
    turned = type(
        "TurnedMobileManipulator",
        (mm_cls,),
        {
            "uid": "test_turned_mobile_manipulator",
            "keyframes": {
                "home": ra.Keyframe(
                    qpos={
                        "root_x_axis_joint": 1.5,
                        "root_z_rotation_joint": np.pi / 2,
                        "torso_lift_joint": 0.1,
                        "j2": -0.5,
                        "j3": 1.0,
                        "j5": 0.5,
                    }
                )
            },
        },
    )
    boxes = []
    for cls in (mm_cls, turned):
        scene = ra.Scene(cls)
        scene.reset()
        agent = scene.agents[0]
        boxes.append(np.array(agent.params.ee_constraint[0]))
        at_rest = agent.frame_pose("tool", relative_to=agent.params.base_link)[:, :3]  # the tool in the base frame
        np.testing.assert_array_equal(agent.clip_ee_to_workspace(at_rest), at_rest)
        scene.close()
    np.testing.assert_allclose(boxes[1], boxes[0], atol=1e-9)


def test_gripper_state_checks_every_driven_finger(mm_cls: type[ra.Agent]) -> None:
    """``is_gripper_open`` / ``is_gripper_closed`` hold when every driven gripper joint is
    within ``gripper_state_eps`` of the state (Habitat's ``np.amax(...) < eps``): with the
    left finger closed and the right one open the gripper is neither. Only the first
    finger was read, so it counted as closed."""
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    q = agent.qpos
    left, right = (agent.joint_names.index(j) for j in agent.params.gripper_joints)
    q[0, [left, right]] = [0.0, 0.04]  # env 0: left closed, right open
    q[1, [left, right]] = [0.04, 0.0]  # env 1: the other way round
    agent.reset(qpos=q)
    assert not agent.is_gripper_closed().any() and not agent.is_gripper_open().any()
    eps = agent.params.gripper_state_eps
    q[0, [left, right]] = [0.0, 0.9 * eps]  # both within eps of closed
    q[1, [left, right]] = [0.04 - 0.9 * eps, 0.04]  # both within eps of open
    agent.reset(qpos=q)
    assert agent.is_gripper_closed().tolist() == [True, False]
    assert agent.is_gripper_open().tolist() == [False, True]
    scene.close()


def test_arm_motor_pos_and_gripper_joint_pos_are_settable_as_habitats(mm_cls: type[ra.Agent]) -> None:
    """``agent.arm_motor_pos = q`` sets the arm's drive targets (the arm then moves there)
    and ``agent.gripper_joint_pos = g`` teleports the fingers and holds them, as Habitat's
    setters; both raised AttributeError (no setter)."""
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    before = agent.arm_joint_pos
    goal = before + np.array([0.2, -0.1, 0.1, 0.0, 0.1, 0.0])
    agent.arm_motor_pos = goal
    np.testing.assert_array_equal(agent.arm_motor_pos, goal)
    np.testing.assert_array_equal(agent.arm_joint_pos, before)  # not moved
    for _ in range(40):
        scene.step()
    np.testing.assert_allclose(agent.arm_joint_pos, goal, atol=0.01)
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.arm_motor_pos: .*limits"):
        agent.arm_motor_pos = [0.0, 5.0, 0.0, 0.0, 0.0, 0.0]  # j2 beyond [-2, 2]
    np.testing.assert_array_equal(agent.arm_motor_pos, goal)  # refused: unchanged
    agent.gripper_joint_pos = [[0.01, 0.01], [0.03, 0.03]]
    np.testing.assert_array_equal(agent.gripper_joint_pos, [[0.01, 0.01], [0.03, 0.03]])
    for _ in range(10):
        scene.step()
    np.testing.assert_allclose(agent.gripper_joint_pos, [[0.01, 0.01], [0.03, 0.03]], atol=2e-3)  # held
    with pytest.raises(ra.StateError, match=r"TestMobileManipulator\.gripper_joint_pos: expected gripper joint"):
        agent.gripper_joint_pos = [0.01]
    scene.close()


def test_a_gripper_teleport_keeps_the_arm_targets_and_an_arm_teleport_the_gripper_targets(
    mm_cls: type[ra.Agent],
) -> None:
    """Habitat code sets the arm's motor targets, then opens the gripper: the arm still
    goes to its targets. ``open_gripper()`` (and every arm / gripper teleport) held every
    joint of the robot at the measured pose instead, so the arm stayed where it was."""
    scene = ra.Scene(mm_cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    goal = agent.arm_joint_pos + np.array([0.2, -0.1, 0.1, 0.0, 0.1, 0.0])
    agent.arm_motor_pos = goal
    agent.open_gripper()
    np.testing.assert_array_equal(agent.arm_motor_pos, goal)
    agent.set_gripper_target_state(1.0)  # close
    agent.arm_joint_pos = goal  # teleport the arm: the gripper keeps closing
    for _ in range(20):
        scene.step()
    np.testing.assert_allclose(agent.arm_joint_pos, goal, atol=0.01)
    assert agent.is_gripper_closed().all()
    scene.close()


def test_a_teleport_keeps_the_coordinates_it_is_not_given_bit_for_bit(mm_cls: type[ra.Agent]) -> None:
    """``base_pos = ...`` keeps the yaw joint as it is and ``base_rot = ...`` the x / y
    joints, to the bit, on a robot mounted turned: the coordinate not given was read back
    through the body's pose and written again, an ulp off in about half the cases (an
    xy-only teleport turned the base)."""
    mount = (1.0, -0.5, 0.0, float(np.cos(0.35)), 0.0, 0.0, float(np.sin(0.35)))
    scene = ra.Scene(mm_cls, num_envs=2, robot_poses=[mount])
    scene.reset()
    agent = scene.agents[0]
    planar = [agent.joint_names.index(j) for j in ("root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint")]
    for yaw in np.linspace(-3.0, 3.0, 31):
        agent.base_rot = yaw
        before = agent.qpos[:, planar]
        agent.base_pos = agent.base_pos
        np.testing.assert_array_equal(agent.qpos[:, planar[2]], before[:, 2])
        agent.base_pos = [0.3, 0.7]
        before = agent.qpos[:, planar]
        agent.base_rot = agent.base_rot
        np.testing.assert_array_equal(agent.qpos[:, planar[:2]], before[:, :2])
    scene.close()
