"""Two fingers at the end of a two-line robot's chain are a ``Gripper``: a URDF
``mimic`` pair, two independently driven fingers, hinged jaws, or a gripper alone.
Written here as small URDFs; the part's open / closed ends, fingers and tool point are
checked against the geometry, and the derived drive opens and closes the fingers."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.parts.declaration import Arm, Gripper

_LINK = """  <link name="{name}">
    <inertial><origin xyz="{com}"/><mass value="{mass}"/><inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="{com}"/><geometry><box size="{box}"/></geometry></collision>
  </link>
"""


def link(name: str, mass: float = 0.5, com: str = "0 0 0", box: str = "0.04 0.04 0.04") -> str:
    return _LINK.format(name=name, mass=mass, com=com, box=box, i=mass * 1e-3)


def joint(name: str, kind: str, parent: str, child: str, xyz: str, axis: str, low: float, high: float) -> str:
    return (
        f'  <joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}"/><axis xyz="{axis}"/><limit lower="{low}" upper="{high}" effort="20" velocity="1"/>'
        "{mimic}</joint>\n"
    )


def urdf(fingers: str, arm: bool = True) -> str:
    """An arm (two hinges, upright) ending in a hand, or the hand alone, plus ``fingers``."""
    body = link("base", 2.0, box="0.1 0.1 0.05")
    if arm:
        body += link("upper", com="0 0 0.15", box="0.04 0.04 0.3") + link("fore", com="0 0 0.15", box="0.04 0.04 0.3")
        body += joint("shoulder", "revolute", "base", "upper", "0 0 0.05", "0 1 0", -1.5, 1.5).format(mimic="")
        body += joint("elbow", "revolute", "upper", "fore", "0 0 0.3", "0 1 0", -1.5, 1.5).format(mimic="")
        body += link("hand", 0.3, com="0 0 0.02", box="0.04 0.16 0.04")
        body += '  <joint name="wrist_fixed" type="fixed"><parent link="fore"/><child link="hand"/><origin xyz="0 0 0.3"/></joint>\n'
    else:
        body = link("hand", 0.3, com="0 0 0.02", box="0.04 0.16 0.04")
    return f'<robot name="gripper_test">\n{body}{fingers}</robot>\n'


def slide_fingers(mimic: bool) -> str:
    """Two fingers sliding apart along y: 0 closed, 0.04 open (the right one mirrored
    through the mimic, or its own joint on -y)."""
    out = link("left_finger", 0.05, com="0 0 0.03", box="0.01 0.01 0.05")
    out += link("right_finger", 0.05, com="0 0 0.03", box="0.01 0.01 0.05")
    out += joint("left_joint", "prismatic", "hand", "left_finger", "0 0.01 0.05", "0 1 0", 0.0, 0.04).format(mimic="")
    follower = '<mimic joint="left_joint" multiplier="1" offset="0"/>' if mimic else ""
    out += joint("right_joint", "prismatic", "hand", "right_finger", "0 -0.01 0.05", "0 -1 0", 0.0, 0.04).format(
        mimic=follower
    )
    return out


def hinge_jaws() -> str:
    """Two jaws hinged on the hand, closing when their angle falls to 0 (upright) and
    opening outwards to 0.6 rad."""
    out = link("left_jaw", 0.05, com="0 0 0.04", box="0.01 0.01 0.08")
    out += link("right_jaw", 0.05, com="0 0 0.04", box="0.01 0.01 0.08")
    out += joint("left_hinge", "revolute", "hand", "left_jaw", "0 0.02 0.05", "-1 0 0", 0.0, 0.6).format(mimic="")
    out += joint("right_hinge", "revolute", "hand", "right_jaw", "0 -0.02 0.05", "1 0 0", 0.0, 0.6).format(mimic="")
    return out


def robot(tmp_path: Path, text: str) -> type[ra.Agent]:
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    return type("GripperTest", (ra.Agent,), {"uid": "gripper_test", "urdf_path": path})


def reset_scene(cls: type[ra.Agent]) -> ra.Scene:
    """A scene of ``cls`` at its default keyframe (load notes silenced)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        scene = ra.Scene(cls)
    scene.reset()
    return scene


