"""Two fingers at the end of a two-line robot's chain are a ``Gripper``: a URDF
``mimic`` pair, two independently driven fingers, hinged jaws, or a gripper alone.
Written here as small URDFs; the part's open / closed ends, fingers and tool point are
checked against the geometry, and the derived drive opens and closes the fingers."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import mujoco
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
    action[0, agent.controller.slices.get("gripper", slice(None))] = command  # (a gripper alone: its one action)
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


def test_the_tool_point_is_between_the_fingers_pads(tmp_path: Path) -> None:
    """Fingers whose mass sits low (at 1 cm) and whose collision box (the pad) reaches
    from 4 to 10 cm: the tool point is between the pads' centres, 7 cm past the finger
    joints, not between the centres of mass."""
    out = ""
    for side, y in (("left", 0.01), ("right", -0.01)):
        out += (
            f'<link name="{side}_finger"><inertial><origin xyz="0 0 0.01"/><mass value="0.05"/>'
            '<inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial>'
            '<collision><origin xyz="0 0 0.07"/><geometry><box size="0.01 0.01 0.06"/></geometry></collision></link>\n'
        )
        axis = "0 1 0" if side == "left" else "0 -1 0"
        out += joint(f"{side}_joint", "prismatic", "hand", f"{side}_finger", f"0 {y} 0.05", axis, 0.0, 0.04).format(
            mimic=""
        )
    checked = robot(tmp_path, urdf(out)).check()
    arm = checked.parts[0]
    assert isinstance(arm, Arm)
    np.testing.assert_allclose(arm.end_effectors[0].pos, (0.0, 0.0, 0.05 + 0.07), atol=1e-9)


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


def linkage() -> str:
    """A four-bar-like linkage on each side, as xArm's and Robotiq's grippers: one driven
    outer knuckle (0 closed, 0.8 open, hinged 4.5 cm up on the hand, 3 cm long), the
    other side's knuckle, both inner knuckles and both fingers (hinged at the knuckles'
    tips, turning back so that they stay upright) following it through mimics."""
    out = ""
    for side, sign in (("left", 1), ("right", -1)):
        axis = "-1 0 0" if sign > 0 else "1 0 0"
        back = "1 0 0" if sign > 0 else "-1 0 0"
        out += link(f"{side}_outer", 0.02, com="0 0 0.015", box="0.01 0.006 0.03")
        out += link(f"{side}_inner", 0.02, com="0.015 0 0.015", box="0.006 0.006 0.03")
        out += link(f"{side}_finger", 0.03, com=f"0 {-sign * 0.024} 0.02", box="0.02 0.006 0.04")
        mimic = '<mimic joint="left_outer_joint" multiplier="1" offset="0"/>'
        out += joint(f"{side}_outer_joint", "revolute", "hand", f"{side}_outer", f"0 {sign * 0.03} 0.045", axis, 0, 0.8)
        out = out.format(mimic="" if side == "left" else mimic)
        out += joint(f"{side}_inner_joint", "revolute", "hand", f"{side}_inner", f"0 {sign * 0.02} 0.05", axis, 0, 0.8)
        out = out.format(mimic=mimic)
        out += joint(f"{side}_finger_joint", "revolute", f"{side}_outer", f"{side}_finger", "0 0 0.03", back, 0, 0.8)
        out = out.format(mimic=mimic)
    return out


def one_jaw(low: float = -0.5, high: float = 0.3) -> str:
    """A fixed jaw (a plate welded to the hand, from 4 to 12 cm up) and a moving jaw
    (a 7 cm plate hinged 5 cm up, 3 cm beside it) that turns onto it: upright at 0,
    touching it near 0.3 rad, leaning away at -0.5 rad."""
    out = link("fixed_jaw", 0.05, com="0 -0.01 0.08", box="0.03 0.01 0.08")
    out += '  <joint name="fixed_jaw_weld" type="fixed"><parent link="hand"/><child link="fixed_jaw"/></joint>\n'
    out += link("moving_jaw", 0.05, com="0 0 0.035", box="0.03 0.01 0.07")
    out += joint("jaw_joint", "revolute", "hand", "moving_jaw", "0 0.02 0.05", "1 0 0", low, high).format(mimic="")
    return out


def finger_distance(scene: ra.Scene, fingers: tuple[str, str]) -> float:
    """The distance between two of the robot's bodies' centres of mass in env 0 (m)."""
    model = scene.model
    data = mujoco.MjData(model)
    data.qpos[:] = scene.world.qpos[0]
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    a, b = (int(model.body(scene.agents[0].prefix + f).id) for f in fingers)
    return float(np.linalg.norm(data.xipos[a] - data.xipos[b]))


def test_a_mimic_linkage_is_a_gripper_of_one_action(tmp_path: Path) -> None:
    cls = robot(tmp_path, urdf(linkage()))
    checked = cls.check()
    arm, gripper = checked.parts
    assert isinstance(arm, Arm) and isinstance(gripper, Gripper)
    followers = (
        "left_finger_joint",
        "left_inner_joint",
        "right_outer_joint",
        "right_finger_joint",
        "right_inner_joint",
    )
    assert checked.part_joints["arm"] == ("shoulder", "elbow")
    assert checked.part_joints["gripper"] == ("left_outer_joint", *followers)  # the leader, then model order
    assert gripper.open == (0.8,) * 6 and gripper.closed == (0.0,) * 6
    assert gripper.squeeze == pytest.approx(0.08)
    assert gripper.fingers == (("left_finger",), ("right_finger",))  # the links whose distance changes most
    # the tool point: between the closed fingers' centres of mass (upright, 3 cm above the knuckles' hinges)
    np.testing.assert_allclose(arm.end_effectors[0].pos, (0.0, 0.0, 0.045 + 0.03 + 0.02), atol=1e-9)
    assert all(len(checked.modes[m]["gripper"].joint_names) == 1 for m in checked.modes)  # type: ignore[index]
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0, 60) > 0.95
    opened = finger_distance(scene, ("left_finger", "right_finger"))
    assert opening_after(scene, -1.0, 60) < 0.05
    closed = finger_distance(scene, ("left_finger", "right_finger"))
    assert opened - closed == pytest.approx(2 * 0.03 * np.sin(0.8), abs=2e-3)  # the knuckles' tips' stroke
    agent = scene.agents[0]
    q = agent.qpos[0]
    for name in followers:  # each follower at its coupling's value
        assert q[agent.joint_names.index(name)] == pytest.approx(
            q[agent.joint_names.index("left_outer_joint")], abs=0.02
        )


def test_one_jaw_turning_onto_a_fixed_jaw_is_a_gripper(tmp_path: Path) -> None:
    cls = robot(tmp_path, urdf(one_jaw()))
    checked = cls.check()
    arm, gripper = checked.parts
    assert isinstance(arm, Arm) and isinstance(gripper, Gripper)
    assert checked.part_joints == {"arm": ("shoulder", "elbow"), "gripper": ("jaw_joint",)}
    assert gripper.open == (-0.5,) and gripper.closed == (0.3,)  # the tip nearest the fixed jaw at 0.3
    assert gripper.fingers == (("moving_jaw",), ("hand", "fixed_jaw"))
    # the tool point: where the closed tip meets the fixed jaw, in the hand's frame
    ee = arm.end_effectors[0]
    assert ee.link == "hand"
    tip = np.array(
        [0.0, 0.02 - 0.07 * np.sin(0.3) + 0.005 * np.cos(0.3), 0.05 + 0.07 * np.cos(0.3) + 0.005 * np.sin(0.3)]
    )
    assert abs(ee.pos[0]) < 1e-9
    assert np.linalg.norm(np.array(ee.pos) - tip) < 0.01
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0) > 0.95
    opened = finger_distance(scene, ("moving_jaw", "fixed_jaw"))
    assert opening_after(scene, -1.0) < 0.05
    closed = finger_distance(scene, ("moving_jaw", "fixed_jaw"))
    assert opened - closed > 0.02


@pytest.mark.parametrize("fingers", ["linkage", "one jaw"])
def test_the_inferred_gripper_grasps_a_box_when_closed_on_it(tmp_path: Path, fingers: str) -> None:
    """The gripper alone, fingers up: a 2 cm box stands on the hand between the open
    fingers; closing squeezes it from two sides, opening lets it go."""
    text = urdf(linkage() if fingers == "linkage" else one_jaw(), arm=False)
    cls = robot(tmp_path, text)
    centre = (0.0, 0.0, 0.08) if fingers == "linkage" else (0.0, 0.0, 0.09)
    box = ra.Prop("box", "box", (0.01, 0.01, 0.04 if fingers == "linkage" else 0.05), pos=centre, mass=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        scene = ra.Scene(cls, props=[box])
    scene.reset()
    agent = scene.agents[0]
    assert opening_after(scene, 1.0, 20) > 0.95
    assert not agent.is_grasping("box")[0]
    opening = opening_after(scene, -1.0, 40)
    assert 0.05 < opening < 0.9  # stopped on the box
    assert agent.is_grasping("box")[0]
    opening_after(scene, 1.0, 20)
    assert not agent.is_grasping("box")[0]


def test_ambiguous_or_folding_structures_get_no_gripper(tmp_path: Path) -> None:
    """An elbow folding back onto its upper link is not a jaw, and a linkage with
    another joint below its hand is ambiguous: both stay in the arm, as before."""
    elbow = link("upper", com="0 0 0.15", box="0.04 0.04 0.3") + link("fore", com="0 0 0.15", box="0.04 0.04 0.3")
    elbow += joint("shoulder", "revolute", "base", "upper", "0 0 0.05", "0 1 0", -1.5, 1.5).format(mimic="")
    elbow += joint("elbow", "revolute", "upper", "fore", "0 0 0.3", "0 1 0", 0.0, 3.0).format(mimic="")
    text = f'<robot name="gripper_test">\n{link("base", 2.0, box="0.1 0.1 0.05")}{elbow}</robot>\n'
    checked = robot(tmp_path, text).check()
    assert [type(p).__name__ for p in checked.parts] == ["Arm"]
    assert checked.part_joints["arm"] == ("shoulder", "elbow")
    extra = link("camera", 0.02, box="0.01 0.01 0.01")
    extra += joint("camera_pan", "revolute", "hand", "camera", "0.03 0 0.02", "0 0 1", -1, 1).format(mimic="")
    checked = robot(tmp_path, urdf(extra + linkage())).check()
    assert not any(isinstance(p, Gripper) for p in checked.parts)
    # a jaw that never comes near the fixed jaw (it leans away over its whole range) is not
    # one, nor one that turns half a turn or more (a flange: KUKA iiwa's joint 7 was taken
    # for a jaw closing on link 6 at one end of its +-3.05 rad before this rule)
    for low, high in ((-0.8, -0.4), (-2.0, 1.2)):
        checked = robot(tmp_path, urdf(one_jaw(low, high))).check()
        assert not any(isinstance(p, Gripper) for p in checked.parts)


#: One jaw and a linkage written in MJCF with round geoms (capsules, cylinders, spheres):
#: the same rules, the gap measured on points sampled on the primitives' surfaces.
MJCF_ONE_JAW = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="hand" pos="0 0 0.1">
      <geom type="box" size="0.02 0.08 0.02" mass="0.3"/>
      <geom type="capsule" fromto="0 -0.01 0.03 0 -0.01 0.11" size="0.005" mass="0.05"/>
      <body name="jaw" pos="0 0.02 0.03">
        <joint name="jaw_joint" axis="1 0 0" range="-0.5 0.3"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.07" size="0.005" mass="0.05"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

MJCF_LINKAGE = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="hand" pos="0 0 0.1">
      <geom type="box" size="0.02 0.08 0.02" mass="0.3"/>
      <body name="left_knuckle" pos="0 0.03 0.025">
        <joint name="leader" axis="-1 0 0" range="0 0.8"/>
        <geom type="cylinder" fromto="0 0 0 0 0 0.03" size="0.004" mass="0.02"/>
        <body name="left_finger" pos="0 0 0.03">
          <joint name="left_finger_joint" axis="1 0 0" range="0 0.8"/>
          <geom type="sphere" pos="0 -0.02 0.02" size="0.008" mass="0.03"/>
        </body>
      </body>
      <body name="right_knuckle" pos="0 -0.03 0.025">
        <joint name="right_knuckle_joint" axis="1 0 0" range="0 0.8"/>
        <geom type="cylinder" fromto="0 0 0 0 0 0.03" size="0.004" mass="0.02"/>
        <body name="right_finger" pos="0 0 0.03">
          <joint name="right_finger_joint" axis="-1 0 0" range="0 0.8"/>
          <geom type="sphere" pos="0 0.02 0.02" size="0.008" mass="0.03"/>
        </body>
      </body>
    </body>
  </worldbody>
  <equality>
    <joint joint1="left_finger_joint" joint2="leader" polycoef="0 1 0 0 0"/>
    <joint joint1="right_knuckle_joint" joint2="leader" polycoef="0 1 0 0 0"/>
    <joint joint1="right_finger_joint" joint2="leader" polycoef="0 1 0 0 0"/>
  </equality>
</mujoco>
"""


