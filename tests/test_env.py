"""The Gymnasium environment: API contract, batching, exact state, determinism, rendering."""

from __future__ import annotations

import copy
import warnings
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import robot_agents as ra


@pytest.mark.parametrize("obs_mode", ["state", "state_dict"])
@pytest.mark.parametrize("uid", ["panda", "panda_stick", "floating_panda_gripper"])
def test_check_env_passes_without_warnings(uid: str, obs_mode: str) -> None:
    env = ra.make_env("Empty-v1", robot_uids=uid, obs_mode=obs_mode, render_mode="rgb_array", render_size=(64, 48))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=False)
    env.close()


def test_make_env_and_gymnasium_make_agree() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_pos", sim_freq=400, control_freq=20)
    env2 = gym.make(
        "robot_agents/Empty-v1", robot_uids="panda", control_mode="pd_joint_pos", sim_freq=400, control_freq=20
    )
    for e in (env, env2):
        u = e.unwrapped
        assert isinstance(u.agent, ra.Agent) and u.agent.uid == "panda"
        assert isinstance(u.model, mujoco.MjModel) and isinstance(u.data, mujoco.MjData)
        assert (u.sim_freq, u.control_freq) == (400, 20)
        assert u.scene.substeps == 20 and u.model.opt.timestep == pytest.approx(1 / 400)
        assert u.agent.control_mode == "pd_joint_pos"
    o1, _ = env.reset(seed=3)
    o2, _ = env2.reset(seed=3)
    np.testing.assert_array_equal(o1, o2)
    with pytest.raises(ra.UnknownNameError, match="Empty-v1"):
        ra.make_env("Emptyy-v1")


def test_batched_shapes_and_copies() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=4, obs_mode="state_dict")
    u = env.unwrapped
    obs, _ = env.reset(seed=0)
    assert obs["agent"]["qpos"].shape == (4, 9)
    assert obs["agent"]["qvel"].shape == (4, 9)
    assert obs["agent"]["controller"]["arm"]["target_qpos"].shape == (4, 7)
    assert obs["extra"]["tcp_pose"].shape == (4, 7)
    assert env.action_space.shape == (4, 8) and u.single_action_space.shape == (8,)
    obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
    assert reward.shape == terminated.shape == truncated.shape == (4,)
    # Returned arrays are copies: writing into them changes nothing in the simulation.
    qpos = u.agent.qpos
    qpos[:] = 123.0
    assert not np.any(u.agent.qpos == 123.0)
    assert not np.shares_memory(u.agent.qpos, u.data.qpos)
    # Each env was reset with its own noise draw.
    assert not np.allclose(obs["agent"]["qpos"][0], obs["agent"]["qpos"][1])


def test_truncation_after_max_episode_steps() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", max_episode_steps=3)
    env.reset(seed=0)
    flags = [env.step(np.zeros(8))[3] for _ in range(3)]
    assert flags == [False, False, True]
    assert isinstance(flags[0], bool)


def rollout(env: gym.Env, actions: list[np.ndarray]) -> np.ndarray:
    return np.stack([np.asarray(env.step(a)[0]) for a in actions])


@pytest.mark.parametrize("num_envs", [1, 3])
def test_same_seed_same_actions_bit_identical(num_envs: int) -> None:
    rng = np.random.default_rng(1)
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=num_envs, control_mode="pd_joint_target_delta_pos")
    actions = [rng.uniform(-1, 1, (num_envs, 8)) for _ in range(15)]
    env.reset(seed=7)
    first = rollout(env, actions)
    state_a = env.unwrapped.get_state()["physics"]
    env.reset(seed=7)
    second = rollout(env, actions)
    assert np.array_equal(first, second)
    assert np.array_equal(state_a, env.unwrapped.get_state()["physics"])
    env.reset(seed=8)
    assert not np.array_equal(first, rollout(env, actions))


def test_thread_count_does_not_change_results() -> None:
    rng = np.random.default_rng(2)
    actions = [rng.uniform(-1, 1, (6, 8)) for _ in range(10)]
    results = []
    for threads in (1, 2, 3):
        env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=6, num_threads=threads)
        env.reset(seed=0)
        results.append(rollout(env, actions))
        env.close()
    assert np.array_equal(results[0], results[1]) and np.array_equal(results[0], results[2])


