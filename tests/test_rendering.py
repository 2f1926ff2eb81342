"""What cameras see, checked against geometry: depth of a plane, a point cloud on a box's
faces, segmentation ids that name links and objects, exact intrinsics, shadows."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.sensors.pointcloud import pixel_rays, world_points
from robot_agents.sensors.segmentation import deformable_ids, flex_bodies
from tests.test_touch import lift_class

BOX_POS = np.array([0.6, 0.4, 0.1])
BOX_HALF = np.array([0.05, 0.08, 0.1])
BOX_QUAT = (math.cos(math.pi / 12), 0.0, 0.0, math.sin(math.pi / 12))  # 30 deg about z


class BoxEnv(ra.RobotEnv):
    """A Panda, a static box and three task cameras."""

    def _scene_props(self) -> Sequence[ra.Prop]:
        return (ra.Prop("box", "box", size=tuple(BOX_HALF), pos=tuple(BOX_POS), quat=BOX_QUAT, mass=None),)

    def _scene_cameras(self) -> Sequence[ra.CameraConfig]:
        small: dict[str, Any] = {"width": 64, "height": 64, "fovy": 60.0}
        return (
            ra.CameraConfig.look_at("front", eye=(1.2, 0.8, 0.6), target=BOX_POS, **small),
            ra.CameraConfig.look_at("side", eye=(0.2, 1.1, 0.5), target=BOX_POS, **small),
            ra.CameraConfig.look_at("overview", eye=(1.6, -0.9, 1.1), target=(0.3, 0.1, 0.35), **small),
        )


def box_distance(points: np.ndarray) -> np.ndarray:
    """Unsigned distance (m) of world points ``(P, 3)`` to the box's surface."""
    local = (points - BOX_POS) @ quat_to_matrix(BOX_QUAT)  # rows: R^T (p - c)
    q = np.abs(local) - BOX_HALF
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    inside = np.minimum(q.max(axis=1), 0.0)
    return np.abs(outside + inside)


def test_depth_of_a_plane_is_its_distance() -> None:
    """A camera 0.7 m above the floor looking straight down sees 0.7 m everywhere (depth
    is along the optical axis); tilted 30 deg, each pixel sees the depth where its ray meets
    the floor (0.61-1.19 m, within 1e-5 m), the centre pixel the distance to its target."""
    down = ra.CameraConfig.look_at("down", eye=(3, 3, 0.7), target=(3, 3, 0), up=(1, 0, 0), width=65, height=65)
    tilted = ra.CameraConfig.look_at("tilted", eye=(3, 3, 0.7), target=(3.4, 3, 0), width=65, height=65, fovy=60.0)
    scene = ra.Scene("panda", cameras=[down, tilted])
    images = scene.cameras.capture(scene.world, ("depth",))
    depth = images["down"]["depth"]
    assert depth.dtype == np.float32 and depth.shape == (1, 65, 65, 1)
    assert depth[0, 32, 32, 0] == pytest.approx(0.7, abs=1e-3)
    assert np.max(np.abs(depth - 0.7)) < 1e-3
    assert images["tilted"]["depth"][0, 32, 32, 0] == pytest.approx(math.hypot(0.4, 0.7), abs=1e-3)
    # Every pixel of the tilted view: the floor where the pixel's ray meets z = 0, at the
    # depth along the optical axis z_cam = 0.7 / (-d_z), d = R K^-1 (u, v, 1) (OpenCV axes).
    params = scene.cameras.params(scene.world)["tilted"]
    rotation = params["extrinsic_cv"][0, :, :3].T  # camera (OpenCV) to world
    v, u = np.divmod(np.arange(65 * 65), 65)
    rays = rotation @ np.linalg.inv(params["intrinsic_cv"][0]) @ np.stack([u, v, np.ones_like(u)])
    assert np.all(rays[2] < -0.15)  # the whole view sees the floor, nearer than 5 m
    expected = (0.7 / -rays[2]).reshape(65, 65)
    np.testing.assert_allclose(images["tilted"]["depth"][0, :, :, 0], expected, atol=1e-5, rtol=0)  # 2.2e-7 measured
    # Looking at the sky: nothing within the far plane reads exactly `far`.
    up = ra.CameraConfig.look_at("up", eye=(3, 3, 0.7), target=(3, 3, 2), up=(1, 0, 0), width=8, height=8, far=5.0)
    scene = ra.Scene("panda", cameras=[up])
    assert np.all(scene.cameras.capture(scene.world, ("depth",))["up"]["depth"] == 5.0)
    # One texture by its name (not its letters: "unknown texture 'd'" before).
    assert list(scene.cameras.capture(scene.world, "depth")["up"]) == ["depth"]
    with pytest.raises(ra.UnknownNameError, match=r"unknown texture 'dpeth'\. Did you mean 'depth'"):
        scene.cameras.capture(scene.world, "dpeth")


