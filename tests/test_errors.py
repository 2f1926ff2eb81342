"""Bad input raises a library error that says where, what was expected, what was given
and what is available, and leaves the simulation exactly as it was."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import robot_agents as ra
from tests.conftest import INERTIAL, make_pendulum_class


@pytest.fixture
def env():  # type: ignore[no-untyped-def]
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, control_mode="pd_joint_target_delta_pos")
    env.reset(seed=0)
    env.step(np.full((2, 8), 0.3))
    yield env
    env.close()


def assert_unchanged(env, call: Callable[[], object], error: type[Exception], *fragments: str) -> None:  # type: ignore[no-untyped-def]
    before = env.unwrapped.get_state()
    ctrl_before = env.unwrapped.scene.world.ctrl.copy()
    targets = env.unwrapped.agent.drives.targets
    targets_before = [targets.position.copy(), targets.velocity.copy(), targets.effort.copy()]
    mode_before = env.unwrapped.agent.control_mode
    with pytest.raises(error) as caught:
        call()
    message = str(caught.value)
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"
    assert isinstance(caught.value, ra.RobotAgentsError)
    after = env.unwrapped.get_state()
    assert np.array_equal(before["physics"], after["physics"])
    assert env.unwrapped.agent.control_mode == mode_before
    np.testing.assert_array_equal(ctrl_before, env.unwrapped.scene.world.ctrl)
    for before_targets, now in zip(targets_before, (targets.position, targets.velocity, targets.effort), strict=True):
        np.testing.assert_array_equal(before_targets, now)
    for part, state in before["agents"][0]["controller"].items():
        for key, value in state.items():
            np.testing.assert_array_equal(value, after["agents"][0]["controller"][part][key])


@pytest.mark.parametrize(
    ("action", "fragments"),
    [
        (np.zeros((2, 7)), ["expected shape (2, 8) or (8,)", "got (2, 7)", "arm: 7, gripper: 1"]),
        (np.zeros(9), ["got (9,)"]),
        (np.zeros((3, 8)), ["got (3, 8)"]),
        (np.array([["a"] * 8] * 2), ["expected a float", "dtype <U1"]),
        (np.zeros((2, 8), dtype=complex), ["dtype complex128"]),
        (np.zeros((2, 8), dtype=bool), ["dtype bool"]),
        ([[0.0] * 8, [0.0] * 7], ["expected a numeric array"]),
        (np.full((2, 8), math.nan), ["NaN or inf", "(env, index) [[0, 0]"]),
        (np.where(np.eye(2, 8) > 0, np.inf, 0.0), ["NaN or inf", "[[0, 0], [1, 1]]"]),
    ],
)
def test_bad_actions_rejected_state_unchanged(env, action: object, fragments: list[str]) -> None:  # type: ignore[no-untyped-def]
    assert_unchanged(
        env, lambda: env.step(action), ra.ActionError, "Panda.set_action", "pd_joint_target_delta_pos", *fragments
    )


def test_unknown_control_mode(env) -> None:  # type: ignore[no-untyped-def]
    assert_unchanged(
        env,
        lambda: env.unwrapped.set_control_mode("pd_joint_delta"),
        ra.UnknownNameError,
        "unknown control mode 'pd_joint_delta'",
        "Did you mean 'pd_joint_delta_pos'",
        "'pd_joint_vel'",
    )
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'pd_ee_delta_pose'"):
        ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_ee_delta_pse")


def test_unknown_keyframe(env) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    assert_unchanged(
        env,
        lambda: agent.reset(keyframe="rset"),
        ra.UnknownNameError,
        "unknown keyframe 'rset'",
        "Did you mean 'rest'",
        "'ready'",
    )


@pytest.mark.parametrize(
    ("kwargs", "fragments"),
    [
        ({"qpos": np.zeros(7)}, ["expected qpos of shape (9,) or (2, 9)", "got (7,)"]),
        ({"qpos": np.zeros((3, 9))}, ["got (3, 9)"]),
        ({"qpos": np.full(9, math.nan)}, ["NaN or inf"]),
        ({"qpos": np.zeros(9)}, ["'panda_joint4' is 0", "outside its limits [-3.0718, -0.0698]"]),
        ({"keyframe": "rest", "qvel": np.zeros(4)}, ["qvel of shape (9,)"]),
        ({"keyframe": "rest", "env_ids": [5]}, ["env ids in [0, 2)", "[5]"]),
    ],
)
def test_bad_reset_arguments(env, kwargs: dict[str, object], fragments: list[str]) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    assert_unchanged(env, lambda: agent.reset(**kwargs), ra.StateError, "Panda.reset", *fragments)


def test_bad_set_state(env) -> None:  # type: ignore[no-untyped-def]
    u = env.unwrapped
    state = u.get_state()
    bad_physics = {**state, "physics": state["physics"][:, :-1]}
    assert_unchanged(env, lambda: u.set_state(bad_physics), ra.StateError, "expected a physics state of shape (2,")
    bad_mode = {**state, "agents": [{**state["agents"][0], "control_mode": "nope"}]}
    assert_unchanged(env, lambda: u.set_state(bad_mode), ra.UnknownNameError, "unknown control mode 'nope'")
    assert_unchanged(env, lambda: u.set_state({"physics": 1}), ra.StateError, "keys 'physics' and 'agents'")


def test_a_misspelt_state_key_is_refused_not_ignored(env) -> None:  # type: ignore[no-untyped-def]
    """An unknown key of a state (env, vector env, scene, a scene's robot entry, a
    robot's own) is refused with the closest key: ignored, the part it meant (the step
    counts here) would silently stay as it was."""
    u = env.unwrapped
    state, agent_state = u.get_state(), u.agent.get_state()
    env.step(np.zeros((2, 8)))
    misspelt = {key if key != "elapsed_steps" else "elapsed_step": value for key, value in state.items()}
    assert_unchanged(
        env, lambda: u.set_state(misspelt), ra.StateError, "['elapsed_step']", "did you mean 'elapsed_steps'?"
    )
    np.testing.assert_array_equal(u.elapsed_steps, [2, 2])
    vector_state = {**state, "autoreset": np.zeros(2, dtype=bool)}
    assert_unchanged(env, lambda: u.set_state(vector_state), ra.StateError, "RobotVectorEnv.set_state")
    assert_unchanged(env, lambda: u.scene.set_state(state), ra.StateError, "restore it with RobotEnv.set_state")
    robot = {**state, "agents": [agent_state]}  # a robot's own state in the scene's list: its joints would be lost
    assert_unchanged(env, lambda: u.set_state(robot), ra.StateError, "['base_pose', 'qpos', 'qvel', 'warmstart']")
    extra = {**agent_state, "control_modes": agent_state["control_mode"]}
    assert_unchanged(env, lambda: u.agent.set_state(extra), ra.StateError, "did you mean 'control_mode'?")
    drives = {**agent_state, "drives": {**agent_state["drives"], "positions": agent_state["drives"]["position"]}}
    assert_unchanged(env, lambda: u.agent.set_state(drives), ra.StateError, "unknown drive target keys ['positions']")
    fetch = ra.make_env("Empty-v1", robot_uids="fetch", num_envs=2).unwrapped
    fetch.reset(seed=0)
    fetch_state = fetch.get_state()
    base = {**fetch_state["agents"][0], "base": {**fetch_state["agents"][0]["base"], "refused_move": 0}}
    with pytest.raises(ra.StateError, match="did you mean 'refused_moves'"):
        fetch.set_state({**fetch_state, "agents": [base]})
    np.testing.assert_array_equal(fetch.get_state()["physics"], fetch_state["physics"])
    fetch.close()
    vector = gym.make_vec("robot_agents/Empty-v1", num_envs=2, vectorization_mode="vector_entry_point")
    vector.reset(seed=0)
    saved = vector.get_state()
    renamed = {key if key != "autoreset" else "auto_reset": value for key, value in saved.items()}
    with pytest.raises(ra.StateError, match="did you mean 'autoreset'"):
        vector.set_state(renamed)
    vector.set_state(saved)
    vector.close()


def test_keyframe_of_wrong_size_fails_at_load(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, keyframes={"bad": ra.Keyframe(qpos=(0.1, 0.2, 0.3))})
    with pytest.raises(ra.ConfigError) as err:
        ra.Scene(cls)
    assert "keyframes['bad']" in str(err.value) and "expected 2 joint positions (shoulder, elbow), got 3" in str(
        err.value
    )


def test_unknown_joint_in_control_mode(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, control_modes={"m": ra.PDJointPosConfig(joint_names=("shoulder", "elbw"))})
    with pytest.raises(ra.UnknownNameError) as err:
        ra.Scene(cls)
    assert "control_modes['m']" in str(err.value) and "unknown joint 'elbw'" in str(err.value)
    assert "Did you mean 'elbow'" in str(err.value)


def test_unknown_link_names_in_declaration(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, link_materials={"lnk1": ra.FrictionMaterial()})
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'link1'"):
        ra.Scene(cls)
    cls = make_pendulum_class(
        pendulum_file, parts=(ra.Arm(name="arm", joints=".*", end_effectors=(ra.EndEffector("tipp"),)),)
    )
    with pytest.raises(ra.UnknownNameError, match=r"end effector 'tipp'.*Did you mean 'tip'"):
        ra.Scene(cls)


def test_missing_model_file(tmp_path: Path) -> None:
    cls = make_pendulum_class(tmp_path / "nowhere.xml")
    with pytest.raises(ra.ModelError, match=r"nowhere.xml' does not exist"):
        ra.Scene(cls)


@pytest.mark.parametrize(
    ("name", "text", "fragment"),
    [
        ("broken.xml", "<mujoco><worldbody><body></worldbody></mujoco>", "not well-formed XML"),
        ("wrong_root.xml", "<robot name='x'/>", "expected an MJCF file with a <mujoco> root"),
        (
            "bad_attr.xml",
            "<mujoco><worldbody><body><joint type='spiral'/><geom size='.1'/></body></worldbody></mujoco>",
            "MuJoCo rejected",
        ),
        ("broken.urdf", "<robot name='x'><link name='a'></robot>", "not well-formed XML"),
        ("empty.urdf", "<robot name='x'/>", "has no <link>"),
        ("notes.txt", "hello", "ending in .urdf, .xml or .mjcf"),
    ],
)
def test_malformed_model_files(tmp_path: Path, name: str, text: str, fragment: str) -> None:
    path = tmp_path / name
    path.write_text(text)
    cls = make_pendulum_class(path)
    with pytest.raises(ra.ModelError) as err:
        ra.Scene(cls)
    assert fragment in str(err.value) and name in str(err.value)


def _urdf(joint_type: str = "revolute", mesh: str | None = None, floating_below_root: bool = False) -> str:
    geometry = f'<mesh filename="{mesh}"/>' if mesh else '<box size="0.1 0.1 0.1"/>'
    extra = ""
    if floating_below_root:
        extra = f'<link name="c">{INERTIAL.format(m=1)}</link><joint name="float" type="floating"><parent link="b"/><child link="c"/></joint>'
    return f"""<robot name="r">
  <link name="a">{INERTIAL.format(m=1)}<collision><geometry>{geometry}</geometry></collision></link>
  <link name="b">{INERTIAL.format(m=1)}</link>
  <joint name="j" type="{joint_type}"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>{extra}
