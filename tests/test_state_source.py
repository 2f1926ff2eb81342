"""What made an env's state (``state["source"]``): a state of another task, robot or
scene is refused naming the field; the fingerprint is plain data, the same in another
process; a state saved without it restores with a warning."""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.envs.state_source import SOURCE_FIELDS


def _refused(env: ra.RobotEnv, state: dict[str, Any], *fragments: str) -> None:
    """``env.set_state(state)`` raises StateError with ``fragments`` and changes nothing."""
    before = env.get_state()
    with pytest.raises(ra.StateError) as caught:
        env.set_state(state)
    for fragment in fragments:
        assert fragment in str(caught.value), (fragment, str(caught.value))
    after = env.get_state()
    np.testing.assert_array_equal(after["physics"], before["physics"])
    assert repr(after) == repr(before)


def test_a_state_of_another_task_with_the_same_arrays_is_refused() -> None:
    """PickCube's and PushCube's Panda scenes have the same array layout (a table, one
    free cube, a 3-D goal): without its source, a PickCube state restores into PushCube
    (the unchecked path, with a warning); with it, the task is named, expected and given."""
    pick = ra.make_env("PickCube-v1", robot_uids="panda").unwrapped
    push = ra.make_env("PushCube-v1", robot_uids="panda").unwrapped
    pick.reset(seed=0)
    push.reset(seed=1)
    state = pick.get_state()
    _refused(
        push,
        state,
        "PushCubeEnv.set_state",
        "expected its source task to be 'PushCubeEnv' (this env's), got 'PickCubeEnv'",
    )
    unchecked = {key: value for key, value in state.items() if key != "source"}
    with pytest.warns(UserWarning, match="the state has no 'source'"):
        push.set_state(unchecked)  # the arrays fit: this is what the source stops
    pick.close()
    push.close()


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"sim_freq": 1000}, "source sim_freq to be 1000 (this env's), got 500"),
        ({"control_freq": 25}, "source control_freq to be 25 (this env's), got 20"),
        ({"sleep": True}, "source sleep to be True (this env's), got False"),
        (
            {"robot_poses": [(0.0, 0.5, 0.0, 1.0, 0.0, 0.0, 0.0)]},
            "source robot_poses[0][1] to be 0.5 (this env's), got 0.0",
        ),
        ({"robot_uids": "so100"}, "source robots[0] to be 'so100-0' (this env's), got 'panda-0'"),
    ],
)
def test_a_state_of_other_scene_arguments_is_refused(kwargs: dict[str, Any], fragment: str) -> None:
    """Each argument that changes what a state means is named with both values."""
    saved = ra.make_env("Empty-v1", robot_uids="panda").unwrapped
    saved.reset(seed=0)
    other = ra.make_env("Empty-v1", **{"robot_uids": "panda", **kwargs}).unwrapped
    other.reset(seed=0)
    _refused(other, saved.get_state(), fragment)
    saved.close()
    other.close()


class _BlockEnv(ra.RobotEnv):
    """A Panda and a free block whose size is an option of the task."""

    def __init__(self, half_size: float = 0.02, **kwargs: Any) -> None:
        self.half_size = half_size
        super().__init__(**kwargs)

    def _scene_props(self) -> Sequence[ra.Prop]:
        return (ra.Prop("block", "box", (self.half_size,) * 3, pos=(0.5, 0.0, self.half_size)),)


def test_a_state_of_another_prop_is_refused_and_other_settings_may_differ() -> None:
    """A prop of another size gives the same arrays, another scene: refused, naming the
    entry. What does not change a state's meaning (observation and render settings,
    reset noise, episode limit, control mode: restored from the state) may differ."""
    small = _BlockEnv(robot_uids="panda", num_envs=2)
    small.reset(seed=0)
    small.step(np.full((2, 8), 0.2))
    state = small.get_state()
    large = _BlockEnv(robot_uids="panda", num_envs=2, half_size=0.03)
    _refused(large, state, "source props[0]['size'][0] to be 0.03 (this env's), got 0.02")
    other = _BlockEnv(
        robot_uids="panda",
        num_envs=2,
        obs_mode="state_dict",
        render_mode="rgb_array",
        robot_init_qpos_noise=0.0,
        max_episode_steps=7,
        control_mode="pd_joint_pos",
    )
    other.set_state(state)
    np.testing.assert_array_equal(other.get_state()["physics"], state["physics"])
    assert other.agent.control_mode == small.agent.control_mode
    for env in (small, large, other):
        env.close()