@pytest.mark.parametrize(
    ("far", "short_of_far"),
    [(5.0, 5e-5), (5.0, 2e-6), (10.0, 5e-5), (10.0, 1e-6), (10.0, -3e-7), (100.0, 8e-5), (100.0, 2e-5)],
)
def test_depth_reads_far_exactly_where_nothing_is_seen(far: float, short_of_far: float) -> None:
    """A wall facing the camera ``far * short_of_far`` short of the far plane: a pixel
    either sees it (segmentation names the wall, depth its distance within 1e-6 relative)
    or sees nothing (id -1, depth exactly ``far``). Before, depth within 1e-4 of ``far``
    was snapped to ``far`` (MuJoCo's converted far plane falls short of ``far``: 99.9934 m
    of 100 m), so the wall read ``far`` while segmentation named it; now the pixels that
    read what an empty scene reads are snapped. The walls 2e-6 short of 5 m and 2e-5
    short of 100 m lie beyond MuJoCo's far plane (9.6e-6 and 6.6e-5 short, Mesa): nothing
    is seen there, and depth and segmentation agree; the others are in view. The wall
    3e-7 beyond 10 m lies inside MuJoCo's plane (10.000006 m): seen, it reads ``far``
    (depth stays within the observation space's ``[0, far]``)."""
    distance = far * (1.0 - short_of_far)
    camera = ra.CameraConfig.look_at("c", eye=(0, 0, 50), target=(1, 0, 50), width=8, height=8, fovy=10.0, far=far)
    wall = ra.Prop("wall", "box", size=(0.01, 20.0, 20.0), pos=(distance + 0.01, 0.0, 50.0), mass=None)
    scene = ra.Scene("panda", cameras=[camera], props=[wall])
    images = scene.cameras.capture(scene.world, ("depth", "segmentation"))["c"]
    depth, seg = images["depth"][0, :, :, 0].astype(np.float64), images["segmentation"][0, :, :, 0]
    seen = seg == scene.model.body("wall").id
    assert np.all(seen | (seg == -1))
    np.testing.assert_allclose(depth[seen], distance, rtol=1e-6)
    assert np.all(depth[~seen] == far) and depth.max() <= far
    assert seen.all() or not seen.any()
    beyond_mujocos_far_plane = (far, short_of_far) in ((5.0, 2e-6), (10.0, -3e-7), (100.0, 2e-5))
    assert seen.all() or beyond_mujocos_far_plane  # inside the 1e-4 band: seen
    # What an empty render reads is MuJoCo's conversion of the cleared (reversed-Z) buffer,
    # 0: d / c with glFrustum's coefficients in float32 (mujoco.Renderer.render).
    renderer = scene.cameras._renderer
    assert renderer is not None
    extent = scene.cameras.model.stat.extent
    z_near = np.float32(float(np.float32(0.01 / extent)) * extent)  # vis.map.znear holds near / extent, float32
    z_far = np.float32(far)
    c = np.float32(-0.5) * (-(z_far + z_near) / (z_far - z_near)) - np.float32(0.5)
    d = np.float32(-0.5) * (-(np.float32(2) * z_far * z_near) / (z_far - z_near))
    empty = renderer._nothing_seen[(0.01, far)]
    assert empty == np.float32(np.float64(d) / np.float64(c))
    assert empty == pytest.approx({5.0: 4.99995, 10.0: 10.000006, 100.0: 99.9934}[far], abs=5e-5)
    scene.close()


def test_full_intrinsic_matrix_is_rendered_exactly() -> None:
    """Off-centre principal point and fx != fy: back-projected floor pixels lie on z = 0."""
    k = [[70.0, 0.0, 40.0], [0.0, 55.0, 20.0], [0.0, 0.0, 1.0]]
    camera = ra.CameraConfig.look_at("k", eye=(3, 3, 0.9), target=(3.5, 3.2, 0), width=64, height=48, intrinsic=k)
    scene = ra.Scene("panda", cameras=[camera])
    depth = scene.cameras.capture(scene.world, ("depth",))["k"]["depth"]
    pose = scene.cameras.params(scene.world)["k"]["cam2world_gl"]
    points = world_points(depth, pixel_rays(np.array(k), 64, 48), pose)
    assert np.max(np.abs(points[0, :, 2])) < 1e-3
    np.testing.assert_allclose(scene.cameras.intrinsic("k"), k)


