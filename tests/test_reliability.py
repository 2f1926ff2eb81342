"""Promises under bad input and misuse, one test per promise (docs/reliability.md):
a rejected call raises a library error and leaves the complete state bit-identical;
configs reject non-finite numbers when built; unbounded joints get finite bounds; a
closed env refuses use; episodes truncate per env at any batch size."""

from __future__ import annotations

import copy
import math
import warnings
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import robot_agents as ra
from tests.conftest import INERTIAL


def snapshot(env: Any) -> tuple[Any, ...]:
    u = env.unwrapped
    state = u.get_state()
    targets = [(a.drives.targets.position.copy(), a.drives.targets.velocity.copy()) for a in u.agents]
    return (
        state["physics"].copy(),
        repr(state["agents"]),
        u.elapsed_steps.copy(),
        repr([u.np_random.bit_generator.state, *(u.env_rng(i).bit_generator.state for i in range(u.num_envs))]),
        [a.control_mode for a in u.agents],
        targets,
        u.scene.world.ctrl.copy(),
    )


def assert_same(a: tuple[Any, ...], b: tuple[Any, ...]) -> None:
    np.testing.assert_array_equal(a[0], b[0])
    assert a[1] == b[1] and a[3] == b[3] and a[4] == b[4]
    np.testing.assert_array_equal(a[2], b[2])
    for (p1, v1), (p2, v2) in zip(a[5], b[5], strict=True):
        np.testing.assert_array_equal(p1, p2)
        np.testing.assert_array_equal(v1, v2)
    np.testing.assert_array_equal(a[6], b[6])


class RaisesOnArray:
    def __array__(self, *args: object, **kwargs: object) -> np.ndarray:
        raise RuntimeError("no array for you")


def bad_calls(env: Any, rng: np.random.Generator) -> list[tuple[str, Any]]:
    u = env.unwrapped
    agent = u.agent
    dim = agent.controller.action_dim
    state = u.get_state()
    n = u.num_envs
    calls = [
        ("step(None)", lambda: env.step(None)),
        ("step(dict)", lambda: env.step({"a": 1})),
        ("step(wrong shape)", lambda: env.step(np.zeros(dim + 1))),
        ("step(nan)", lambda: env.step(np.full(dim, np.nan))),
        ("step(str)", lambda: env.step("up")),
        ("step(__array__ raises)", lambda: env.step(RaisesOnArray())),
        ("reset(options='x')", lambda: env.reset(seed=5, options="x")),
        ("reset(keyframe=5)", lambda: env.reset(seed=5, options={"keyframe": 5})),
        ("reset(keyframe='nope')", lambda: env.reset(seed=5, options={"keyframe": "nope"})),
        ("reset(env_ids dup)", lambda: env.reset(seed=5, options={"env_ids": [0, 0]})),
        ("reset(env_ids out)", lambda: env.reset(seed=5, options={"env_ids": [n]})),
        ("reset(unknown option)", lambda: env.reset(seed=5, options={"keyframes": "rest"})),
        ("reset(seed=-1)", lambda: env.reset(seed=-1)),
        ("set_state(elapsed nan)", lambda: u.set_state({**state, "elapsed_steps": np.full(n, np.nan)})),
        ("set_state(elapsed -5)", lambda: u.set_state({**state, "elapsed_steps": np.full(n, -5)})),
        ("set_state(elapsed 1.7)", lambda: u.set_state({**state, "elapsed_steps": np.full(n, 1.7)})),
        ("set_state(physics shape)", lambda: u.set_state({**state, "physics": state["physics"][:, :-1]})),
        ("set_state(1)", lambda: u.set_state(1)),
        ("set_control_mode(list)", lambda: u.set_control_mode(["pd_joint_pos"])),
        ("set_control_mode(robot=1)", lambda: u.set_control_mode(agent.control_mode, robot=1)),
        ("set_control_mode(nope)", lambda: u.set_control_mode("nope")),
        ("agent.reset(keyframe list)", lambda: agent.reset(keyframe=["rest"])),
        ("agent.reset(qpos nan)", lambda: agent.reset(qpos=np.full(agent.nq, np.nan))),
        ("agent.reset(qpos far)", lambda: agent.reset(qpos=np.full(agent.nq, 1e3))),
        ("agent.set_state(far)", lambda: agent.set_state({**agent.get_state(), "qpos": np.full((n, agent.nq), 1e3)})),
        ("frame_pose(5)", lambda: agent.frame_pose(5)),
        ("frame_pose(nope)", lambda: agent.frame_pose("nope")),
        ("is_static('x')", lambda: agent.is_static("x")),
        ("is_static(nan)", lambda: agent.is_static(math.nan)),
        ("is_grasping(5)", lambda: agent.is_grasping(5) if agent.grippers.parts else agent.is_static(-1.0)),
        ("is_grasping(nan)", lambda: agent.is_grasping("world", min_force=math.nan)),
    ]
    order = rng.permutation(len(calls))
    return [calls[i] for i in order]