</robot>"""


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        (_urdf(joint_type="spherical"), "has type 'spherical'; expected one of revolute"),
        (_urdf(mesh="meshes/base.dae"), "mesh 'meshes/base.dae' referenced by"),
        (_urdf(mesh="package://my_robot/meshes/base.stl"), "was not found; looked at"),
        (_urdf(floating_below_root=True), "floating joint 'float'"),
    ],
)
def test_urdf_with_unsupported_pieces(tmp_path: Path, text: str, fragment: str) -> None:
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    cls = make_pendulum_class(
        path,
        actuators=(ra.PDActuator(joints="j", stiffness=10.0),),
        parts=(),
        control_modes={"m": ra.PDJointPosConfig(joint_names=("j",))},
        keyframes={},
    )
    with pytest.raises(ra.ModelError) as err:
        ra.Scene(cls)
    assert fragment in str(err.value)


def test_user_urdf_loads_and_moves(urdf_file: Path) -> None:
    class TwoLink(ra.Agent):
        uid = "two_link"
        urdf_path = urdf_file
        actuators = (ra.PDActuator(joints="joint_[ab]", stiffness=300.0, damping=30.0, effort_limit=(50.0, 20.0)),)
        # the tool is a fixed link: kept as a body
        parts = (ra.Arm(name="arm", joints="joint_[ab]", end_effectors=(ra.EndEffector("tool"),)),)
        keyframes = {"home": ra.Keyframe(qpos={"joint_a": 0.0, "joint_b": 0.5})}
        control_modes = ra.joint_control_modes(ra.JointGroup(joint_names=("joint_a", "joint_b")))

    scene = ra.Scene(TwoLink, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    assert agent.joint_names == ("joint_a", "joint_b")
    np.testing.assert_allclose(agent.qpos_limits, [[-3, 3], [-2, 2]])
    for _ in range(40):
        agent.set_action([0.4, -0.6])
        scene.step()
    np.testing.assert_allclose(agent.qpos[0], [0.4, -0.6], atol=2e-3)
    # Forward kinematics of the tool frame: base 0.05 + upper 0.3 up, then 0.2 along the bent lower link.
    # Its base box reaches 5 cm into the floor at the origin: the robot is mounted 1 mm above.
    assert agent.base_pose[0, 2] == pytest.approx(0.051)
    height = agent.base_pose[0, 2]
    expected = np.array(
        [np.cos(0.4) * 0.2 * np.sin(-0.6), np.sin(0.4) * 0.2 * np.sin(-0.6), height + 0.35 + 0.2 * np.cos(-0.6)]
    )
    np.testing.assert_allclose(agent.tcp_pose[0, :3], expected, atol=2e-3)


def test_urdf_package_mesh_resolves(tmp_path: Path) -> None:
    pkg = tmp_path / "my_robot"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    # A tetrahedron as a Wavefront OBJ.
    (pkg / "meshes" / "base.obj").write_text(
        "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    )
    path = pkg / "urdf" / "robot.urdf"
    path.write_text(_urdf(mesh="package://my_robot/meshes/base.obj"))
    cls = make_pendulum_class(
        path,
        actuators=(ra.PDActuator(joints="j", stiffness=10.0),),
        parts=(),
        control_modes={"m": ra.PDJointPosConfig(joint_names=("j",), normalize_action=False)},
        keyframes={},
    )
    scene = ra.Scene(cls)
    assert scene.model.nmesh == 1


def test_scene_argument_errors() -> None:
    with pytest.raises(ra.ConfigError, match="multiple of control_freq"):
        ra.Scene("panda", sim_freq=500, control_freq=30)
    with pytest.raises(ra.ConfigError, match="positive integer"):
        ra.Scene("panda", sim_freq=0)
    with pytest.raises(ra.ConfigError, match="num_envs to be a whole number >= 1, got 0"):
        ra.Scene("panda", num_envs=0)
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'panda'"):
        ra.Scene("pand")
    with pytest.raises(ra.ConfigError, match="one mode per robot"):
        ra.Scene(["panda", "panda"], control_modes=["pd_joint_pos"])
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'rgbd'"):
        ra.make_env("Empty-v1", obs_mode="rgbdd")


def test_reset_arguments_in_the_other_order_say_which_keyword_to_use() -> None:
    """``Scene.reset`` takes env ids first, ``Agent.reset`` a keyframe first: each call
    in the other's order names the keyword to use, and changes nothing."""
    scene = ra.Scene("panda", num_envs=2)
    scene.reset()
    before = scene.world.get_state().copy()
    with pytest.raises(ra.StateError, match=r"got 'rest'; a keyframe goes by keyword: reset\(keyframes='rest'\)"):
        scene.reset("rest")  # type: ignore[arg-type]
    with pytest.raises(
        ra.StateError, match=r"got \[0\]; env ids go by keyword: reset\(env_ids=...\). Keyframes: 'rest'"
    ):
        scene.agents[0].reset([0])  # type: ignore[arg-type]
    np.testing.assert_array_equal(scene.world.get_state(), before)
    scene.close()


