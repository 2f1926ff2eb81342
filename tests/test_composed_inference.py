"""A user's arm file with a built-in piece mounted on its flange and nothing else
declared: the arm's own joints get what the file alone would get (derived drives, an
arm part with a measured task space), the piece brings its own drives and parts, and the
arm's end effector is the piece's ``tcp`` (its grasp point)."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import mujoco
import pytest

import robot_agents as ra
from robot_agents.agent.declaration import _prefix_part
from robot_agents.controllers.rules import EE_MODES
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.robots.panda.panda import PANDA_GRIPPER, PandaHand, PandaStickTool, RealSenseD415
from robot_agents.robots.robotiq.robotiq import ROBOTIQ_GRIPPER, Robotiq2F85
from tests.test_derived_task_space import JOINTS, arm_urdf
from tests.test_measured_task_space import composed
from tests.test_scripted_solvers import load_solver

ARM_JOINTS = tuple(name for name, *_ in JOINTS)
FLANGE = f"{ARM_JOINTS[-1]}_link"


def mounted(path: Path, piece: type[ra.Agent], prefix: str = "gripper_", **attrs: object) -> type[ra.Agent]:
    """The arm file at ``path`` with ``piece`` 6 cm out of its flange, and ``attrs``."""
    attachment = ra.Attachment(piece, at=FLANGE, prefix=prefix, pos=(0.0, 0.0, 0.06))
    uid = f"arm_with_{piece.__name__.lower()}"
    return type(
        f"ArmWith{piece.__name__}", (ra.Agent,), {"uid": uid, "urdf_path": path, "attachments": (attachment,), **attrs}
    )


@pytest.fixture
def arm_file(tmp_path: Path) -> Path:
    """The written six-joint arm: no actuators, no effort limits, as many files come."""
    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf(6, effort=0.0))
    return path


def successes(cls: type[ra.Agent], task: str, seeds: int = 20) -> int:
    ra.register_agent(cls, override=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return int(load_solver().success_rate(task, cls.uid, seeds)[0])
    finally:
        ra.unregister_agent(cls.uid)  # (the solver suites list every registered robot)


def test_the_arm_is_inferred_and_the_piece_brings_the_gripper(arm_file: Path) -> None:
    checked = mounted(arm_file, Robotiq2F85).check()
    arm, gripper = checked.parts
    assert isinstance(arm, ra.Arm) and checked.part_joints["arm"] == ARM_JOINTS
    assert [ee.link for ee in arm.end_effectors] == ["gripper_robotiq_tcp"]
    assert gripper == _prefix_part(ROBOTIQ_GRIPPER, "gripper_")  # the piece's declaration, renamed
    assert set(EE_MODES) <= set(checked.modes) and checked.default_mode == "pd_joint_delta_pos"
    sources = {d.joint: d.source for d in checked.drives}
    assert all(sources[j] == "derived gains (see robot_agents.actuators.gains)" for j in ARM_JOINTS)
    # the piece's drives as it declares them; its linkage followers stay passive
    on_piece = [d for d in checked.drives if d.joint.startswith("gripper_")]
    assert [dataclasses.replace(d, source="") for d in on_piece] == [
        dataclasses.replace(d, joint=f"gripper_{d.joint}", source="") for d in Robotiq2F85.check().drives
    ]


def test_it_equals_the_composition_declared_by_hand(arm_file: Path, tmp_path: Path) -> None:
    """With the same stated servos, the inferred robot gets the arm, task space and
    drives of the robot that declares its arm with MeasuredTaskSpace()."""
    servos = (ra.DerivedActuators(effort_limit=50.0, armature=0.02),)
    inferred = mounted(arm_file, Robotiq2F85, actuators=servos).check()
    declared = composed(tmp_path, ra.MeasuredTaskSpace()).check()
    assert inferred.drives == declared.drives
    (arm, _), (by_hand, _) = inferred.parts, declared.parts
    assert isinstance(arm, ra.Arm) and isinstance(by_hand, ra.Arm)
    assert arm.task_space == by_hand.task_space
    assert arm.end_effectors[0].link == by_hand.end_effectors[0].link
    assert inferred.part_joints["arm"] == declared.part_joints["arm"]


def test_the_inferred_composition_picks(arm_file: Path) -> None:
    """PickCube with the scripted solver: the 2F-85 (19 of 20 measured) and the Franka
    Hand (20 of 20) on the arm, drives derived, nothing stated."""
    assert successes(mounted(arm_file, Robotiq2F85), "PickCube-v1") >= 18
    hand = mounted(arm_file, PandaHand, prefix="")
    checked = hand.check()
    assert [p.name for p in checked.parts] == ["arm", "gripper"] and checked.parts[1] == PANDA_GRIPPER
    assert checked.parts[0].end_effectors[0].link == "panda_hand_tcp"  # type: ignore[attr-defined]
    assert successes(hand, "PickCube-v1") >= 18


def test_a_tool_without_fingers_and_a_camera(arm_file: Path) -> None:
    """A stick's tcp is the arm's end effector; a camera mount declares none, and the arm
    ends at its own flange, not inside the mount."""
    stick = mounted(arm_file, PandaStickTool).check()
    assert [(p.name, p.end_effectors[0].link) for p in stick.parts] == [("arm", "gripper_panda_stick_tcp")]  # type: ignore[attr-defined]
    assert set(EE_MODES) <= set(stick.modes)
    camera = mounted(arm_file, RealSenseD415, prefix="camera_").check()
    assert [(p.name, p.end_effectors[0].link) for p in camera.parts] == [("arm", FLANGE)]  # type: ignore[attr-defined]


def test_a_file_that_drives_its_joints_keeps_its_actuators(arm_file: Path, tmp_path: Path) -> None:
    """The file's own actuators are adopted and no drive is derived beside them, as for
    the file alone: the joints it leaves undriven stay so."""
    spec = mujoco.MjSpec.from_file(str(arm_file))
    for joint in ARM_JOINTS:
        spec.add_actuator(name=joint, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT).set_to_position(
            kp=300.0, kv=30.0
        )
    path = tmp_path / "arm_with_actuators.xml"
    path.write_text(spec.to_xml())
    cls = type(
        "FileDriven", (mounted(arm_file, Robotiq2F85),), {"uid": "file_driven", "urdf_path": None, "mjcf_path": path}
    )
    sources = {d.joint: d.source for d in cls.check().drives}
    assert [sources[j] for j in ARM_JOINTS] == [f"the model file (actuator {j!r})" for j in ARM_JOINTS]


def test_a_piece_tcp_must_name_a_body_or_site(arm_file: Path) -> None:
    typo = type("Typo2F85", (Robotiq2F85,), {"tcp": "robotiq_tpc"})
    with pytest.raises(UnknownNameError, match=r"Typo2F85\.tcp.*robotiq_tpc.*robotiq_tcp"):
        mounted(arm_file, typo).check()
    wrong = type("Wrong2F85", (Robotiq2F85,), {"tcp": 3})
    with pytest.raises(ConfigError, match=r"Wrong2F85\.tcp: expected a body or site name, or None, got 3"):
        wrong.validate_definition()


GRIPPER_URDF = """<robot name="grip">
  <link name="palm"><inertial><mass value="0.3"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/>
    </inertial><collision><geometry><box size="0.04 0.1 0.02"/></geometry></collision></link>
  <link name="left"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/>
    </inertial><collision><origin xyz="0 0 0.02"/><geometry><box size="0.01 0.01 0.04"/></geometry></collision></link>
  <link name="right"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/>
    </inertial><collision><origin xyz="0 0 0.02"/><geometry><box size="0.01 0.01 0.04"/></geometry></collision></link>
  <joint name="fl" type="prismatic"><parent link="palm"/><child link="left"/><origin xyz="0 0.02 0.01"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.03" effort="20" velocity="0.1"/></joint>
  <joint name="fr" type="prismatic"><parent link="palm"/><child link="right"/><origin xyz="0 -0.02 0.01"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="0.03" effort="20" velocity="0.1"/><mimic joint="fl"/></joint>