@pytest.mark.parametrize("uid", ra.list_agents())
def test_fuzz_rejected_calls_leave_everything_bit_identical(uid: str) -> None:
    """Seeded random bad calls over the public entry points, for every registered robot:
    each raises a library error, and physics, controllers, RNG, episode counters,
    targets and controls are bit-identical afterwards."""
    env = ra.make_env("Empty-v1", robot_uids=uid, num_envs=2)
    env.reset(seed=1)
    env.step(env.action_space.sample())
    rng = np.random.default_rng(abs(hash(uid)) % 2**32)
    for name, call in bad_calls(env, rng):
        before = snapshot(env)
        with pytest.raises(ra.RobotAgentsError):
            call()
        try:
            assert_same(before, snapshot(env))
        except AssertionError as err:
            raise AssertionError(f"{uid}: {name} changed the state") from err
    env.close()


def test_fuzz_rejected_calls_in_a_scene_of_two_different_robots() -> None:
    """The fuzz of bad calls in a Panda + SO100 scene: a bad action of one robot applies
    neither robot's, another robot's state, keyframe or mode is refused, and everything
    is bit-identical afterwards."""
    env = ra.make_env("Empty-v1", robot_uids=("panda", "so100"), num_envs=2)
    u = env.unwrapped
    env.reset(seed=np.int64(1))
    good = {rid: np.full(space.shape, 0.3) for rid, space in u.action_space.items()}
    env.step(good)
    state = u.get_state()
    panda, so100 = u.agents
    calls = [
        lambda: env.step({**good, "so100-1": np.zeros((2, 5))}),
        lambda: env.step({**good, "so100-1": np.full((2, 6), np.nan)}),
        lambda: env.step({**good, "panda-0": "up"}),
        lambda: env.step({"panda-0": good["panda-0"]}),
        lambda: env.step({**good, "so100-2": good["so100-1"]}),
        lambda: env.step(good["panda-0"]),
        lambda: u.set_state({**state, "agents": state["agents"][::-1]}),
        lambda: u.set_state({**state, "agents": state["agents"][:1]}),
        lambda: so100.set_state(panda.get_state()),
        lambda: env.reset(seed=5, options={"keyframe": ("rest", "ready")}),
        lambda: env.reset(seed=5, options={"keyframe": ["rest"]}),
        lambda: u.set_control_mode("pd_ee_delta_pose", robot=1),
        lambda: u.set_control_mode("pd_joint_pos", robot=2),
        lambda: u.scene.reset(qpos=[None, np.zeros(3)]),
    ]
    for k in np.random.default_rng(7).permutation(len(calls)):
        before = snapshot(env)
        with pytest.raises(ra.RobotAgentsError):
            calls[k]()
        try:
            assert_same(before, snapshot(env))
        except AssertionError as err:
            raise AssertionError(f"bad call {k} changed the state") from err
    env.close()


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda: ra.PDActuator(joints=".*", stiffness=math.nan), "stiffness"),
        (lambda: ra.PDActuator(joints=".*", stiffness=1.0, effort_limit=-1.0), "effort_limit"),
        (lambda: ra.PDJointPosConfig(joint_names=("a",), stiffness=math.inf), "stiffness"),
        (lambda: ra.PDJointPosConfig(joint_names=("a",), effort_limit=-5.0), "effort_limit"),
        (lambda: ra.Keyframe(qpos=("a", 0.0)), "expected numbers"),
        (lambda: ra.Keyframe(qpos={"j": math.inf}), "finite"),
        (lambda: ra.CompilerSettings(boundmass=math.nan), "boundmass"),
        (lambda: ra.make_env("Empty-v1", robot_uids="panda", robot_init_qpos_noise=math.inf), "robot_init_qpos_noise"),
        (lambda: ra.make_env("Empty-v1", robot_uids=None), "robot uid"),
        (lambda: ra.make_env("Empty-v1", robot_uids="panda", control_mode=5), "control_modes"),
        (lambda: ra.make_env("Empty-v1", robot_uids="panda", num_threads="x"), "num_threads"),
        (lambda: ra.make_env("Empty-v1", robot_uids="panda", num_envs=2.5), "whole number"),
        (lambda: ra.make_env("Empty-v1", robot_uids="panda", max_episode_steps=0), "max_episode_steps"),
    ],
)
def test_configs_reject_bad_numbers_when_built(make: Any, fragment: str) -> None:
    with pytest.raises(ra.RobotAgentsError, match=fragment):
        make()