def test_bad_controller_state_rejected(env) -> None:  # type: ignore[no-untyped-def]
    u = env.unwrapped
    state = u.get_state()
    controller = state["agents"][0]["controller"]
    bad_shape = {**controller, "arm": {**controller["arm"], "target_qpos": np.zeros((2, 6))}}
    bad = {**state, "agents": [{**state["agents"][0], "controller": bad_shape}]}
    assert_unchanged(
        env, lambda: u.set_state(bad), ra.StateError, "arm.target_qpos of shape (2, 7)", "got shape (2, 6)"
    )
    missing = {**state, "agents": [{**state["agents"][0], "controller": {"arm": controller["arm"]}}]}
    assert_unchanged(env, lambda: u.set_state(missing), ra.StateError, "parts ['arm', 'gripper']")


def test_unknown_gripper_and_finger_names(pendulum_file: Path) -> None:
    def gripper(joints: str, fingers: tuple[str, str]) -> tuple[ra.Arm, ra.Gripper]:
        return (
            ra.Arm(name="arm", joints="shoulder"),
            ra.Gripper(name="gripper", joints=joints, open=0.5, closed=0.0, fingers=fingers),
        )

    cls = make_pendulum_class(pendulum_file, parts=gripper("elbo", ("link1", "link2")))
    with pytest.raises(
        ra.UnknownNameError, match=r"part 'gripper'.*unknown joint \(pattern\) 'elbo'.*Did you mean 'elbow'"
    ):
        ra.Scene(cls)
    cls = make_pendulum_class(pendulum_file, parts=gripper("elbow", ("link1", "lnk2")))
    with pytest.raises(ra.UnknownNameError, match=r"fingers.*Did you mean 'link2'"):
        ra.Scene(cls)
    arm, jaw = gripper("elbow", ("link1", "link2"))
    cls = make_pendulum_class(pendulum_file, parts=(arm, dataclasses.replace(jaw, grasp_frame="lnk2")))
    with pytest.raises(ra.UnknownNameError, match=r"'gripper'\.grasp_frame.*'lnk2'.*Did you mean 'link2'"):
        ra.Scene(cls)
    with pytest.raises(ra.ConfigError, match=r"grasp_frame: expected a body or site name or None, got ''"):
        dataclasses.replace(jaw, grasp_frame="")


def test_scene_reset_checks_every_robot_before_rewinding_any_env() -> None:
    scene = ra.Scene(("panda", "widowx250s"))
    scene.reset()
    rng = np.random.default_rng(0)
    for _ in range(3):
        for agent in scene.agents:
            agent.set_action(rng.uniform(-1, 1, agent.action_space.shape))
        scene.step()
    before = scene.get_state()
    for kwargs, fragment in (
        ({"qpos": [None, np.zeros(2)]}, "Scene.reset (WidowX250S): expected qpos of shape (8,)"),
        ({"qpos": [np.full(9, 10.0), None]}, "Scene.reset (Panda): qpos of joint 'panda_joint1' is 10"),
        ({"qpos": [None]}, "one qpos (or None) per robot (2), got 1"),
        ({"qpos": 5}, "one qpos (or None) per robot (2), got 5"),
    ):
        with pytest.raises(ra.StateError) as caught:
            scene.reset(**kwargs)  # type: ignore[arg-type]
        assert fragment in str(caught.value)
        after = scene.get_state()
        np.testing.assert_array_equal(before["physics"], after["physics"])
        for was, now in zip(before["agents"], after["agents"], strict=True):
            for part, state in was["controller"].items():
                for key, value in state.items():
                    np.testing.assert_array_equal(value, now["controller"][part][key])
    scene.close()


@pytest.mark.parametrize(
    ("mount_pose", "fragment"),
    [
        ((math.nan, 0, 0, 1, 0, 0, 0), "(NaN or inf)"),
        ((0, 0, 0), "expected 7 finite numbers (x, y, z, qw, qx, qy, qz)"),
        ((0, 0, 0, 0, 0, 0, 0), "expected a unit quaternion (qw, qx, qy, qz), got (0.0, 0.0, 0.0, 0.0) (zero)"),
        ("0000000", "expected 7 finite numbers"),
        ((0, 0, 0, True, 0, 0, 0), "expected 7 finite numbers"),
    ],
)
def test_mount_pose_is_checked_with_the_declaration(pendulum_file: Path, mount_pose: object, fragment: str) -> None:
    cls = make_pendulum_class(pendulum_file, uid="test_bad_mount", mount_pose=mount_pose)
    with pytest.raises(ra.ConfigError) as caught:
        cls.check()
    assert "Pendulum.mount_pose" in str(caught.value) and fragment in str(caught.value)
    with pytest.raises(ra.ConfigError, match=r"Pendulum\.mount_pose"):
        ra.register_agent()(make_pendulum_class(pendulum_file, uid="test_bad_mount", mount_pose=mount_pose))
    assert "test_bad_mount" not in ra.list_agents()