def test_point_cloud_of_a_box_lies_on_its_faces() -> None:
    env = BoxEnv(robot_uids="panda", obs_mode="pointcloud", num_envs=2, robot_init_qpos_noise=0.0)
    obs, _ = env.reset(seed=0)
    cloud = obs["pointcloud"]
    assert cloud["xyzw"].shape == (2, 3 * 64 * 64, 4) and cloud["xyzw"].dtype == np.float32
    assert cloud["rgb"].shape == (2, 3 * 64 * 64, 3) and cloud["segmentation"].shape == (2, 3 * 64 * 64, 1)
    box_id = env.model.body("box").id
    seg, xyzw = cloud["segmentation"][0, :, 0], cloud["xyzw"][0].astype(np.float64)
    on_box = (seg == box_id) & (xyzw[:, 3] == 1)
    per_camera = on_box.reshape(3, -1).sum(axis=1)
    assert per_camera[0] > 50 and per_camera[1] > 50, per_camera  # seen from two sides
    assert np.max(box_distance(xyzw[on_box, :3])) < 2e-3
    floor = (seg == 0) & (xyzw[:, 3] == 1)
    assert floor.sum() > 1000 and np.max(np.abs(xyzw[floor, 2])) < 2e-3
    # Pixels that see nothing are marked w = 0 with xyz = 0.
    sky = xyzw[:, 3] == 0
    assert np.all(seg[sky] == -1) and np.all(xyzw[sky, :3] == 0)
    np.testing.assert_array_equal(cloud["xyzw"][0], cloud["xyzw"][1])  # same state, same cloud


def test_segmentation_names_robot_links_and_scene_objects() -> None:
    env = BoxEnv(robot_uids="panda", obs_mode="segmentation", robot_init_qpos_noise=0.0)
    obs, _ = env.reset(seed=0)
    id_map = env.segmentation_id_map
    seg = obs["sensor_data"]["overview"]["segmentation"]
    assert seg.dtype == np.int16 and seg.shape == (1, 64, 64, 1)
    ids = set(np.unique(seg).tolist())
    box_id = env.model.body("box").id
    assert box_id in ids and id_map[box_id] == ra.SegmentationEntry("box", "object")
    assert 0 in ids and id_map[0].kind == "world"  # the floor
    links = {id_map[i].link for i in ids if i >= 0 and id_map[i].kind == "robot_link"}
    assert {"panda_link0", "panda_link1", "panda_link2", "panda_link3", "panda_link4", "panda_hand"} <= links
    assert all(
        id_map[i].robot == "panda-0" and id_map[i].name == f"panda-0/{id_map[i].link}"
        for i in ids
        if i > 0 and i != box_id
    )
    assert ids <= set(id_map) | {-1}
    # The pixel where the box's centre projects shows the box (parameters and ids agree).
    params = {k: v[0].astype(np.float64) for k, v in obs["sensor_param"]["front"].items()}
    u, v, w = params["intrinsic_cv"] @ params["extrinsic_cv"] @ np.append(BOX_POS, 1.0)
    assert obs["sensor_data"]["front"]["segmentation"][0, round(v / w), round(u / w), 0] == box_id


def test_shadows_are_configurable() -> None:
    """With shadows on, the robot's shadow darkens a patch of the floor by ~100 levels."""
    camera = ra.CameraConfig.look_at("view", eye=(1.0, 0.6, 0.9), target=(0.0, 0.2, 0.2), width=64, height=64)
    images = []
    for shadows in (True, False, False):
        scene = ra.Scene("panda", cameras=[camera], sensor_configs={"view": {"shadows": shadows}})
        scene.reset()
        images.append(scene.cameras.capture(scene.world)["view"]["rgb"][0].astype(float).mean(axis=-1))
        scene.close()
    change = images[0] - images[1]
    assert np.mean(change < -10) > 0.02 and change.min() < -60
    np.testing.assert_array_equal(images[1], images[2])  # deterministic without them


SITE_AND_TENDON_MJCF = """
<mujoco>
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.05" pos="0 0 0.05" mass="5"/>
      <site name="anchor" pos="0.3 0 0.6" size="0.01"/>
      <body name="pad" pos="0 0 0.1">
        <joint name="lift" type="slide" axis="0 0 1" range="-0.05 0.05"/>
        <geom name="pad" type="box" size="0.08 0.08 0.01" pos="0 0 0.01" mass="0.5"/>
        <site name="pad_top" type="box" size="0.081 0.081 0.002" pos="0 0 0.02"/>
        <site name="marker" type="sphere" size="0.05" pos="0.3 0 0.3"/>
      </body>
    </body>
  </worldbody>
  <tendon><spatial name="cable" width="0.02"><site site="anchor"/><site site="pad_top"/></spatial></tendon>
</mujoco>
"""


def test_sensor_cameras_see_geoms_only_not_sites_or_tendons(tmp_path: Path) -> None:
    """A model file's sites (MuJoCo's default group 0) and a spatial tendon are not
    drawn: the depth over a pad is the pad's (not the touch site 2 mm above it), and
    every pixel that sees something names a body (no -1 within the far plane)."""
    path = tmp_path / "pad.xml"
    path.write_text(SITE_AND_TENDON_MJCF)
    robot = lift_class("SitePad", "site_pad", path)
    camera = ra.CameraConfig.look_at("top", eye=(0.0, 0.0, 1.2), target=(0, 0, 0), up=(1, 0, 0), width=64, height=64)
    scene = ra.Scene(robot, cameras=[camera])
    images = scene.cameras.capture(scene.world, ("depth", "segmentation"))["top"]
    depth, seg = images["depth"][0, :, :, 0], images["segmentation"][0, :, :, 0]
    pad = scene.render_model.geom("site_pad-0/pad")
    pad_top = scene.world.render_sources()[0].geom_xpos[pad.id, 2] + pad.size[2]  # 0.12 m
    assert depth[31:33, 31:33] == pytest.approx(1.2 - pad_top, abs=1e-4)  # not the site's top, 2 mm higher
    assert not np.any((depth < camera.far) & (seg == -1))  # the tendon drew id -1 pixels
    ids = set(np.unique(seg).tolist())
    assert ids == {0, scene.render_model.body("site_pad-0/base").id, scene.render_model.body("site_pad-0/pad").id}
    scene.close()


