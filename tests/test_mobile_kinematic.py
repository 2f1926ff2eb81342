"""Kinematic bases (Habitat's navmesh-style base), refused colliding moves, and wheels
that turn with the base's actual motion (differential kinematics)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.envs.empty import EmptyEnv

WHEEL_RADIUS = 0.1
WHEEL_SEPARATION = 0.4

# A wheeled chassis on planar joints with two passive wheels (hinges about the robot's
# left, +y, so positive turns roll forward) that touch the floor, and a 2-joint arm.
WHEELED_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base_link" pos="0 0 0.12">
      <joint name="root_x" type="slide" axis="1 0 0"/>
      <joint name="root_y" type="slide" axis="0 1 0"/>
      <joint name="root_yaw" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.3 0.15 0.1" mass="20"/>
      <body name="l_wheel_link" pos="0 0.2 -0.02">
        <joint name="l_wheel_joint" axis="0 1 0" damping="0.01"/>
        <geom type="cylinder" size="0.1 0.02" euler="1.5708 0 0" mass="1"/>
      </body>
      <body name="r_wheel_link" pos="0 -0.2 -0.02">
        <joint name="r_wheel_joint" axis="0 1 0" damping="0.01"/>
        <geom type="cylinder" size="0.1 0.02" euler="1.5708 0 0" mass="1"/>
      </body>
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


def wheeled_robot(path: Path, dynamics: str, refuse: bool = False, holonomic: bool = False) -> type[ra.Agent]:
    return type(
        "WheeledArm",
        (ra.Agent,),
        {
            "uid": "wheeled_arm",
            "mjcf_path": path,
            "actuators": (
                ra.VelocityActuator(joints="root_.*", damping=(4000.0, 4000.0, 400.0)),
                ra.PDActuator(joints="shoulder|elbow", stiffness=300.0, damping=30.0),
            ),
            "parts": (
                ra.Arm(name="arm", joints="shoulder|elbow", end_effectors=(ra.EndEffector("tool"),)),
                ra.Base(
                    name="base",
                    joints="root_.*",
                    holonomic=holonomic,
                    max_speed=0.5,
                    max_turn=1.0,
                    dynamics=dynamics,
                    refuse_collisions=refuse,
                    wheels=("l_wheel_joint", "r_wheel_joint"),
                    wheel_radius=WHEEL_RADIUS,
                    wheel_separation=WHEEL_SEPARATION,
                ),
            ),
            "keyframes": {"home": ra.Keyframe(qpos={"shoulder": -0.3})},
        },
    )


@pytest.fixture
def wheeled_file(tmp_path: Path) -> Path:
    path = tmp_path / "wheeled.xml"
    path.write_text(WHEELED_MJCF)
    return path


def run(agent: ra.Agent, scene: ra.Scene, action: list[float], seconds: float) -> None:
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(action)
        scene.step()


def planar(agent: ra.Agent) -> np.ndarray:
    return agent.qpos[0, :3].copy()


def wheels(agent: ra.Agent) -> np.ndarray:
    return agent.qpos[0, 3:5].copy()


#: A static wall whose near face is at x = 1.15 m.
WALL = ra.Prop("wall", "box", (0.05, 2.0, 0.3), pos=(1.2, 0.0, 0.3), mass=None)


def make(path: Path, dynamics: str, refuse: bool = False) -> tuple[ra.Scene, ra.Agent]:
    scene = ra.Scene(wheeled_robot(path, dynamics, refuse), control_modes="pd_joint_delta_pos", props=[WALL])
    scene.reset()
    return scene, scene.agents[0]


def test_kinematic_base_holds_while_the_arm_moves(wheeled_file: Path) -> None:
    scene, agent = make(wheeled_file, "kinematic")
    before = planar(agent)
    tool = agent.tcp_pose[0, :3].copy()
    run(agent, scene, [0.5, 0.0, 0.0, 0.0], 1.0)  # arm swings, base commanded still
    assert np.array_equal(planar(agent), before)
    assert np.linalg.norm(agent.tcp_pose[0, :3] - tool) > 0.05  # the arm's dynamics ran
    np.testing.assert_array_equal(wheels(agent), [0.0, 0.0])


def test_kinematic_base_integrates_the_commanded_velocity(wheeled_file: Path) -> None:
    scene, agent = make(wheeled_file, "kinematic")
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 2.0)  # 0.2 m/s forward (+x) for 2 s
    x, y, yaw = planar(agent)
    assert x == pytest.approx(0.4, abs=1e-9) and abs(y) < 1e-12 and abs(yaw) < 1e-12
    np.testing.assert_allclose(wheels(agent), [0.4 / WHEEL_RADIUS] * 2, atol=1e-9)  # distance / radius
    start = planar(agent)
    run(agent, scene, [0.0, 0.0, 0.0, 0.5], 2.0)  # 0.5 rad/s in place
    assert planar(agent)[2] - start[2] == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(planar(agent)[:2], start[:2], atol=1e-12)
    # in place, the left wheel rolls back and the right forward by w b / 2 / r
    turned = 1.0 * WHEEL_SEPARATION / 2 / WHEEL_RADIUS
    np.testing.assert_allclose(wheels(agent) - 4.0, [-turned, turned], atol=1e-9)


def test_kinematic_move_into_a_wall_is_refused(wheeled_file: Path) -> None:
    scene, agent = make(wheeled_file, "kinematic", refuse=True)
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 6.0)  # 1.2 m of commands toward a wall 0.85 m ahead
    x = planar(agent)[0]
    # base front face at x + 0.3 (and the wheels' rims) stop at the wall's face, 1.15 m
    assert 1.15 - 0.3 - 0.2 * scene.control_timestep <= x + 1e-9 and x + 0.3 < 1.15
    assert agent.mobile.refused_moves[0] > 0 and agent.mobile.last_refused[0]
    # without the check the base goes through the wall
    scene, agent = make(wheeled_file, "kinematic", refuse=False)
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 6.0)
    assert planar(agent)[0] == pytest.approx(1.2, abs=1e-9) and agent.mobile.refused_moves[0] == 0


def test_a_base_already_in_the_wall_may_back_out_but_not_go_deeper(wheeled_file: Path) -> None:
    """A base that starts a step touching the world (put there, or something came to rest
    against it) may move out of the contact or along it; a move deeper is refused. Every
    move was refused, so it could never leave."""
    scene, agent = make(wheeled_file, "kinematic", refuse=True)
    agent.set_base_pose([0.87, 0.0], 0.0)  # front face at 1.17 m: 2 cm into the wall
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 0.5)  # deeper: refused
    assert planar(agent)[0] == pytest.approx(0.87, abs=1e-12) and agent.mobile.last_refused[0]
    refused = agent.mobile.refused_moves[0]
    run(agent, scene, [0.0, 0.0, 0.0, 0.5], 0.5)  # turning in place at the wall: a corner goes deeper
    assert planar(agent)[2] == 0.0 and agent.mobile.last_refused[0]
    run(agent, scene, [0.0, 0.0, -0.4, 0.0], 0.5)  # back out at 0.2 m/s for 0.5 s
    assert planar(agent)[0] == pytest.approx(0.87 - 0.1, abs=1e-9) and not agent.mobile.last_refused[0]
    assert agent.mobile.refused_moves[0] >= refused
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 2.0)  # and forward again: it stops at the wall's face
    assert planar(agent)[0] + 0.3 <= 1.15 + 1e-9 and agent.mobile.last_refused[0]
    scene.close()


def test_env_info_reports_refused_moves(wheeled_file: Path) -> None:
    class WalledEmpty(EmptyEnv):
        def _scene_props(self) -> list[ra.Prop]:
            return [WALL]

    env = WalledEmpty(
        robot_uids=wheeled_robot(wheeled_file, "kinematic", True),
        control_mode="pd_joint_delta_pos",
        robot_init_qpos_noise=0.0,
    )
    env.reset(seed=0)
    refused = []
    for _ in range(6 * 20):  # 0.2 m/s toward the wall 0.85 m ahead for 6 s
        refused.append(bool(env.step(np.array([0.0, 0.0, 0.4, 0.0]))[4]["base_move_refused"][0]))
    first = refused.index(True)
    assert 0 < first < len(refused) and all(refused[first:])  # once at the wall, every move is refused
    assert env.agent.mobile.refused_moves[0] == len(refused) - first
    env.close()


def test_dynamic_base_turns_its_wheels_with_its_motion(wheeled_file: Path) -> None:
    scene, agent = make(wheeled_file, "dynamic")
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 2.0)
    x, y, _ = planar(agent)
    assert x == pytest.approx(0.4, rel=0.05) and abs(y) < 0.01
    np.testing.assert_allclose(wheels(agent), [x / WHEEL_RADIUS] * 2, rtol=1e-3)


def test_base_dynamics_can_be_switched_per_robot(wheeled_file: Path) -> None:
    scene, agent = make(wheeled_file, "dynamic")
    agent.set_base_dynamics("kinematic", refuse_collisions=True)
    run(agent, scene, [0.0, 0.0, 0.4, 0.0], 2.0)
    assert planar(agent)[0] == pytest.approx(0.4, abs=1e-9)
    with pytest.raises(ra.ConfigError, match="dynamic"):
        agent.set_base_dynamics("floating")
    with pytest.raises(ra.ConfigError, match="refuse_collisions to be a bool"):
        agent.set_base_dynamics("dynamic", refuse_collisions="no")  # type: ignore[arg-type]
    assert agent.mobile.dynamics == "kinematic" and agent.mobile.refuse_collisions  # unchanged
    with pytest.raises(ra.ConfigError, match="dynamics"):
        ra.Base(name="b", joints="root_.*", dynamics="teleport")
    with pytest.raises(ra.ConfigError, match="wheels"):
        ra.Base(name="b", joints="root_.*", wheels=("l",), wheel_radius=0.1, wheel_separation=0.4)


def test_make_env_overrides_the_base_dynamics(wheeled_file: Path) -> None:
    cls = wheeled_robot(wheeled_file, "dynamic")
    env = ra.make_env(
        "Empty-v1",
        robot_uids=cls,
        base_dynamics="kinematic",
        control_mode="pd_joint_delta_pos",
        robot_init_qpos_noise=0.0,
    )
    env.reset(seed=0)
    agent = env.unwrapped.agent if hasattr(env.unwrapped, "agent") else env.unwrapped.scene.agents[0]
    assert agent.mobile.dynamics == "kinematic"
    start = agent.qpos[0, 0]
    for _ in range(20):
        env.step(np.array([[0.0, 0.0, 0.4, 0.0]]))
    assert agent.qpos[0, 0] - start == pytest.approx(0.2, abs=1e-9)  # 0.2 m/s for 1 s, exactly
    with pytest.raises(ra.ConfigError, match="Base part"):
        ra.make_env("Empty-v1", robot_uids="panda", base_dynamics="kinematic")


def test_the_base_dynamics_are_part_of_the_state() -> None:
    """A state taken with the base kinematic continues kinematic after ``set_state``, bit
    for bit, whatever the base was switched to meanwhile; the refusal counters come back
    too, and a bad base entry is refused with the state unchanged."""
    env = ra.make_env("Empty-v1", robot_uids="fetch", control_mode="pd_joint_delta_pos")
    unwrapped = env.unwrapped
    agent = unwrapped.agent
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, dtype=np.float32)
    action[0, agent.controller.slices["base"].start] = 0.5  # forward
    agent.set_base_dynamics("kinematic", refuse_collisions=True)
    state = unwrapped.get_state()
    assert state["agents"][0]["base"]["dynamics"] == "kinematic"
    first = []
    for _ in range(10):
        first.append(env.step(action)[0])
    agent.set_base_dynamics("dynamic", refuse_collisions=False)
    agent.mobile.refused_moves[:] = 7
    bad = {**state, "agents": [{**state["agents"][0], "base": {**state["agents"][0]["base"], "dynamics": "flying"}}]}
    with pytest.raises(ra.StateError, match="base dynamics 'dynamic' or 'kinematic'"):
        unwrapped.set_state(bad)
    assert agent.mobile.dynamics == "dynamic" and agent.mobile.refused_moves[0] == 7  # unchanged
    unwrapped.set_state(state)
    assert agent.mobile.dynamics == "kinematic" and agent.mobile.refuse_collisions
    assert agent.mobile.refused_moves[0] == 0
    for expected in first:
        np.testing.assert_array_equal(env.step(action)[0], expected)
    env.close()


def test_from_raw_refuses_a_command_of_the_wrong_size() -> None:
    env = ra.make_env("Empty-v1", robot_uids="fetch")
    base = env.unwrapped.agent.controller.parts["base"]
    with pytest.raises(
        ra.ActionError, match=r"from_raw: expected finite raw commands of shape \(\.\.\., 2\), got \(1, 3\)"
    ):
        base.from_raw(np.zeros((1, 3)))
    with pytest.raises(ra.ActionError, match="not finite"):
        base.from_raw(np.array([np.nan, 0.0]))
    np.testing.assert_array_equal(base.from_raw(np.zeros((1, 2))), np.zeros((1, 2)))
    env.close()


def registered_bases() -> list[str]:
    """Registered robots with a planar Base part (a new one joins by being registered)."""
    return [uid for uid in ra.list_agents() if any(isinstance(p, ra.Base) for p in ra.get_agent(uid).check().parts)]


def drive(uid: str, dynamics: str, speed: float, turn: float, steps: int) -> tuple[np.ndarray, float]:
    """Base pose (x, y), yaw after ``steps`` control steps (20 Hz) at ``speed`` (m/s) and
    ``turn`` (rad/s) from the origin, then 10 steps at zero (the pose's error settles)."""
    env = ra.make_env("Empty-v1", robot_uids=uid, base_dynamics=dynamics)
    env.reset(seed=0)
    agent = env.unwrapped.agent
    agent.set_base_pose([0.0, 0.0], 0.0)
    controller = agent.controller
    part = next(p.name for p in agent.parts_by_name.values() if isinstance(p, ra.Base))
    base = controller.parts[part]
    raw = np.zeros((1, base.action_dim))
    raw[0, 0], raw[0, -1] = speed, turn
    action = np.zeros(env.action_space.shape)
    action[0, controller.slices[part]] = base.from_raw(raw)[0]
    for _ in range(steps):
        env.step(action)
    action[0, controller.slices[part]] = base.from_raw(np.zeros_like(raw))[0]
    for _ in range(10):
        env.step(action)
    pose = agent.base_pos[0, :2].copy(), float(agent.base_rot[0])
    env.close()
    return pose


@pytest.mark.parametrize("uid", registered_bases())
@pytest.mark.parametrize("dynamics", ["dynamic", "kinematic"])
def test_built_in_bases_drive_and_turn_by_the_commanded_amounts(uid: str, dynamics: str) -> None:
    """Odometry of every registered base against the command (docs/mobile-manipulators.md,
    "Odometry"): 1 m forward at 0.5 m/s (a slower base, Stretch's 0.3 m/s, at half its top
    speed) and 90 deg in place in 3 s. A kinematic base is exact to rounding; a dynamic
    one within 1 mm sideways and 1 mrad of heading (measured: 0.29 mm, 0.08 mrad)."""
    max_speed = next(p for p in ra.get_agent(uid).check().parts if isinstance(p, ra.Base)).max_speed
    speed = 0.5 if max_speed >= 0.5 else 0.25
    xy, yaw = drive(uid, dynamics, speed, 0.0, round(1.0 / speed / 0.05))
    turned_xy, turned = drive(uid, dynamics, 0.0, np.pi / 6, 60)
    exact = dynamics == "kinematic"
    assert abs(xy[0] - 1.0) < (1e-12 if exact else 1e-4)
    assert abs(xy[1]) < (1e-12 if exact else 1e-3) and abs(yaw) < (1e-12 if exact else 1e-3)
    assert abs(turned - np.pi / 2) < (1e-12 if exact else 1e-4)
    assert np.linalg.norm(turned_xy) < (1e-12 if exact else 1e-4)


@pytest.mark.parametrize("uid", registered_bases())
@pytest.mark.parametrize("dynamics", ["dynamic", "kinematic"])
def test_built_in_bases_drive_the_commanded_arc(uid: str, dynamics: str) -> None:
    """Driving and turning at once (0.5 m/s, Stretch 0.25, and 1 rad/s for 1 s): the base
    ends on the arc the command describes, ``(sin 1, 1 - cos 1) v / w``. The command is
    turned by the heading at mid-step and shortened to the arc's chord: a kinematic base
    lands on the arc exactly (to rounding), a dynamic one within 1.5 % of the arc's
    length (measured 0.04-1.2 %). Turned by the heading at the step's start, every base
    slid outward, 12 mm of 0.5 m kinematic (2.4 %) and 12-18 mm dynamic (2.5-3.6 %)."""
    max_speed = next(p for p in ra.get_agent(uid).check().parts if isinstance(p, ra.Base)).max_speed
    speed = 0.5 if max_speed >= 0.5 else 0.25
    xy, yaw = drive(uid, dynamics, speed, 1.0, 20)
    ideal = np.array([np.sin(1.0), 1.0 - np.cos(1.0)]) * speed
    exact = dynamics == "kinematic"
    assert np.linalg.norm(xy - ideal) < (1e-12 if exact else 0.015 * speed)
    assert abs(yaw - 1.0) < (1e-12 if exact else 5e-3)


def test_base_targets_of_one_env_are_those_of_a_batch() -> None:
    """The base controller's one-env path (Python floats) sends the batch path's targets
    bit for bit: turning, still, and a turn so small that half a step of it is 0."""
    from types import SimpleNamespace

    scene = ra.Scene("fetch", num_envs=5)
    scene.reset()
    base = scene.agents[0].controller.parts["base"]
    rng = np.random.default_rng(0)
    qpos = np.array(scene.world.qpos)
    qpos[:, base.binding.qpos_adr[2]] = [0.3, -0.0, -2.5, 7.0, 1e-9]
    raw = np.c_[rng.uniform(-1.0, 1.0, 5), [0.7, 0.0, -3.0, 1e-300, 5e-324]]
    base.apply(raw, SimpleNamespace(qpos=qpos, qvel=None))
    batch = base.target_qvel.copy()
    for env in range(5):
        base.apply(raw[env : env + 1], SimpleNamespace(qpos=qpos[env : env + 1], qvel=None))
        assert base.target_qvel[0].tobytes() == batch[env].tobytes()
    scene.close()