def mjcf_robot(tmp_path: Path, text: str) -> type[ra.Agent]:
    path = tmp_path / "robot.xml"
    path.write_text(text)
    return type("GripperTest", (ra.Agent,), {"uid": "gripper_test", "mjcf_path": path})


def test_mjcf_one_jaw_and_linkage_with_round_geoms(tmp_path: Path) -> None:
    cls = mjcf_robot(tmp_path, MJCF_ONE_JAW)
    checked = cls.check()
    (jaw,) = checked.parts
    assert isinstance(jaw, Gripper)
    assert checked.part_joints == {"gripper": ("jaw_joint",)}
    assert jaw.open == (-0.5,) and jaw.closed == (0.3,)
    assert jaw.fingers == (("jaw",), ("hand",))
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0) > 0.95
    assert opening_after(scene, -1.0) < 0.05

    cls = mjcf_robot(tmp_path, MJCF_LINKAGE)
    checked = cls.check()
    (linkage_part,) = checked.parts
    assert isinstance(linkage_part, Gripper)
    assert checked.part_joints["gripper"] == (
        "leader",
        "left_finger_joint",
        "right_knuckle_joint",
        "right_finger_joint",
    )
    assert linkage_part.open == (0.8,) * 4 and linkage_part.closed == (0.0,) * 4
    assert linkage_part.fingers == (("left_finger",), ("right_finger",))
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0, 60) > 0.95
    opened = finger_distance(scene, ("left_finger", "right_finger"))
    assert opening_after(scene, -1.0, 60) < 0.05
    closed = finger_distance(scene, ("left_finger", "right_finger"))
    assert opened - closed == pytest.approx(2 * 0.03 * np.sin(0.8), abs=2e-3)


