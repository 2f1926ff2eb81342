"""One rule per input check: poses and quaternions, numbers and flags, joint limits and
closed objects are checked by :mod:`robot_agents.validation`, the same way everywhere.
These tests pin the rules that became uniform (a bool or a string is no longer taken
for a number where some entry points took it)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.errors import ConfigError, StateError
from robot_agents.real import RealRobot, SimulatedBus
from robot_agents.robots.panda.panda import PandaHand
from robot_agents.tuning.cycles import drive_cycle_bounds
from robot_agents.validation import (
    check_open,
    check_pose,
    check_quat,
    check_quat_rows,
    check_real,
    check_vector,
    outside_limits,
)
from tests.conftest import make_pendulum_class

BAD_NUMBERS = [
    ((True, 0, 0, 0), "(True, 0, 0, 0)"),
    (("1", 0, 0, 0), "('1', 0, 0, 0)"),
    ([[1, 0], [0, 0]], "[[1, 0], [0, 0]]"),
    (np.array([[1.0, 0.0], [0.0, 0.0]]), "array("),
    ("1000", "'1000'"),
    ((1, 0, 0), "(1, 0, 0)"),
    (5, "5"),
]


@pytest.mark.parametrize(("value", "given"), BAD_NUMBERS)
def test_check_quat_takes_only_four_real_numbers(value: Any, given: str) -> None:
    with pytest.raises(ConfigError) as caught:
        check_quat(value, "Here.quat")
    message = str(caught.value)
    assert message.startswith("Here.quat: expected 4 finite numbers (w, x, y, z) (a quaternion), got ")
    assert given in message


def test_check_quat_and_check_pose_normalize_as_the_declarations_did() -> None:
    rng = np.random.default_rng(0)
    for _ in range(200):
        quat = tuple(float(q) for q in rng.normal(size=4))
        norm = math.sqrt(sum(q * q for q in quat))
        assert check_quat(quat, "q") == tuple(q / norm for q in quat)
        assert check_quat(np.array(quat), "q") == tuple(q / norm for q in quat)
        assert check_pose((0.1, 0.2, 0.3, *quat), "p") == (0.1, 0.2, 0.3, *(q / norm for q in quat))
    assert check_quat((np.float32(2.0), np.int64(0), 0, 0), "q") == (1.0, 0.0, 0.0, 0.0)
    assert check_quat((-2.0, 0, 0, 0), "q") == (-1.0, 0.0, 0.0, 0.0)  # the sign is kept


@pytest.mark.parametrize("quat", [(0, 0, 0, 0), (1e-12, 0, 0, 0)])
def test_a_zero_quaternion_is_refused_the_same_way_everywhere(quat: tuple[float, ...]) -> None:
    with pytest.raises(ConfigError, match=r"q: expected a unit quaternion \(w, x, y, z\), got .* \(zero\)") as caught:
        check_quat(quat, "q")
    assert "non-zero quaternion" in str(caught.value)
    with pytest.raises(ConfigError, match=r"p: expected a unit quaternion \(qw, qx, qy, qz\), got .* \(zero\)"):
        check_pose((0, 0, 0, *quat), "p")
    with pytest.raises(StateError, match=r"w: expected rows with a unit quaternion, got .* in env 1 \(zero\)"):
        check_quat_rows(np.array([[1.0, 0, 0, 0], quat]), "rows", "w")


def test_check_vector_and_check_pose_name_nan() -> None:
    with pytest.raises(ConfigError, match=r"v: expected 3 finite numbers \(x, y, z\) \(m\), got .* \(NaN or inf\)"):
        check_vector((0.0, math.inf, 0.0), 3, "(x, y, z) (m)", "v")
    with pytest.raises(ConfigError, match=r"p: expected 7 finite numbers \(x, y, z, qw, qx, qy, qz\)"):
        check_pose((0, 0, 0, 1, 0, 0, math.nan), "p")


def test_limits_and_closed_objects_have_one_rule() -> None:
    np.testing.assert_array_equal(
        outside_limits([-1.0 - 2e-9, -1.0 - 5e-10, 1.0 + 5e-10, 1.0 + 2e-9], -1.0, 1.0), [True, False, False, True]
    )
    assert not outside_limits(5.0, -1.0, 1.0, margin=10.0)
    check_open(False, "this thing", "T.f")
    with pytest.raises(StateError, match=r"^T\.f: this thing is closed; make a new one\.$"):
        check_open(True, "this thing", "T.f")
    assert check_real(np.float32(0.5), "x", "w", 0.0, unit=" (m)") == 0.5
    with pytest.raises(ConfigError, match=r"w: expected x to be a finite number in \[0.0, inf\] \(m\), got -1"):
        check_real(-1, "x", "w", 0.0, unit=" (m)")


# ---------------------------------------------------------------- the entry points that became stricter
@pytest.mark.parametrize("pose", [(0, 0, 0, True, 0, 0, 0), (0, 0, "0.5", 1, 0, 0, 0)])
def test_robot_poses_refuse_bools_and_strings(pose: tuple[object, ...]) -> None:
    with pytest.raises(ConfigError, match=r"Scene\.robot_poses\[0\]: expected 7 finite numbers"):
        ra.Scene("panda", robot_poses=[pose])  # type: ignore[list-item]
    with pytest.raises(ConfigError, match=r"Scene\.robot_poses: expected 1 poses of 7 finite numbers"):
        ra.Scene("panda", robot_poses=(p for p in [pose]))  # type: ignore[arg-type]


def test_robot_poses_take_an_array_and_normalize_its_quaternions() -> None:
    scene = ra.Scene("panda", robot_poses=np.array([[0.1, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0]]))  # type: ignore[arg-type]
    scene.reset()
    np.testing.assert_array_equal(scene.agents[0].base_pose[0], [0.1, 0, 0, 1, 0, 0, 0])
    scene.close()


def test_attachments_refuse_bools_and_strings() -> None:
    with pytest.raises(ConfigError, match=r"Attachment\(PandaHand\)\.quat: expected 4 finite numbers"):
        ra.Attachment(PandaHand, at="x", quat=(True, 0, 0, 0))
    with pytest.raises(ConfigError, match=r"Attachment\(PandaHand\)\.pos: expected 3 finite numbers \(x, y, z\)"):
        ra.Attachment(PandaHand, at="x", pos=("0.1", 0, 0))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"Attachment\(PandaHand\)\.quat: expected a unit quaternion"):
        ra.Attachment(PandaHand, at="x", quat=(0, 0, 0, 0))
    assert ra.Attachment(PandaHand, at="x", quat=(0, 0, 0, 3)).quat == (0.0, 0.0, 0.0, 1.0)


def test_keyframe_end_effector_and_sensor_quaternions_refuse_bools_and_nesting() -> None:
    with pytest.raises(ConfigError, match=r"Keyframe\.base_quat: expected 4 finite numbers"):
        ra.Keyframe(qpos=(0.0,), base_quat=(True, 0, 0, 0))
    with pytest.raises(ConfigError, match=r"Keyframe\.base_quat: expected 4 finite numbers"):
        ra.Keyframe(qpos=(0.0,), base_quat=np.eye(2))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"EndEffector 'tool'\.quat: expected 4 finite numbers"):
        ra.EndEffector("tool", quat=(1, 0, 0, False))
    with pytest.raises(ConfigError, match=r"CameraConfig 'cam'\.quat: expected 4 finite numbers"):
        ra.CameraConfig("cam", quat=[[1, 0], [0, 0]])  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"CameraConfig 'cam'\.quat: expected 4 finite numbers"):
        ra.CameraConfig("cam", quat=(True, 0, 0, 0))


def test_declared_numbers_refuse_bools() -> None:
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.sliding: expected a number >= 0, got True"):
        ra.FrictionMaterial(sliding=True)
    with pytest.raises(ConfigError, match=r"CompilerSettings\.boundmass: expected a finite number >= 0, got True"):
        ra.CompilerSettings(boundmass=True)
    with pytest.raises(ConfigError, match=r"max_delta: expected a positive number \(rad or m\), got True"):
        ra.Arm(name="arm", joints=".*", max_delta=True)
    with pytest.raises(ConfigError, match=r"PowerGrasp\.cube_edge: expected a positive length \(m\), got True"):
        ra.PowerGrasp("base_link", (0.04, 0.0, 0.0), True, (1.0, 0.0, 0.0))
    with pytest.raises(ConfigError, match=r"drive_cycle_bounds: expected samples to be a whole number >= 0, got True"):
        drive_cycle_bounds("panda", samples=True)


def test_an_end_effector_index_is_not_a_bool() -> None:
    scene = ra.Scene("panda")
    scene.reset()
    agent = scene.agents[0]
    assert agent.ee_transform(np.int64(0)).shape == (1, 4, 4)
    with pytest.raises(ConfigError, match=r"expected an end-effector index in \[0, 1\), got False"):
        agent.ee_transform(False)  # was taken as index 0
    scene.close()


def test_mount_pose_messages_keep_their_form(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, uid="test_zero_mount", mount_pose=(0, 0, 0, 0, 0, 0, 0))
    with pytest.raises(ConfigError) as caught:
        cls.check()
    assert str(caught.value).startswith(
        "Pendulum.mount_pose: expected a unit quaternion (qw, qx, qy, qz), got (0.0, 0.0, 0.0, 0.0) (zero)."
    )


# ---------------------------------------------------------------- the entry points that became looser
def test_numpy_scalars_are_taken_where_python_numbers_were() -> None:
    env = ra.RobotEnv(robot_uids="panda", robot_init_qpos_noise=np.float32(0.25), raise_on_instability=np.True_)  # type: ignore[arg-type]
    assert env.robot_init_qpos_noise == 0.25 and type(env.robot_init_qpos_noise) is float
    assert env.raise_on_instability is True
    env.close()
    with pytest.raises(ConfigError, match=r"robot_init_qpos_noise to be a finite number in \[0.0, inf\] \(rad or m\)"):
        ra.make_env("Empty-v1", robot_uids="panda", robot_init_qpos_noise=True)
    with pytest.raises(ConfigError, match=r"expected raise_on_instability to be a bool \(True or False\), got 1"):
        ra.make_env("Empty-v1", robot_uids="panda", raise_on_instability=1)
    robot = RealRobot("widowx250s", SimulatedBus("widowx250s"), control_mode="pd_joint_delta_pos")
    assert robot.move_to("sleep", steps=np.int64(5)) >= 0.0
    with pytest.raises(ConfigError, match=r"RealRobot\.move_to: expected steps to be a whole number >= 1, got True"):
        robot.move_to("sleep", steps=True)
    robot.close()


@pytest.mark.parametrize(
    ("keyword", "value", "message"),
    [
        ("max_episode_steps", 0, "expected max_episode_steps >= 1, got 0"),
        ("max_episode_steps", 2.5, "expected max_episode_steps to be an int or None, got 2.5"),
        ("raise_on_instability", "yes", "expected raise_on_instability to be a bool"),
    ],
)
def test_bad_env_arguments_are_refused_before_the_scene_is_built(
    keyword: str, value: object, message: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Checked first: a bad value cost the whole build (models compiled, renderers made)."""

    def no_scene(*args: object, **kwargs: object) -> None:
        raise AssertionError("the scene was built before the arguments were checked")

    monkeypatch.setattr("robot_agents.envs.base_env.Scene", no_scene)
    with pytest.raises(ConfigError, match=message):
        ra.make_env("PickCube-v1", robot_uids="panda", **{keyword: value})