def test_a_malformed_source_is_refused() -> None:
    """Not a dict, a misspelt or a missing field, an entry of another type: refused
    before anything is written (a bool is not the number 1, a string not a list)."""
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2).unwrapped
    env.reset(seed=0)
    state = env.get_state()
    source = state["source"]
    assert list(source) == list(SOURCE_FIELDS)
    _refused(env, {**state, "source": "panda"}, "expected 'source' to be a dict")
    renamed = {("robot" if key == "robots" else key): value for key, value in source.items()}
    _refused(env, {**state, "source": renamed}, "unknown source keys ['robot']", "did you mean 'robots'?")
    missing = {key: value for key, value in source.items() if key != "sleep"}
    _refused(env, {**state, "source": missing}, "got none for ['sleep']")
    for field, value, fragment in (
        ("sleep", 0, "source sleep to be False"),
        ("control_freq", True, "source control_freq to be 20"),
        ("robots", "panda-0", "source robots to be ['panda-0']"),
        ("robot_poses", [[0.0] * 6], "source robot_poses[0] to be"),
        ("props", None, "source props to be []"),
    ):
        _refused(env, {**state, "source": {**source, field: value}}, fragment)
    env.close()


def test_the_source_is_plain_data_the_same_in_another_process(tmp_path: Path) -> None:
    """The fingerprint holds only str, int, float, bool, None, lists and dicts: it
    survives pickle and JSON, and another process (which lays PickCube's table out from
    the robot again) writes the same one; its state restores here, exactly."""
    env = ra.make_env("PickCube-v1", robot_uids="panda", num_envs=2).unwrapped
    env.reset(seed=3)
    source = env.get_state()["source"]
    assert json.loads(json.dumps(source)) == source
    assert pickle.loads(pickle.dumps(source)) == source
    path = tmp_path / "state.pkl"
    script = (
        "import pickle, sys, numpy as np, robot_agents as ra\n"
        "env = ra.make_env('PickCube-v1', robot_uids='panda', num_envs=2).unwrapped\n"
        "env.reset(seed=3)\n"
        "env.step(np.full((2, 8), 0.3))\n"
        "pickle.dump(env.get_state(), open(sys.argv[1], 'wb'))\n"
    )
    src = str(Path(ra.__file__).parents[1])
    run_env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    subprocess.run([sys.executable, "-c", script, str(path)], check=True, env=run_env, timeout=120)
    with path.open("rb") as file:
        saved = pickle.load(file)  # written by the test itself
    assert saved["source"] == source
    env.set_state(saved)
    env.step(np.full((2, 8), -0.2))
    again = env.get_state()
    env.set_state(saved)
    env.step(np.full((2, 8), -0.2))
    np.testing.assert_array_equal(env.get_state()["physics"], again["physics"])
    env.close()


def test_a_state_saved_without_a_source_restores_with_a_warning() -> None:
    """A state saved before states recorded their source restores exactly (what was
    checked before is still checked), with a warning that says it was not checked; the
    vector env passes the source to its env."""
    env = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2).unwrapped
    env.reset(seed=0)
    env.step(np.full((2, 8), 0.3))
    state = env.get_state()
    older = {key: value for key, value in state.items() if key != "source"}
    env.step(np.full((2, 8), -0.3))
    with pytest.warns(UserWarning, match=r"EmptyEnv.set_state: the state has no 'source'"):
        env.set_state(older)
    assert repr(env.get_state()) == repr(state)
    env.close()
    vector = gym.make_vec(
        "robot_agents/Empty-v1", num_envs=2, vectorization_mode="vector_entry_point", robot_uids="panda"
    )
    vector.reset(seed=0)
    other = gym.make_vec(
        "robot_agents/Empty-v1", num_envs=2, vectorization_mode="vector_entry_point", robot_uids="so100"
    )
    other.reset(seed=0)
    with pytest.raises(ra.StateError, match="source robots"):
        vector.set_state(other.get_state())
    vector.close()
    other.close()
