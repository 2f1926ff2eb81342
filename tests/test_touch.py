"""Touch sensors read normal contact force in newtons: a resting box reads its weight,
the Panda's fingertip pads read the squeeze on a grasped cube."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

import robot_agents as ra

PAD_MJCF = """
<mujoco>
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.05" pos="0 0 0.05" mass="5"/>
      <body name="pad" pos="0 0 0.1">
        <joint name="lift" type="slide" axis="0 0 1" range="-0.05 0.05"/>
        <geom name="pad" type="box" size="0.08 0.08 0.01" pos="0 0 0.01" mass="0.5"/>
        <site name="pad_top" type="box" size="0.081 0.081 0.002" pos="0 0 0.02"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def lift_class(name: str, uid: str, path: Path, **extra: Any) -> type[ra.Agent]:
    """Robot ``name`` (uid ``uid``) of model file ``path``, whose one joint, the slide
    ``lift``, is held by a stiff PD drive at 0 (keyframe ``home``); ``extra``: further
    class attributes."""
    attrs: dict[str, Any] = {
        "uid": uid,
        "mjcf_path": path,
        "keyframes": {"home": ra.Keyframe(qpos={"lift": 0.0})},  # (other joints: the file's)
        "actuators": (ra.PDActuator(joints="lift", stiffness=5000.0, damping=200.0, effort_limit=200.0),),
        "control_modes": ra.joint_control_modes(ra.JointGroup(joint_names=("lift",))),
    }
    attrs.update(extra)
    return type(name, (ra.Agent,), attrs)


def touch_pad_class(path: Path, **extra: Any) -> type[ra.Agent]:
    """A fixed base carrying a 16 x 16 cm pad on a position-controlled slide; touch
    sensors on a new site over the pad (``pad_touch``) and on the file's site."""
    touch = (
        ra.TouchSensorConfig("pad_touch", link="pad", pos=(0.0, 0.0, 0.02), size=(0.085, 0.085, 0.003)),
        ra.TouchSensorConfig("site_touch", site="pad_top"),
    )
    return lift_class("TouchPad", "touch_pad", path, **{"touch_sensors": touch, **extra})


@pytest.fixture
def pad_file(tmp_path: Path) -> Path:
    path = tmp_path / "pad.xml"
    path.write_text(PAD_MJCF)
    return path


def test_one_kilogram_box_on_a_touch_pad_reads_its_weight(pad_file: Path) -> None:
    box = ra.Prop("box", "box", size=(0.04, 0.04, 0.04), pos=(0.0, 0.0, 0.165), mass=1.0)
    scene = ra.Scene(touch_pad_class(pad_file), props=[box], num_envs=2, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    assert agent.touch.shape == (2, 2)
    np.testing.assert_array_equal(agent.touch, 0.0)  # the box starts 5 mm above the pad
    for _ in range(scene.control_freq):  # 1 s: land and settle
        agent.set_action(np.zeros(1))
        scene.step()
    np.testing.assert_allclose(agent.touch, 9.81, rtol=0.02)
    proprioception = agent.get_proprioception()["touch"]
    np.testing.assert_array_equal(proprioception, agent.touch)


def test_touch_declaration_errors(pad_file: Path) -> None:
    with pytest.raises(ra.ConfigError, match="exactly one of link"):
        ra.TouchSensorConfig("t", link="pad", site="pad_top")
    with pytest.raises(ra.ConfigError, match="size of a sphere"):
        ra.TouchSensorConfig("t", link="pad", shape="sphere", size=(0.01, 0.02))
    with pytest.raises(ra.ConfigError, match="shape in"):
        ra.TouchSensorConfig("t", link="pad", shape="cone")
    with pytest.raises(ra.ConfigError, match="positive sizes"):
        ra.TouchSensorConfig("t", link="pad", size=(0.01, 0.0, 0.01))
    # Names are checked when declared (a site index reached MuJoCo's TypeError, a list
    # shape Python's "unhashable type").
    for fields, fragment in (
        ({"site": 3}, "expected site to be a non-empty name, got 3"),
        ({"link": ""}, "expected link to be a non-empty name, got ''"),
        ({"link": "pad", "shape": ["box"]}, "expected shape in"),
        # On an existing site the site's own shape senses: a size was ignored without a word.
        ({"site": "pad_top", "size": (0.1, 0.1, 0.1)}, r"site='pad_top' senses over .* got size=\(0.1, 0.1, 0.1\)"),
        ({"site": "pad_top", "pos": (0, 0, 0.01)}, r"expected no shape, size, pos or quat .* got pos=\(0, 0, 0.01\)"),
    ):
        with pytest.raises(ra.ConfigError, match=fragment):
            ra.TouchSensorConfig("t", **fields)  # type: ignore[arg-type]
    # A robot's touch site rides on one of its links: a site on "world" was built into
    # the robot's own world and lost when the robot entered the scene (the TouchReader
    # then raised "touch sensor 'touch_pad-0/t' is not in the compiled model").
    on_world = touch_pad_class(pad_file, touch_sensors=(ra.TouchSensorConfig("t", link="world"),))
    with pytest.raises(
        ra.UnknownNameError, match=r"TouchPad.touch_sensors\['t'\].link: unknown body 'world'. Available: 'base', 'pad'"
    ):
        ra.Scene(on_world)
    bad_link = touch_pad_class(pad_file, touch_sensors=(ra.TouchSensorConfig("t", link="padd"),))
    with pytest.raises(
        ra.UnknownNameError, match=r"TouchPad.touch_sensors\['t'\].link: unknown body 'padd'. Did you mean 'pad'"
    ):
        ra.Scene(bad_link)
    bad_site = touch_pad_class(pad_file, touch_sensors=(ra.TouchSensorConfig("t", site="pad_tip"),))
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'pad_top'"):
        ra.Scene(bad_site)
    twice = touch_pad_class(
        pad_file, touch_sensors=(ra.TouchSensorConfig("t", link="pad"), ra.TouchSensorConfig("t", link="base"))
    )
    with pytest.raises(ra.ConfigError, match="two entries have the uid 't'"):
        ra.Scene(twice)


def normal_force(model: mujoco.MjModel, data: mujoco.MjData, body_a: int, body_b: int) -> float:
    """Sum of the normal forces (N) of the contacts between two bodies."""
    total, wrench = 0.0, np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        if {model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]} == {body_a, body_b}:
            mujoco.mj_contactForce(model, data, i, wrench)
            total += wrench[0]
    return total