@pytest.mark.parametrize("mode", ["pd_joint_target_delta_pos", "pd_joint_vel", "pd_joint_delta_pos_vel"])
def test_get_state_set_state_round_trip_is_exact(mode: str) -> None:
    rng = np.random.default_rng(3)
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, control_mode=mode)
    u = env.unwrapped
    env.reset(seed=0)
    shape = env.action_space.shape
    rollout(env, [rng.uniform(-1, 1, shape) for _ in range(5)])
    saved = u.get_state()
    continuation = [rng.uniform(-1, 1, shape) for _ in range(10)]
    expected = rollout(env, continuation)
    expected_state = u.get_state()
    # Wander off: other mode, other actions, a reset; then restore and replay.
    u.set_control_mode("pd_joint_pos")
    env.reset(seed=99)
    rollout(env, [u.agent.qpos[:, :8].copy() for _ in range(3)])
    u.set_state(saved)
    assert u.agent.control_mode == mode
    replay = rollout(env, continuation)
    assert np.array_equal(expected, replay)
    assert np.array_equal(expected_state["physics"], u.get_state()["physics"])
    np.testing.assert_array_equal(expected_state["elapsed_steps"], u.get_state()["elapsed_steps"])


def test_a_restored_control_mode_brings_its_spaces_back() -> None:
    """``set_state`` of a state saved in another control mode: the action and
    observation spaces follow the restored mode (they stayed at the switched one, and
    a sampled action was refused), for one robot and for each of two."""
    env = ra.make_env("PickCube-v1", robot_uids="panda", num_envs=2, control_mode="pd_joint_delta_pos")
    env.reset(seed=0)
    saved = env.unwrapped.get_state()
    env.unwrapped.set_control_mode("pd_ee_delta_pose")
    assert env.action_space.shape == (2, 7)
    env.unwrapped.set_state(saved)
    assert env.unwrapped.agent.control_mode == "pd_joint_delta_pos"
    assert env.action_space.shape == (2, 8)
    obs, *_ = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    two = ra.make_env("Empty-v1", robot_uids=("panda", "panda"), num_envs=2).unwrapped
    two.reset(seed=0)
    saved, spaces = two.get_state(), two.action_space
    two.set_control_mode("pd_ee_delta_pose", robot=1)
    two.set_state(saved)
    assert two.action_space == spaces and two.observation_space.contains(two.step(two.action_space.sample())[0])
    same = two.action_space
    two.set_state(saved)  # the same modes: the spaces (and their random streams) are kept
    assert two.action_space is same


def test_the_spaces_follow_a_mode_changed_below_the_env() -> None:
    """A control mode changed through the robot (``Agent.set_state`` of a state saved in
    another mode, ``Agent.set_control_mode``) or the scene: the env's and the vector
    env's spaces follow (they stayed at the old mode, and the observations no longer
    fitted the observation space)."""
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, control_mode="pd_ee_delta_pose")
    u = env.unwrapped
    env.reset(seed=0)
    robot_state = u.agent.get_state()
    u.set_control_mode("pd_joint_pos")
    u.agent.set_state(robot_state)
    assert env.action_space.shape == u.action_space.shape == (2, 7)
    obs, *_ = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    u.agent.set_control_mode("pd_joint_vel")
    assert env.action_space == u.agent.action_space
    assert env.observation_space.contains(u.step(env.action_space.sample())[0])
    same = env.action_space
    assert env.action_space is same  # unchanged modes: the spaces (and their random streams) are kept
    vector = gym.make_vec(
        "robot_agents/Empty-v1", num_envs=2, vectorization_mode="vector_entry_point", control_mode="pd_joint_pos"
    )
    vector.reset(seed=0)
    saved = vector.env.get_state()
    vector.env.agent.set_control_mode("pd_ee_delta_pose")
    assert vector.single_action_space.shape == (7,) and vector.action_space.shape == (2, 7)
    obs, *_ = vector.step(vector.action_space.sample())
    assert vector.observation_space.contains(obs)
    vector.env.set_state(saved)
    assert vector.single_action_space.shape == (8,) and vector.action_space.shape == (2, 8)
    assert vector.observation_space.contains(vector.step(vector.action_space.sample())[0])
    vector.close()
    env.close()