def test_a_derived_gripper_gets_pads_and_its_motors_force(tmp_path: Path) -> None:
    """The sliding fingers (20 N effort limit in the file, 4 cm stroke, 50 g each): their
    colliding geoms get the built-in Panda's stiff fingertip contact with priority, the
    file's friction kept; the finger drive presses with the whole effort limit a full
    stroke from its target (kp 20 / 0.04 = 500 N/m, where 10 Hz on the finger alone
    gave 0.05 * (2 pi 10)^2 = 197 N/m); a link_materials entry wins over the pads."""
    cls = robot(tmp_path, urdf(slide_fingers(mimic=True)))
    checked = cls.check()
    assert checked.derived_pads == ("left_finger", "right_finger")
    assert checked.derived_gains is not None
    kp, kv, effort = checked.derived_gains["left_joint"]
    assert kp == pytest.approx(20.0 / 0.04) and effort == 20.0
    assert kv == pytest.approx(2.0 * math.sqrt(kp * 0.05), rel=1e-3)  # critical on the 50 g finger
    scene = reset_scene(cls)
    model = scene.model
    for g in range(model.ngeom):
        body = model.body(model.geom_bodyid[g]).name.split("/")[-1]
        if not (model.geom_contype[g] or model.geom_conaffinity[g]) or body == "world":
            continue
        finger = body in ("left_finger", "right_finger")
        assert model.geom_priority[g] == (1 if finger else 0), body
        np.testing.assert_array_equal(model.geom_solref[g], [0.002, 1.0] if finger else [0.02, 1.0])
        np.testing.assert_array_equal(model.geom_friction[g], [1.0, 0.005, 0.0001])
    soft = ra.FrictionMaterial(sliding=0.8)
    declared = type("Declared", (cls,), {"uid": "gripper_declared", "link_materials": {"left_finger": soft}})
    model = reset_scene(declared).model
    left = [g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.endswith("/left_finger")]
    right = [g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.endswith("/right_finger")]
    assert all(model.geom_priority[g] == 0 and model.geom_friction[g, 0] == 0.8 for g in left)
    assert all(model.geom_priority[g] == 1 for g in right)