def test_a_non_unit_mount_quaternion_is_normalized(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, mount_pose=(0.1, 0, 0.2, 2.0, 0, 0, 0))
    assert cls.check().mount_pose == (0.1, 0.0, 0.2, 1.0, 0.0, 0.0, 0.0)
    scene = ra.Scene(cls)
    np.testing.assert_allclose(scene.agents[0].base_pose[0, 3:], [1, 0, 0, 0], atol=1e-12)
    scene.close()


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"fix_root_link": "yes"}, "Pendulum: expected fix_root_link to be a bool, got 'yes'."),
        ({"disable_self_collisions": 1}, "Pendulum: expected disable_self_collisions to be a bool, got 1."),
        ({"gravity_compensation": "yes"}, "expected gravity_compensation to be a bool, None or a tuple of body names"),
        ({"mjcf_path": None, "urdf_path": 5}, "Pendulum.urdf_path: expected a file path (str or pathlib.Path), got 5."),
        ({"mjcf_path": 5}, "Pendulum.mjcf_path: expected a file path (str or pathlib.Path), got 5."),
    ],
)
def test_declared_flags_and_paths_are_typed(pendulum_file: Path, attrs: dict[str, object], message: str) -> None:
    cls = make_pendulum_class(pendulum_file, uid="test_bad_flag", **attrs)
    with pytest.raises(ra.ConfigError) as caught:
        ra.register_agent()(cls)
    assert message in str(caught.value)
    with pytest.raises(ra.ConfigError) as caught:
        ra.Scene(cls)
    assert message in str(caught.value)


def test_set_state_refuses_absurd_speeds(env) -> None:  # type: ignore[no-untyped-def]
    u = env.unwrapped
    state = u.get_state()
    physics = state["physics"].copy()
    physics[1, 1 + u.model.nq + 3] = 1e7  # env 1, the 4th joint speed
    assert_unchanged(
        env,
        lambda: u.set_state({**state, "physics": physics}),
        ra.StateError,
        "Scene.set_state: expected joint speeds below 10000 (rad/s or m/s)",
        "got up to 1e+07",
    )
    agent_state = u.agent.get_state()
    assert_unchanged(
        env,
        lambda: u.agent.set_state({**agent_state, "qvel": np.full_like(agent_state["qvel"], 1e7)}),
        ra.StateError,
        "Panda.set_state: expected joint speeds below 10000",
    )


def test_set_state_refuses_a_zero_base_quaternion() -> None:
    env = ra.make_env("Empty-v1", robot_uids="anymal_c")
    env.reset(seed=0)
    env.step(env.action_space.sample())
    agent = env.unwrapped.agent
    state = agent.get_state()
    for bad in ([0, 0, 0.5, 0, 0, 0, 0], [0, 0, 0.5, 1e-12, 0, 0, 0]):
        assert_unchanged(
            env,
            lambda bad=bad: agent.set_state({**state, "base_pose": np.array(bad)}),
            ra.StateError,
            "AnymalC.set_state: expected base_pose (x, y, z, qw, qx, qy, qz) with a unit quaternion",
        )
    agent.set_state(state)  # a get_state() pose is restored bit for bit
    np.testing.assert_array_equal(agent.base_pose, state["base_pose"])
    agent.set_state({**state, "base_pose": np.array([0, 0, 0.6, 2.0, 0, 0, 0])})  # normalized
    np.testing.assert_allclose(agent.base_pose[0, 3:], [1, 0, 0, 0], atol=1e-12)
    env.close()


def test_make_env_rejects_a_render_mode_the_task_does_not_offer() -> None:
    for mode in ("human", "rgb"):
        with pytest.raises(ra.UnknownNameError) as caught:
            ra.make_env("Empty-v1", robot_uids="panda", render_mode=mode)
        assert f"make_env('Empty-v1'): unknown render_mode '{mode}'" in str(caught.value)
        assert "Available: 'rgb_array'." in str(caught.value)


def test_misspelt_keywords_are_named_with_suggestions() -> None:
    import gymnasium

    with pytest.raises(ra.UnknownNameError) as caught:
        ra.make_env("Empty-v1", robot_uids="panda", contol_mode="pd_joint_pos")
    message = str(caught.value)
    assert "make_env('Empty-v1'): unknown keyword argument 'contol_mode'. Did you mean 'control_mode'" in message
    assert "'render_size'" in message and "'robot_uids'" in message
    with pytest.raises(ra.UnknownNameError, match=r"unknown keyword argument 'robot_uid'\. Did you mean 'robot_uids'"):
        gymnasium.make_vec(
            "robot_agents/PickCube-v1", num_envs=2, vectorization_mode="vector_entry_point", robot_uid="panda"
        )
    # a task's own keywords are accepted and suggested
    with pytest.raises(ra.UnknownNameError, match=r"PickCubeEnv: unknown keyword argument 'reward_mod'.*'reward_mode'"):
        gymnasium.make("robot_agents/PickCube-v1", reward_mod="dense")
    with pytest.raises(ra.UnknownNameError, match=r"EmptyEnv: unknown keyword argument 'sleeep'.*Did you mean 'sleep'"):
        ra.envs.EmptyEnv(sleeep=True)


@pytest.mark.parametrize("size", ["ab", 5, None, (-1, 10), (100000, 100000), (0, 0), (10.5, 3), (True, 5), (1, 2, 3)])
def test_render_size_is_checked(size: object) -> None:
    with pytest.raises(ra.ConfigError) as caught:
        ra.make_env("Empty-v1", robot_uids="panda", render_mode="rgb_array", render_size=size)
    assert (
        f"EmptyEnv: expected render_size to be (width, height), integer numbers of pixels in [1, 8192], got {size!r}."
        in str(caught.value)
    )


