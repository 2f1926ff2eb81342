"""Mobile-base velocity control: commands in the robot's frame move the base by the
commanded distance in the commanded direction (odometry against numbers)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra

# A 20 kg chassis on planar joints (x, y slides; yaw hinge), floating 2 cm above the
# floor (no wheel contact: the drives move it), with a 2-joint arm on top.
MOBILE_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base_link" pos="0 0 0.12">
      <joint name="root_x" type="slide" axis="1 0 0"/>
      <joint name="root_y" type="slide" axis="0 1 0"/>
      <joint name="root_yaw" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.3 0.25 0.1" mass="20"/>
      <body name="upper_arm" pos="0 0 0.15">
        <joint name="shoulder" axis="0 1 0" range="-1.5 1.5"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
        <body name="forearm" pos="0.3 0 0">
          <joint name="elbow" axis="0 1 0" range="-2 2"/>
          <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.025" mass="0.5"/>
          <site name="tool" pos="0.25 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def mobile_robot(path: Path, holonomic: bool) -> type[ra.Agent]:
    return type(
        "MobileArm",
        (ra.Agent,),
        {
            "uid": "mobile_arm",
            "mjcf_path": path,
            "actuators": (
                ra.VelocityActuator(joints="root_.*", damping=(4000.0, 4000.0, 400.0)),
                ra.PDActuator(joints="shoulder|elbow", stiffness=300.0, damping=30.0),
            ),
            "parts": (
                ra.Arm(name="arm", joints="shoulder|elbow", end_effectors=(ra.EndEffector("tool"),)),
                ra.Base(name="base", joints="root_.*", holonomic=holonomic, max_speed=0.5, max_turn=1.0),
            ),
            "keyframes": {"facing_y": ra.Keyframe(qpos={"root_yaw": math.pi / 2, "shoulder": -0.3})},
        },
    )


@pytest.fixture
def mobile_file(tmp_path: Path) -> Path:
    path = tmp_path / "mobile.xml"
    path.write_text(MOBILE_MJCF)
    return path


def drive(cls: type[ra.Agent], base_action: list[float], seconds: float = 2.0) -> ra.Agent:
    scene = ra.Scene(cls, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action([0.0, 0.0, *base_action])  # arm holds, base moves
        scene.step()
    return agent


def base_state(agent: ra.Agent) -> np.ndarray:
    return agent.qpos[0, :3]  # x, y (m), yaw (rad)


def test_holonomic_base_moves_in_the_robot_frame(mobile_file: Path) -> None:
    cls = mobile_robot(mobile_file, holonomic=True)
    agent = drive(cls, [0.4, 0.0, 0.0])  # 0.4 of 0.5 m/s = 0.2 m/s forward, robot facing +y
    x, y, yaw = base_state(agent)
    assert y == pytest.approx(0.4, rel=0.05) and abs(x) < 0.01 and yaw == pytest.approx(math.pi / 2, abs=1e-3)
    agent = drive(cls, [0.0, 0.4, 0.0])  # 0.2 m/s to the robot's left: world -x
    x, y, _ = base_state(agent)
    assert x == pytest.approx(-0.4, rel=0.05) and abs(y) < 0.01
    assert agent.controller.slices["base"] == slice(2, 5)


def test_differential_base_drives_forward_and_turns(mobile_file: Path) -> None:
    cls = mobile_robot(mobile_file, holonomic=False)
    agent = drive(cls, [0.4, 0.0])
    x, y, _ = base_state(agent)
    assert y == pytest.approx(0.4, rel=0.05) and abs(x) < 0.01
    agent = drive(cls, [0.0, 0.5])  # 0.5 rad/s for 2 s
    _, _, yaw = base_state(agent)
    assert yaw - math.pi / 2 == pytest.approx(1.0, rel=0.05)
    assert agent.single_action_space.shape == (4,)  # arm 2 + (v, wz)


def test_base_pos_and_rot_round_trip_and_wrap(mobile_file: Path) -> None:
    """Habitat's base_pos / base_rot: exact round trips, yaw in (-pi, pi], incremental turns wrap."""
    lifted = (1.0, -2.0, 0.0, math.cos(0.3), 0.0, 0.0, math.sin(0.3))  # mounted turned 0.6 rad
    scene = ra.Scene(mobile_robot(mobile_file, holonomic=True), num_envs=2, robot_poses=[lifted])
    scene.reset()
    agent = scene.agents[0]
    np.testing.assert_allclose(agent.base_rot, wrap(math.pi / 2 + 0.6), atol=1e-9)
    np.testing.assert_allclose(agent.base_pos[:, :2], [[1.0, -2.0]] * 2, atol=1e-12)
    for yaw in np.linspace(-math.pi, math.pi, 8):
        agent.set_base_pose(xy=[0.25, -0.5], yaw=yaw, env_ids=[1])
        np.testing.assert_allclose(agent.base_pos[1], [0.25, -0.5, 0.0], atol=1e-12)
        assert abs(wrap(agent.base_rot[1] - yaw)) < 1e-6
        assert -math.pi < agent.base_rot[1] <= math.pi
    np.testing.assert_allclose(agent.base_pos[0, :2], [1.0, -2.0], atol=1e-12)  # env 0 untouched
    agent.set_base_pose(yaw=math.pi - 0.1)
    agent.set_base_pose(yaw=agent.base_rot + 0.2)  # crosses pi
    np.testing.assert_allclose(agent.base_rot, -math.pi + 0.1, atol=1e-9)
    with pytest.raises(ra.StateError, match="base position"):
        agent.set_base_pose(xy=[0.0, 0.0, 0.0])


