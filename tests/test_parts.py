"""Parts and their roles: grasp detection for any number of fingers, mode tables
generated from parts, end-effector commands in a frame that moves (a torso)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.parts import grasped

# A lifting torso (slide) carrying a 3-joint arm with a tool site.
TORSO_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 0.1">
      <geom type="box" size="0.15 0.15 0.1" mass="10"/>
      <body name="torso_link" pos="0 0 0.1">
        <joint name="lift" type="slide" axis="0 0 1" range="0 0.5"/>
        <geom type="box" size="0.05 0.05 0.2" pos="0 0 0.2" mass="2"/>
        <body name="l1" pos="0 0 0.45">
          <joint name="j1" axis="0 0 1" range="-3 3"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
          <body name="l2" pos="0.3 0 0">
            <joint name="j2" axis="0 1 0" range="-2 2"/>
            <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.02" mass="0.3"/>
            <body name="l3" pos="0.25 0 0">
              <joint name="j3" axis="0 1 0" range="-2 2"/>
              <geom type="capsule" fromto="0 0 0 0.15 0 0" size="0.015" mass="0.2"/>
              <site name="tool" pos="0.15 0 0"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def torso_robot(path: Path, command_frame: str | None) -> type[ra.Agent]:
    return type(
        "TorsoArm",
        (ra.Agent,),
        {
            "uid": "torso_arm",
            "mjcf_path": path,
            "actuators": (
                ra.PDActuator(joints="lift", stiffness=5000.0, damping=500.0),
                ra.PDActuator(joints="j[1-3]", stiffness=300.0, damping=30.0),
            ),
            "parts": (
                ra.Arm(
                    name="arm",
                    joints="j[1-3]",
                    end_effectors=(ra.EndEffector("tool", command_frame=command_frame),),
                    task_space=ra.TaskSpace(
                        position_bounds=ra.WorkspaceBox(lower=(-1, -1, -1), upper=(1, 1, 1)),
                        modes=("pd_ee_target_delta_pos",),
                    ),
                ),
                ra.Torso(name="torso", joints="lift", max_delta=0.05),
            ),
            "keyframes": {"home": ra.Keyframe(qpos={"lift": 0.1, "j2": 0.3, "j3": 0.6})},
            "default_control_mode": "pd_ee_target_delta_pos",
        },
    )


@pytest.fixture
def torso_file(tmp_path: Path) -> Path:
    path = tmp_path / "torso.xml"
    path.write_text(TORSO_MJCF)
    return path


def lift(cls: type[ra.Agent]) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Raise the torso with a zero arm command: how far it rose (m), and the tool
    positions before and after, in the world and in the torso frame."""
    scene = ra.Scene(cls)
    scene.reset()
    agent = scene.agents[0]
    world0, torso0 = agent.tcp_pose[0, :3], agent.frame_pose("tool", relative_to="torso_link")[0, :3]
    for _ in range(12):
        agent.set_action([0.0, 0.0, 0.0, 1.0])  # arm: hold the target; torso: +0.05 m on the measured
        scene.step()
    for _ in range(20):
        agent.set_action([0.0, 0.0, 0.0, 0.0])
        scene.step()
    rise = float(agent.qpos[0, 0] - 0.1)
    assert rise > 0.2
    return rise, world0, torso0, agent.tcp_pose[0, :3], agent.frame_pose("tool", relative_to="torso_link")[0, :3]


def test_commands_in_a_moving_torso_frame_ride_with_it(torso_file: Path) -> None:
    rise, world0, torso0, world1, torso1 = lift(torso_robot(torso_file, command_frame="torso_link"))
    np.testing.assert_allclose(torso1, torso0, atol=2e-3)  # held in the torso frame ...
    assert world1[2] - world0[2] == pytest.approx(rise, abs=3e-3)  # ... so it rose with the torso
    # Commanded in the fixed root frame the same zero command keeps the target in the
    # world: the arm reaches down against the lift (until the target leaves its reach).
    rise, world0, torso0, world1, torso1 = lift(torso_robot(torso_file, command_frame=None))
    assert world1[2] - world0[2] < 0.5 * rise
    assert torso0[2] - torso1[2] > 0.5 * rise