def test_unbounded_joints_get_finite_bounds_and_cannot_disable_others(tmp_path: Path) -> None:
    urdf = f"""<robot name="wheel"><link name="base">{INERTIAL.format(m=2)}</link>
    <link name="wheel">{INERTIAL.format(m=0.5)}<collision><geometry><sphere radius="0.05"/></geometry></collision></link>
    <link name="arm">{INERTIAL.format(m=0.5)}</link>
    <joint name="spin" type="continuous"><parent link="base"/><child link="wheel"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/></joint>
    <joint name="lift" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.6"/><axis xyz="1 0 0"/>
      <limit lower="-1" upper="1" effort="20" velocity="1"/></joint></robot>"""
    path = tmp_path / "wheel.urdf"
    path.write_text(urdf)
    cls = type("Wheel", (ra.Agent,), {"uid": "wheel", "urdf_path": path})
    scene = ra.Scene(cls, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    space = agent.single_action_space
    np.testing.assert_allclose(space.low, [-2 * np.pi, -1.0])
    np.testing.assert_allclose(space.high, [2 * np.pi, 1.0])
    for _ in range(10):
        agent.set_action([1e30, 0.5])  # clipped to 2 pi; the other joint keeps its control
        scene.step()
    assert np.all(np.isfinite(scene.world.ctrl))
    assert agent.qpos[0, 1] == pytest.approx(0.5, abs=0.02)


def test_a_closed_env_refuses_use() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=4, render_mode="rgb_array", render_size=(32, 24))
    env.reset(seed=0)
    u, agent = env.unwrapped, env.unwrapped.agent
    state, agent_state = u.get_state(), agent.get_state()
    env.close()
    for call in (
        lambda: env.step(np.zeros((4, 8))),
        lambda: env.reset(seed=0),
        lambda: u.set_state({}),
        lambda: u.set_state(state),
        u.get_state,
        env.render,
        lambda: u.set_control_mode("pd_joint_pos"),
        agent.reset,
        lambda: agent.set_action(np.zeros(8)),
        lambda: agent.set_state(agent_state),
        lambda: agent.set_control_mode("pd_joint_pos"),
        lambda: setattr(agent, "arm_joint_pos", np.zeros(7)),
        agent.open_gripper,
        lambda: agent.set_gripper_target_state(0.5),
        u.scene.reset,
        u.scene.step,
        u.scene.get_state,
        lambda: u.scene.set_state(state),
    ):
        with pytest.raises(ra.StateError, match="closed"):
            call()
    assert u._renderer is None  # render built no renderer


@pytest.mark.parametrize("num_envs", [1, 3])
def test_max_episode_steps_truncates_per_env(num_envs: int) -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=num_envs, max_episode_steps=3)
    env.reset(seed=0)
    flags = [env.step(env.action_space.sample())[3] for _ in range(3)]
    assert np.shape(flags[-1]) == (() if num_envs == 1 else (num_envs,))
    assert not np.any(flags[0]) and not np.any(flags[1]) and np.all(flags[2])
    env.reset(seed=0, options={"env_ids": [0]})
    if num_envs > 1:
        truncated = env.step(env.action_space.sample())[3]
        np.testing.assert_array_equal(truncated, [False] + [True] * (num_envs - 1))


def test_a_mimic_of_a_missing_joint_is_an_error(tmp_path: Path) -> None:
    urdf = f"""<robot name="m"><link name="a">{INERTIAL.format(m=1)}</link><link name="b">{INERTIAL.format(m=1)}</link>
    <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="k"/></joint></robot>"""
    path = tmp_path / "m.urdf"
    path.write_text(urdf)
    with pytest.raises(
        ra.ModelError,
        match=r"joint 'j' in .*m\.urdf' \(line 3\) mimics joint 'k', which is not in the URDF; joints: \['j'\]",
    ):
        ra.Scene(type("M", (ra.Agent,), {"uid": "m", "urdf_path": path}))