def wrap(angle: float | np.ndarray) -> np.ndarray:
    return np.pi - np.mod(np.pi - np.asarray(angle), 2 * np.pi)


def test_gripper_open_and_closed_states() -> None:
    scene = ra.Scene("panda", control_modes="pd_joint_pos")
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    assert agent.is_gripper_open()[0] and not agent.is_gripper_closed()[0]
    scene.reset(keyframes="closed_rest")
    assert agent.is_gripper_closed()[0] and not agent.is_gripper_open()[0]
    agent.reset(qpos=np.concatenate([agent.keyframe_qpos("rest")[:7], [0.02, 0.02]]))
    assert not agent.is_gripper_open()[0] and not agent.is_gripper_closed()[0]
    with pytest.raises(ra.ConfigError, match="no mobile base"):
        agent.base_rot  # noqa: B018


def test_the_float_wrap_is_the_array_wrap_bit_for_bit() -> None:
    """The one-env wheel roll wraps its turn on Python floats; it must equal the batched
    path's NumPy wrap exactly, at the +-pi seam, at +-0 and far out."""
    from robot_agents.agent.mobile import wrap_angle, wrap_angle_float

    rng = np.random.default_rng(0)
    seams = [math.pi, -math.pi, 3 * math.pi, -3 * math.pi, 0.0, -0.0, 2 * math.pi, 1e-300, -1e-300]
    near = [np.nextafter(x, direction) for x in seams for direction in (-np.inf, np.inf)]
    angles = np.concatenate([seams, near, rng.uniform(-20, 20, 20000), rng.uniform(-1e6, 1e6, 2000)])
    floats = np.array([wrap_angle_float(float(a)) for a in angles])
    assert floats.tobytes() == wrap_angle(angles).tobytes()


def test_set_base_pose_checks_limited_base_joints(tmp_path: Path) -> None:
    path = tmp_path / "fenced.xml"
    path.write_text(MOBILE_MJCF.replace('name="root_x" type="slide"', 'name="root_x" type="slide" range="-1 1"'))
    scene = ra.Scene(mobile_robot(path, holonomic=True))
    scene.reset()
    agent = scene.agents[0]
    before = scene.get_state()["physics"]
    with pytest.raises(
        ra.StateError,
        match=r"MobileArm.set_base_pose: qpos of base joint 'root_x' would be 2, outside its limits \[-1, 1\]",
    ):
        agent.set_base_pose(xy=[2.0, 0.0])
    np.testing.assert_array_equal(before, scene.get_state()["physics"])
    agent.set_base_pose(xy=[0.5, 0.3])
    np.testing.assert_allclose(agent.base_pos[0, :2], [0.5, 0.3], atol=1e-9)
    scene.close()
