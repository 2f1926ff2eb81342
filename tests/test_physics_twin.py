"""The simulated twin: a scene without its visual-only geoms simulates the same motion,
bit for bit, and renders the same pictures."""

from __future__ import annotations

import copy
import hashlib

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.model.physics_twin import (
    copy_spec,
    geoms_giving_mass,
    physics_twin,
    shared_geoms,
    visual_only_geoms,
)

MODEL = """
<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="arm" pos="0 0 0.5">
      <joint name="hinge" axis="0 1 0"/>
      <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
      <geom name="link" type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>
      <geom name="paint" type="box" size="0.03 0.03 0.03" contype="0" conaffinity="0" group="2"/>
      <geom name="paired" type="sphere" size="0.02" pos="0 0 -0.2" contype="0" conaffinity="0"/>
      <geom name="sensed" type="sphere" size="0.01" pos="0 0 -0.1" contype="0" conaffinity="0"/>
      <body name="loose" pos="0 0 -0.2">
        <joint name="free_hinge" axis="0 1 0"/>
        <geom name="heavy_paint" type="box" size="0.02 0.02 0.02" contype="0" conaffinity="0"/>
        <geom name="massless_paint" type="box" size="0.02 0.02 0.02" contype="0" conaffinity="0" mass="0"/>
      </body>
    </body>
  </worldbody>
  <contact><pair geom1="paired" geom2="floor"/></contact>
  <sensor><distance geom1="sensed" geom2="floor"/></sensor>
</mujoco>
"""


def twin_of(xml: str) -> tuple[mujoco.MjModel, mujoco.MjModel | None]:
    spec = mujoco.MjSpec.from_string(xml)
    full = spec.compile()
    return full, physics_twin(spec, full)


def geom_names(model: mujoco.MjModel) -> set[str]:
    return {model.geom(g).name for g in range(model.ngeom)}


def test_only_geoms_that_change_nothing_are_left_out() -> None:
    full, twin = twin_of(MODEL)
    assert twin is not None
    # a pair, a sensor and a body's mass keep theirs; the massless paint goes too
    assert geom_names(full) - geom_names(twin) == {"paint", "massless_paint"}
    assert {full.geom(g).name for g in visual_only_geoms(full)} == {"paint", "heavy_paint", "massless_paint"}
    np.testing.assert_array_equal(twin.body_mass, full.body_mass)
    np.testing.assert_array_equal(twin.body_inertia, full.body_inertia)


def test_a_model_without_visual_only_geoms_has_no_twin() -> None:
    _, twin = twin_of("<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>")
    assert twin is None


def test_copy_spec_keeps_material_textures() -> None:
    scene = ra.Scene("panda", render_only_visuals=False)
    copy = copy_spec(scene.spec)
    model = copy.compile()  # MuJoCo 4.0's own copy garbles the floor material's textures
    np.testing.assert_array_equal(model.mat_texid, scene.model.mat_texid)
    scene.close()


def trajectory_digest(uid: str, mode: str, render_only_visuals: bool, task: str = "Empty-v1") -> str:
    env = ra.make_env(task, robot_uids=uid, control_mode=mode, render_only_visuals=render_only_visuals)
    obs, _ = env.reset(seed=2)
    rng = np.random.default_rng(0)
    digest = hashlib.sha256(np.asarray(obs).tobytes())
    for _ in range(40):
        obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        digest.update(np.asarray(obs).tobytes() + np.asarray(reward).tobytes())
    digest.update(np.asarray(env.unwrapped.get_state()["physics"]).tobytes())
    env.close()
    return digest.hexdigest()


@pytest.mark.parametrize(
    ("uid", "mode", "task"),
    [
        ("panda", "pd_joint_delta_pos", "PickCube-v1"),
        ("xarm6_robotiq", "pd_ee_delta_pose", "Empty-v1"),
        ("fetch", "pd_joint_delta_pos", "Empty-v1"),
        ("floating_robotiq_2f_85_gripper", "pd_joint_delta_pos", "Empty-v1"),
    ],
)
def test_the_twin_simulates_the_same_motion_bit_for_bit(uid: str, mode: str, task: str) -> None:
    scene = ra.Scene(uid)
    assert scene.model.ngeom < scene.render_model.ngeom  # the twin is in use
    scene.close()
    assert trajectory_digest(uid, mode, True, task) == trajectory_digest(uid, mode, False, task)


def test_renders_and_camera_images_are_the_same_with_the_twin() -> None:
    images = []
    for render_only_visuals in (True, False):
        env = ra.make_env(
            "Empty-v1",
            robot_uids="panda_wristcam",
            obs_mode="rgb+depth+segmentation",
            render_mode="rgb_array",
            render_size=(96, 72),
            render_only_visuals=render_only_visuals,
        )
        env.reset(seed=1)
        for _ in range(3):
            obs, *_ = env.step(np.full(env.action_space.shape, 0.5))
        images.append((env.render(), obs["sensor_data"]))
        env.close()
    (frame_twin, sensors_twin), (frame_one, sensors_one) = images
    np.testing.assert_array_equal(frame_twin, frame_one)
    for camera, textures in sensors_one.items():
        for texture, image in textures.items():
            np.testing.assert_array_equal(sensors_twin[camera][texture], image)
    # what is drawn has the visual geoms: the simulated model alone draws another picture
    scene = ra.Scene("panda")
    scene.reset()
    world, pictures = scene.world, []
    for model, data in (
        (scene.render_model, world.render_sources([0])[0]),
        (scene.model, world.physics_sources([0])[0]),
    ):
        renderer = mujoco.Renderer(model, 72, 96)
        renderer.update_scene(data)
        pictures.append(renderer.render().copy())
        renderer.close()
    assert np.mean(np.any(pictures[0] != pictures[1], axis=2)) > 0.01
    scene.close()