def test_arm_joint_pos_setter_checks_the_joint_limits(env) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    assert_unchanged(
        env,
        lambda: setattr(agent, "arm_joint_pos", np.full(7, 10.0)),
        ra.StateError,
        "Panda.arm_joint_pos: qpos of joint 'panda_joint1' is 10, outside its limits [-2.8973, 2.8973].",
    )
    assert_unchanged(
        env,
        lambda: agent.manipulator.set_arm_joint_pos(np.full(7, math.nan)),
        ra.StateError,
        "Panda.arm_joint_pos: arm joint positions contains NaN or inf at (env, index) [[0, 0], [0, 1], [0, 2], [0, 3]] "
        "and 10 more; expected finite values",
    )
    assert_unchanged(
        env,
        lambda: agent.set_gripper_target_state("closed"),
        ra.StateError,
        "Panda.set_gripper_target_state: expected a state in [0, 1] or 2 of them, got 'closed'.",
    )
    inside = agent.keyframe_qpos(agent.default_keyframe())[:7]
    agent.arm_joint_pos = inside
    np.testing.assert_allclose(agent.arm_joint_pos, np.broadcast_to(inside, (2, 7)))


def test_malformed_agent_states_rejected(env) -> None:  # type: ignore[no-untyped-def]
    u = env.unwrapped
    state = u.get_state()
    not_a_list = {**state, "agents": 5}
    assert_unchanged(env, lambda: u.set_state(not_a_list), ra.StateError, "expected 'agents' to be a list", "got int")
    not_a_dict = {**state, "agents": ["pd_joint_pos"]}
    assert_unchanged(
        env, lambda: u.set_state(not_a_dict), ra.StateError, "agents[0] (panda-0)", "'control_mode' and 'controller'"
    )
    no_controller = {**state, "agents": [{"control_mode": state["agents"][0]["control_mode"]}]}
    assert_unchanged(env, lambda: u.set_state(no_controller), ra.StateError, "agents[0] (panda-0)")


@pytest.mark.parametrize("options", [3, "abc", [1, 2]])
def test_vector_reset_rejects_options_that_are_not_a_dict(options: object) -> None:
    from robot_agents.envs import RobotVectorEnv

    vec = RobotVectorEnv("Empty-v1", num_envs=2, robot_uids="panda")
    vec.reset(seed=0)
    before = vec.env.get_state()
    with pytest.raises(ra.ConfigError, match=r"RobotVectorEnv.reset: expected options to be a dict"):
        vec.reset(options=options)  # type: ignore[arg-type]
    np.testing.assert_array_equal(before["physics"], vec.env.get_state()["physics"])
    vec.close()


@pytest.mark.parametrize(("env_ids", "fragment"), [([5], "[5]"), ("a", "['a']"), ([-1], "[-1]"), ([1, 1], "distinct")])
def test_camera_rig_checks_env_ids(env, env_ids: object, fragment: str) -> None:  # type: ignore[no-untyped-def]
    rig = env.unwrapped.scene.cameras
    world = env.unwrapped.scene.world
    with pytest.raises(ra.StateError) as caught:
        rig.capture(world, ("rgb",), env_ids=env_ids)  # type: ignore[arg-type]
    assert "CameraRig.capture" in str(caught.value) and fragment in str(caught.value)


def test_camera_rig_checks_camera_keys_and_textures(env) -> None:  # type: ignore[no-untyped-def]
    rig = env.unwrapped.scene.cameras
    with pytest.raises(ra.UnknownNameError, match=r"unknown camera .*Available: 'base_camera'"):
        rig.camera_id(["base_camera"])  # type: ignore[arg-type]
    with pytest.raises(ra.UnknownNameError, match="unknown texture"):
        rig.capture(env.unwrapped.scene.world, 5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kwargs", "error", "fragment"),
    [
        ({"restarts": "a"}, ra.ConfigError, "restarts to be a whole number >= 0, got 'a'"),
        ({"restarts": 1.5}, ra.ConfigError, "got 1.5"),
        ({"restarts": -1}, ra.ConfigError, "got -1"),
        ({"restarts": True}, ra.ConfigError, "got True"),
        ({"position_only": "no"}, ra.ConfigError, "position_only to be a bool"),
        ({"pose": "abc"}, ra.StateError, "expected finite poses of shape (2, 7)"),
        ({"pose": [[0.4, 0, 0.3, 0, 0, 0, 0]] * 2}, ra.StateError, "non-zero quaternion"),
    ],
)
def test_ik_arguments_checked(env, kwargs: dict[str, object], error: type[Exception], fragment: str) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    arguments: dict[str, object] = {"pose": [[0.4, 0.0, 0.3, 0.0, 1.0, 0.0, 0.0]] * 2, **kwargs}
    assert_unchanged(
        env,
        lambda: agent.calculate_ee_inverse_kinematics(**arguments),
        error,
        "Panda.calculate_ee_inverse_kinematics",
        fragment,
    )


def test_gripper_target_state_rejects_non_numbers(env) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    for bad in ("abc", [0.5, "x"], 2.0):
        assert_unchanged(
            env, lambda bad=bad: agent.set_gripper_target_state(bad), ra.StateError, "set_gripper_target_state"
        )


def test_keyframe_qpos_rejects_non_names(env) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    with pytest.raises(ra.UnknownNameError, match=r"Panda.keyframe_qpos: unknown keyframe .*'ready'"):
        agent.keyframe_qpos(["ready"])  # type: ignore[arg-type]


def test_scene_props_and_floor_checked() -> None:
    with pytest.raises(ra.ConfigError, match=r"props to be a sequence of robot_agents\.Prop, got \[1\]"):
        ra.Scene("panda", props=[1])  # type: ignore[list-item]
    with pytest.raises(ra.ConfigError, match="props to be a sequence"):
        ra.Scene("panda", props=5)  # type: ignore[arg-type]
    cube = ra.Prop(name="cube", shape="box", size=(0.02, 0.02, 0.02))
    with pytest.raises(ra.ConfigError, match="single Prop 'cube'"):
        ra.Scene("panda", props=cube)  # type: ignore[arg-type]
    with pytest.raises(ra.ConfigError, match="expected floor to be a bool, got 'no'"):
        ra.Scene("panda", floor="no")  # type: ignore[arg-type]


@pytest.mark.parametrize("name", ["control_freq", "sim_freq"])
def test_rates_are_not_bools(name: str) -> None:
    with pytest.raises(ra.ConfigError, match=f"expected {name} to be a positive integer \\(Hz\\), got True"):
        ra.make_env("Empty-v1", robot_uids="panda", **{name: True})


def test_frame_names_suggest_world_root_and_end_effectors(env) -> None:  # type: ignore[no-untyped-def]
    agent = env.unwrapped.agent
    with pytest.raises(ra.UnknownNameError) as caught:
        agent.frame_pose("panda_hand", relative_to="rooot")
    message = str(caught.value)
    assert "Panda.frame_pose" in message and "Did you mean 'root'" in message
    assert "'world'" in message and "'panda_link0'" in message
    with pytest.raises(ra.ConfigError, match="relative_to"):
        agent.frame_pose("panda_hand", relative_to=["root"])  # type: ignore[arg-type]
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'panda_hand'"):
        agent.frame_pose("panda_hnd")