def test_empty_or_two_dimensional_env_ids_are_refused() -> None:
    """An empty selection is refused whatever holds it (a list was, an empty int array
    reset nothing), and so is an array of two dimensions (it was flattened)."""
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2)
    env.reset(seed=0)
    u = env.unwrapped
    before = u.get_state()
    for ids in ([], np.array([], dtype=int)):
        with pytest.raises(ra.StateError, match=r"at least one env id.*empty selection"):
            env.reset(options={"env_ids": ids})
    with pytest.raises(ra.StateError, match=r"1-D sequence, got an array of shape \(1, 1\)"):
        env.reset(options={"env_ids": np.array([[1]])})
    for mask in (np.array([True, False]), [True, True]):  # a bool mask is named as one
        with pytest.raises(ra.StateError, match=r"got bools .*np\.flatnonzero\(mask\)"):
            env.reset(options={"env_ids": mask})
    assert np.array_equal(u.get_state()["physics"], before["physics"])
    env.reset(options={"env_ids": np.array([1])})
    env.reset(options={"env_ids": 0})


@pytest.mark.parametrize("base_dynamics", ["dynamic", "kinematic"])
def test_a_state_restores_the_drive_targets_no_action_writes(base_dynamics: str) -> None:
    """Spot's held legs take no action: their drive targets are state. A restore in
    the same env and in a fresh one continues bit for bit (the targets were overwritten
    with the pose measured before the restore: 0.07 in the observation, 1.5 fresh)."""
    env = ra.make_env("Empty-v1", robot_uids="spot", num_envs=2, base_dynamics=base_dynamics)
    u = env.unwrapped
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-1, 1, (20, *env.action_space.shape))
    rollout(env, list(actions[:10]))
    saved = copy.deepcopy(u.get_state())
    expected = rollout(env, list(actions[10:]))
    u.set_state(saved)
    assert np.array_equal(rollout(env, list(actions[10:])), expected)
    fresh = ra.make_env("Empty-v1", robot_uids="spot", num_envs=2, base_dynamics=base_dynamics)
    fresh.unwrapped.set_state(saved)
    assert np.array_equal(rollout(fresh, list(actions[10:])), expected)
    env.close()
    fresh.close()


def test_set_state_of_get_state_changes_no_sensor_reading() -> None:
    """A step ends with poses updated, not sensors: the touch pads read what the last
    physics step measured. Restoring a state puts those readings back (its forward
    pass had recomputed them at the restored state: 0 N against 6.1 N here)."""
    env = ra.make_env("Empty-v1", robot_uids="panda_touch", obs_mode="state_dict")
    u = env.unwrapped
    env.reset(seed=0)
    action = np.zeros(8)
    action[-1] = -1.0  # close the fingers: the pads meet
    for _ in range(3):
        touch = env.step(action)[0]["agent"]["touch"].copy()
    u.set_state(u.get_state())
    np.testing.assert_array_equal(u.agent.touch, touch)
    env.close()


def test_a_task_state_restores_its_goals_and_random_streams() -> None:
    """The goals drawn at reset and each env's random stream are state: a restore
    continues bit for bit through an autoreset (which draws a new goal), also in a
    fresh env."""

    def run(vector: Any, actions: np.ndarray) -> np.ndarray:
        return np.concatenate([vector.step(a)[0] for a in actions])

    def make() -> Any:
        return gym.make_vec(
            "robot_agents/PickCube-v1",
            num_envs=2,
            vectorization_mode="vector_entry_point",
            robot_uids="panda",
            max_episode_steps=15,
        )

    actions = np.random.default_rng(0).uniform(-1, 1, (20, 2, 8)).astype(np.float32)
    env = make()
    env.reset(seed=0)
    run(env, actions[:10])
    saved = copy.deepcopy(env.env.get_state())
    expected = run(env, actions[10:])  # truncated at step 15, a new episode from step 16
    env.env.set_state(saved)
    assert np.array_equal(run(env, actions[10:]), expected)
    fresh = make()
    fresh.reset(seed=5)
    fresh.env.set_state(saved)
    assert np.array_equal(run(fresh, actions[10:]), expected)
    env.close()
    fresh.close()


def test_render_rgb_array() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", render_mode="rgb_array", render_size=(96, 64))
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (64, 96, 3) and frame.dtype == np.uint8
    assert frame.std() > 5  # not a blank image: floor, robot, shading
    env.close()
    batched = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, render_mode="rgb_array", render_size=(32, 32))
    batched.reset(seed=0)
    assert batched.render().shape == (2, 32, 32, 3)
    # wider than the scene's offscreen framebuffer (1280 x 960): it is enlarged, as for cameras
    wide = ra.make_env("Empty-v1", robot_uids="panda", render_mode="rgb_array", render_size=(1500, 16))
    wide.reset(seed=0)
    assert wide.render().shape == (16, 1500, 3)
    wide.close()


