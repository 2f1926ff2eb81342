"""Observation modes with cameras: Gymnasium's checker passes for each, the layout is
ManiSkill's, and the spaces contain the observations."""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import robot_agents as ra

SMALL = {"hand_camera": {"width": 24, "height": 16}, "base_camera": {"width": 20, "height": 20}}
VISUAL_MODES = ["sensor_data", "rgb", "depth", "rgbd", "segmentation", "pointcloud", "rgb+segmentation"]


def make(obs_mode: str, **kwargs: Any) -> Any:
    options: dict[str, Any] = {"robot_uids": "panda_wristcam", "obs_mode": obs_mode, "sensor_configs": SMALL}
    options.update(kwargs)
    return ra.make_env("Empty-v1", **options)


@pytest.mark.parametrize("obs_mode", VISUAL_MODES)
def test_check_env_passes_for_camera_modes(obs_mode: str) -> None:
    # Both cameras 16 x 16 (one OpenGL context); render() is checked once, for sensor_data.
    same_size = {"hand_camera": {"width": 16, "height": 16}, "base_camera": {"width": 16, "height": 16}}
    env = make(obs_mode, sensor_configs=same_size, render_mode="rgb_array", render_size=(32, 24))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=obs_mode != "sensor_data")
    env.close()


@pytest.mark.parametrize(
    ("obs_mode", "textures"),
    [
        ("sensor_data", ["depth", "rgb", "segmentation"]),
        ("rgb", ["rgb"]),
        ("depth", ["depth"]),
        ("rgbd", ["depth", "rgb"]),
        ("segmentation", ["segmentation"]),
        ("depth+segmentation", ["depth", "segmentation"]),
    ],
)
def test_sensor_data_layout(obs_mode: str, textures: list[str]) -> None:
    env = make(obs_mode, num_envs=3)
    obs, _ = env.reset(seed=0)
    assert set(obs) == {"agent", "extra", "sensor_param", "sensor_data"}
    assert obs["agent"]["qpos"].shape == (3, 9) and obs["extra"]["tcp_pose"].shape == (3, 7)
    assert list(obs["sensor_data"]) == ["hand_camera", "base_camera"]  # robot cameras first
    expected = {"rgb": (3, np.uint8), "depth": (1, np.float32), "segmentation": (1, np.int16)}
    for key, (h, w) in (("hand_camera", (16, 24)), ("base_camera", (20, 20))):
        assert sorted(obs["sensor_data"][key]) == textures
        for texture, image in obs["sensor_data"][key].items():
            channels, dtype = expected[texture]
            assert image.shape == (3, h, w, channels) and image.dtype == dtype
        params = obs["sensor_param"][key]
        assert params["intrinsic_cv"].shape == (3, 3, 3) and params["extrinsic_cv"].shape == (3, 3, 4)
        assert params["cam2world_gl"].shape == (3, 4, 4) and params["cam2world_gl"].dtype == np.float32
    assert env.observation_space.contains(obs)
    obs, *_ = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs)
    if "depth" in textures:
        depth = obs["sensor_data"]["base_camera"]["depth"]
        assert depth.min() > 0.3 and depth.max() <= 10.0  # metres: floor and robot 0.5-1.5 m away; far plane 10 m


def test_pointcloud_layout_and_space() -> None:
    env = make("pointcloud", num_envs=2)
    obs, _ = env.reset(seed=0)
    points = 16 * 24 + 20 * 20
    assert set(obs) == {"agent", "extra", "sensor_param", "pointcloud"}
    assert obs["pointcloud"]["xyzw"].shape == (2, points, 4)
    assert obs["pointcloud"]["rgb"].shape == (2, points, 3) and obs["pointcloud"]["rgb"].dtype == np.uint8
    assert obs["pointcloud"]["segmentation"].shape == (2, points, 1)
    space = env.observation_space
    assert isinstance(space, gym.spaces.Dict) and space["pointcloud"]["xyzw"].shape == (2, points, 4)
    assert space.contains(obs)
    w = obs["pointcloud"]["xyzw"][..., 3]
    assert set(np.unique(w).tolist()) <= {0.0, 1.0} and w.mean() > 0.5


def test_spaces_bound_images() -> None:
    space = make("sensor_data").observation_space
    rgb, depth, seg = (space["sensor_data"]["base_camera"][t] for t in ("rgb", "depth", "segmentation"))
    assert (rgb.low.min(), rgb.high.max(), rgb.dtype) == (0, 255, np.uint8)
    assert (depth.low.min(), depth.high.max()) == (0.0, 10.0)
    nbody = make("sensor_data").unwrapped.model.nbody
    assert (seg.low.min(), seg.high.max(), seg.dtype) == (-1, nbody - 1, np.int16)