def test_modes_generated_from_parts() -> None:
    panda = ra.get_agent("panda")
    modes = panda.modes()
    assert list(modes) == [
        "pd_joint_pos",
        "pd_joint_delta_pos",
        "pd_joint_target_delta_pos",
        "pd_joint_vel",
        "pd_joint_pos_vel",
        "pd_joint_delta_pos_vel",
        *ra.controllers.EE_MODES,
    ]
    for table in modes.values():
        assert list(table) == ["arm", "gripper"]  # type: ignore[arg-type]
        gripper = table["gripper"]  # type: ignore[index]
        # -1 squeezes 1 cm past closed, +1 opens to 0.04 m; both fingers from one action.
        assert (gripper.lower, gripper.upper, gripper.joint_names) == (
            -0.01,
            0.04,
            ("panda_finger_joint1", "panda_finger_joint2"),
        )
    # Velocity mode relaxes the servos' stiffness (an explicit override) and uses the datasheet speeds.
    velocity = modes["pd_joint_vel"]["arm"]  # type: ignore[index]
    assert velocity.stiffness == 0.0 and velocity.upper == (2.175,) * 4 + (2.61,) * 3
    floating = ra.get_agent("floating_panda_gripper").modes()
    assert [m for m in floating if m.startswith("pd_ee")] == ["pd_ee_delta_pose", "pd_ee_pose"]


def test_grasp_needs_two_opposing_fingers() -> None:
    def forces(*vectors: tuple[float, float, float]) -> np.ndarray:
        return np.array([vectors], dtype=np.float64)

    squeeze = forces((0, -5, 0), (0, 5, 0))
    assert grasped(squeeze, 0.5, 85.0)[0]
    assert not grasped(forces((0, -5, 0), (0, -5, 0)), 0.5, 85.0)[0]  # both push one way
    assert not grasped(forces((0, -5, 0), (0, 0, 0)), 0.5, 85.0)[0]  # one finger only
    assert not grasped(forces((0, -0.4, 0), (0, 0.4, 0)), 0.5, 85.0)[0]  # too light
    # A three-finger hand: thumb against two fingers 120 deg apart.
    c, s = math.cos(math.radians(120)), math.sin(math.radians(120))
    assert grasped(forces((3, 0, 0), (3 * c, 3 * s, 0), (3 * c, -3 * s, 0)), 0.5, 85.0)[0]
    # Forces 80 deg apart do not oppose (the limit is 180 - 85 = 95 deg).
    a = math.radians(80)
    assert not grasped(forces((1, 0, 0), (math.cos(a), math.sin(a), 0)), 0.5, 85.0)[0]
    batch = np.concatenate([squeeze, forces((0, -5, 0), (0, -5, 0))])
    np.testing.assert_array_equal(grasped(batch, 0.5, 85.0), [True, False])


def test_gripper_opening_and_part_errors() -> None:
    scene = ra.Scene("panda")
    scene.reset(keyframes="closed_rest")
    agent = scene.agents[0]
    np.testing.assert_allclose(agent.gripper_opening(), [0.0], atol=1e-12)
    scene.reset(keyframes="rest")
    np.testing.assert_allclose(agent.gripper_opening(), [1.0], atol=1e-12)
    with pytest.raises(ra.UnknownNameError, match="Did you mean 'gripper'"):
        agent.gripper("griper")
    with pytest.raises(ra.ConfigError, match="at least two fingers"):
        ra.Gripper(name="g", joints="a", open=1.0, closed=0.0, fingers=("one",))
    with pytest.raises(ra.ConfigError, match="part name without '/'"):
        ra.Arm(name="a/b", joints="x")


def test_gripper_positions_take_one_value_or_one_per_joint() -> None:
    """``open`` / ``closed``: a scalar or one value per matched joint, checked against
    the model (the Panda's fingers are two joints)."""
    from robot_agents.robots.panda.panda import PANDA_GRIPPER, PandaHand

    class ThreeValues(PandaHand):
        parts = (dataclasses.replace(PANDA_GRIPPER, open=(0.04, 0.04, 0.04)),)

    with pytest.raises(ra.ConfigError, match=r"'gripper'\.open: expected 1 or 2 values.*panda_finger_joint1"):
        ThreeValues.check()

    class TwoValues(PandaHand):
        parts = (dataclasses.replace(PANDA_GRIPPER, closed=(0.0, 0.0)),)

    assert TwoValues.check().parts[0].closed == (0.0, 0.0)

    class PastTheStop(PandaHand):  # the fingers' range is [0, 0.04] m
        parts = (dataclasses.replace(PANDA_GRIPPER, open=0.08),)

    with pytest.raises(
        ra.ConfigError,
        match=r"'gripper'\.open: joint 'panda_finger_joint1' at 0\.08 is outside its limits \[0, 0\.04\]",
    ):
        PastTheStop.check()
    for field, value in (("squeeze", -0.01), ("tolerance", math.nan), ("closed", (0.0, math.inf))):
        with pytest.raises(ra.ConfigError, match=field):
            dataclasses.replace(PANDA_GRIPPER, **{field: value})


