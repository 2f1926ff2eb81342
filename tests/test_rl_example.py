"""examples/train_ppo_reach.py: the SB3 adapter over our vector env, and two PPO iterations.

Runs only where the optional ``[rl]`` extra (Stable-Baselines3, torch, matplotlib) is
installed; CI installs ``[test]`` only, so it skips there.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def example() -> ModuleType:
    spec = importlib.util.spec_from_file_location("train_ppo_reach", ROOT / "examples" / "train_ppo_reach.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["train_ppo_reach"] = module
    spec.loader.exec_module(module)
    return module


def test_adapter_reports_episode_ends_as_sb3_expects(example: ModuleType) -> None:
    import gymnasium as gym

    venv = gym.make_vec(
        "robot_agents/ReachPose-v1",
        num_envs=2,
        vectorization_mode="vector_entry_point",
        robot_uids="panda",
        autoreset_mode="same_step",
        max_episode_steps=3,
    )
    env = example.SB3VecEnv(venv, bootstrap_at_success=False)
    assert env.num_envs == 2 and env.observation_space == venv.single_observation_space
    env.seed(7)
    first = env.reset()
    again = example.SB3VecEnv(venv).reset()  # unseeded: the streams go on, new goals
    assert not np.array_equal(first, again)
    env.seed(7)
    np.testing.assert_array_equal(env.reset(), first)  # seeds 7, 8 again
    zero = np.zeros((2, *env.action_space.shape), dtype=np.float32)
    for step in range(3):
        obs, reward, dones, infos = env.step(zero)
        assert obs.shape == first.shape and reward.shape == (2,) and reward.dtype == np.float32
        assert np.all(np.isfinite(reward)) and np.all((reward >= 0) & (reward <= 1))
        if step < 2:
            assert not dones.any() and infos == [{}, {}]
    assert dones.all()  # truncated after 3 steps
    for i, info in enumerate(infos):
        assert info["TimeLimit.truncated"] is True and info["is_success"] is False
        last = info["terminal_observation"]
        assert last.shape == first.shape[1:] and not np.array_equal(last, obs[i])  # obs[i]: the next episode's
    env.close()


def test_two_ppo_iterations_run_and_evaluate(example: ModuleType, tmp_path: Path) -> None:
    rows = example.main(
        [
            "--num-envs", "2", "--n-steps", "16", "--batch-size", "16", "--timesteps", "64",
            "--eval-envs", "2", "--eval-every", "32", "--out", str(tmp_path),
        ]
    )  # fmt: skip
    assert [row["steps"] for row in rows] == [32, 64, 64]  # after iterations 1, 2 and the final evaluation
    for row in rows:
        assert 0.0 <= row["eval_success"] <= 1.0 and 0.0 < row["eval_return"] <= 100.0
    assert (tmp_path / "curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "ppo_reach_panda.zip").exists() and (tmp_path / "curve.csv").exists()