def test_multi_robot_action_keys_suggest_robot_ids() -> None:
    env = ra.make_env("Empty-v1", robot_uids=["panda", "widowx250s"])
    env.reset(seed=0)
    u = env.unwrapped
    before = u.get_state()["physics"].copy()
    sizes = {rid: agent.single_action_space.shape for rid, agent in zip(u.scene.robot_ids, u.agents, strict=True)}
    with pytest.raises(ra.UnknownNameError, match=r"unknown robot id 'widowx250s-1x'\. Did you mean 'widowx250s-1'"):
        env.step({"panda-0": np.zeros(sizes["panda-0"]), "widowx250s-1x": np.zeros(sizes["widowx250s-1"])})
    with pytest.raises(ra.ConfigError, match=r"no action for \['widowx250s-1'\]"):
        env.step({"panda-0": np.zeros(sizes["panda-0"])})
    with pytest.raises(ra.ConfigError, match="expected a dict of actions"):
        env.step(np.zeros(3))
    np.testing.assert_array_equal(before, u.get_state()["physics"])
    env.close()


def test_huge_finite_actions_step_without_warnings(env) -> None:  # type: ignore[no-untyped-def]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env.step(np.full(8, 1e308))  # finite: accepted (the controller clips it)
        with pytest.raises(ra.ActionError, match="NaN or inf"):
            env.step(np.array([np.inf, -np.inf, 0, 0, 0, 0, 0, 0]))


def test_too_many_envs_is_a_clean_error(monkeypatch: pytest.MonkeyPatch) -> None:
    import mujoco

    from robot_agents.sim.world import BatchedWorld

    scene = ra.Scene("panda")
    real = mujoco.MjData
    made = []

    def scarce(model: mujoco.MjModel) -> mujoco.MjData:  # memory runs out at the fourth
        if len(made) == 3:
            raise mujoco.FatalError("Could not allocate memory")
        made.append(1)
        return real(model)

    monkeypatch.setattr(mujoco, "MjData", scarce)
    with pytest.raises(ra.ConfigError) as caught:
        BatchedWorld(scene.model, num_envs=10**9, substeps=1)
    message = str(caught.value)
    assert "num_envs=1000000000" in message and "MiB each" in message and "3 were allocated" in message
    assert "Could not allocate memory" in message


# -- found by the code review (2026-11-28) ------------------------------------------------------
@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda: ra.IKConfig(damping="x"), "damping"),  # type: ignore[arg-type]
        (lambda: ra.IKConfig(max_iterations=True), "max_iterations"),
        (lambda: ra.IKConfig(null_space_gain=2.0), "null_space_gain"),
        (lambda: ra.Attachment(ra.get_agent("panda"), at="tip", pos=None), "pos"),  # type: ignore[arg-type]
        (lambda: ra.Attachment(ra.get_agent("panda"), at="tip", pos=("a", 0, 0)), "pos"),  # type: ignore[arg-type]
    ],
)
def test_public_configs_raise_library_errors(make: Callable[[], object], fragment: str) -> None:
    """IKConfig and Attachment raised raw TypeError / ValueError for these."""
    with pytest.raises(ra.ConfigError, match=fragment):
        make()


def test_helpers_raise_library_errors() -> None:
    from robot_agents.actuators import gains_from_inertia
    from robot_agents.kinematics.rotations import matrix_to_quat

    scene = ra.Scene("panda")
    with pytest.raises(ra.ConfigError, match="qpos"):
        gains_from_inertia(scene.model, ["panda-0/panda_joint1"], qpos=[1.0, 2.0])
    with pytest.raises(ra.ConfigError, match="bandwidth"):
        gains_from_inertia(scene.model, ["panda-0/panda_joint1"], bandwidth_hz=True)  # type: ignore[arg-type]
    with pytest.raises(ra.ConfigError, match="3, 3"):
        matrix_to_quat(np.eye(4))
    scene.close()


def test_world_writes_refuse_env_ids_out_of_range() -> None:
    """A negative id indexed the env list from its end: env 1 was written."""
    scene = ra.Scene("panda", num_envs=2)
    scene.reset()
    world = scene.world
    before = world.get_state()
    adr = scene.agents[0].qpos_adr[:1]
    with pytest.raises(ra.StateError, match="env ids"):
        world.write_joint_state([-1], adr, np.zeros((1, 1)), scene.agents[0].dof_adr[:1], np.zeros((1, 1)))
    with pytest.raises(ra.StateError, match="env ids"):
        world.sync_ctrl([2])
    np.testing.assert_array_equal(world.get_state(), before)
    scene.close()


def test_render_datas_allocate_with_a_clean_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """The render mirror's MjData (made at the first render of a scene with
    visual-only geoms) go through the same allocation as the simulated ones."""
    import mujoco

    scene = ra.Scene("panda", num_envs=2)  # its visual-only geoms: a separate render model
    scene.reset()
    assert scene.world.render_model is not scene.model

    def scarce(model: mujoco.MjModel) -> mujoco.MjData:
        raise mujoco.FatalError("Could not allocate memory")

    monkeypatch.setattr(mujoco, "MjData", scarce)
    with pytest.raises(ra.ConfigError, match="num_envs=2"):
        scene.world.render_sources()
    monkeypatch.undo()
    scene.close()


def test_a_bool_is_not_a_gripper_state() -> None:
    env = ra.make_env("Empty-v1", robot_uids="fetch")
    env.reset(seed=0)
    agent = env.unwrapped.agent
    before = agent.drives.get_target_state()
    with pytest.raises(ra.StateError, match="expected a state in"):
        agent.set_gripper_target_state(True)
    after = agent.drives.get_target_state()
    assert all(np.array_equal(before[k], after[k]) for k in before)
    agent.set_gripper_target_state(1.0)  # a number is
    env.close()


@pytest.mark.parametrize("name", ["random", "seed", "default_rng"])
def test_a_bad_random_state_leaves_numpys_global_stream_alone(env, name: str) -> None:  # type: ignore[no-untyped-def]
    """A state's ``rng`` entry names its bit generator; a name of ``np.random`` that is
    none (``random``, ``seed``) was called before the entry was refused, drawing from or
    re-seeding NumPy's global stream."""
    u = env.unwrapped
    state = u.get_state()
    np.random.seed(3)
    before = np.random.get_state()
    bad = {**state, "rng": [{"bit_generator": name}, None]}
    assert_unchanged(env, lambda: u.set_state(bad), ra.StateError, "expected rng[0]")
    after = np.random.get_state()
    assert after[2] == before[2] and np.array_equal(after[1], before[1])


def test_a_state_of_another_num_envs_is_named_as_such(env) -> None:  # type: ignore[no-untyped-def]
    """A state saved by an env of another ``num_envs`` is refused saying so (it was
    refused for the first array whose shape differed: ``elapsed_steps``), by the env and
    by the vector env."""
    three = ra.make_env("Empty-v1", robot_uids="panda", num_envs=3, control_mode="pd_joint_target_delta_pos")
    three.reset(seed=0)
    other = three.unwrapped.get_state()
    u = env.unwrapped
    assert_unchanged(env, lambda: u.set_state(other), ra.StateError, "the state is of 3 envs", "num_envs=2")
    vector = gym.make_vec("robot_agents/Empty-v1", num_envs=2, vectorization_mode="vector_entry_point")
    with pytest.raises(ra.StateError, match="the state is of 3 envs"):
        vector.set_state({**other, "autoreset": np.zeros(3, dtype=bool)})
    vector.close()
    three.close()


