"""Composed robots: pieces attached at a body or site bring their model, drives, parts
and default keyframe; the Panda family is built that way."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.agent.declaration import composition
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.robots.catalog import BUILTIN_PIECES
from robot_agents.robots.panda.panda import FINGERTIP_TOUCH, PandaHand

# A fixed bar with two tool sites, 40 cm apart, the right one turned 90 deg about z.
BAR_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="bar" pos="0 0 0.5">
      <geom type="box" size="0.05 0.3 0.02" mass="2"/>
      <body name="carriage">
        <joint name="slide" type="slide" axis="1 0 0" range="-0.2 0.2"/>
        <geom type="box" size="0.02 0.02 0.02" mass="0.5"/>
        <site name="left_mount" pos="0 0.2 -0.03" quat="0 1 0 0"/>
        <site name="right_mount" pos="0 -0.2 -0.03" quat="0 0.70710678 0.70710678 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture
def two_hands(tmp_path: Path) -> type[ra.Agent]:
    path = tmp_path / "bar.xml"
    path.write_text(BAR_MJCF)

    class TwoHands(ra.Agent):
        uid = "two_hands"
        mjcf_path = path
        actuators = (ra.PDActuator(joints="slide", stiffness=500.0, damping=50.0),)
        parts = (ra.Torso(name="carriage", joints="slide"),)
        attachments = (
            ra.Attachment(PandaHand, at="left_mount", prefix="left/"),
            ra.Attachment(PandaHand, at="right_mount", prefix="right/", pos=(0.0, 0.0, 0.01)),
        )
        keyframes = {"home": ra.Keyframe(qpos={"slide": 0.1, "right/panda_finger_joint1": 0.01})}

    return TwoHands


def test_pieces_bring_drives_parts_and_default_keyframe(two_hands: type[ra.Agent]) -> None:
    scene = ra.Scene(two_hands)
    scene.reset()
    agent = scene.agents[0]
    assert agent.joint_names == (
        "slide",
        "left/panda_finger_joint1",
        "left/panda_finger_joint2",
        "right/panda_finger_joint1",
        "right/panda_finger_joint2",
    )
    assert agent.drives.size == 5 and scene.model.nu == 5  # the hands' drives came along, once each
    assert set(agent.part_joints) == {"carriage", "left_gripper", "right_gripper"}
    # The left hand takes its piece's default keyframe (open); the right one follows the
    # keyframe, its second finger through the hand's own coupling.
    np.testing.assert_allclose(agent.qpos[0], [0.1, 0.04, 0.04, 0.01, 0.01])
    # Modes from the parts: the carriage leads, each gripper adds one action.
    assert agent.controller.slices == {
        "carriage": slice(0, 1),
        "left_gripper": slice(1, 2),
        "right_gripper": slice(2, 3),
    }
    assert not agent.is_grasping("world", gripper="left_gripper")[0]


def test_a_piece_sits_at_its_site_with_its_offset(two_hands: type[ra.Agent]) -> None:
    scene = ra.Scene(two_hands)
    scene.reset()
    model = scene.model
    data = scene.world.physics_sources([0])[0]
    for side, offset in (("left", 0.0), ("right", 0.01)):
        site = model.site(f"two_hands-0/{side}_mount").id
        hand = model.body(f"two_hands-0/{side}/panda_hand").id
        rotation = data.site_xmat[site].reshape(3, 3)
        np.testing.assert_allclose(data.xpos[hand], data.site_xpos[site] + rotation @ [0.0, 0.0, offset], atol=1e-12)
        hand_rotation = np.zeros(9)
        mujoco.mju_quat2Mat(hand_rotation, data.xquat[hand])
        np.testing.assert_allclose(hand_rotation.reshape(3, 3), rotation, atol=1e-12)


def test_panda_is_composed_from_arm_and_hand() -> None:
    panda = ra.get_agent("panda")
    checked = panda.check()
    assert [d.joint for d in checked.drives] == [
        *(f"panda_joint{i}" for i in range(1, 8)),
        "panda_finger_joint1",
        "panda_finger_joint2",
    ]
    assert checked.part_joints == {
        "arm": tuple(f"panda_joint{i}" for i in range(1, 8)),
        "gripper": ("panda_finger_joint1", "panda_finger_joint2"),
    }
    # closed_rest names only the first finger: the second follows through the hand's coupling.
    np.testing.assert_allclose(checked.keyframes["closed_rest"].qpos[7:], [0.0, 0.0])
    np.testing.assert_allclose(checked.keyframes["rest"].qpos[7:], [0.04, 0.04])  # the hand's default: open
    model = ra.Scene("panda").model
    assert sum(
        model.body_mass[model.body(f"panda-0/panda_{n}").id] for n in ("hand", "leftfinger", "rightfinger")
    ) == pytest.approx(0.76, abs=1e-6)


def test_wrist_camera_housing_is_a_piece() -> None:
    scene = ra.Scene("panda_wristcam")
    model = scene.model
    housing = model.body("panda_wristcam-0/camera_housing").id
    assert model.body_parentid[housing] == model.body("panda_wristcam-0/panda_hand").id
    assert model.body_mass[housing] == pytest.approx(0.072)  # Intel D415 datasheet
    np.testing.assert_allclose(model.body_pos[housing], [0.0465, 0.0, 0.0235])


def test_sensors_of_a_piece_mounted_twice_are_named_by_its_prefix(two_hands: type[ra.Agent]) -> None:
    """A piece with a camera and touch pads, mounted twice ("left/", "right/"): each copy's
    sensors are named like its parts (``left_palm_camera``), each camera rides its own
    hand and each pad its own finger (both copies declared the same uid before: "the
    model already has a camera named 'palm_camera'")."""
    offset_quat = (0.0, 0.70710678, 0.70710678, 0.0)

    class SensingHand(PandaHand):
        cameras = (
            ra.CameraConfig(
                "palm_camera", mount="panda_hand", pos=(0.05, 0.0, 0.03), quat=offset_quat, width=8, height=8
            ),
        )
        touch_sensors = FINGERTIP_TOUCH

    attachments = (
        ra.Attachment(SensingHand, at="left_mount", prefix="left/"),
        ra.Attachment(SensingHand, at="right_mount", prefix="right/", pos=(0.0, 0.0, 0.01)),
    )
    scene = ra.Scene(type("SensingHands", (two_hands,), {"attachments": attachments}))
    scene.reset()
    model, data, agent = scene.model, scene.world.datas[0], scene.agents[0]
    assert scene.cameras.keys == ["left_palm_camera", "right_palm_camera"]
    params = scene.cameras.params(scene.world)
    offset = np.eye(4)
    offset[:3, :3], offset[:3, 3] = quat_to_matrix(offset_quat), (0.05, 0.0, 0.03)
    positions = []
    for side in ("left", "right"):
        hand = model.body(f"two_hands-0/{side}/panda_hand").id
        link = np.eye(4)
        link[:3, :3], link[:3, 3] = data.xmat[hand].reshape(3, 3), data.xpos[hand]
        pose = params[f"{side}_palm_camera"]["cam2world_gl"][0]
        np.testing.assert_allclose(pose, link @ offset, atol=1e-6)
        positions.append(pose[:3, 3])
    assert np.linalg.norm(positions[0] - positions[1]) > 0.3  # the mounts are 0.4 m apart
    names = ("left_left_pad_touch", "left_right_pad_touch", "right_left_pad_touch", "right_right_pad_touch")
    assert agent.touch_reader.names == names and agent.touch.shape == (1, 4)
    for name, finger in zip(
        names,
        ("left/panda_leftfinger", "left/panda_rightfinger", "right/panda_leftfinger", "right/panda_rightfinger"),
        strict=True,
    ):
        site = model.sensor_objid[model.sensor(f"two_hands-0/{name}").id]
        assert model.site_bodyid[site] == model.body(f"two_hands-0/{finger}").id
    scene.close()


def test_bad_attachments_are_clear(two_hands: type[ra.Agent]) -> None:
    bad = type("BadMount", (two_hands,), {"attachments": (ra.Attachment(PandaHand, at="left_mnt"),)})
    with pytest.raises(ra.UnknownNameError, match=r"body or site 'left_mnt'.*Did you mean 'left_mount'"):
        ra.Scene(bad)
    with pytest.raises(ra.ConfigError, match="expected an Agent subclass"):
        ra.Attachment(int, at="x")
    clash = type(
        "Clash",
        (two_hands,),
        {"attachments": (ra.Attachment(PandaHand, at="left_mount"), ra.Attachment(PandaHand, at="right_mount"))},
    )
    with pytest.raises(ra.RobotAgentsError):
        ra.Scene(clash)


# A one-hinge wrist whose flange faces down, turned about z, off the hinge's axis.
WRIST_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="link" pos="0 0 0.6">
      <joint name="wrist" axis="0 0 1" range="-3 3"/>
      <geom type="cylinder" size="0.04 0.05" mass="1"/>
      <body name="flange" pos="0.02 0 -0.06" quat="0 0.38268343 0.92387953 0"/>
    </body>
  </worldbody>
</mujoco>
"""


#: How far out of the flange each piece's tcp lies (m): the Franka Hand's TCP 0.1034 m past
#: its flange (Franka), the stick's tip, the 2F-85's pad centres closed (Menagerie), the
#: WidowX gripper's ee_gripper_link (0.043 + 0.023 + 0.027575 m, Interbotix).
TCP_OUT = {"franka_hand": 0.1034, "panda_stick": 0.15, "robotiq_2f85": 0.1553, "widowx250s_gripper": 0.093575}
TCP_OUT |= {"ability_hand_right": 0.09}  # the Ability Hand: level with its power grasp's cube


@pytest.mark.parametrize("name", sorted(BUILTIN_PIECES))
def test_every_builtin_piece_points_its_tcp_out_of_the_flange(tmp_path: Path, name: str) -> None:
    """The pieces' convention (robot_agents.robots.catalog.BUILTIN_PIECES): mounted with
    no turn, each piece's ``tcp`` lies on the flange's z axis, out of the flange; the
    piece brings its parts under its prefix and rests free of contacts."""
    path = tmp_path / "wrist.xml"
    path.write_text(WRIST_MJCF)
    piece = ra.get_piece(name)

    class Wrist(ra.Agent):
        mjcf_path = path
        actuators = (ra.PDActuator(joints="wrist", stiffness=50.0, damping=5.0),)
        attachments = (ra.Attachment(piece, at="flange", prefix="tool/"),)
        parts = (ra.Arm(name="arm", joints="wrist", end_effectors=(ra.EndEffector(f"tool/{piece.tcp}", name="tcp"),)),)

    scene = ra.Scene(Wrist)
    scene.reset()
    agent = scene.agents[0]
    assert set(agent.part_joints) == {"arm", *(f"tool_{part.name}" for part in composition(piece).parts)}
    assert scene.world.datas[0].ncon == 0
    tcp = agent.frame_pose(f"tool/{piece.tcp}", relative_to="flange")[0, :3]
    np.testing.assert_allclose(tcp[:2], 0.0, atol=1e-9)
    assert 0.05 < tcp[2] < 0.2, tcp
    if name in TCP_OUT:  # (docs/robots.md, "Pieces")
        assert tcp[2] == pytest.approx(TCP_OUT[name], abs=1e-9)
    scene.close()


@pytest.mark.parametrize("name", sorted(BUILTIN_PIECES))
def test_every_builtin_piece_declares_its_own_drives(name: str) -> None:
    """A built-in piece's drives are its own ``actuators`` (none come from a piece mounted
    on it), so a subclass that declares others mounts the same gripper with other drives
    (the Bridge setups' WidowX gripper: tests/test_widowx_bridge_gripper.py)."""
    piece = ra.get_piece(name)
    assert composition(piece).actuators == tuple(piece.actuators)
    if not piece.actuators:  # a rigid tool
        return

    class Other(piece):  # type: ignore[valid-type,misc]
        actuators = tuple(dataclasses.replace(a, effort_limit=1.0) for a in piece.actuators)

    scene = ra.Scene(Other)
    scene.reset()
    np.testing.assert_array_equal(scene.model.actuator_forcerange, [[-1.0, 1.0]] * scene.model.nu)
    scene.close()
