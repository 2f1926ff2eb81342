"""Gymnasium's vector API over one batched env: make_vec, spaces, autoreset in the
documented step (NEXT_STEP and SAME_STEP), per-env termination and truncation, partial
resets, and bit-identical agreement with single envs and Gymnasium's SyncVectorEnv."""

from __future__ import annotations

import warnings
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import robot_agents as ra
from robot_agents.envs import RobotVectorEnv

KW: dict[str, Any] = {"robot_uids": "panda", "control_mode": "pd_joint_delta_pos", "max_episode_steps": 4}


def make_vec(task: str = "PickCube-v1", num_envs: int = 4, **kwargs: Any) -> RobotVectorEnv:
    env = gym.make_vec(
        f"robot_agents/{task}", num_envs=num_envs, vectorization_mode="vector_entry_point", **{**KW, **kwargs}
    )
    assert isinstance(env, RobotVectorEnv)
    return env


def test_make_vec_gives_a_vector_env_over_one_batched_env() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # e.g. Gymnasium's warning about missing autoreset metadata
        env = gym.make_vec(
            "robot_agents/PickCube-v1", num_envs=64, vectorization_mode="vector_entry_point", robot_uids="panda"
        )
    assert isinstance(env, gym.vector.VectorEnv) and env.num_envs == 64
    assert env.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
    assert env.env.num_envs == 64 and env.env.scene.world.num_envs == 64  # one world, no subprocesses
    assert env.single_action_space.shape == (8,) and env.action_space.shape == (64, 8)
    assert env.single_observation_space.shape == env.observation_space.shape[1:]
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs) and info["elapsed_steps"].shape == (64,)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    assert reward.shape == terminated.shape == truncated.shape == info["success"].shape == (64,)
    assert terminated.dtype == truncated.dtype == bool
    env.close()
    assert env.closed
    for call, where in (
        (lambda: env.step(env.action_space.sample()), "step"),
        (env.reset, "reset"),
        (env.render, "render"),
    ):
        with pytest.raises(ra.StateError, match=rf"^RobotVectorEnv\.{where}: this env is closed"):
            call()  # named as the vector env's call (it named the task's PickCubeEnv.step)
    # dict observations: the single space is the batched one without its leading axis
    dict_env = make_vec(num_envs=2, obs_mode="state_dict")
    obs, _ = dict_env.reset(seed=0)
    assert dict_env.observation_space.contains(obs)
    assert dict_env.single_observation_space["extra"]["goal_pos"].shape == (3,)  # type: ignore[index]
    # and make_env keeps giving the batched env itself
    assert isinstance(ra.make_env("PickCube-v1", robot_uids="panda", num_envs=2).unwrapped, ra.RobotEnv)


def test_next_step_autoreset_happens_in_the_step_after_truncation() -> None:
    env = make_vec(num_envs=3)
    env.reset(seed=1)
    zero = np.zeros(env.action_space.shape)
    for k in range(1, 5):
        obs, reward, terminated, truncated, info = env.step(zero)
        np.testing.assert_array_equal(info["elapsed_steps"], [k, k, k])
    assert truncated.all() and not terminated.any()  # step 4: the episode's last observation
    last_goal = env.env.goal_pos.copy()
    obs, reward, terminated, truncated, info = env.step(np.ones(env.action_space.shape))  # actions ignored
    np.testing.assert_array_equal(info["elapsed_steps"], [0, 0, 0])
    np.testing.assert_array_equal(reward, [0.0, 0.0, 0.0])
    assert not terminated.any() and not truncated.any()
    assert not np.array_equal(env.env.goal_pos, last_goal)  # new episodes, new goals
    # the returned observation is the fresh episode's first one
    np.testing.assert_array_equal(obs, env.env._get_obs())
    np.testing.assert_array_equal(env.env.agent.qvel, np.zeros_like(env.env.agent.qvel))
    info = env.step(zero)[4]
    np.testing.assert_array_equal(info["elapsed_steps"], [1, 1, 1])  # stepping again