def test_a_random_state_numpy_would_truncate_is_refused(env) -> None:  # type: ignore[no-untyped-def]
    """NumPy takes a bit generator's state of 1.5 or True as 1: a state that is not the
    one given is refused (it was restored as another stream); every bit generator's own
    state still restores."""
    u = env.unwrapped
    state = u.get_state()
    for value in (1.5, True):
        entry = {**state["rng"][0], "state": {**state["rng"][0]["state"], "state": value}}
        assert_unchanged(env, lambda entry=entry: u.set_state({**state, "rng": [entry, None]}), ra.StateError, "rng[0]")
    for name in ("PCG64", "MT19937", "Philox", "SFC64", "PCG64DXSM"):
        stream = np.random.Generator(getattr(np.random, name)(5))
        u.set_state({**state, "rng": [stream.bit_generator.state, None]})
        assert u.env_rng(0).random() == stream.random()


def test_a_base_dynamics_of_another_type_is_a_library_error() -> None:
    """A base state's or a ``Base`` part's ``dynamics`` that is an array raised NumPy's
    ``ValueError`` (an array's truth value) instead of the library's error."""
    env = ra.make_env("Empty-v1", robot_uids="fetch", num_envs=2).unwrapped
    env.reset(seed=0)
    state = env.get_state()
    agent_state = state["agents"][0]
    bad = {**agent_state, "base": {**agent_state["base"], "dynamics": np.array(["dynamic", "kinematic"])}}
    with pytest.raises(ra.StateError, match="expected base dynamics"):
        env.set_state({**state, "agents": [bad]})
    np.testing.assert_array_equal(env.get_state()["physics"], state["physics"])
    with pytest.raises(ra.ConfigError, match="dynamics must be"):
        ra.Base(name="base", joints=("x",), dynamics=np.array(["dynamic"]))  # type: ignore[arg-type]
    env.close()


def test_the_model_file_options_are_one_list_checked_by_name_and_type(pendulum_file: Path) -> None:
    """``robot_from_file`` and ``resolve_robot`` take :class:`FileOptions`' fields (one
    list, no longer two kept in step by hand); a misspelt option is named with the close
    ones (was Python's ``TypeError``), and an option of the wrong type is refused
    (``floating="no"`` gave a free root: a non-empty string is true)."""
    import dataclasses
    import inspect

    from robot_agents.cli import build_parser
    from robot_agents.robot_source import UP_AXES, FileOptions, resolve_robot, robot_from_file

    names = [option.name for option in dataclasses.fields(FileOptions)]
    for function in (robot_from_file, resolve_robot):
        assert list(inspect.signature(function).parameters)[1:] == names
    # the command line's flags are the same options, with the same defaults
    args = build_parser().parse_args(["info", "panda"])
    assert {name: getattr(args, name) for name in names} == dataclasses.asdict(FileOptions())
    # as documented: floating positional or by name, the others by name
    assert robot_from_file(pendulum_file, True).fix_root_link is False
    assert resolve_robot(str(pendulum_file), floating=True).fix_root_link is False
    assert robot_from_file(pendulum_file, up="y").mount_pose == (0.0, 0.0, 0.0, *UP_AXES["y"])
    file = str(pendulum_file)
    refused: list[tuple[Callable[[], object], type[Exception], str]] = [
        (
            lambda: robot_from_file(pendulum_file, flaoting=True),
            ra.UnknownNameError,
            "robot_from_file: unknown option 'flaoting'. Did you mean 'floating'?",
        ),
        (
            lambda: resolve_robot(file, at_axes="x"),
            ra.UnknownNameError,
            "resolve_robot: unknown option 'at_axes'. Did you mean 'at_axis'?",
        ),
        (
            lambda: robot_from_file(pendulum_file, True, "z", None, None, None, "z", 1),
            ra.ConfigError,
            "too many positional arguments; the options after the path are floating, up, gripper",
        ),
        (
            lambda: robot_from_file(pendulum_file, True, floating=True),
            ra.ConfigError,
            "multiple values for argument 'floating'",
        ),
        (
            lambda: robot_from_file(pendulum_file, floating="no"),
            ra.ConfigError,
            "robot_from_file: expected floating to be a bool (True or False), got 'no'.",
        ),
        (
            lambda: resolve_robot(file, root_body=3),
            ra.ConfigError,
            "resolve_robot: expected root_body to be a non-empty name (str) or None, got 3.",
        ),
        (
            lambda: resolve_robot(file, up="Y"),
            ra.UnknownNameError,
            "resolve_robot: unknown up axis 'Y'. Did you mean 'y'?",
        ),
        (
            lambda: robot_from_file(pendulum_file, gripper="robotiq", at="link"),
            ra.UnknownNameError,
            "unknown gripper (a built-in piece) 'robotiq'. Did you mean 'robotiq_2f85'?",
        ),
        (lambda: resolve_robot("panda", up="Y"), ra.UnknownNameError, "resolve_robot: unknown up axis 'Y'"),
        (
            lambda: resolve_robot("panda", gripper="franka_hand"),
            ra.ConfigError,
            "gripper='franka_hand' is mounted on a model file, and 'panda' is a registered uid or a class (declare its attachments instead)",
        ),
    ]
    for call, error, fragment in refused:
        with pytest.raises(error) as caught:
            call()
        assert fragment in str(caught.value)


def test_env_rng_takes_an_env_index_only(env) -> None:  # type: ignore[no-untyped-def]
    """``env_rng(-1)`` gave the last env's stream, ``env_rng(2)`` of two envs an
    ``IndexError`` and ``env_rng("0")`` a ``TypeError``."""
    u = env.unwrapped
    for bad in (2, -1, "0", 1.0, True):
        assert_unchanged(
            env,
            lambda bad=bad: u.env_rng(bad),
            ra.StateError,
            "EmptyEnv.env_rng: expected an env index in [0, 2)",
            f"got {bad!r}",
        )
    assert u.env_rng(np.int64(1)) is u.env_rng(1)