@pytest.mark.parametrize("value", [True, (1.0, True), "10", (), [[1.0, 2.0]], np.ones((2, 2))])
def test_per_joint_values_are_numbers_or_tuples_of_numbers(value: Any) -> None:
    """Drive and mode gains (``PerJoint``) take one number or a flat sequence of numbers:
    a bool is not a gain (it was taken as 1), nor a string, an empty or a nested list."""
    with pytest.raises(ConfigError, match=r"PDActuator\.stiffness: expected a number or a tuple of numbers"):
        ra.PDActuator(joints="j", stiffness=value)
    with pytest.raises(ConfigError, match=r"PDJointPosConfig\.damping: expected a number or a tuple of numbers"):
        ra.PDJointPosConfig(joint_names=("j",), damping=value)


def test_per_joint_values_take_numpy_numbers_and_arrays() -> None:
    actuator = ra.PDActuator(joints="j", stiffness=np.array([1.0, 2.0]), damping=np.float32(3.0))
    assert actuator.damping == 3.0
    with pytest.raises(ConfigError, match=r"PDActuator\.armature: expected finite values >= 0, got -1"):
        ra.PDActuator(joints="j", stiffness=1.0, armature=-1)


def test_contact_softness_of_a_material_is_checked() -> None:
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solref: expected 2 finite numbers"):
        ra.FrictionMaterial(solref=(0.01,))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solref: expected \(timeconst s, dampratio\) both > 0"):
        ra.FrictionMaterial(solref=(-100.0, 1.0))
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solimp: expected 3 finite numbers"):
        ra.FrictionMaterial(solimp=(0.9, 0.95, 0.001, 0.5))
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solimp: expected 0 < d_min, d_max < 1"):
        ra.FrictionMaterial(solimp=(0.9, 1.0, 0.001))
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solimp: expected 0 < d_min, d_max < 1"):
        ra.FrictionMaterial(solimp=(0.9, 0.95, 0.001, 0.5, 0.5))
    with pytest.raises(ConfigError, match=r"FrictionMaterial\.solref: expected 2 finite numbers"):
        ra.FrictionMaterial(solref=(True, 1.0))  # type: ignore[arg-type]
    direct = ra.FrictionMaterial(solref=[-5000, -50], solimp=np.array([0.9, 0.99, 0.002, 0.4, 3]))  # type: ignore[arg-type]
    assert direct.solref == (-5000.0, -50.0) and direct.solimp == (0.9, 0.99, 0.002, 0.4, 3.0)


