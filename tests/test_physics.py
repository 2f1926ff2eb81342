"""Physical claims checked against numbers: kinematics against Franka's DH table,
gravity compensation, a grasp that holds a cube, contact forces, free-floating roots."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents import notes
from tests.conftest import make_pendulum_class

# Franka's modified DH parameters (a, d, alpha) for joints 1..7, then the flange.
DH = [
    (0, 0.333, 0),
    (0, 0, -math.pi / 2),
    (0, 0.316, math.pi / 2),
    (0.0825, 0, math.pi / 2),
    (-0.0825, 0.384, -math.pi / 2),
    (0, 0, math.pi / 2),
    (0.088, 0, math.pi / 2),
]
FLANGE_D = 0.107
HAND_TCP = 0.1034


def dh_transform(a: float, d: float, alpha: float, theta: float) -> np.ndarray:
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -d * sa], [st * sa, ct * sa, ca, d * ca], [0, 0, 0, 1]])


def panda_tcp_from_dh(q: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    for (a, d, alpha), theta in zip(DH, q, strict=True):
        pose = pose @ dh_transform(a, d, alpha, theta)
    pose = pose @ dh_transform(0, FLANGE_D, 0, -math.pi / 4)  # flange, hand turned -45 deg
    return pose @ dh_transform(0, HAND_TCP, 0, 0)


def test_panda_forward_kinematics_match_dh_table() -> None:
    scene = ra.Scene("panda")
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        expected = panda_tcp_from_dh(q[:7])
        tcp = agent.tcp_pose[0]
        np.testing.assert_allclose(tcp[:3], expected[:3, 3], atol=1e-9)  # arm + hand composed at load
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, tcp[3:])
        np.testing.assert_allclose(rotation.reshape(3, 3), expected[:3, :3], atol=1e-9)


def test_panda_limits_from_datasheet() -> None:
    scene = ra.Scene("panda")
    agent = scene.agents[0]
    np.testing.assert_allclose(
        agent.qpos_limits[:7],
        [
            [-2.8973, 2.8973],
            [-1.7628, 1.7628],
            [-2.8973, 2.8973],
            [-3.0718, -0.0698],
            [-2.8973, 2.8973],
            [-0.0175, 3.7525],
            [-2.8973, 2.8973],
        ],
    )
    np.testing.assert_allclose(agent.qpos_limits[7:], [[0, 0.04], [0, 0.04]])
    ids = agent.drives.actuator_ids[agent.drives.columns(agent.part_joints["arm"], "test")]
    np.testing.assert_allclose(scene.model.actuator_forcerange[ids, 1], [87, 87, 87, 87, 12, 12, 12])
    arm_mass = sum(scene.model.body_mass[scene.model.body(f"panda-0/panda_link{i}").id] for i in range(8))
    assert arm_mass == pytest.approx(16.69, abs=0.01)  # identified link masses, link0..link7


def test_gravity_compensation_holds_the_arm_with_motors_off() -> None:
    """With every actuator passive, gravcomp alone keeps the arm still; without it, it falls."""
    drift = {}
    for gravcomp in (True, False):
        cls = type(
            "PandaPassive",
            (ra.get_agent("panda"),),
            {
                "uid": "panda_passive",
                "gravity_compensation": gravcomp,
                "default_control_mode": "off",
                "control_modes": {"off": ra.PassiveConfig(joint_names=ra.get_agent("panda").check().index.joint_names)},
            },
        )
        scene = ra.Scene(cls)
        scene.reset()
        start = scene.agents[0].qpos[0, :7]
        for _ in range(20):  # 1 s
            scene.agents[0].set_action(np.zeros(0))
            scene.step()
        drift[gravcomp] = float(np.max(np.abs(scene.agents[0].qpos[0, :7] - start)))
    assert drift[True] < 1e-6
    assert drift[False] > 0.1


def grasp_scene() -> tuple[ra.Scene, ra.Agent]:
    # A 4 cm, 100 g cube on a pedestal, centred on the Panda's rest TCP (0.615, 0, 0.170).
    props = [
        ra.Prop(
            name="pedestal",
            shape="box",
            size=(0.05, 0.05, 0.075),
            pos=(0.615, 0.0, 0.075),
            mass=None,
            rgba=(0.5, 0.5, 0.5, 1),
        ),
        ra.Prop(name="cube", shape="box", size=(0.02, 0.02, 0.02), pos=(0.615, 0.0, 0.1701), mass=0.1),
    ]
    scene = ra.Scene("panda", props=props, control_modes="pd_joint_pos")
    scene.reset()
    return scene, scene.agents[0]


def test_grasp_holds_and_lifts_a_cube() -> None:
    scene, agent = grasp_scene()
    rest = agent.keyframe_qpos("rest")[:7]
    for _ in range(10):
        agent.set_action(np.concatenate([rest, [1.0]]))  # open, settle
        scene.step()
    assert not agent.is_grasping("cube")[0]
    for _ in range(20):
        agent.set_action(np.concatenate([rest, [-1.0]]))  # close
        scene.step()
    assert agent.is_grasping("cube")[0]
    fingers = agent.qpos[0, 7:]
    np.testing.assert_allclose(fingers, [0.0195, 0.0195], atol=1e-3)  # 4 cm cube, pads 0.5 mm proud
    # Squeeze force: kp * (q - target) = 1000 N/m * (q + 0.01 m) per finger.
    body = lambda name: mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_BODY, name)  # noqa: E731
    sources = [[body("panda-0/panda_leftfinger")], [body("panda-0/panda_rightfinger")], [body("pedestal")]]
    left, right, pedestal = scene.world.contact_forces(sources, body("cube"))[0]
    squeeze = 1000.0 * (fingers[0] + 0.01)
    assert np.linalg.norm(left) == pytest.approx(squeeze, rel=0.1)
    assert np.linalg.norm(right) == pytest.approx(squeeze, rel=0.1)
    # The cube is in equilibrium: the pedestal and the fingers together carry its weight.
    np.testing.assert_allclose(left + right + pedestal, [0.0, 0.0, 0.1 * 9.81], atol=0.05)
    cube_z0 = scene.body_pose("cube")[0, 2]
    lift = rest + np.array([0.0, -0.3, 0.0, 0.2, 0.0, 0.0, 0.0])
    for i in range(60):  # 3 s: lift over 1 s, hold 2 s
        blend = min(1.0, (i + 1) / 20)
        agent.set_action(np.concatenate([rest + blend * (lift - rest), [-1.0]]))
        scene.step()
    cube = scene.body_pose("cube")[0]
    tcp = agent.tcp_pose[0]
    assert cube[2] - cube_z0 > 0.08
    assert np.linalg.norm(cube[:3] - tcp[:3]) < 0.01  # still centred between the pads
    assert agent.is_grasping("cube")[0]
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'cube'"):
        agent.is_grasping("cub")


def test_is_static_reflects_arm_motion() -> None:
    scene = ra.Scene("panda", control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    agent.set_action(np.zeros(8))
    scene.step()
    assert agent.is_static(0.01)[0]
    agent.set_action(np.concatenate([np.ones(7), [0.0]]))
    scene.step()
    assert not agent.is_static(0.2)[0]


def test_free_root_robot_falls_and_starts_at_keyframe_base_pose(pendulum_file: Path) -> None:
    cls = make_pendulum_class(
        pendulum_file,
        fix_root_link=False,
        keyframes={"air": ra.Keyframe(qpos=(0.0, 0.0), base_pos=(0.3, 0.2, 2.0))},  # root pose, not the file's
    )
    scene = ra.Scene(cls)
    scene.reset()
    agent = scene.agents[0]
    assert agent.dof == 2  # the free joint is the base pose, not part of qpos
    np.testing.assert_allclose(agent.base_pose[0], [0.3, 0.2, 2.0, 1, 0, 0, 0])
    assert scene.model.body_gravcomp.max() == 0.0  # off by default for free robots
    for _ in range(4):  # 0.2 s of free fall: z drops by g t^2 / 2 = 0.196 m
        agent.set_action(np.zeros(2))
        scene.step()
    assert agent.base_pose[0, 2] == pytest.approx(2.0 - 0.5 * 9.81 * 0.2**2, abs=2e-3)


def test_agent_state_round_trip_and_rejection() -> None:
    scene = ra.Scene("panda", num_envs=2, control_modes="pd_joint_target_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    agent.set_action(np.full(8, 0.5))
    scene.step()
    saved = agent.get_state()
    assert saved["qpos"].shape == (2, 9) and saved["base_pose"].shape == (2, 7)
    agent.set_control_mode("pd_joint_vel")
    agent.reset(keyframe="ready")
    agent.set_state(saved)
    assert agent.control_mode == "pd_joint_target_delta_pos"
    np.testing.assert_array_equal(agent.qpos, saved["qpos"])
    np.testing.assert_array_equal(agent.qvel, saved["qvel"])
    np.testing.assert_array_equal(
        agent.controller.get_state()["arm"]["target_qpos"], saved["controller"]["arm"]["target_qpos"]
    )
    before = scene.world.get_state()
    with pytest.raises(ra.StateError, match=r"expected qpos of shape \(9,\) or \(2, 9\), got \(2, 7\)"):
        agent.set_state({**saved, "qpos": saved["qpos"][:, :7]})
    with pytest.raises(ra.StateError, match="missing"):
        agent.set_state({"qpos": saved["qpos"]})
    assert np.array_equal(before, scene.world.get_state())
    assert agent.control_mode == "pd_joint_target_delta_pos"


def _agent_round_trip(uid: str, drop: tuple[str, ...] = ()) -> float:
    """Largest difference (time left out) between the physics state 15 steps after a
    robot's own state was saved, and after it was restored (keys ``drop`` left out) once
    3 other steps had moved the robot on: 0.0 for a bit-identical continuation."""
    env = ra.make_env("Empty-v1", robot_uids=uid).unwrapped
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (20, *env.action_space.shape))
    for action in actions[:5]:
        env.step(action)
    saved = {key: value for key, value in env.agent.get_state().items() if key not in drop}
    for action in actions[5:]:
        env.step(action)
    expected = env.get_state()["physics"][:, 1:]
    for action in actions[5:8]:
        env.step(action)
    env.agent.set_state(saved)
    for action in actions[5:]:
        env.step(action)
    difference = float(np.abs(env.get_state()["physics"][:, 1:] - expected).max())
    env.close()
    return difference


@pytest.mark.parametrize("uid", ["unitree_go2", "anymal_c", "panda"])
def test_a_robots_own_state_continues_exactly(uid: str) -> None:
    """With the rest of the scene as it was, ``Agent.set_state`` continues bit for bit:
    the state holds a free base's velocity (the Go2's base kept moving as it was at the
    restore: 0.044 rad apart 15 steps on) and the solver's warm start of the robot's dofs
    (cleared, ANYmal C's feet on the floor ended 4.5e-5 apart). An older state without
    them still restores, as before."""
    assert _agent_round_trip(uid) == 0.0
    if uid == "unitree_go2":
        assert _agent_round_trip(uid, drop=("base_velocity",)) > 1e-3
    if uid == "anymal_c":
        assert _agent_round_trip(uid, drop=("warmstart",)) > 1e-6


def test_a_base_velocity_and_a_warm_start_are_checked() -> None:
    """A ``base_velocity`` for a robot without a free base, one of another shape or
    faster than ``MAX_SPEED``, and a warm start of another shape or with NaN are refused
    before anything is written."""
    env = ra.make_env("Empty-v1", robot_uids="unitree_go2", num_envs=2).unwrapped
    env.reset(seed=0)
    env.step(np.full((2, 12), 0.3))
    agent = env.agent
    saved = agent.get_state()
    assert saved["base_velocity"].shape == (2, 6) and saved["warmstart"].shape == (2, 18)
    before = env.get_state()
    for key, bad, fragment in (
        ("base_velocity", np.zeros((2, 5)), r"expected base_velocity of shape \(6,\) or \(2, 6\)"),
        ("base_velocity", np.full(6, 1e5), "base_velocity"),
        ("warmstart", np.zeros((2, 12)), r"expected warmstart of shape \(18,\) or \(2, 18\)"),
        ("warmstart", np.full((2, 18), np.nan), "warmstart contains NaN"),
    ):
        with pytest.raises(ra.StateError, match=fragment):
            agent.set_state({**saved, key: bad})
        assert repr(env.get_state()) == repr(before)
    panda = ra.make_env("Empty-v1", robot_uids="panda").unwrapped
    panda.reset(seed=0)
    state = panda.agent.get_state()
    assert "base_velocity" not in state and state["warmstart"].shape == (1, 9)
    with pytest.raises(ra.StateError, match="has no free base"):
        panda.agent.set_state({**state, "base_velocity": np.zeros(6)})
    env.close()
    panda.close()


def test_a_state_pushed_past_a_joint_limit_restores() -> None:
    """Joint limits are soft: random end-effector poses press the Panda's joints past
    them (0.056 rad here, up to 0.13 rad measured), and what ``get_state`` saved there
    must restore (a 0.05 rad margin refused it); a joint a radian past is still refused."""
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_ee_pose", num_envs=4).unwrapped
    env.reset(seed=0)
    scene, agent = env.scene, env.agent
    low, high = agent.qpos_limits[:, 0], agent.qpos_limits[:, 1]
    rng = np.random.default_rng(0)
    for _ in range(17):
        agent.set_action(rng.uniform(-1, 1, agent.action_space.shape))
        scene.step()
    past = float(np.max(np.maximum(agent.qpos - high, low - agent.qpos)))
    assert past > 0.05
    saved = agent.get_state()
    agent.reset(keyframe="ready")
    agent.set_state(saved)
    np.testing.assert_array_equal(agent.qpos, saved["qpos"])
    far = saved["qpos"].copy()
    far[0, 3] = high[3] + 1.01
    before = scene.get_state()
    with pytest.raises(ra.StateError, match=r"more than 1\.0 beyond its limits"):
        agent.set_state({**saved, "qpos": far})
    np.testing.assert_array_equal(before["physics"], scene.get_state()["physics"])


def test_instability_is_reported_and_cleared_by_reset(pendulum_file: Path) -> None:
    # A 1e7 N*m/rad gain on a light link at a 2 ms step blows up: MuJoCo resets the
    # env silently, and the world reports it.
    cls = make_pendulum_class(
        pendulum_file,
        control_modes={
            "stiff": ra.PDJointPosConfig(
                joint_names=("shoulder", "elbow"),
                stiffness=1e9,
                damping=0.0,
                effort_limit=1e12,
                normalize_action=False,
            )
        },
    )
    scene = ra.Scene(cls)
    scene.reset(keyframes="down")
    # MuJoCo's warning reaches a program as the library's notes do, a RuntimeWarning (it
    # went to a logger: two ways), raised once MuJoCo's step has returned: a filter set to
    # "error" raises it from step, after the step (inside MuJoCo's callback it would abort)
    raised = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for _ in range(5):
            scene.agents[0].set_action([2.0, -2.0])
            try:
                scene.step()
            except RuntimeWarning as note:
                raised.append(str(note))
    assert raised and all(n.startswith("BatchedWorld.step: MuJoCo: ") and "unstable" in n for n in raised)
    assert notes.RUNTIME == []  # every message passed on, none left for a later call
    assert scene.world.instability_counts()[0] > 0
    scene.reset()
    assert scene.world.instability_counts()[0] == 0


def test_free_robot_keyframe_base_is_relative_to_its_mount(pendulum_file: Path) -> None:
    cls = make_pendulum_class(
        pendulum_file,
        fix_root_link=False,
        keyframes={"air": ra.Keyframe(qpos=(0.0, 0.0), base_pos=(0.1, 0.0, 1.0))},
    )
    quarter_turn = (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))  # 90 deg about z
    scene = ra.Scene([cls, cls], robot_poses=[(0, 0, 0, 1, 0, 0, 0), (2.0, 0.0, 0.0, *quarter_turn)])
    scene.reset()
    np.testing.assert_allclose(scene.agents[0].base_pose[0], [0.1, 0, 1, 1, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(scene.agents[1].base_pose[0], [2.0, 0.1, 1, *quarter_turn], atol=1e-12)


def test_instability_is_in_info_and_can_raise(
    pendulum_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo would write MUJOCO_LOG.TXT here
    stiff = {
        "stiff": ra.PDJointPosConfig(
            joint_names=("shoulder", "elbow"), stiffness=1e9, damping=0.0, effort_limit=1e12, normalize_action=False
        )
    }
    cls = make_pendulum_class(pendulum_file, uid="unstable_pendulum", control_modes=stiff)
    env = ra.RobotEnv(robot_uids=cls, num_envs=2, robot_init_qpos_noise=0.0)
    env.reset(seed=0)
    _, _, _, _, info = env.step(np.zeros((2, 2)))
    np.testing.assert_array_equal(info["physics_unstable"], [False, False])
    flags = []
    # MuJoCo's warning, passed on as the library's notes are (robot_agents.notes)
    with pytest.warns(RuntimeWarning, match=r"BatchedWorld.step: MuJoCo: .*simulation is unstable"):
        for _ in range(5):
            _, _, _, _, info = env.step(np.array([[2.0, -2.0], [0.0, 0.0]]))  # env 0 blows up, env 1 holds
            flags.append(info["physics_unstable"].copy())
    assert any(f[0] for f in flags) and not any(f[1] for f in flags)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    world = env.scene.world
    total = world.unstable_steps.copy()
    assert total[0] > 0 and total[1] == 0
    env.reset(seed=0)  # MuJoCo's own counters are cleared by a reset; ours keep counting
    np.testing.assert_array_equal(world.instability_counts(), [0, 0])
    np.testing.assert_array_equal(world.unstable_steps, total)
    raising = ra.RobotEnv(robot_uids=cls, raise_on_instability=True)
    raising.reset(seed=0)
    with (
        pytest.raises(ra.PhysicsError, match=r"unstable in env\(s\) \[0\].*lower the gains"),
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", RuntimeWarning)  # (MuJoCo's note, seen above)
        for _ in range(5):
            raising.step(np.array([2.0, -2.0]))


def test_observed_poses_match_observed_joints_and_survive_a_state_round_trip() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_delta_pos", num_envs=2)
    env.reset(seed=0)
    agent = env.unwrapped.agent
    for _ in range(3):
        env.step(np.ones((2, 8)))  # fast motion: a stale pose would lag by millimetres
    expected = agent.frame_pose("tcp", qpos=agent.qpos)  # forward kinematics at the observed joints
    np.testing.assert_allclose(agent.tcp_pose, expected, atol=1e-12)
    u = env.unwrapped
    before = u._get_obs().copy()
    u.set_state(u.get_state())
    np.testing.assert_array_equal(u._get_obs(), before)