def test_renderers_fit_the_offscreen_framebuffer(tmp_path: Path) -> None:
    """A frame wider or taller than the model's offscreen buffer (1280 x 960) renders:
    make_renderer grows the buffer (the demo's scene view raised MuJoCo's ValueError
    at 1920 x 1080); the demo checks its size and fps before anything is simulated."""
    from robot_agents.demo import run_demo
    from robot_agents.sensors.renderer import make_renderer

    scene = ra.Scene("panda")
    renderer = make_renderer(scene.render_model, 1920, 1080)
    renderer.update_scene(scene.world.render_sources()[0], camera="render_camera")
    frame = renderer.render()
    assert frame.shape == (1080, 1920, 3) and frame.std() > 5  # the robot on the floor, not a blank frame
    renderer.close()
    scene.close()
    # Each OpenGL context holds a framebuffer of its own image size, not of the largest
    # camera in the scene (a 16 x 16 camera beside a 2048 x 2048 one held 2048 x 2048:
    # ~100 MB more per context in software rendering).
    big = ra.CameraConfig("big", pos=(1.0, 0.0, 0.8), width=2048, height=2048)
    small = ra.CameraConfig("small", pos=(1.0, 0.0, 0.8), width=16, height=16)
    scene = ra.Scene("panda", cameras=[big, small])
    scene.cameras.prepare()
    contexts = {
        size: renderer._mjr_context  # MuJoCo's context: its offscreen buffer's size
        for size, renderer in scene.cameras._renderer._renderers.items()  # type: ignore[union-attr]
    }
    assert {size: (c.offWidth, c.offHeight) for size, c in contexts.items()} == {
        (2048, 2048): (2048, 2048),
        (16, 16): (16, 16),
    }
    model_buffer = scene.render_model.vis.global_
    assert (model_buffer.offwidth, model_buffer.offheight) == (2048, 2048)  # the model keeps its values
    images = scene.cameras.capture(scene.world, ("depth",))
    assert images["small"]["depth"][0, 8, 8, 0] == pytest.approx(images["big"]["depth"][0, 1024, 1024, 0], abs=1e-3)
    scene.close()
    for size in ((0, 10), (200, 100.5), (320,)):
        with pytest.raises(ra.ConfigError, match=r"run_demo: expected size to be \(width, height\)"):
            run_demo("panda", tmp_path / "demo.gif", size=size)  # type: ignore[arg-type]
    with pytest.raises(ra.ConfigError, match="run_demo: expected fps to be a positive number of frames per second"):
        run_demo("panda", tmp_path / "demo.gif", fps=0)
    assert not (tmp_path / "demo.gif").exists()


def test_headlight_changes_to_the_simulated_model_show_as_with_one_model() -> None:
    """``env.model.vis.headlight`` (MuJoCo's camera-fixed light) is a light of the
    simulated model: a change to it is drawn as with one model (with the render twin it
    was not: the floor's green channel read 152 instead of 173)."""
    images = []
    for render_only_visuals in (True, False):
        env = ra.make_env("Empty-v1", robot_uids="panda", obs_mode="rgb", render_only_visuals=render_only_visuals)
        env.reset(seed=0)
        model = env.unwrapped.model
        assert (model is env.unwrapped.render_model) is not render_only_visuals
        model.vis.headlight.ambient[:] = (0.9, 0.9, 0.9)
        model.vis.headlight.diffuse[:] = (0.1, 0.1, 0.1)
        model.vis.headlight.specular[:] = (0.0, 0.0, 0.0)
        images.append(env.unwrapped._get_obs()["sensor_data"]["base_camera"]["rgb"])
        model.vis.headlight.active = 0
        images.append(env.unwrapped._get_obs()["sensor_data"]["base_camera"]["rgb"])
        env.close()
    np.testing.assert_array_equal(images[0], images[2])
    np.testing.assert_array_equal(images[1], images[3])
    assert np.abs(images[0].astype(int) - images[1]).mean() > 20  # the headlight lights the scene