BALL_ARM_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base" pos="0 0 1">
  <geom type="box" size="0.05 0.05 0.05" mass="1"/>
  <body name="arm"><joint name="shoulder" type="ball"/>
    <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="1"/>
    <body name="fore" pos="0 0 -0.3"><joint name="elbow" axis="0 1 0" range="-2 2"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/></body></body>
</body></worldbody></mujoco>"""


def test_declarations_of_the_wrong_type_or_value_fail_at_the_class_check(tmp_path: Path) -> None:
    """Each a ConfigError naming the declaration, at construction or at ``check()``, not
    a TypeError from inside, nor MuJoCo's compiler later."""
    from robot_agents.robots.panda.panda import Panda

    with pytest.raises(ConfigError, match=r"PDActuator\.joints: expected a joint name pattern .* got 3"):
        ra.PDActuator(joints=3, stiffness=1.0)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"PDActuator\.effort_limit: expected values > 0"):
        ra.PDActuator(joints="a", stiffness=1.0, effort_limit=0.0)
    with pytest.raises(ConfigError, match=r"VelocityActuator\.velocity_limit: expected values > 0"):
        ra.VelocityActuator(joints="a", damping=1.0, velocity_limit=(1.0, 0.0))
    cases: list[tuple[dict[str, Any], str]] = [
        ({"control_modes": {"m": 3}}, r"X\.control_modes\['m'\]: expected a ControllerConfig or a non-empty dict"),
        ({"control_modes": {"m": {}}}, r"X\.control_modes\['m'\]: expected a ControllerConfig or a non-empty dict"),
        ({"control_modes": [1]}, r"X\.control_modes: expected a dict"),
        ({"default_control_mode": 3}, r"X\.default_control_mode: expected a mode name \(str\) or None, got 3"),
        ({"keyframes": {"": ra.Keyframe(qpos={"panda_joint1": 0.0})}}, r"X\.keyframes: expected non-empty names"),
    ]
    for attrs, message in cases:
        with pytest.raises(ConfigError, match=message):
            type("X", (Panda,), attrs).check()
    path = tmp_path / "ball_arm.xml"
    path.write_text(BALL_ARM_MJCF)
    ball_driven = make_pendulum_class(
        path, uid="ball_driven", actuators=(ra.PDActuator(joints="shoulder|elbow", stiffness=10.0),), parts=()
    )
    with pytest.raises(ConfigError, match=r"claims joint 'shoulder', a ball joint: a drive needs a hinge or a slide"):
        ball_driven.check()