def test_diverging_motion_is_reported_and_absurd_speeds_refused(tmp_path: Path) -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, robot_init_qpos_noise=0.0)
    env.reset(seed=0)
    agent = env.unwrapped.agent
    with pytest.raises(ra.StateError, match="joint speeds below 10000"):
        agent.reset(qvel=np.full(agent.dof, 1e12))
    # A speed MuJoCo does not reset yet (its guard is 1e10) still marks the step.
    agent.reset(qvel=np.full(agent.dof, 9e3), env_ids=[1])
    with pytest.warns(RuntimeWarning, match="BatchedWorld.step: MuJoCo: "):  # MuJoCo's own word, as a note
        info = env.step(np.zeros((2, 8)))[4]
    np.testing.assert_array_equal(info["physics_unstable"], [False, True])


@pytest.mark.parametrize("num_envs", [1, 2])
def test_a_step_that_ends_with_nan_speeds_is_reported(num_envs: int) -> None:
    """MuJoCo checks a substep's speeds before integrating it: a blow-up in the last
    substep of a control step leaves NaN joint speeds that its guard only resets at the
    next step. Such a step is unstable (it was not flagged: ``NaN > MAX_SPEED`` is
    false), at one substep per action and with several envs."""
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=num_envs, control_freq=500).unwrapped
    env.reset(seed=0)
    env.model.dof_damping[:] = -100.0  # negative damping pumps energy in until it blows up
    ended_nan = 0
    with warnings.catch_warnings(record=True) as caught:  # MuJoCo's own words, as notes
        warnings.simplefilter("always")
        for _ in range(60):
            info = env.step(np.zeros((num_envs, 8)))[4]
            nan = ~np.all(np.isfinite(env.agent.qvel), axis=1)
            ended_nan += int(nan.sum())
            assert np.all(info["physics_unstable"][nan])
    notes = [str(w.message) for w in caught]
    assert notes and all(n.startswith("BatchedWorld.step: MuJoCo: ") for n in notes)
    assert any("The simulation is unstable" in n for n in notes)
    assert ended_nan > 0
    env.close()


def _state_paths(tree: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    paths = [path]
    if isinstance(tree, dict):
        for key, value in tree.items():
            paths += _state_paths(value, (*path, key))
    elif isinstance(tree, list):
        for k, value in enumerate(tree):
            paths += _state_paths(value, (*path, k))
    return paths


def _corrupted(state: Any, rng: np.random.Generator) -> Any:
    """A copy of ``state`` with one entry dropped, replaced by junk, given a NaN / inf /
    huge value, or cut."""
    junk = [None, "x", 1, 1.5, True, math.nan, [], {}, np.zeros(3), np.zeros((2, 0)), np.array(["a"]), [1, 2]]
    state = copy.deepcopy(state)
    paths = _state_paths(state)[1:]
    path = paths[rng.integers(len(paths))]
    parent = state
    for key in path[:-1]:
        parent = parent[key]
    key, value, op = path[-1], parent[path[-1]], rng.integers(4)
    if op == 0:
        del parent[key]
    elif op == 1:
        parent[key] = junk[rng.integers(len(junk))]
    elif op == 2 and isinstance(value, np.ndarray) and value.size:
        value = value.astype(np.float64)
        value.flat[rng.integers(value.size)] = [math.nan, math.inf, -1e300, 1e5][rng.integers(4)]
        parent[key] = value
    elif isinstance(value, np.ndarray) and value.ndim:
        parent[key] = value[..., :-1] if rng.random() < 0.5 else value[:1]
    return state


@pytest.mark.parametrize("robots", [("panda", "so100"), "fetch"])
def test_fuzz_corrupted_states_raise_library_errors_and_change_nothing(robots: Any) -> None:
    """Seeded corruptions of a saved state, at the env and at the robot level: accepted,
    or refused with a library error and everything as it was (a base's ``dynamics`` as an
    array raised NumPy's ``ValueError``)."""
    env = ra.make_env("Empty-v1", robot_uids=robots, num_envs=2, sleep=True)
    u = env.unwrapped
    env.reset(seed=0)
    space = u.action_space
    env.step(
        {k: np.full(s.shape, 0.2) for k, s in space.items()}
        if isinstance(space, gym.spaces.Dict)
        else np.full(space.shape, 0.2)
    )
    rng = np.random.default_rng(0)
    for target in (u, u.agents[-1]):
        saved = target.get_state()
        for _ in range(120):
            bad = _corrupted(saved, rng)
            before = u.get_state()
            try:
                target.set_state(bad)
            except ra.RobotAgentsError:
                assert repr(u.get_state()) == repr(before)
            target.set_state(saved)
    env.close()