</robot>"""


def test_a_two_line_gripper_piece_brings_the_gripper_it_infers(arm_file: Path, tmp_path: Path) -> None:
    # a user's own gripper file mounted as a two-line piece: its fingers got a drive and
    # no part, so no control mode commanded them (the action was the arm's alone)
    from robot_agents.robot_source import robot_from_file

    path = tmp_path / "grip.urdf"
    path.write_text(GRIPPER_URDF)
    piece = robot_from_file(path)
    assert piece.check().part_joints == {"gripper": ("fl", "fr")}
    checked = mounted(arm_file, piece, prefix="g/").check()
    assert checked.part_joints == {"arm": ARM_JOINTS, "g_gripper": ("g/fl", "g/fr")}
    gripper = checked.parts[1]
    assert isinstance(gripper, ra.Gripper) and gripper.finger_links == (("g/left",), ("g/right",))
    scene = ra.Scene(mounted(arm_file, piece, prefix="g/"))
    scene.reset()
    agent = scene.agents[0]
    assert agent.action_space.shape == (1, len(ARM_JOINTS) + 1)
    for command, width in ((1.0, 0.03), (-1.0, 0.0)):
        for _ in range(30):
            agent.set_action([0.0] * len(ARM_JOINTS) + [command])
            scene.step()
        assert agent.qpos[0, -2:] == pytest.approx([width, width], abs=1e-3)


def test_a_two_line_arm_piece_brings_no_parts(arm_file: Path, tmp_path: Path) -> None:
    # a second arm file mounted as a piece infers an arm whose end effector is "ee" as
    # the robot's own: it brings nothing, as before (a bimanual robot declares its parts),
    # and its driven joints, which no mode commands, are named in a note (silent before)
    from robot_agents.robot_source import robot_from_file

    with pytest.warns(RuntimeWarning, match=r"joints \['right/yaw', .* have drives and are in none of the robot's"):
        checked = mounted(arm_file, robot_from_file(arm_file), prefix="right/").check()
    assert checked.part_joints == {"arm": ARM_JOINTS}


GRIPPER_MJCF = """<mujoco model="grip"><compiler angle="radian"/><worldbody>
  <body name="palm"><geom type="box" size="0.02 0.05 0.01" mass="0.3"/>
    <body name="left" pos="0 0.02 0.01"><joint name="fl" type="slide" axis="0 1 0" range="0 0.03"/>
      <geom type="box" size="0.005 0.005 0.02" pos="0 0 0.02" mass="0.05"/></body>
    <body name="right" pos="0 -0.02 0.01"><joint name="fr" type="slide" axis="0 -1 0" range="0 0.03"/>
      <geom type="box" size="0.005 0.005 0.02" pos="0 0 0.02" mass="0.05"/></body>
  </body></worldbody>
  <equality><joint joint1="fr" joint2="fl"/></equality>
  <actuator><position name="grip" joint="fl" kp="500" kv="10" ctrlrange="0 0.03" forcerange="-20 20"/></actuator>