def opening_after(scene: ra.Scene, command: float, steps: int = 30) -> float:
    """The gripper's opening (0 closed, 1 open) after ``steps`` control steps of
    ``command`` with the arm held."""
    agent = scene.agents[0]
    action = np.zeros((1, agent.action_space.shape[-1]))
    action[0, agent.controller.slices["gripper"]] = command
    for _ in range(steps):
        agent.set_action(action)
        scene.step()
    return float(agent.gripper_opening()[0])


@pytest.mark.parametrize("mimic", [True, False], ids=["mimic", "two-driven"])
def test_two_sliding_fingers_at_the_chain_end_are_a_gripper(tmp_path: Path, mimic: bool) -> None:
    cls = robot(tmp_path, urdf(slide_fingers(mimic)))
    checked = cls.check()
    arm, gripper = checked.parts
    assert isinstance(arm, Arm) and isinstance(gripper, Gripper)
    assert checked.part_joints == {"arm": ("shoulder", "elbow"), "gripper": ("left_joint", "right_joint")}
    assert gripper.open == (0.04, 0.04) and gripper.closed == (0.0, 0.0)  # apart at the ranges' upper ends
    assert gripper.squeeze == pytest.approx(0.004)
    assert gripper.fingers == (("left_finger",), ("right_finger",))
    # the tool point: on the hand, between the closed fingers' centres of mass
    (ee,) = arm.end_effectors
    assert ee.link == "hand" and ee.name == "ee"
    np.testing.assert_allclose(ee.pos, (0.0, 0.0, 0.08), atol=1e-9)
    modes = checked.modes
    assert all("gripper" in modes[m] for m in modes if isinstance(modes[m], dict))  # one action in every mode
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0) > 0.95
    assert opening_after(scene, -1.0) < 0.05
    left, right = (scene.agents[0].joint_names.index(j) for j in ("left_joint", "right_joint"))
    qpos = scene.agents[0].qpos[0]
    assert abs(qpos[left] - qpos[right]) < 1e-3  # both fingers closed


def test_hinged_jaws_open_where_they_spread(tmp_path: Path) -> None:
    cls = robot(tmp_path, urdf(hinge_jaws()))
    checked = cls.check()
    gripper = checked.parts[1]
    assert isinstance(gripper, Gripper)
    assert gripper.open == (0.6, 0.6) and gripper.closed == (0.0, 0.0)
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0) > 0.95
    assert opening_after(scene, -1.0) < 0.05


def test_a_gripper_alone_is_its_only_part(tmp_path: Path) -> None:
    checked = robot(tmp_path, urdf(slide_fingers(mimic=True), arm=False)).check()
    (gripper,) = checked.parts
    assert isinstance(gripper, Gripper)
    assert list(checked.modes) == ["pd_joint_pos"]


def test_fingers_that_do_not_oppose_stay_in_the_arm(tmp_path: Path) -> None:
    """Two sibling slides that move together (the distance between them constant) are
    not a gripper: the chain is not serial, so the robot gets one Body part."""
    fingers = link("a", 0.05, box="0.01 0.01 0.05") + link("b", 0.05, box="0.01 0.01 0.05")
    fingers += joint("ja", "prismatic", "hand", "a", "0 0.03 0.05", "1 0 0", 0.0, 0.04).format(mimic="")
    fingers += joint("jb", "prismatic", "hand", "b", "0 -0.03 0.05", "1 0 0", 0.0, 0.04).format(mimic="")
    checked = robot(tmp_path, urdf(fingers)).check()
    assert [type(p).__name__ for p in checked.parts] == ["Body"]
