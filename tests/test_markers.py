"""Goal markers: drawn into env.render()'s frames, never into the model or the cameras."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.envs.markers import Marker, draw_markers, goal_disc, goal_sphere, pose_axes
from robot_agents.errors import RenderError
from robot_agents.kinematics.rotations import quat_to_matrix


def _frames(task: str, markers: bool, **kwargs: object) -> np.ndarray:
    env = ra.make_env(task, robot_uids="panda", render_mode="rgb_array", **kwargs)
    env.reset(seed=3)
    if not markers:
        env.unwrapped._render_markers = lambda env_index: ()
    frame = np.asarray(env.render())
    env.close()
    return frame


@pytest.mark.parametrize("task", ["PickCube-v1", "PushCube-v1", "ReachPose-v1"])
def test_the_goal_is_drawn_in_green_in_the_render_frame(task: str) -> None:
    with_goal, without = _frames(task, True), _frames(task, False)
    changed = np.any(with_goal != without, axis=-1)
    assert changed.sum() > 20  # the marker covers pixels
    colour = with_goal[changed].astype(float).mean(axis=0)
    if task != "ReachPose-v1":  # (its axes are red, green and blue)
        assert colour[1] > colour[0] and colour[1] > colour[2]


def test_markers_are_not_in_the_model_nor_the_cameras() -> None:
    def observe(markers: bool) -> tuple[int, np.ndarray]:
        env = ra.make_env("PickCube-v1", robot_uids="panda_wristcam", obs_mode="rgb")
        if not markers:
            env.unwrapped._render_markers = lambda env_index: ()
        obs, _ = env.reset(seed=3)
        ngeom = env.unwrapped.scene.render_model.ngeom
        images = np.concatenate([np.asarray(v["rgb"]).ravel() for v in obs["sensor_data"].values()])
        env.close()
        return ngeom, images

    (ngeom, images), (ngeom_without, images_without) = observe(True), observe(False)
    assert ngeom == ngeom_without
    np.testing.assert_array_equal(images, images_without)


def test_each_env_draws_its_own_goal() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="panda", num_envs=2, render_mode="rgb_array")
    env.reset(seed=0)
    goals = env.unwrapped.goal_pos
    assert not np.allclose(goals[0], goals[1])
    markers = [env.unwrapped._render_markers(i)[0] for i in range(2)]
    assert [m.pos for m in markers] == [tuple(goals[0]), tuple(goals[1])]
    assert markers[0].size == (env.unwrapped.goal_threshold,)
    frames = env.render()
    assert frames.shape[0] == 2 and not np.array_equal(frames[0], frames[1])
    env.close()


def test_pose_axes_run_along_the_pose_axes() -> None:
    quat = np.array([0.9, 0.1, -0.3, 0.2])
    quat /= np.linalg.norm(quat)
    pose = np.array([0.1, -0.2, 0.3, *quat])
    rotation = quat_to_matrix(quat)
    markers = pose_axes(pose, length=0.08, radius=0.002)
    for axis, marker in enumerate(markers):
        np.testing.assert_allclose(marker.pos, pose[:3] + 0.04 * rotation[:, axis], atol=1e-12)
        # the capsule's own z axis (its length) lies along the pose's axis
        np.testing.assert_allclose(quat_to_matrix(np.array(marker.quat))[:, 2], rotation[:, axis], atol=1e-12)
        assert marker.size == (0.002, 0.04)
    assert [m.rgba[:3].index(max(m.rgba[:3])) for m in markers] == [0, 1, 2]  # red, green, blue


def test_goal_shapes() -> None:
    assert goal_sphere([1, 2, 3], 0.02) == Marker("sphere", (0.02,), (1.0, 2.0, 3.0))
    disc = goal_disc([0, 0, 0.75], 0.1)
    assert disc.shape == "cylinder" and disc.size == (0.1, 0.001) and disc.pos == (0.0, 0.0, 0.75)


def test_bad_markers_are_clean_errors() -> None:
    with pytest.raises(RenderError, match="expected shape in"):
        Marker("cone", (0.1,), (0.0, 0.0, 0.0))
    with pytest.raises(RenderError, match="positive sizes"):
        Marker("sphere", (0.0,), (0.0, 0.0, 0.0))
    with pytest.raises(RenderError, match="finite"):
        Marker("sphere", (0.1,), (np.nan, 0.0, 0.0))


def test_a_full_visual_scene_takes_no_marker() -> None:
    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom size='0.1'/></worldbody></mujoco>")
    scene = mujoco.MjvScene(model, maxgeom=2)
    draw_markers(scene, [goal_sphere([0, 0, 0], 0.1)])
    assert scene.ngeom == 1 and scene.geoms[0].type == mujoco.mjtGeom.mjGEOM_SPHERE
    with pytest.raises(RenderError, match="holds 2 geoms and has 1; 2 markers do not fit"):
        draw_markers(scene, [goal_sphere([0, 0, 0], 0.1)] * 2)
    assert scene.ngeom == 1