def test_an_autoreset_step_observes_once() -> None:
    """NEXT_STEP: the step that resets the envs that ended is observed once, by their
    reset (which observes every env); the step's own observation, camera renders and
    all, was taken and thrown away before."""
    env = make_vec(num_envs=2, obs_mode="rgb", max_episode_steps=2)
    env.reset(seed=0)
    calls: list[int] = []
    observe = env.env._get_obs

    def counting() -> Any:
        calls.append(1)
        return observe()

    env.env._get_obs = counting
    zero = np.zeros(env.action_space.shape)
    for step, (observed, reset) in enumerate([(1, False), (1, False), (1, True), (1, False)]):
        calls.clear()
        obs, _, _, _, info = env.step(zero)
        assert len(calls) == observed, step
        assert (info["elapsed_steps"] == 0).all() == reset
    env.env._get_obs = observe
    rgb = obs["sensor_data"]["base_camera"]["rgb"]
    assert rgb.shape[0] == 2 and rgb.any()
    env.close()


def test_a_state_saved_with_an_autoreset_pending_continues_exactly() -> None:
    """NEXT_STEP: a state saved on the step that ended the episodes holds the pending
    autoresets (``env.get_state()`` alone did not: the restored envs were not reset);
    the vector spaces follow a restored control mode; bad flags are refused first."""
    import pickle

    env = make_vec(num_envs=2, max_episode_steps=3)
    env.reset(seed=0)
    zero = np.zeros((2, 8), np.float32)
    for _ in range(3):
        *_, truncated, _ = env.step(zero)
    assert truncated.all()
    saved = env.get_state()
    assert saved["autoreset"].tolist() == [True, True]

    def steps() -> list[bytes]:
        return [pickle.dumps(env.step(zero)[:4]) for _ in range(3)]

    expected = steps()
    env.set_control_mode("pd_ee_delta_pose")
    assert env.single_action_space.shape == (7,)
    env.set_state(saved)
    assert env.single_action_space.shape == (8,) and env.action_space.shape == (2, 8)
    assert env.observation_space.shape == (2, *env.single_observation_space.shape)
    assert env.observation_space.shape == env.env.observation_space.shape
    assert steps() == expected
    before = env.get_state()
    with pytest.raises(ra.StateError, match=r"'autoreset' to be a bool array of shape \(2,\)"):
        env.set_state({**saved, "autoreset": np.array([1, 1])})
    after = env.get_state()
    assert np.array_equal(after["physics"], before["physics"]) and after["autoreset"].tolist() == [False, False]
    env.close()


def test_empty_env_has_the_vector_api_too() -> None:
    env = gym.make_vec("robot_agents/Empty-v1", num_envs=2, robot_uids="so100", max_episode_steps=2)
    assert isinstance(env, RobotVectorEnv)
    env.reset(seed=0)
    for expected in ([1, 1], [2, 2], [0, 0]):
        info = env.step(np.zeros(env.action_space.shape))[4]
        np.testing.assert_array_equal(info["elapsed_steps"], expected)
    env.close()


def test_info_masks_are_new_writable_arrays_each_step() -> None:
    """The ``_<key>`` masks are all True, one new array per key and step, as
    SyncVectorEnv's are (its ``_add_info`` writes masks in place): a caller that keeps
    a step's info or changes a mask touches no other key's, no later step's and not
    the array they are copied from."""
    env = gym.make_vec("robot_agents/Empty-v1", num_envs=2, robot_uids="so100", max_episode_steps=5)
    _, first = env.reset(seed=0)
    kept = env.step(np.zeros(env.action_space.shape))[4]
    masks = [kept[key] for key in kept if key.startswith("_")] + [first[key] for key in first if key.startswith("_")]
    assert len(masks) > 2 and len({id(m) for m in masks}) == len(masks)
    for mask in masks:
        assert mask.dtype == np.bool_ and mask.flags.writeable and mask.flags.owndata
        np.testing.assert_array_equal(mask, [True, True])
        mask[0] = False  # a caller's write
    later = env.step(np.zeros(env.action_space.shape))[4]
    for key in (key for key in later if key.startswith("_")):
        np.testing.assert_array_equal(later[key], [True, True])
    np.testing.assert_array_equal(kept["_elapsed_steps"], [False, True])
    env.close()


def test_terminated_env_resets_alone() -> None:
    env = make_vec("ReachPose-v1", num_envs=3, max_episode_steps=50)
    env.reset(seed=2)
    zero = np.zeros(env.action_space.shape)
    env.step(zero)
    goals = env.env.goal_pose.copy()
    env.env.goal_pose[1] = env.env.agent.tcp_pose[1]  # env 1 is at its goal
    _, reward, terminated, _, info = env.step(zero)
    np.testing.assert_array_equal(terminated, [False, True, False])
    assert reward[1] == 1.0 and info["success"].tolist() == [False, True, False]
    state = env.env.get_state()["physics"].copy()
    _obs, reward, terminated, _truncated, info = env.step(zero)
    np.testing.assert_array_equal(info["elapsed_steps"], [3, 0, 3])
    assert reward[1] == 0.0 and not terminated.any()
    assert not info["success"][1]  # the metrics of env 1 describe its new first state
    assert not np.array_equal(env.env.goal_pose[1], env.env.agent.tcp_pose[1])
    np.testing.assert_array_equal(env.env.goal_pose[[0, 2]], goals[[0, 2]])  # the others go on
    assert not np.array_equal(env.env.get_state()["physics"][1], state[1])