def test_render_sources_follow_the_simulated_state() -> None:
    scene = ra.Scene("panda")
    scene.reset()
    world = scene.world
    agent = scene.agents[0]
    for _ in range(3):
        agent.set_action(np.full(agent.controller.action_dim, 0.3))
        scene.step()
    simulated, drawn = world.physics_sources([0])[0], world.render_sources([0])[0]
    assert drawn is not simulated
    np.testing.assert_array_equal(drawn.qpos, simulated.qpos)
    np.testing.assert_array_equal(drawn.xpos, simulated.xpos)  # same bodies, same poses
    hand = scene.render_model.body("panda-0/panda_hand").id
    np.testing.assert_array_equal(drawn.xquat[hand], simulated.xquat[hand])
    scene.close()


def test_render_only_visuals_is_checked() -> None:
    with pytest.raises(ra.ConfigError, match="render_only_visuals"):
        ra.Scene("panda", render_only_visuals="yes")  # type: ignore[arg-type]
    scene = ra.Scene("panda", render_only_visuals=False)
    assert scene.model is scene.render_model
    scene.close()


@pytest.mark.parametrize("uid", ra.list_agents())
def test_every_built_in_robot_simulates_only_what_matters(uid: str) -> None:
    """Each robot's scene gets its twin, and a visual-only geom left in it gives its body
    mass; a robot whose every geom collides (the capsule humanoid) simulates its one model."""
    scene = ra.Scene(uid)
    full = scene.render_model
    visual = visual_only_geoms(full)
    if not visual:
        assert scene.model is scene.render_model
        scene.close()
        return
    assert scene.model is not scene.render_model
    assert scene.model.ngeom < scene.render_model.ngeom
    kept = len(visual) - (full.ngeom - scene.model.ngeom)
    assert kept == len(geoms_giving_mass(scene.spec, full, visual))
    scene.close()


def test_a_twin_that_simulates_something_else_is_refused() -> None:
    """The check after compiling catches any difference besides geoms."""
    from robot_agents.model import physics_twin as twin_module

    full, twin = twin_of(MODEL)
    assert twin is not None and twin_module._same_physics(full, twin)
    for change in (
        lambda m: m.body_mass.__setitem__(1, 2.0),
        lambda m: m.dof_damping.__setitem__(0, 0.5),
        lambda m: setattr(m.opt, "iterations", 7),
        lambda m: m.sensor_objid.__setitem__(0, 0),  # the distance sensor names another geom
    ):
        other = copy.copy(twin)
        change(other)
        assert not twin_module._same_physics(full, other)


def test_changes_to_the_simulated_model_show_in_what_is_drawn() -> None:
    """Moving a static body, or recolouring / resizing a geom, in ``env.model`` is drawn
    as with one model; the visual-only geoms follow their bodies."""
    # sleeping off: with it, MuJoCo 4.0's forward pass keeps a static body's pose after a
    # change to the model (its tree counts as asleep), which is not what this test is about
    env = ra.make_env("PickCube-v1", robot_uids="panda", render_mode="rgb_array", render_size=(64, 48), sleep=False)
    env.reset(seed=0)
    u = env.unwrapped
    simulated, drawn, world = u.model, u.render_model, u.scene.world
    mirror_ids = shared_geoms(drawn, simulated)
    assert [simulated.geom(i).name for i in range(simulated.ngeom)] == [drawn.geom(int(j)).name for j in mirror_ids]
    table = simulated.body("table").id
    table_geom = int(np.flatnonzero(simulated.geom_bodyid == table)[0])
    before = env.render()
    simulated.body_pos[table, 2] -= 0.05
    simulated.geom_rgba[table_geom] = (0.0, 1.0, 0.0, 1.0)
    simulated.geom_size[table_geom, 0] *= 1.5
    data = world.render_sources([0])[0]
    shown = int(mirror_ids[table_geom])
    np.testing.assert_array_equal(drawn.body_pos[table], simulated.body_pos[table])
    np.testing.assert_array_equal(drawn.geom_rgba[shown], (0.0, 1.0, 0.0, 1.0))
    np.testing.assert_array_equal(drawn.geom_size[shown], simulated.geom_size[table_geom])
    simulated.light_diffuse[0] = (0.1, 0.2, 0.3)
    world.render_sources([0])
    np.testing.assert_array_equal(drawn.light_diffuse[0], simulated.light_diffuse[0])
    mujoco.mj_forward(simulated, world.physics_sources([0])[0])
    np.testing.assert_allclose(data.geom_xpos[shown], world.physics_sources([0])[0].geom_xpos[table_geom])
    assert np.any(env.render() != before)
    # a visual-only geom of the hand follows the hand
    hand = simulated.body("panda-0/panda_hand").id
    visual = [g for g in visual_only_geoms(drawn) if int(drawn.geom_bodyid[g]) == hand]
    assert visual
    offset = data.xmat[hand].reshape(3, 3).T @ (data.geom_xpos[visual[0]] - data.xpos[hand])
    np.testing.assert_allclose(offset, drawn.geom_pos[visual[0]], atol=1e-12)
    env.close()