def test_a_jaw_that_opens_a_little_past_its_widest_is_still_a_jaw(tmp_path: Path) -> None:
    """The one-jaw fixture opened to -0.85 rad: its tip is farthest from the fixed jaw
    near -0.75 rad (65 mm) and 4-5 mm closer at the stop, as the SO-100 file's jaw
    (75.8 mm at 0.9 rad, 72.3 at its 1.1 rad stop). Growing by less than a tenth of the
    open gap between samples it still closes steadily: a gripper, open at the stop (the
    1 mm rule alone rejected it)."""
    checked = robot(tmp_path, urdf(one_jaw(-0.85, 0.3))).check()
    assert [type(p).__name__ for p in checked.parts] == ["Arm", "Gripper"]
    gripper = checked.parts[1]
    assert isinstance(gripper, Gripper) and gripper.open == (-0.85,) and gripper.closed == (0.3,)


def test_a_jaw_without_an_effort_limit_gets_a_stiffer_overdamped_spring(tmp_path: Path) -> None:
    """The one-jaw fixture with ``effort="0"`` on its jaw (the mani-skill wheel's SO-100
    and Koch URDFs): nothing states its force, so its derived drive is a
    ``GRIP_BANDWIDTH_HZ`` spring on the jaw's inertia, not the drives' 10 Hz one
    ((25 / 10)^2 = 6.25 times as stiff), overdamped over ``GRIP_TIME_CONSTANT``, still
    without an effort limit; the arm's joints keep theirs. With the file's 20 N*m the
    hinged jaw keeps its inertia gains. It still opens and closes fully."""
    from robot_agents.actuators.gains import GRIP_BANDWIDTH_HZ, GRIP_TIME_CONSTANT

    limited = robot(tmp_path, urdf(one_jaw())).check().derived_gains
    text = urdf(one_jaw()).replace(
        '<limit lower="-0.5" upper="0.3" effort="20"', '<limit lower="-0.5" upper="0.3" effort="0"'
    )
    free_path = tmp_path / "free"
    free_path.mkdir()
    cls = robot(free_path, text)
    free = cls.check().derived_gains
    assert limited is not None and free is not None
    kp_limited, kv_limited, effort_limited = limited["jaw_joint"]
    kp, kv, effort = free["jaw_joint"]
    assert effort_limited == 20.0 and not math.isfinite(effort)
    assert kv_limited == pytest.approx(2.0 * kp_limited / (2.0 * math.pi * 10.0), rel=1e-6)  # critical at 10 Hz
    assert kp == pytest.approx(kp_limited * (GRIP_BANDWIDTH_HZ / 10.0) ** 2, rel=1e-6)
    assert kv == pytest.approx(kp * GRIP_TIME_CONSTANT)
    for name in ("shoulder", "elbow"):
        assert free[name][:2] == limited[name][:2]
    scene = reset_scene(cls)
    assert opening_after(scene, 1.0) > 0.95
    assert opening_after(scene, -1.0) < 0.05