def test_partial_reset_with_a_mask_touches_only_those_envs() -> None:
    env = make_vec(num_envs=4, max_episode_steps=50)
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(3):
        env.step(rng.uniform(-1, 1, env.action_space.shape))
    before = env.env.get_state()["physics"].copy()
    goals = env.env.goal_pos.copy()
    obs, info = env.reset(options={"reset_mask": np.array([False, True, False, True])})
    after = env.env.get_state()["physics"]
    np.testing.assert_array_equal(after[[0, 2]], before[[0, 2]])
    np.testing.assert_array_equal(env.env.goal_pos[[0, 2]], goals[[0, 2]])
    np.testing.assert_array_equal(info["elapsed_steps"], [3, 0, 3, 0])
    assert env.observation_space.contains(obs)
    with pytest.raises(ra.StateError, match="reset_mask"):
        env.reset(options={"reset_mask": np.zeros(4, dtype=bool)})
    with pytest.raises(ra.StateError, match="reset_mask"):
        env.reset(options={"reset_mask": np.array([1, 0, 0, 0])})  # not bools


def test_an_unknown_reset_option_names_the_vector_env_and_its_options() -> None:
    """The vector env's reset takes ``reset_mask`` besides the env's ``env_ids`` and
    ``keyframe``: a misspelt option is refused naming it and all three, nothing reset
    (before, the batched env's message named ``PickCubeEnv.reset`` and left
    ``reset_mask`` out)."""
    env = make_vec(num_envs=2)
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))
    before = env.get_state()
    with pytest.raises(
        ra.ConfigError, match=r"RobotVectorEnv\.reset.*'resetmask'.*'reset_mask', 'env_ids', 'keyframe'"
    ):
        env.reset(seed=1, options={"resetmask": np.array([True, False])})
    after = env.get_state()
    np.testing.assert_array_equal(after["physics"], before["physics"])
    np.testing.assert_array_equal(after["elapsed_steps"], before["elapsed_steps"])
    assert after["rng"] == before["rng"]


def test_an_int_seed_is_the_vector_envs_np_random_seed() -> None:
    """As ``gymnasium.vector.VectorEnv.reset``: ``reset(seed=s)`` seeds the vector env's
    own ``np_random`` (it drew an unseeded one before); a rejected seed leaves it."""
    env = make_vec(num_envs=2)
    env.reset(seed=4)
    assert env.np_random_seed == 4
    first = env.np_random.random()
    env.reset(seed=4)
    assert env.np_random.random() == first
    with pytest.raises(ra.ConfigError):
        env.reset(seed=-3)
    assert env.np_random_seed == 4
    env.reset(seed=[1, 2])  # one per env: the vector env's own generator is left as it was
    assert env.np_random_seed == 4
    env.close()


def test_same_step_autoreset_returns_the_final_observation_in_info() -> None:
    env = make_vec(num_envs=2, autoreset_mode="same_step", max_episode_steps=2)
    assert env.metadata["autoreset_mode"] is AutoresetMode.SAME_STEP
    env.reset(seed=4)
    zero = np.zeros(env.action_space.shape)
    obs, _, _, truncated, info = env.step(zero)
    assert not truncated.any() and "final_obs" not in info
    state_before = env.env.agent.qpos.copy()
    obs, _, _, truncated, info = env.step(zero)
    assert truncated.all()
    np.testing.assert_array_equal(info["_final_obs"], [True, True])
    assert info["final_obs"].dtype == object and info["final_obs"][0].shape == env.single_observation_space.shape
    np.testing.assert_array_equal(info["final_info"]["elapsed_steps"], [2, 2])
    np.testing.assert_array_equal(info["elapsed_steps"], [0, 0])  # already reset
    assert not np.array_equal(info["final_obs"][0], obs[0])
    assert not np.allclose(env.env.agent.qpos, state_before)
    with pytest.raises(ra.ConfigError, match="autoreset_mode"):
        make_vec(autoreset_mode="sometimes")