def test_light_and_material_changes_to_the_simulated_model_show_as_with_one_model() -> None:
    """A light's type, attenuation and spot cone, and a material's texture tiling, changed
    in ``env.model``, are drawn as with one model (with the render twin they were not:
    each changed a shadowed view by 8-48 of 255 on average with one model, not at all
    with the twin)."""
    images = []
    for render_only_visuals in (True, False):
        env = ra.make_env(
            "Empty-v1",
            robot_uids="panda",
            obs_mode="rgb",
            render_only_visuals=render_only_visuals,
            sensor_configs={"base_camera": {"shadows": True}},
        )
        env.reset(seed=0)
        before = env.unwrapped._get_obs()["sensor_data"]["base_camera"]["rgb"]
        model = env.unwrapped.model
        model.light_type[0] = mujoco.mjtLightType.mjLIGHT_SPOT
        model.light_attenuation[0] = (1.0, 0.5, 0.5)
        model.light_cutoff[0] = 20.0
        model.light_exponent[0] = 30.0
        model.mat_texrepeat[model.geom_matid[model.geom("floor").id]] = (1.0, 1.0)
        images.append(env.unwrapped._get_obs()["sensor_data"]["base_camera"]["rgb"])
        assert np.abs(images[-1].astype(int) - before).mean() > 10
        env.close()
    np.testing.assert_array_equal(images[0], images[1])


def test_cameras_of_a_closed_scene_refuse_to_render() -> None:
    """After ``Scene.close`` (which frees the OpenGL contexts) a capture raised nothing
    and made the contexts again, never to be freed; it now raises StateError."""
    scene = ra.Scene("panda_wristcam")
    assert scene.cameras.capture(scene.world, "depth")["hand_camera"]["depth"].shape == (1, 128, 128, 1)
    scene.close()
    for call in (lambda: scene.cameras.capture(scene.world, "rgb"), lambda: scene.cameras.params(scene.world)):
        with pytest.raises(ra.StateError, match=r"CameraRig\.(capture|params): this scene is closed"):
            call()
    assert scene.cameras._renderer is None  # no context made again


@pytest.mark.parametrize("render_size", [(480, 360), (120, 480)])
def test_the_render_camera_frames_the_robots_in_portrait_images_too(render_size: tuple[int, int]) -> None:
    """The robots' bounding sphere fits the narrower of the two fields of view of
    ``env.render()``: in a 120 x 480 frame the horizontal one (11.8 deg against 45 deg
    vertical; framed by the vertical one alone, the sphere spanned 4x the width)."""
    env = ra.make_env("Empty-v1", robot_uids="panda", render_mode="rgb_array", render_size=render_size)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (render_size[1], render_size[0], 3)
    env_ = env.unwrapped
    lower, upper = env_._render_bounds()
    camera = env_._render_cameras[0]
    radius = float(np.linalg.norm(upper - lower)) / 2
    width, height = render_size
    half_fovy = math.radians(float(env_.render_model.vis.global_.fovy)) / 2
    half_fovx = math.atan(math.tan(half_fovy) * width / height)
    seen = math.asin(min(1.0, radius / camera.distance))  # the sphere's angular radius
    assert seen <= min(half_fovx, half_fovy) + 1e-9
    assert seen == pytest.approx(min(half_fovx, half_fovy), rel=1e-6)  # and fills the narrower one
    env.close()


def test_a_render_is_a_function_of_the_state_not_of_earlier_renders() -> None:
    """``render()`` of a state is the same frame whatever was drawn before: a renderer's
    first frame, and the first after a reset re-framed the camera, showed the floor laid
    out around the previous camera (1505 of 9216 values differed from a fresh env's)."""
    kwargs: dict[str, Any] = {"robot_uids": "panda", "num_envs": 2, "render_mode": "rgb_array", "render_size": (64, 48)}
    env = ra.make_env("PickCube-v1", **kwargs).unwrapped
    env.reset(seed=0)
    first = env.render()
    np.testing.assert_array_equal(first, env.render())
    env.step(np.ones((2, 8)))
    env.render()
    env.reset(seed=1)
    fresh = ra.make_env("PickCube-v1", **kwargs).unwrapped
    fresh.reset(seed=1)
    np.testing.assert_array_equal(env.render(), fresh.render())
    env.close()
    fresh.close()


