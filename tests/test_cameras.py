"""Camera declarations, overrides and poses: configs are validated, overrides reach the
model, a wrist camera moves with its link, parameters follow the OpenCV / OpenGL
conventions, and rendering never changes the simulation."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.robots.panda.panda import HAND_CAMERA, Panda

SMALL = {"hand_camera": {"width": 32, "height": 32}, "base_camera": None}


def wristcam_env(**kwargs: Any) -> Any:
    options: dict[str, Any] = {"robot_uids": "panda_wristcam", "obs_mode": "rgb", "sensor_configs": SMALL}
    options.update(kwargs)
    return ra.make_env("Empty-v1", **options).unwrapped


@pytest.mark.parametrize(
    ("fields", "fragments"),
    [
        ({"width": 0}, ["width", "[1, 8192]", "got 0"]),
        ({"height": 12.5}, ["height", "got 12.5"]),
        ({"width": True}, ["width", "got True"]),
        ({"fovy": 180.0}, ["fovy in (0, 180) degrees", "got 180.0"]),
        ({"fovy": 60.0, "intrinsic": np.eye(3)}, ["either fovy or intrinsic, got both"]),
        ({"intrinsic": [[50, 1, 16], [0, 50, 16], [0, 0, 1]]}, ["no skew"]),
        ({"intrinsic": [[50, 0, 40], [0, 50, 16], [0, 0, 1]], "width": 32}, ["principal point", "(40.0, 16.0)"]),
        ({"intrinsic": [[-5, 0, 16], [0, 50, 16], [0, 0, 1]]}, ["fx, fy > 0"]),
        ({"near": 0.5, "far": 0.1}, ["0 < near < far", "near=0.5, far=0.1"]),
        ({"quat": (0, 0, 0, 0)}, ["non-zero quaternion"]),
        ({"pos": (0, 0)}, ["pos (m) as 3 finite numbers"]),
        ({"mount": ""}, ["mount"]),
        ({"shadows": "yes"}, ["shadows to be True or False"]),
    ],
)
def test_camera_config_rejects_bad_values(fields: dict[str, Any], fragments: list[str]) -> None:
    with pytest.raises(ra.ConfigError) as caught:
        ra.CameraConfig("cam", **fields)
    for fragment in fragments:
        assert fragment in str(caught.value), str(caught.value)
    assert "CameraConfig 'cam'" in str(caught.value)
    with pytest.raises(ra.ConfigError, match="without '/'"):
        ra.CameraConfig("robot/cam")


def test_intrinsics_from_field_of_view_and_resizing() -> None:
    camera = ra.CameraConfig("cam", width=128, height=96, fovy=90.0)
    k = camera.intrinsic_matrix()
    # f = (H / 2) / tan(fovy / 2) = 48 px; pixel centres at integers: centre (63.5, 47.5).
    np.testing.assert_allclose(k, [[48.0, 0, 63.5], [0, 48.0, 47.5], [0, 0, 1]])
    full = ra.CameraConfig("cam", width=64, height=48, intrinsic=[[60, 0, 30], [0, 50, 20], [0, 0, 1]])
    assert full.fovy is None and full.vertical_fov() == pytest.approx(math.degrees(2 * math.atan(24 / 50)))
    doubled = full.resized(128, 96)
    # Scaling maps pixel edges onto pixel edges: c' = (c + 0.5) * 2 - 0.5.
    np.testing.assert_allclose(doubled.intrinsic_matrix(), [[120, 0, 60.5], [0, 100, 40.5], [0, 0, 1]])
    for size in (("64", 48), (64, None), (0, 48)):  # a string or None raised TypeError in the scaling
        with pytest.raises(
            ra.ConfigError, match=r"CameraConfig 'cam'.resized: expected (width|height) to be an integer"
        ):
            full.resized(*size)  # type: ignore[arg-type]


def test_look_at_points_the_camera_at_the_target() -> None:
    eye, target = np.array([1.0, -0.5, 0.8]), np.array([0.2, 0.1, 0.3])
    camera = ra.CameraConfig.look_at("cam", eye=eye, target=target)
    rot = quat_to_matrix(camera.quat)
    view = (target - eye) / np.linalg.norm(target - eye)
    np.testing.assert_allclose(rot @ [0, 0, -1], view, atol=1e-12)  # looks along its -z
    assert (rot @ [0, 1, 0])[2] > 0 and abs((rot @ [1, 0, 0])[2]) < 1e-12  # image up is world up; horizon level
    np.testing.assert_allclose(camera.pos, eye)
    with pytest.raises(ra.ConfigError, match="parallel to up"):
        ra.CameraConfig.look_at("cam", eye=(0, 0, 1), target=(0, 0, 0))
    with pytest.raises(ra.ConfigError, match=r"look_at 'cam': the pose comes from eye, target and up; expected no pos"):
        ra.CameraConfig.look_at("cam", eye=eye, target=target, pos=(0, 0, 1))  # a TypeError before


def test_wrist_camera_pose_follows_its_link() -> None:
    """After moving the joints, cam2world_gl == pose of panda_hand x the mount offset."""
    env = wristcam_env(control_mode="pd_joint_delta_pos")
    obs, _ = env.reset(seed=1)
    start = obs["sensor_param"]["hand_camera"]["cam2world_gl"][0].astype(np.float64)
    action = np.array([1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 0.0])
    for _ in range(4):
        obs, *_ = env.step(action)
    data, hand = env.data, env.agent.index.body_id("panda_hand", "test")
    link = np.eye(4)
    link[:3, :3], link[:3, 3] = data.xmat[hand].reshape(3, 3), data.xpos[hand]
    offset = np.eye(4)
    offset[:3, :3], offset[:3, 3] = quat_to_matrix(HAND_CAMERA.quat), HAND_CAMERA.pos
    expected = link @ offset
    pose = obs["sensor_param"]["hand_camera"]["cam2world_gl"][0].astype(np.float64)
    np.testing.assert_allclose(pose, expected, atol=1e-6)
    assert np.linalg.norm(pose[:3, 3] - start[:3, 3]) > 0.05  # it really moved
    # The camera looks along the gripper's approach axis (hand +z).
    np.testing.assert_allclose(pose[:3, :3] @ [0, 0, -1], link[:3, 2], atol=1e-6)


def test_extrinsic_is_world_to_camera_in_opencv_axes() -> None:
    env = wristcam_env()
    obs, _ = env.reset(seed=0)
    params = {k: v[0].astype(np.float64) for k, v in obs["sensor_param"]["hand_camera"].items()}
    cam2world_cv = params["cam2world_gl"] @ np.diag([1.0, -1.0, -1.0, 1.0])
    np.testing.assert_allclose(params["extrinsic_cv"] @ cam2world_cv, np.eye(4)[:3], atol=1e-6)
    # A point 0.3 m straight ahead of the camera projects to the principal point.
    ahead = params["cam2world_gl"] @ [0, 0, -0.3, 1]
    x_cam = params["extrinsic_cv"] @ ahead
    assert x_cam[2] == pytest.approx(0.3, abs=1e-6)
    u, v, w = params["intrinsic_cv"] @ x_cam
    assert (u / w, v / w) == pytest.approx((15.5, 15.5), abs=1e-4)


def test_overrides_reach_the_images_and_parameters() -> None:
    env = wristcam_env(
        num_envs=2, sensor_configs={"hand_camera": {"width": 40, "height": 30, "fovy": 60.0}, "base_camera": None}
    )
    obs, _ = env.reset(seed=0)
    assert list(obs["sensor_data"]) == ["hand_camera"] and list(obs["sensor_param"]) == ["hand_camera"]
    assert obs["sensor_data"]["hand_camera"]["rgb"].shape == (2, 30, 40, 3)
    focal = 15 / math.tan(math.radians(30))
    np.testing.assert_allclose(
        obs["sensor_param"]["hand_camera"]["intrinsic_cv"][1],
        [[focal, 0, 19.5], [0, focal, 14.5], [0, 0, 1]],
        rtol=1e-6,
    )
    camera = env.model.camera("panda_wristcam-0/hand_camera")
    assert camera.fovy[0] == pytest.approx(60.0) and tuple(env.model.cam_resolution[camera.id]) == (40, 30)
    assert "base_camera" not in {env.model.camera(i).name for i in range(env.model.ncam)}


@pytest.mark.parametrize(
    ("overrides", "error", "fragments"),
    [
        (
            {"hand_cam": {"width": 64}},
            ra.UnknownNameError,
            ["sensor_configs", "unknown camera 'hand_cam'", "Did you mean 'hand_camera'", "'base_camera'"],
        ),
        (
            {"hand_camera": {"widht": 64}},
            ra.UnknownNameError,
            ["sensor_configs['hand_camera']", "unknown camera field 'widht'", "Did you mean 'width'"],
        ),
        ({"hand_camera": {"uid": "other"}}, ra.UnknownNameError, ["unknown camera field 'uid'"]),
        ({"hand_camera": {"height": -4}}, ra.ConfigError, ["sensor_configs['hand_camera']", "height", "got -4"]),
        (
            {"hand_camera": {"intrinsic": [[50, 0, 64], [0, 50, 64], [0, 0, 1]], "width": 64}},
            ra.ConfigError,
            ["sensor_configs['hand_camera']: CameraConfig 'hand_camera'", "principal point", "(64.0, 64.0)"],
        ),
        ({"hand_camera": 64}, ra.ConfigError, ["expected a dict of camera fields or None"]),
        (
            {"hand_camera": {"mount": "panda_hnd"}},
            ra.UnknownNameError,
            ["PandaWristCam.cameras['hand_camera'].mount", "Did you mean 'panda_hand'"],
        ),
        ({"hand_camera": None, "base_camera": None}, ra.ConfigError, ["obs_mode 'rgb' needs at least one camera"]),
    ],
)
def test_bad_overrides_raise(overrides: dict[str, Any], error: type[Exception], fragments: list[str]) -> None:
    with pytest.raises(error) as caught:
        wristcam_env(sensor_configs=overrides)
    for fragment in fragments:
        assert fragment in str(caught.value), str(caught.value)


def test_camera_mounts_are_checked() -> None:
    class BadMount(Panda):
        uid = "bad_mount_panda"
        cameras = (ra.CameraConfig("cam", mount="panda_hnd"),)

    with pytest.raises(
        ra.UnknownNameError,
        match=r"BadMount.cameras\['cam'\].mount: unknown body 'panda_hnd'. Did you mean 'panda_hand'",
    ):
        ra.Scene(BadMount)

    class WorldMount(Panda):
        uid = "world_mount_panda"
        cameras = (ra.CameraConfig("cam", mount="world"),)

    with pytest.raises(ra.UnknownNameError, match="unknown body 'world'"):  # a robot camera rides on a link
        ra.Scene(WorldMount)
    with pytest.raises(ra.UnknownNameError, match=r"scene cameras\['top'\].mount: unknown body 'tabel'"):
        ra.Scene("panda", cameras=[ra.CameraConfig("top", mount="tabel")])
    with pytest.raises(ra.ConfigError, match="already has a camera named 'render_camera'"):
        ra.Scene("panda", cameras=[ra.CameraConfig("render_camera")])
    # A task camera may ride on a robot link, by its full name.
    scene = ra.Scene("panda", cameras=[ra.CameraConfig("on_hand", mount="panda-0/panda_hand")])
    assert scene.model.cam_bodyid[scene.cameras.camera_id("on_hand")] == scene.agents[0].index.body_id(
        "panda_hand", "test"
    )


def test_camera_keys_with_several_robots() -> None:
    scene = ra.Scene(["panda_wristcam", "panda_wristcam"], cameras=[ra.CameraConfig("top", pos=(0, 0, 2))])
    assert scene.cameras.keys == ["panda_wristcam-0/hand_camera", "panda_wristcam-1/hand_camera", "top"]
    with pytest.raises(
        ra.UnknownNameError, match=r"unknown camera 'hand_camera'\. Did you mean .*'panda_wristcam-0/hand_camera'"
    ):
        ra.Scene(["panda_wristcam", "panda_wristcam"], sensor_configs={"hand_camera": None})


def test_rendering_does_not_change_the_simulation() -> None:
    """Same seed and actions: the physics of an rgbd env and a state env are bit-identical,
    and a saved state continues bit-identically after renders in between."""
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-1, 1, 8) for _ in range(6)]
    states = []
    for mode in ("state", "rgbd"):
        env = wristcam_env(obs_mode=mode)
        env.reset(seed=3)
        for action in actions:
            env.step(action)
        states.append(env.get_state()["physics"])
    assert np.array_equal(states[0], states[1])
    saved = env.get_state()
    first = [env.step(a)[0] for a in actions]
    env.set_state(saved)
    second = [env.step(a)[0] for a in actions]
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a["agent"]["qpos"], b["agent"]["qpos"])
        np.testing.assert_array_equal(a["sensor_data"]["hand_camera"]["rgb"], b["sensor_data"]["hand_camera"]["rgb"])