ARM3_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base">
  <geom type="box" size="0.05 0.05 0.05"/>
  <body name="link1" pos="0 0 0.1"><joint name="j1" axis="0 0 1" range="-3 3"/>
    <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.03"/>
    <body name="link2" pos="0 0 0.3"><joint name="j2" axis="0 1 0" range="-2 2"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="flange" pos="0.3 0 0"/></body></body>
</body></worldbody></mujoco>"""


def test_mode_settings_fail_when_declared_not_when_the_mode_is_first_used(tmp_path: Path) -> None:
    """Task-space and joint-mode settings are checked when they are made or when the
    class is checked (``register_agent``), not at a later ``set_control_mode``."""
    box = ra.WorkspaceBox((-1, -1, 0), (1, 1, 1.5))
    with pytest.raises(ConfigError, match=r"TaskSpace\.max_translation: expected a finite number > 0"):
        ra.TaskSpace(position_bounds=box, max_translation=-0.1)
    with pytest.raises(ConfigError, match=r"JointGroup: expected max_delta to be a finite number"):
        ra.JointGroup(joint_names=("a",), max_delta=-1.0)
    with pytest.raises(ConfigError, match=r"JointGroup\.joint_names: expected a non-empty tuple"):
        ra.JointGroup(joint_names=())
    with pytest.raises(ConfigError, match=r"expected lower <= upper for every joint"):
        ra.PDJointPosConfig(joint_names=("a", "b"), lower=1.0, upper=-1.0, use_delta=True)
    with pytest.raises(ConfigError, match=r"lower: expected a number or 2 \(one per joint\)"):
        ra.PDJointPosConfig(joint_names=("a", "b"), lower=(-1, -1, -1), upper=1.0, use_delta=True)
    with pytest.raises(ConfigError, match=r"expected vel_lower <= vel_upper"):
        ra.PDJointPosVelConfig(joint_names=("a",), vel_lower=1.0, vel_upper=0.0)
    path = tmp_path / "arm.xml"
    path.write_text(ARM3_MJCF)

    def arm(task_space: ra.TaskSpace, *end_effectors: ra.EndEffector) -> type[ra.Agent]:
        part = ra.Arm(name="arm", joints="j.", end_effectors=end_effectors, task_space=task_space)
        return type("Arm3", (ra.Agent,), {"uid": "", "mjcf_path": path, "parts": (part,)})

    misnamed = arm(ra.TaskSpace(position_bounds=box, end_effector="tpc"), ra.EndEffector("flange", name="tcp"))
    with pytest.raises(ra.UnknownNameError, match=r"task_space: unknown end effector 'tpc'\. Did you mean 'tcp'"):
        misnamed.check()
    with pytest.raises(ConfigError, match=r"end-effector modes need an end effector"):
        arm(ra.TaskSpace(position_bounds=box)).check()


def test_a_piece_whose_names_clash_with_the_robots_is_refused_with_the_way_out(tmp_path: Path) -> None:
    """MuJoCo's compiler says only "repeated name 'base' in body"; the attachment names
    the piece, the clash and the prefix that resolves it."""
    path = tmp_path / "arm.xml"
    path.write_text(ARM3_MJCF)
    gripper = ra.get_piece("robotiq_2f85")  # has a body named 'base', as the arm does

    def mounted(prefix: str) -> type[ra.Agent]:
        attachment = ra.Attachment(gripper, at="flange", prefix=prefix)
        return type("ArmWithGripper", (ra.Agent,), {"uid": "", "mjcf_path": path, "attachments": (attachment,)})

    with pytest.raises(
        ConfigError,
        match=r"Attachment\(Robotiq2F85, at='flange'\): the piece's names clash with the robot's: body 'base'",
    ):
        mounted("").check()
    assert "g_base" in mounted("g_").check().index.model.body("g_base").name


def test_two_end_effectors_of_one_name_are_refused_and_close_names_rank_case_first(tmp_path: Path) -> None:
    from robot_agents.errors import close_names

    path = tmp_path / "arm.xml"
    path.write_text(ARM3_MJCF)
    twice = ra.Arm(
        name="arm", joints="j.", end_effectors=(ra.EndEffector("flange", name="t"), ra.EndEffector("link2", name="t"))
    )
    cls = type("TwoTips", (ra.Agent,), {"uid": "", "mjcf_path": path, "parts": (twice,)})
    with pytest.raises(ConfigError, match="two end effectors are named 't'"):
        cls.check()
    # only the case differs: that name first (it came second, after a longer name holding it)
    assert close_names("PANDA", ["floating_panda_gripper", "panda", "panda_stick"])[0] == "panda"


def test_a_base_on_joints_other_than_two_slides_and_a_hinge_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "arm.xml"
    path.write_text(ARM3_MJCF)
    hinges = type(
        "OnHinges", (ra.Agent,), {"uid": "", "mjcf_path": path, "parts": (ra.Base(name="base", joints="j."),)}
    )
    with pytest.raises(ConfigError, match=r"a Base moves on an x slide, a y slide and a yaw hinge.*j1 \(hinge\)"):
        hinges.check()