def test_a_restored_state_renders_as_where_it_was_saved() -> None:
    """``render()``'s camera is framed at the first render after a reset; it is part of
    the state, so a state restored into a fresh env, or into one that rendered another
    episode, renders the frame it rendered where it was saved (the camera was framed
    again from the restored pose: 6590 of 9216 values differed). A bad camera is refused
    before anything is written, and a state saved before any render frames at the next."""
    kwargs: dict[str, Any] = {"robot_uids": "panda", "render_mode": "rgb_array", "render_size": (64, 48)}
    env = ra.make_env("Empty-v1", **kwargs).unwrapped
    env.reset(seed=0)
    unframed = env.get_state()
    assert unframed["render_camera"] == [None]
    env.render()
    for _ in range(15):
        env.step(np.ones(8))
    saved, frame = env.get_state(), env.render()
    fresh = ra.make_env("Empty-v1", **kwargs).unwrapped
    fresh.set_state(saved)
    np.testing.assert_array_equal(fresh.render(), frame)
    other = ra.make_env("Empty-v1", **kwargs).unwrapped
    other.reset(seed=5)
    other.render()
    before = other.get_state()
    for bad in ([0.0] * 5, [0, 0, 0, -1.0, 0, 0], [math.nan] * 6, "camera"):
        with pytest.raises(ra.StateError, match="render_camera"):
            other.set_state({**saved, "render_camera": bad})
        np.testing.assert_array_equal(other.get_state()["render_camera"], before["render_camera"])
    other.set_state(saved)
    np.testing.assert_array_equal(other.render(), frame)
    other.set_state(unframed)
    assert other.get_state()["render_camera"] == [None]
    for made in (env, fresh, other):
        made.close()


DEFORMABLE_MJCF = """
<mujoco>
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.05" pos="0 0 0.05" mass="5"/>
      <body name="pad" pos="0 0 0.1">
        <joint name="lift" type="slide" axis="0 0 1" range="-0.05 0.05"/>
        <geom name="pad" type="box" size="0.05 0.05 0.01" pos="0 0 0.01" mass="0.5"/>
        <body name="arm" pos="0.4 0 0">
          <geom type="box" size="0.01 0.01 0.01" mass="0.1" group="3"/>
          <flexcomp name="plate" type="grid" count="3 3 1" spacing="0.05 0.05 0.05" pos="0 -0.35 0.2" dim="2"
            rigid="true" radius="0.005"/>
        </body>
      </body>
      <flexcomp name="cloth" type="grid" count="3 3 1" spacing="0.1 0.1 0.1" pos="-0.4 0 0.4" dim="2" radius="0.005">
        <edge equality="true"/>
      </flexcomp>
    </body>
  </worldbody>
  <deformable>
    <skin name="wide" vertex="0 -0.1 0.2  0.4 -0.1 0.2  0 0.1 0.2  0.4 0.1 0.2" face="0 1 2  1 3 2">
      <bone body="pad" bindpos="0 0 0" bindquat="1 0 0 0" vertid="0 2" vertweight="1 1"/>
      <bone body="arm" bindpos="0.4 0 0" bindquat="1 0 0 0" vertid="1 3" vertweight="1 1"/>
    </skin>
    <skin name="patch" vertex="0 0.3 0.2  0.1 0.3 0.2  0 0.4 0.2  0.1 0.4 0.2" face="0 1 2  1 3 2">
      <bone body="arm" bindpos="0 0 0" bindquat="1 0 0 0" vertid="0 1 2 3" vertweight="1 1 1 1"/>
    </skin>
  </deformable>
</mujoco>
"""