</mujoco>"""


def test_a_piece_file_driving_its_joints_leaves_the_arm_its_derived_drives(arm_file: Path, tmp_path: Path) -> None:
    # the piece's own <actuator> counted as the robot's file driving its joints: the arm
    # got no drives at all ("no control mode"), where a piece declaring its drives (the
    # built-in ones) leaves it derived drives
    from robot_agents.robot_source import robot_from_file

    path = tmp_path / "grip.xml"
    path.write_text(GRIPPER_MJCF)
    checked = mounted(arm_file, robot_from_file(path), prefix="g/").check()
    sources = {d.joint: d.source for d in checked.drives}
    assert all(sources[j].startswith("derived gains") for j in ARM_JOINTS)
    assert sources["g/fl"] == "the model file (actuator 'g/grip')"
    assert checked.part_joints == {"arm": ARM_JOINTS, "g_gripper": ("g/fl", "g/fr")}


@pytest.mark.parametrize(
    ("fingers", "links", "joints"),
    [
        ("mimic", ["left_finger", "right_finger"], ["left_joint", "right_joint"]),
        ("two", ["left_finger", "right_finger"], ["left_joint", "right_joint"]),
        ("linkage", ["left_finger", "right_finger"], ["left_outer_joint", "left_inner_joint"]),
        ("one_jaw", ["moving_jaw", "hand", "fixed_jaw"], ["jaw_joint"]),
    ],
)
def test_a_gripper_mounted_beside_the_files_own_fingers_holds_the_end_effector(
    tmp_path: Path, fingers: str, links: list[str], joints: list[str]
) -> None:
    """``--gripper franka_hand --at hand`` on an arm file with a gripper of its own on
    ``hand``: its end effector sat on a finger (``left_finger``, ``moving_jaw``), and
    the finger's joint was the arm's last."""
    from robot_agents.checks import check_random_actions
    from robot_agents.robot_source import robot_from_file
    from tests.test_derived_gripper import linkage, one_jaw, slide_fingers, urdf

    text = {"mimic": slide_fingers(True), "two": slide_fingers(False), "linkage": linkage(), "one_jaw": one_jaw()}
    path = tmp_path / "fingered.urdf"
    path.write_text(urdf(text[fingers]))
    cls = robot_from_file(path, gripper="franka_hand", at="hand")
    with warnings.catch_warnings(record=True) as notes:
        warnings.simplefilter("always")
        checked = cls.check()
    texts = [str(n.message) for n in notes]
    named = f"own gripper on 'hand' (fingers {links}, joints [{', '.join(map(repr, joints))}"  # (then its followers)
    assert any(named in t and "PandaHand ('franka_hand/')" in t for t in texts), texts
    assert not any("are in none of the robot's inferred parts" in t for t in texts)  # one note, not two
    arm, gripper = checked.parts
    assert isinstance(arm, ra.Arm) and checked.part_joints["arm"] == ("shoulder", "elbow")
    assert [ee.link for ee in arm.end_effectors] == ["franka_hand/panda_hand_tcp"]
    assert isinstance(gripper, ra.Gripper)
    assert all(j.startswith("franka_hand/") for j in checked.part_joints[gripper.name])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        result = check_random_actions(cls, seconds=1.0)  # the file's fingers held, the piece's moving
    assert result.passed, result.detail
    # alone, the file's fingers are its gripper, as before
    alone = robot_from_file(path).check()
    assert [type(p).__name__ for p in alone.parts] == ["Arm", "Gripper"]
    assert alone.part_joints["arm"] == ("shoulder", "elbow")