def test_reset_options_keyframe_and_env_ids() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2, robot_init_qpos_noise=0.0)
    u = env.unwrapped
    env.reset(options={"keyframe": "ready"})
    np.testing.assert_allclose(u.agent.qpos, np.tile(u.agent.keyframe_qpos("ready"), (2, 1)))
    env.reset(options={"keyframe": "rest", "env_ids": [1]})
    np.testing.assert_allclose(u.agent.qpos[0], u.agent.keyframe_qpos("ready"))
    np.testing.assert_allclose(u.agent.qpos[1], u.agent.keyframe_qpos("rest"))
    with pytest.raises(ra.UnknownNameError, match="'rest'"):
        env.reset(options={"keyframe": "rests"})
    with pytest.raises(ra.ConfigError, match=r"unknown options.*'keyfram': did you mean 'keyframe'"):
        env.reset(options={"keyfram": "rest"})


def test_two_robots_share_a_scene() -> None:
    env = ra.make_env("Empty-v1", robot_uids=("panda", "panda_stick"), num_envs=2, robot_init_qpos_noise=0.0)
    u = env.unwrapped
    assert [a.uid for a in u.agents] == ["panda", "panda_stick"]
    assert isinstance(env.action_space, gym.spaces.Dict)
    obs, _ = env.reset(seed=0)
    action = {"panda-0": np.zeros(8), "panda_stick-1": np.ones(7)}
    obs, *_ = env.step(action)
    assert obs.shape[0] == 2
    # The stick robot moved toward +0.1 rad per joint (kv / kp = 0.1 s, so ~40% of it
    # in one 0.05 s step), the Panda held still.
    np.testing.assert_allclose(u.agents[0].qpos[0, :7], u.agents[0].keyframe_qpos("rest")[:7], atol=5e-3)
    assert np.all(u.agents[1].qpos[0] > u.agents[1].keyframe_qpos("rest") + 0.02)
    bases = np.array([a.base_pose[0, :3] for a in u.agents])
    assert np.linalg.norm(bases[0] - bases[1]) == pytest.approx(1.0)
    with pytest.raises(ra.ConfigError, match="panda_stick-1"):
        env.step({"panda-0": np.zeros(8)})


def test_switching_mode_updates_spaces() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_pos")
    u = env.unwrapped
    env.reset(seed=0)
    for mode in ("pd_joint_delta_pos_vel", "pd_joint_vel", "pd_joint_pos"):
        u.set_control_mode(mode)
        obs, *_ = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs), mode
        assert env.action_space.shape == (1, u.agent.controller.action_dim)


def test_robot_poses_from_make_env_and_the_robots_own_mount() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", robot_poses=[(0.3, -0.2, 0.5, 1.0, 0.0, 0.0, 0.0)])
    env.reset(seed=0)
    np.testing.assert_allclose(env.unwrapped.agent.base_pose[0], [0.3, -0.2, 0.5, 1, 0, 0, 0], atol=1e-12)
    lifted = type(
        "LiftedPanda", (ra.get_agent("panda"),), {"uid": "lifted_panda", "mount_pose": (0, 0, 0.8, 1, 0, 0, 0)}
    )
    scene = ra.Scene(lifted)
    scene.reset()
    assert scene.agents[0].base_pose[0, 2] == pytest.approx(0.8)
    with pytest.raises(ra.ConfigError, match="unit quaternion"):
        ra.make_env("Empty-v1", robot_uids="panda", robot_poses=[(0, 0, 0, 0, 0, 0, 0)])
    with pytest.raises(ra.ConfigError, match="7 finite numbers"):
        ra.make_env("Empty-v1", robot_uids="panda", robot_poses=[(0, 0, float("nan"), 1, 0, 0, 0)])


def robot_pixel_share(env: ra.RobotEnv, camera: object) -> float:
    """Share of the picture covered by the robot's geoms (segmentation render)."""
    model = env.render_model
    renderer = mujoco.Renderer(model, 120, 160)
    renderer.enable_segmentation_rendering()
    renderer.update_scene(env.scene.world.render_sources([0])[0], camera=camera)  # type: ignore[arg-type]
    ids = renderer.render()[:, :, 0]
    renderer.close()
    robot = [g for g in range(model.ngeom) if model.body_rootid[model.geom_bodyid[g]] != 0]
    return float(np.isin(ids, robot).mean())