def test_one_jaw_closing_axis_is_the_way_its_tip_closes(tmp_path: Path) -> None:
    """The table-top layout's closing axis of a one-jaw gripper runs the way the jaw
    carries the tool point as it closes (``layout._jaw_closing``: the hinge's axis
    crossed with the lever), from the moving jaw (the first finger) towards the fixed
    one: -y of the hand for the one-jaw fixture. The layout keeps the axis of the open
    fingers' nearest points unless it points more than 45 deg off that (the Unitree Z1
    file with its meshes decomposed: along the jaw's width)."""
    from robot_agents.envs.tasks.layout import table_top_layout

    cls = type("OneJawLayout", (robot(tmp_path, urdf(one_jaw())),), {"uid": "one_jaw_layout"})
    ra.register_agent(cls, override=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            geometry = table_top_layout(cls).gripper
        assert geometry is not None
        closing = np.array(geometry.closing_axis)
        assert closing @ np.array([0.0, -1.0, 0.0]) > math.cos(math.radians(10.0))
        # the jaw's own closing direction, at the tool point of the scene's default pose
        from robot_agents.envs.tasks.layout import _jaw_closing

        scene = reset_scene(cls)
        agent = scene.agents[0]
        data = mujoco.MjData(scene.model)
        data.qpos[:] = scene.world.qpos[0]
        mujoco.mj_kinematics(scene.model, data)
        point = agent.frame_pose("ee")[0]
        gripper = agent.gripper()
        opened, _ = gripper.positions(1)
        swept = _jaw_closing(agent, gripper, data, ("jaw_joint",), opened, point, "test")
        assert swept is not None
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, point[3:])
        in_tool = rotation.reshape(3, 3).T @ swept
        assert in_tool @ np.array([0.0, -1.0, 0.0]) > math.cos(math.radians(30.0))  # 20 deg: the lever leans
    finally:
        ra.unregister_agent("one_jaw_layout")  # the registry as found: other tests list every robot