def test_flexes_and_skins_have_segmentation_ids(tmp_path: Path) -> None:
    """MuJoCo's segmentation names a flex or skin by its own index, not a body's (they
    read -1, as the background, before). A skin bound to one bone reads that body's id;
    a cloth (a flex of nine vertex bodies) and a skin bound to two links read ids after
    the bodies, named in the id map and within the observation space's bounds; a rigid
    flex on one link reads the link's id, and an interpolated flex is placed by its
    nodes' bodies."""
    path = tmp_path / "deformable.xml"
    path.write_text(DEFORMABLE_MJCF)
    robot = lift_class("Deformable", "deformable", path)
    camera = ra.CameraConfig.look_at("top", eye=(0.0, 0.0, 1.5), target=(0, 0, 0), up=(1, 0, 0), width=96, height=96)
    scene = ra.Scene(robot, cameras=[camera])
    model = scene.render_model
    nbody = model.nbody
    images = scene.cameras.capture(scene.world, ("depth", "segmentation"))["top"]
    depth, seg = images["depth"][0, :, :, 0], images["segmentation"][0, :, :, 0]
    assert not np.any((depth < camera.far) & (seg == -1))  # everything seen is named
    id_map = scene.cameras.segmentation_id_map
    assert id_map[nbody] == ra.SegmentationEntry("deformable-0/cloth", "flex", "deformable-0")
    assert id_map[nbody + 1] == ra.SegmentationEntry("deformable-0/wide", "skin", "deformable-0")
    assert max(id_map) == nbody + 1
    params = scene.cameras.params(scene.world)["top"]

    def pixel(point: Sequence[float]) -> tuple[int, int]:
        u, v, w = params["intrinsic_cv"][0] @ params["extrinsic_cv"][0] @ np.append(point, 1.0)
        return round(v / w), round(u / w)

    data = scene.world.render_sources()[0]
    arm = model.body("deformable-0/arm").id
    cloth_centre = data.xpos[model.body("deformable-0/cloth_4").id]
    assert seg[pixel(cloth_centre)] == nbody  # the cloth's middle vertex
    assert seg[pixel((0.2, 0.0, 0.3))] == nbody + 1  # the skin between the pad and the arm (z 0.1 + 0.2)
    assert seg[pixel((0.45, 0.35, 0.3))] == arm  # the skin bound to the arm alone: the arm's id
    assert seg[pixel((0.4, -0.35, 0.3))] == arm  # a rigid flex, every vertex on the arm: the arm's id
    assert np.count_nonzero(seg == nbody) > 50 and np.count_nonzero(seg == nbody + 1) > 50
    scene.close()
    env_class = type("DeformableEnv", (ra.RobotEnv,), {"_scene_cameras": lambda self: (camera,)})
    env = env_class(robot_uids=robot, obs_mode="segmentation")
    obs, _ = env.reset(seed=0)
    space = env.observation_space["sensor_data"]["top"]["segmentation"]
    assert space.high.max() == nbody + 1 and space.contains(obs["sensor_data"]["top"]["segmentation"])
    assert np.isin([nbody, nbody + 1], obs["sensor_data"]["top"]["segmentation"]).all()
    env.close()
    # An interpolated flex moves with its 8 nodes' bodies (its vertices' are the world's).
    soft = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><body name="holder" pos="0 0 0.5"><geom type="box" size=".02 .02 .02"/>
        <flexcomp name="soft" type="grid" count="4 4 4" spacing=".05 .05 .05" dim="3" dof="trilinear" radius=".001">
        <edge equality="true"/></flexcomp></body></worldbody></mujoco>"""
    )
    assert soft.flex_interp[0] == 1 and len(set(flex_bodies(soft, 0).tolist())) == 8
    assert deformable_ids(soft).own == ((soft.nbody, "flex", 0),)


def test_fovy_camera_images_follow_its_intrinsic_matrix() -> None:
    """A 96 x 64 camera, fovy 50 deg, 1 m above the floor looking down (image up = world
    +x, right = world -y): the edges of two 1 cm plates, 0.23 m to the right of and
    0.13 m above the optical axis, fall between the pixels K predicts, the vertical
    focal length fx = fy = 32 / tan(25 deg) = 68.62 px serving both axes."""
    eye = np.array([3.0, 3.0, 1.0])
    plates = (
        ra.Prop("right", "box", size=(0.3, 0.3, 0.005), pos=(3.0, 3.0 - 0.23 - 0.3, 0.005), mass=None),
        ra.Prop("ahead", "box", size=(0.3, 0.3, 0.005), pos=(3.0 + 0.13 + 0.3, 3.0 + 0.2, 0.005), mass=None),
    )
    camera = ra.CameraConfig.look_at(
        "down", eye=eye, target=(3.0, 3.0, 0.0), up=(1, 0, 0), width=96, height=64, fovy=50.0
    )
    scene = ra.Scene("panda", props=plates, cameras=[camera])
    k = scene.cameras.intrinsic("down")
    focal = 32 / math.tan(math.radians(25))
    np.testing.assert_allclose(k, [[focal, 0, 47.5], [0, focal, 31.5], [0, 0, 1]])
    seg = scene.cameras.capture(scene.world, ("segmentation",))["down"]["segmentation"][0, :, :, 0]
    right, ahead = (scene.model.body(name).id for name in ("right", "ahead"))
    # The plates' top edges, 0.99 m from the camera: columns right of u, rows above v.
    u = 47.5 + focal * 0.23 / 0.99
    v = 31.5 - focal * 0.13 / 0.99
    assert 0.2 < u % 1 < 0.8 and 0.2 < v % 1 < 0.8  # no pixel centre within 0.2 px of an edge
    row = seg[40]  # below the ahead plate: floor, then the right plate
    np.testing.assert_array_equal(row == right, np.arange(96) > u)
    column = seg[:, 30]  # left of the right plate: the ahead plate, then floor
    np.testing.assert_array_equal(column == ahead, np.arange(64) < v)
    scene.close()


def test_point_cloud_is_the_depth_image_back_projected() -> None:
    """The pointcloud mode's points are the depth mode's pixels back-projected with
    ``intrinsic_cv`` and ``extrinsic_cv`` (inverted here by hand) to within float32
    rounding (1e-6 m; 6.3e-7 m at most measured), and its colours and ids are the images' pixels, row by row."""
    options: dict[str, Any] = {"robot_uids": "panda", "robot_init_qpos_noise": 0.0, "num_envs": 2}
    cloud = BoxEnv(obs_mode="pointcloud", **options).reset(seed=0)[0]
    images = BoxEnv(obs_mode="sensor_data", **options).reset(seed=0)[0]
    start = 0
    for key in ("front", "side", "overview"):
        data, params = images["sensor_data"][key], images["sensor_param"][key]
        n, h, w, _ = data["depth"].shape
        for env in range(n):
            k = params["intrinsic_cv"][env].astype(np.float64)
            extrinsic = params["extrinsic_cv"][env].astype(np.float64)
            depth = data["depth"][env, :, :, 0].astype(np.float64).reshape(-1)
            v, u = np.divmod(np.arange(h * w), w)
            camera_points = np.linalg.inv(k) @ np.stack([u * depth, v * depth, depth])
            world = extrinsic[:, :3].T @ (camera_points - extrinsic[:, 3:])  # x = R^T (x_cam - t)
            xyzw = cloud["pointcloud"]["xyzw"][env, start : start + h * w].astype(np.float64)
            seen = depth < 10.0
            np.testing.assert_array_equal(xyzw[:, 3], seen)
            np.testing.assert_allclose(xyzw[seen, :3], world.T[seen], atol=1e-6)
            np.testing.assert_array_equal(
                cloud["pointcloud"]["rgb"][env, start : start + h * w], data["rgb"][env].reshape(-1, 3)
            )
            np.testing.assert_array_equal(
                cloud["pointcloud"]["segmentation"][env, start : start + h * w],
                data["segmentation"][env].reshape(-1, 1),
            )
        start += h * w
    assert start == cloud["pointcloud"]["xyzw"].shape[1]