def test_camera_modes_need_a_camera() -> None:
    with pytest.raises(ra.ConfigError, match="obs_mode 'depth' needs at least one camera"):
        ra.make_env("Empty-v1", robot_uids="panda", obs_mode="depth", sensor_configs={"base_camera": None})
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'pointcloud'"):
        ra.make_env("Empty-v1", obs_mode="pointclouds")
    with pytest.raises(ra.UnknownNameError, match="unknown obs_mode 'rgb\\+rgb'"):
        ra.make_env("Empty-v1", obs_mode="rgb+rgb")


def test_state_modes_render_nothing() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda_wristcam", obs_mode="state")
    env.reset(seed=0)
    env.step(np.zeros(8))
    assert env.unwrapped.scene.cameras._renderer is None  # no OpenGL context was made


@pytest.mark.parametrize("doc", ["README.md", "docs/sensors.md"])
def test_documented_camera_example_runs(doc: str) -> None:
    """The first camera example of the README and of docs/sensors.md runs as written."""
    text = (Path(__file__).resolve().parents[1] / doc).read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "sensor_data" in b)
    namespace: dict[str, Any] = {"ra": ra}
    exec(compile(block, f"{doc} camera example", "exec"), namespace)
    assert namespace["obs"]["sensor_data"]["hand_camera"]["rgb"].shape == (1, 256, 256, 3)


def test_an_observation_space_too_large_for_memory_is_a_config_error() -> None:
    """Gymnasium's Box holds bounds of the observation's shape: for images too many for
    the memory its allocation raised numpy's MemoryError from make_env; now a
    ConfigError names the mode, the shape, the memory and the cameras."""
    from robot_agents.envs.observations import SensorObservation, parse_obs_mode

    scene = ra.Scene("panda", cameras=[ra.CameraConfig("top", pos=(0, 0, 2), width=64, height=48)])
    sensors = SensorObservation(scene.cameras, parse_obs_mode("rgbd", "Test"), "Test")
    assert sensors.spaces(2)["sensor_data"]["top"]["rgb"].shape == (2, 48, 64, 3)
    with pytest.raises(ra.ConfigError) as caught:
        sensors.spaces(10**11)  # ~4 PB of bounds: no machine allocates it
    message = str(caught.value)
    for fragment in (
        "Test: the observation space of obs_mode 'rgbd'",
        "an entry of shape (100000000000, ",
        "GiB",
        "'top' 64 x 48",
    ):
        assert fragment in message, message
    scene.close()


def _mismatches(space: gym.Space[Any], obs: Any, path: str = "") -> list[str]:
    """Entries of ``obs`` whose keys, dtype, shape or values do not match ``space`` exactly."""
    if isinstance(space, gym.spaces.Dict):
        found = [f"{path}: keys {sorted(obs)} != {sorted(space.spaces)}"] if set(obs) != set(space.spaces) else []
        return found + [m for k in space.spaces if k in obs for m in _mismatches(space[k], obs[k], f"{path}/{k}")]
    assert isinstance(space, gym.spaces.Box)
    array = np.asarray(obs)
    if array.dtype != space.dtype or array.shape != space.shape:
        return [f"{path}: {array.dtype} {array.shape} != {space.dtype} {space.shape}"]
    return [] if space.contains(array) else [f"{path}: values {array.min()}..{array.max()} outside the bounds"]


@pytest.mark.parametrize("obs_mode", ["state", "state_dict", *VISUAL_MODES])
def test_observations_match_their_space_exactly(obs_mode: str) -> None:
    """Every entry has its space's dtype and shape (not merely one that casts) and lies in
    its bounds, after reset and steps, for a robot with touch pads and a wrist camera and
    for Stretch, whose head camera's depth reaches its 100 m far plane."""
    from robot_agents.robots.panda.panda import FINGERTIP_TOUCH, PandaWristCam

    class TouchWristCam(PandaWristCam):
        touch_sensors = FINGERTIP_TOUCH

    for robot, cameras in ((TouchWristCam, SMALL), ("stretch", {"head_camera": {"width": 12, "height": 16}})):
        env = ra.make_env("Empty-v1", robot_uids=robot, obs_mode=obs_mode, num_envs=2, sensor_configs=cameras)
        obs, _ = env.reset(seed=0)
        found = _mismatches(env.observation_space, obs)
        for _ in range(3):
            obs, *_ = env.step(env.action_space.sample())
            found += _mismatches(env.observation_space, obs)
        assert not found, found
        if obs_mode in ("depth", "sensor_data") and robot == "stretch":
            assert obs["sensor_data"]["head_camera"]["depth"].max() == 100.0  # the sky, at the far plane
        env.close()