def test_panda_fingertip_pads_read_the_squeeze() -> None:
    """panda_touch grasps a 4 cm cube: each pad reads the normal force between its finger
    and the cube (1%), which is the gripper's squeeze kp * (q + 0.01 m) (10%)."""
    props = [
        ra.Prop("pedestal", "box", size=(0.05, 0.05, 0.075), pos=(0.615, 0.0, 0.075), mass=None),
        ra.Prop("cube", "box", size=(0.02, 0.02, 0.02), pos=(0.615, 0.0, 0.1701), mass=0.1),
    ]
    scene = ra.Scene("panda_touch", props=props, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    rest = agent.keyframe_qpos("rest")[:7]
    for _ in range(5):
        agent.set_action(np.concatenate([rest, [1.0]]))
        scene.step()
    np.testing.assert_array_equal(agent.touch, 0.0)  # open: nothing touched
    for _ in range(20):
        agent.set_action(np.concatenate([rest, [-1.0]]))
        scene.step()
    model, data = scene.model, scene.world.datas[0]
    cube = model.body("cube").id
    left, right = (agent.index.body_id(f"panda_{side}finger", "test") for side in ("left", "right"))
    touch = agent.touch[0]
    assert touch[0] == pytest.approx(normal_force(model, data, left, cube), rel=0.01)
    assert touch[1] == pytest.approx(normal_force(model, data, right, cube), rel=0.01)
    squeeze = 1000.0 * (agent.qpos[0, 7] + 0.01)
    np.testing.assert_allclose(touch, squeeze, rtol=0.1)
    assert touch.min() > 20.0
    # In the flat state observation the two readings follow the controller targets.
    env = ra.make_env("Empty-v1", robot_uids="panda_touch", obs_mode="state_dict")
    obs, _ = env.reset(seed=0)
    assert obs["agent"]["touch"].shape == (1, 2)
    plain = ra.make_env("Empty-v1", robot_uids="panda", obs_mode="state").observation_space.shape
    assert env.unwrapped.observation_space["agent"]["touch"].shape == (1, 2)
    touch_state = ra.make_env("Empty-v1", robot_uids="panda_touch", obs_mode="state").observation_space.shape
    assert touch_state == (1, plain[1] + 2)


def test_touch_readings_in_the_observations_are_the_weight_on_the_pad(pad_file: Path) -> None:
    """A 2.5 kg box on the pad reads its weight, 24.52 N (2%), in both sensors, at the
    documented place of the flat state (qpos, qvel, targets, touch: one joint, so
    entries 3 and 4) and in ``obs["agent"]["touch"]``, after 1 s of settling."""
    box = ra.Prop("box", "box", size=(0.04, 0.04, 0.04), pos=(0.0, 0.0, 0.165), mass=2.5)
    env_class = type("PadEnv", (ra.RobotEnv,), {"_scene_props": lambda self: (box,)})
    readings = {}
    for mode in ("state", "state_dict"):
        env = env_class(robot_uids=touch_pad_class(pad_file), obs_mode=mode, control_mode="pd_joint_pos")
        obs, _ = env.reset(seed=0)
        for _ in range(env.scene.control_freq):
            obs, *_ = env.step(np.zeros(1))
        readings[mode] = obs[:, 3:5] if mode == "state" else obs["agent"]["touch"]
        np.testing.assert_array_equal(readings[mode], env.agent.touch.astype(np.float32))
        env.close()
    assert readings["state"].shape == (1, 2)
    np.testing.assert_allclose(readings["state"], 2.5 * 9.81, rtol=0.02)
    np.testing.assert_array_equal(readings["state"], readings["state_dict"])