def test_each_env_of_a_batch_renders_as_a_single_env_in_its_state() -> None:
    """Env ``i``'s frame in a batch is that of a single env seeded ``s + i`` after the
    same actions, bit for bit: each env's camera frames the robots in that env (all were
    framed from env 0's robots: 1555 and 1836 of 9216 values differed in envs 1 and 2).
    A reset of some envs frames those again and leaves the others' cameras as they were."""
    kwargs: dict[str, Any] = {"robot_uids": "panda", "render_mode": "rgb_array", "render_size": (64, 48)}
    actions = np.random.default_rng(0).uniform(-1.0, 1.0, (5, 3, 8))
    batch = ra.make_env("PickCube-v1", num_envs=3, **kwargs).unwrapped
    batch.reset(seed=4)
    singles = [ra.make_env("PickCube-v1", **kwargs).unwrapped for _ in range(3)]
    for i, single in enumerate(singles):
        single.reset(seed=4 + i)
    for action in actions:
        batch.step(action)
        for single, row in zip(singles, action, strict=True):
            single.step(row)
    frames = batch.render()
    for i, single in enumerate(singles):
        np.testing.assert_array_equal(frames[i], single.render())
    cameras = batch.get_state()["render_camera"]
    assert len(cameras) == 3 and not np.array_equal(cameras[0], cameras[1])
    batch.reset(seed=9, options={"env_ids": [1]})  # env 1 is seeded 9 + 1
    singles[1].reset(seed=10)
    for action in actions[:2]:
        batch.step(action)
        for single, row in zip(singles, action, strict=True):
            single.step(row)
    frames = batch.render()
    for i, single in enumerate(singles):
        np.testing.assert_array_equal(frames[i], single.render())
    for env in (batch, *singles):
        env.close()


def test_the_render_cameras_of_a_batch_are_saved_per_env() -> None:
    """``state["render_camera"]`` holds one camera per env (``None``: framed at the next
    render); the older forms (``None``, or one camera that framed every env) give every
    env that entry; a list of another length is refused before anything is written."""
    kwargs: dict[str, Any] = {"robot_uids": "panda", "num_envs": 2, "render_mode": "rgb_array", "render_size": (48, 36)}
    env = ra.make_env("Empty-v1", **kwargs).unwrapped
    env.reset(seed=0)
    assert env.get_state()["render_camera"] == [None, None]
    frames = env.render()
    saved = env.get_state()
    fresh = ra.make_env("Empty-v1", **kwargs).unwrapped
    fresh.set_state(saved)
    np.testing.assert_array_equal(fresh.render(), frames)
    for bad in ([saved["render_camera"][0]], [None, None, None], [None, [0.0] * 5]):
        with pytest.raises(ra.StateError, match="render_camera"):
            fresh.set_state({**saved, "render_camera": bad})
    np.testing.assert_array_equal(fresh.get_state()["render_camera"], saved["render_camera"])
    fresh.set_state({**saved, "render_camera": saved["render_camera"][0]})  # one camera for every env
    restored = fresh.get_state()["render_camera"]
    np.testing.assert_array_equal(restored[1], saved["render_camera"][0])
    np.testing.assert_array_equal(fresh.render()[0], frames[0])
    fresh.set_state({**saved, "render_camera": None})
    assert fresh.get_state()["render_camera"] == [None, None]
    np.testing.assert_array_equal(fresh.render(), frames)  # framed again from the same poses
    env.close()
    fresh.close()


def test_a_render_bounds_hook_without_the_env_is_refused() -> None:
    """``_render_bounds`` frames one env's camera: a task written for the one camera of
    env 0 (no parameter) is told the signature instead of failing at its first render."""

    class OldEnv(ra.RobotEnv):
        def _render_bounds(self) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[override]
            return self._robots_extent()

    with pytest.raises(ra.ConfigError, match=r"OldEnv._render_bounds: expected a method taking the env"):
        OldEnv(robot_uids="panda")