def test_a_choice_among_names_suggests_the_close_one() -> None:
    """A value outside a small set of names (a reward mode, a shape, an angle unit, an
    autoreset mode, a base's dynamics) is refused with the close name, as an unknown robot
    or mode is (they listed the choices only), before anything is built."""
    from robot_agents.envs.vector import _autoreset_mode

    refused: list[tuple[Callable[[], object], str]] = [
        (
            lambda: ra.make_env("PickCube-v1", robot_uids="panda", reward_mode="dens"),
            "got 'dens'. Did you mean 'dense'",
        ),
        (lambda: ra.Prop(name="ball", shape="spere", size=(0.02,)), "got 'spere'. Did you mean 'sphere'?"),
        (
            lambda: ra.TouchSensorConfig(uid="pad", link="tip", shape="cylindre"),
            "got 'cylindre'. Did you mean 'cylinder'?",
        ),
        (lambda: ra.CompilerSettings(angle="degrees"), "got 'degrees'. Did you mean 'degree'?"),
        (lambda: _autoreset_mode("next_stp"), "got 'next_stp'. Did you mean 'NEXT_STEP', "),
        (
            lambda: ra.make_env("Empty-v1", robot_uids="panda", disable_env_checker="yes"),
            "expected disable_env_checker to be a bool (True or False), got 'yes'",
        ),
    ]
    for call, fragment in refused:
        with pytest.raises(ra.ConfigError) as caught:
            call()
        assert fragment in str(caught.value)
    env = ra.make_env("Empty-v1", robot_uids="fetch")
    env.reset(seed=0)
    base = env.unwrapped.agent
    before = env.unwrapped.get_state()
    with pytest.raises(
        ra.ConfigError, match=r"expected 'dynamic' or 'kinematic', got 'kinematik'. Did you mean 'kinematic'\?"
    ):
        base.set_base_dynamics("kinematik")
    np.testing.assert_array_equal(env.unwrapped.get_state()["physics"], before["physics"])
    env.close()


def test_the_mode_tables_take_a_joint_group() -> None:
    """``joint_control_modes(("a", "b"))``, names where a ``JointGroup`` goes, was
    ``AttributeError: 'tuple' object has no attribute 'joint_names'``."""
    with pytest.raises(ra.ConfigError, match=r"joint_control_modes: expected a JointGroup .*got \('a', 'b'\)"):
        ra.joint_control_modes(("a", "b"))  # type: ignore[arg-type]
    group = ra.JointGroup(joint_names=("a", "b"))
    with pytest.raises(ra.ConfigError, match=r"ee_control_modes: expected task to be a TaskSpace, got 'tcp'"):
        ra.ee_control_modes(group, "tcp")  # type: ignore[arg-type]


def test_a_misspelt_declaration_is_refused_not_ignored(pendulum_file: Path) -> None:
    """A robot's class attribute under a declaration's name misspelt, one holding what
    only a declaration takes, or one hiding the Agent's own property was ignored without
    a word (the robot built with its derived keyframe, no camera, ...); a user's own
    attribute is still the user's."""

    def robot(**extra: object) -> type[ra.Agent]:
        return make_pendulum_class(pendulum_file, uid="misspelt", **extra)

    keyframe = {"up": ra.Keyframe(qpos=(0.5, 0.0))}
    camera = (ra.CameraConfig(uid="cam", mount="tip"),)
    refused: list[tuple[type[ra.Agent], type[Exception], str]] = [
        (
            robot(keyframe=keyframe),
            ra.UnknownNameError,
            "Pendulum (a class attribute hiding the Agent's method 'keyframe'): unknown declaration 'keyframe'. Did you mean 'keyframes'?",
        ),
        (robot(actuator=()), ra.UnknownNameError, "unknown declaration 'actuator'. Did you mean 'actuators', "),
        (
            robot(sensors=camera),
            ra.ConfigError,
            "Pendulum.sensors: holds CameraConfig entries, and 'sensors' is no declaration, so nothing would read it; CameraConfig entries are declared as cameras.",
        ),
        (
            robot(mode_table={"m": {"arm": ra.PDJointPosConfig(joint_names=("shoulder",))}}),
            ra.ConfigError,
            "Pendulum.mode_table: holds ControllerConfig entries, and 'mode_table' is no declaration",
        ),
        (robot(modes={}), ra.UnknownNameError, "(a class attribute hiding the Agent's method 'modes')"),
        (
            robot(control_mode={}),
            ra.UnknownNameError,
            "Pendulum (a class attribute hiding the Agent's property 'control_mode'): unknown declaration 'control_mode'. Did you mean 'control_modes'",
        ),
    ]
    for cls, error, fragment in refused:
        with pytest.raises(error) as caught:
            cls.check()
        assert fragment in str(caught.value)
    own = robot(link_length=0.3, notes="mine", keyframes=keyframe)  # a user's own attributes beside the declarations
    assert own.check().index.model.nq == 2


def test_a_declaration_class_names_a_misspelt_field_with_the_close_one() -> None:
    """Every public declaration class (a dataclass in ``robot_agents.__all__``) answers a
    misspelt keyword with the fields there are and the one meant (Python's ``TypeError``
    named neither), and too many positional arguments with its fields; a good call, and
    ``dataclasses.replace``, are as before."""
    import dataclasses
    import inspect

    declarations = [getattr(ra, n) for n in ra.__all__ if dataclasses.is_dataclass(getattr(ra, n))]
    assert len(declarations) >= 39
    for cls in declarations:
        first = next(iter(inspect.signature(cls).parameters), "")  # (FileActuators has no field)
        with pytest.raises(ra.UnknownNameError) as caught:
            cls(**{first + "x": 1})
        hint = f" Did you mean '{first}'" if first else " Available: (none)"
        assert str(caught.value).startswith(f"{cls.__name__}: unknown field '{first}x'.{hint}")
    refused: list[tuple[Callable[[], object], type[Exception], str]] = [
        (
            lambda: ra.PDActuator(joint=("j",), stiffness=1.0),
            ra.UnknownNameError,
            "PDActuator: unknown field 'joint'. Did you mean 'joints', 'joint_damping'?",
        ),
        (
            lambda: ra.Arm("arm", ("j",), 0.1, 1.0, (), None, 7),
            ra.ConfigError,
            "Arm: too many positional arguments; its fields are name, joints, max_delta",
        ),
        (
            lambda: dataclasses.replace(ra.Keyframe(qpos=(0.0,)), qpso=(1.0,)),
            ra.UnknownNameError,
            "Keyframe: unknown field 'qpso'. Did you mean 'qpos'?",
        ),
    ]
    for call, error, fragment in refused:
        with pytest.raises(error) as caught_one:
            call()
        assert fragment in str(caught_one.value)
    assert dataclasses.replace(ra.Keyframe(qpos=(0.0,)), qpos=(1.0,)).qpos == (1.0,)
    assert list(inspect.signature(ra.PDActuator).parameters)[:2] == ["joints", "effort_limit"]


def test_render_without_a_render_mode_is_a_note(env) -> None:  # type: ignore[no-untyped-def]
    """``render()`` of an env made without ``render_mode`` returns no frame (Gymnasium's
    convention) with a note, a ``RuntimeWarning`` as the library's others are (it went
    through gymnasium's logger: a second way)."""
    with pytest.warns(
        RuntimeWarning, match=r"EmptyEnv.render: no frame, render_mode is None; pass render_mode='rgb_array'"
    ):
        assert env.render() is None