def test_render_frames_the_robot_whatever_its_size() -> None:
    """The render camera fits the robots' extent: the small floating hand fills about as
    much of the picture as the whole Panda arm, and far more than the fixed scene camera
    shows of it."""
    shares = {}
    for uid in ("panda", "floating_panda_gripper"):
        env = ra.make_env("Empty-v1", robot_uids=uid, render_mode="rgb_array", render_size=(160, 120))
        env.reset(seed=0)
        assert env.render().shape == (120, 160, 3)
        u = env.unwrapped
        shares[uid] = (robot_pixel_share(u, u._render_cameras[0]), robot_pixel_share(u, "render_camera"))
        env.close()
    framed, fixed = shares["floating_panda_gripper"]
    assert framed > 3 * fixed
    for uid, (share, _) in shares.items():
        assert 0.03 < share < 0.6, (uid, share)


def test_each_env_has_its_own_seeded_stream() -> None:
    """reset(seed=s) seeds env i with s + i: env i of a batch starts as a single env
    reset with seed s + i; a list gives each env its own seed (None: keep its stream)."""
    batch = ra.make_env("Empty-v1", robot_uids="panda", num_envs=3)
    single = ra.make_env("Empty-v1", robot_uids="panda")
    batch.reset(seed=11)
    rows = batch.unwrapped.agent.qpos
    for i in range(3):
        single.reset(seed=11 + i)
        np.testing.assert_array_equal(single.unwrapped.agent.qpos[0], rows[i])
    batch.reset(seed=[13, None, 11])
    after = batch.unwrapped.agent.qpos
    single.reset(seed=13)
    np.testing.assert_array_equal(after[0], single.unwrapped.agent.qpos[0])
    np.testing.assert_array_equal(after[2], rows[0])
    assert not np.array_equal(after[1], rows[1])  # env 1 went on with its stream
    with pytest.raises(ra.ConfigError, match="one per env"):
        batch.reset(seed=[1, 2])
    batch.reset(seed=np.array([11, 12, 13]))  # an integer array, as Gymnasium's SyncVectorEnv takes
    np.testing.assert_array_equal(batch.unwrapped.agent.qpos, rows)
    with pytest.raises(ra.ConfigError, match="one per env"):
        batch.reset(seed=np.array([1.0, 2.0, 3.0]))


def test_an_env_refuses_pickling_and_names_whose_action_was_bad() -> None:
    import copy
    import pickle

    env = ra.make_env("Empty-v1", robot_uids=("panda", "panda"))
    env.reset(seed=0)
    for copier in (pickle.dumps, copy.deepcopy):
        with pytest.raises(ra.StateError, match=r"cannot be pickled or copied .* save env\.unwrapped\.get_state\(\)"):
            copier(env.unwrapped)
    assert pickle.loads(pickle.dumps(env.unwrapped.get_state()))["elapsed_steps"].shape == (1,)
    before = env.unwrapped.get_state()
    with pytest.raises(ra.ActionError, match=r"step, action\['panda-1'\]: Panda\.set_action .* expected finite values"):
        env.step({"panda-0": np.zeros(8), "panda-1": np.full(8, np.nan)})
    after = env.unwrapped.get_state()
    np.testing.assert_array_equal(after["physics"], before["physics"])
    env.close()


def test_reset_keyframes_by_robot_id() -> None:
    """``options["keyframe"]`` keyed by robot id, as actions are (a robot left out takes
    its default): the same reset as one name per robot; an unknown id is named with the
    closest, before anything is reset."""
    env = ra.make_env("Empty-v1", robot_uids=("panda", "so100"), num_envs=2, robot_init_qpos_noise=0.0)
    u = env.unwrapped
    env.reset(seed=0, options={"keyframe": (None, "zero")})
    expected = u.get_state()["physics"]
    env.reset(seed=0, options={"keyframe": {"so100-1": "zero"}})
    np.testing.assert_array_equal(u.get_state()["physics"], expected)
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'so100-1'"):
        env.reset(seed=1, options={"keyframe": {"so100-0": "zero"}})
    with pytest.raises(ra.UnknownNameError, match="unknown keyframe 'zeros'"):
        env.reset(seed=1, options={"keyframe": {"so100-1": "zeros"}})
    np.testing.assert_array_equal(u.get_state()["physics"], expected)
    env.close()