def test_position_modes_of_a_short_arm_solve_for_position_alone(torso_file: Path) -> None:
    """A 3-joint arm cannot hold its tool's orientation while it moves sideways: with
    ``hold_orientation=False`` its position modes solve for the position and succeed."""
    results = {}
    for hold in (True, False):
        base = torso_robot(torso_file, command_frame=None)
        arm = base.parts[0]
        task = dataclasses.replace(arm.task_space, hold_orientation=hold, modes=("pd_ee_delta_pos",))  # type: ignore[attr-defined]
        parts = (dataclasses.replace(arm, task_space=task), base.parts[1])
        cls = type("Short", (base,), {"parts": parts, "default_control_mode": "pd_ee_delta_pos"})
        scene = ra.Scene(cls, control_modes="pd_ee_delta_pos")
        scene.reset()
        agent = scene.agents[0]
        start = agent.tcp_pose[0, :3]
        successes = []
        for _ in range(5):
            agent.set_action([0.0, 0.2, 0.0, 0.0])  # +2 cm along y (0.2 of the 0.1 m bound)
            scene.step()
            successes.append(bool(agent.controller.step_info()["ik_success"][0]))
        for _ in range(10):
            agent.set_action([0.0, 0.0, 0.0, 0.0])
            scene.step()
        results[hold] = (successes, agent.tcp_pose[0, :3] - start)
    assert not all(results[True][0])  # orientation cannot be held: IK reports failure
    assert all(results[False][0])
    np.testing.assert_allclose(results[False][1], [0.0, 0.1, 0.0], atol=5e-3)


def test_a_part_takes_its_joints_in_the_order_of_its_patterns(pendulum_file: Path) -> None:
    from tests.conftest import make_pendulum_class

    reversed_arm = ra.Arm(name="arm", joints=("elbow", "shoulder"))
    cls = make_pendulum_class(pendulum_file, parts=(reversed_arm,), control_modes={})
    scene = ra.Scene(cls, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert agent.part_joints["arm"] == ("elbow", "shoulder")
    assert agent.joint_names == ("shoulder", "elbow")  # qpos keeps the model's order
    agent.set_action([0.3, -0.2])  # elbow first
    np.testing.assert_allclose(agent.controller.parts["main"].target_qpos[0], [0.3, -0.2])
    assert agent.controller.parts["main"].config.joint_names == ("elbow", "shoulder")
    # one pattern matching both keeps the model's order
    cls = make_pendulum_class(pendulum_file, parts=(ra.Arm(name="arm", joints="elbow|shoulder"),), control_modes={})
    assert ra.Scene(cls).agents[0].part_joints["arm"] == ("shoulder", "elbow")


def test_a_hand_on_an_arm_takes_absolute_targets_where_the_arm_does() -> None:
    """A hand beside an arm: absolute joint targets in the arm's absolute modes, deltas
    in the others; a body part beside the arm keeps its deltas everywhere."""
    from robot_agents.controllers.joint import PDJointPosConfig
    from robot_agents.controllers.rules import modes_from_parts

    hand = ra.Hand(name="hand", joints=("f1", "f2"), open=0.0, closed=1.0)
    parts = (ra.Arm(name="arm", joints=("a1", "a2")), hand, ra.Body(name="head", joints=("h",)))
    joints = {"arm": ("a1", "a2"), "hand": ("f1", "f2"), "head": ("h",)}
    modes = modes_from_parts(parts, joints, dict.fromkeys(("a1", "a2", "f1", "f2", "h"), 1.0))
    for mode, absolute in (("pd_joint_pos", True), ("pd_joint_pos_vel", True), ("pd_joint_delta_pos", False)):
        entry = modes[mode]
        assert isinstance(entry, dict)
        config, head = entry["hand"], entry["head"]
        assert isinstance(config, PDJointPosConfig) and isinstance(head, PDJointPosConfig)
        assert config.use_delta is not absolute and config.normalize_action is not absolute, mode
        assert config.joint_names == ("f1", "f2") and head.use_delta, mode
    assert modes["pd_joint_vel"]["hand"].use_delta  # type: ignore[index,union-attr]