def _sync_reference(task: str, num_envs: int, mode: AutoresetMode, **kwargs: Any) -> SyncVectorEnv:
    def single() -> gym.Env[Any, Any]:
        return ra.make_env(task, num_envs=1, **{**KW, **kwargs})

    return SyncVectorEnv([single for _ in range(num_envs)], autoreset_mode=mode)


@pytest.mark.parametrize(
    ("mode", "control_mode"),
    [
        (AutoresetMode.NEXT_STEP, "pd_joint_delta_pos"),
        (AutoresetMode.SAME_STEP, "pd_joint_delta_pos"),
        (AutoresetMode.NEXT_STEP, "pd_ee_delta_pose"),
    ],
)
def test_batch_equals_single_envs_and_gymnasium_sync_vector_env(mode: AutoresetMode, control_mode: str) -> None:
    """num_envs = 4 gives, bit for bit, what four num_envs = 1 envs seeded s + i give,
    autoresets included; Gymnasium's SyncVectorEnv over single envs agrees."""
    task, n, seed, steps = "PickCube-v1", 4, 7, 11
    kw = {"max_episode_steps": 3, "control_mode": control_mode}
    batch = make_vec(task, num_envs=n, autoreset_mode=mode, **kw)
    singles = [make_vec(task, num_envs=1, autoreset_mode=mode, **kw) for _ in range(n)]
    reference = _sync_reference(task, n, mode, **kw)
    rng = np.random.default_rng(5)
    actions = [rng.uniform(-1, 1, batch.action_space.shape).astype(np.float32) for _ in range(steps)]
    b_obs, b_info = batch.reset(seed=seed)
    results_batch = [b_obs]
    results_single = [np.concatenate([s.reset(seed=seed + i)[0] for i, s in enumerate(singles)])]
    r_obs, r_info = reference.reset(seed=seed)
    results_reference = [r_obs[:, 0]]
    _same_info(b_info, r_info, n)
    for action in actions:
        b = batch.step(action)
        s = [env.step(action[i : i + 1]) for i, env in enumerate(singles)]
        r = reference.step(action[:, None, :])
        _same_info(b[4], r[4], n)
        results_batch.append(b[0])
        results_single.append(np.concatenate([x[0] for x in s]))
        results_reference.append(r[0][:, 0])
        for k in (1, 2, 3):  # reward, terminated, truncated
            np.testing.assert_array_equal(b[k], np.concatenate([x[k] for x in s]))
            np.testing.assert_array_equal(b[k], r[k])
        if mode is AutoresetMode.SAME_STEP and "final_obs" in b[4]:
            np.testing.assert_array_equal(b[4]["_final_obs"], r[4]["_final_obs"])
            for i in np.flatnonzero(b[4]["_final_obs"]):
                np.testing.assert_array_equal(b[4]["final_obs"][i], r[4]["final_obs"][i][0])
    assert np.stack(results_batch).std(axis=0).max() > 0.01  # the observations do change
    np.testing.assert_array_equal(np.stack(results_batch), np.stack(results_single))
    np.testing.assert_array_equal(np.stack(results_batch), np.stack(results_reference))
    for env in (batch, reference, *singles):
        env.close()


def _same_info(ours: dict[str, Any], sync: dict[str, Any], n: int) -> None:
    """Every info key of ``SyncVectorEnv``'s, Gymnasium's ``"_<key>"`` masks included
    (ours all ``True``: an env reset in the step reports its first state's metrics where
    the sync env reports only the reset's keys, so ours may hold more), and the same
    values where both report."""
    assert set(sync) <= set(ours)
    assert all(f"_{key}" in ours for key in ours if not key.startswith("_"))
    for key in (k for k in sync if not k.startswith("_") and k not in ("final_obs", "final_info")):
        np.testing.assert_array_equal(ours[f"_{key}"], np.ones(n, dtype=bool))
        mask = sync[f"_{key}"]
        np.testing.assert_array_equal(ours[key][mask], np.reshape(sync[key], ours[key].shape)[mask])


def test_docs_vector_block_runs() -> None:
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "tasks.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "make_vec" in b)
    namespace: dict[str, Any] = {}
    exec(compile(block, "docs/tasks.md vector block", "exec"), namespace)
    assert namespace["obs"].shape == (64, namespace["envs"].single_observation_space.shape[0])
    namespace["envs"].close()
