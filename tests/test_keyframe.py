from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from tests.conftest import make_pendulum_class

BALL_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 1">
      <geom type="box" size="0.05 0.05 0.05" mass="1"/>
      <body name="arm">
        <joint name="shoulder" type="ball"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="1"/>
        <body name="forearm" pos="0 0 -0.3">
          <joint name="elbow" axis="0 1 0" range="-2 2"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/>
          <body name="finger_a" pos="0 0 -0.2">
            <joint name="finger_a" type="slide" axis="1 0 0" range="0 0.04"/>
            <geom type="box" size="0.01 0.01 0.01" mass="0.01"/>
          </body>
          <body name="finger_b" pos="0 0 -0.2">
            <joint name="finger_b" type="slide" axis="-1 0 0" range="0 0.04"/>
            <geom type="box" size="0.01 0.01 0.01" mass="0.01"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <equality><joint joint1="finger_b" joint2="finger_a"/></equality>
</mujoco>
"""


def test_keyframe_normalizes_and_copies() -> None:
    frame = ra.Keyframe(qpos=[0.1, 0.2], base_quat=(2.0, 0.0, 0.0, 0.0))
    assert frame.qpos == (0.1, 0.2)
    assert frame.base_quat == (1.0, 0.0, 0.0, 0.0)
    named = ra.Keyframe(qpos={"a.*": 0.5, "b": (0.1, 0.2)})
    assert named.by_name and named.qpos == {"a.*": 0.5, "b": (0.1, 0.2)}


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"qpos": [0.0, math.nan]}, "finite"),
        ({"qpos": {"a": "x"}}, "expected numbers"),
        ({"qpos": {"(": 0.0}}, "not a valid regular expression"),
        ({"qpos": [0.0], "base_pos": [0.0, 0.0]}, "expected 3 values"),
        ({"qpos": [0.0], "base_quat": [0.0, 0.0, 0.0, 0.0]}, "unit quaternion"),
    ],
)
def test_keyframe_rejects_bad_values(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(ra.ConfigError, match=match):
        ra.Keyframe(**kwargs)  # type: ignore[arg-type]


@pytest.fixture
def ball_cls(tmp_path: Path) -> type[ra.Agent]:
    path = tmp_path / "ball.xml"
    path.write_text(BALL_MJCF)
    return make_pendulum_class(
        path,
        uid="ball_arm",
        actuators=(ra.PDActuator(joints="elbow|finger_a", stiffness=50.0, damping=5.0),),
        parts=(),
        control_modes={"m": ra.PDJointPosConfig(joint_names=("elbow", "finger_a"), normalize_action=False)},
        keyframes={
            "bent": ra.Keyframe(
                qpos={"shoulder": (math.cos(0.3), math.sin(0.3), 0.0, 0.0), "elbow": -0.7, "finger_a": 0.03},
                qvel={"elbow": 0.25},
            ),
            "partial": ra.Keyframe(qpos={"finger_.": 0.01}),
        },
    )


def test_ball_joint_resets_to_unit_quaternion(ball_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(ball_cls)
    agent = scene.agents[0]
    assert agent.nq == 7 and agent.dof == 6  # ball 4 + 3 scalar joints; ball 3 + 3
    scene.reset(keyframes="partial")
    # Unnamed joints take the model's default: the identity quaternion, not (0, 0, 0, 0).
    np.testing.assert_array_equal(agent.qpos[0, :4], [1.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(agent.qpos[0, 4:], [0.0, 0.01, 0.01])


def test_named_keyframe_resets_exactly_with_followers_filled(ball_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(ball_cls, num_envs=2)
    scene.reset(keyframes="bent")
    agent = scene.agents[0]
    expected = [math.cos(0.3), math.sin(0.3), 0.0, 0.0, -0.7, 0.03, 0.03]  # finger_b follows finger_a
    np.testing.assert_array_equal(agent.qpos, np.tile(expected, (2, 1)))
    np.testing.assert_array_equal(agent.qvel[:, 3], [0.25, 0.25])  # elbow's qvel entry (after the ball's 3)
    np.testing.assert_array_equal(np.delete(agent.qvel, 3, axis=1), 0.0)


def test_reset_noise_keeps_ball_quaternions_unit(ball_cls: type[ra.Agent]) -> None:
    scene = ra.Scene(ball_cls, num_envs=3)
    scene.reset(keyframes="bent")
    agent = scene.agents[0]
    noisy = agent.perturbed_qpos(np.arange(3), 0.2, np.random.default_rng(0))
    np.testing.assert_allclose(np.linalg.norm(noisy[:, :4], axis=1), 1.0, atol=1e-12)
    assert np.all(np.abs(noisy[:, :4] - agent.qpos[:, :4]).max(axis=1) > 1e-3)  # it did turn
    assert np.all((noisy[:, 5:] >= 0.0) & (noisy[:, 5:] <= 0.04))  # clipped into the finger limits
    agent.reset(qpos=noisy)
    np.testing.assert_allclose(agent.qpos, noisy, atol=1e-15)


@pytest.mark.parametrize(
    ("qpos", "fragment"),
    [
        ({"elbw": 0.1}, "unknown joint (pattern) 'elbw'. Did you mean 'elbow'"),
        ({"elbow": 2.5}, "joint 'elbow' at 2.5 is outside its limits [-2, 2]"),
        ({"shoulder": 1.0}, "joint 'shoulder' is a ball joint; give its quaternion"),
        ({"shoulder": (0.0, 0.0, 0.0, 0.0)}, "with a unit quaternion, got [0.0, 0.0, 0.0, 0.0] in env 0 (zero)"),
        ({"finger_.*": (0.01, 0.02, 0.03)}, "matches 2 joint(s) (finger_a, finger_b) with 2 values; got 3"),
        ({"elbow": 0.1, "elb.*": 0.2}, "joint 'elbow' is named by both 'elbow' and 'elb.*'"),
        (
            {"finger_a": 0.02, "finger_b": 0.0},
            "joint 'finger_b' follows 'finger_a' (a joint coupling), which puts it at 0.02, but the keyframe gives 0",
        ),
        ((0.0, 0.1), "expected 7 joint positions"),
    ],
)
def test_bad_keyframe_fails_at_class_check_with_its_name(ball_cls: type[ra.Agent], qpos: object, fragment: str) -> None:
    cls = type("BadBall", (ball_cls,), {"keyframes": {"oops": ra.Keyframe(qpos=qpos)}})  # type: ignore[arg-type]
    with pytest.raises(ra.RobotAgentsError) as err:
        cls.check()
    assert "BadBall.keyframes['oops']" in str(err.value) and fragment in str(err.value)


@pytest.mark.filterwarnings("ignore:.*touch at the default keyframe")
def test_a_ball_quaternion_of_any_length_is_normalized_and_its_range_checked(tmp_path: Path) -> None:
    """As documented (defining-a-robot.md): ``(0.995, 0.0998, 0, 0)`` (norm 0.999993)
    is taken and normalized, like a reset's ``qpos`` and a keyframe's ``base_quat``; a
    limited ball joint turned beyond its range is refused in a keyframe and in a reset."""
    path = tmp_path / "ball.xml"
    path.write_text(BALL_MJCF.replace('type="ball"/>', 'type="ball" range="0 1.5" limited="true"/>'))
    frames = {
        "documented": ra.Keyframe(qpos={"shoulder": (0.995, 0.0998, 0, 0)}, qvel={"elbow": 0.25}),
        "long": ra.Keyframe(qpos={"shoulder": (2.0, 0.0, 0.0, 0.0)}),
    }
    cls = make_pendulum_class(
        path,
        uid="ball_arm",
        actuators=(ra.PDActuator(joints="elbow|finger_a", stiffness=50.0, damping=5.0),),
        parts=(),
        control_modes={"m": ra.PDJointPosConfig(joint_names=("elbow", "finger_a"), normalize_action=False)},
        keyframes=frames,
    )
    scene = ra.Scene(cls)
    agent = scene.agents[0]
    scene.reset(keyframes="documented")
    norm = math.hypot(0.995, 0.0998)
    np.testing.assert_allclose(agent.qpos[0, :4], [0.995 / norm, 0.0998 / norm, 0.0, 0.0], atol=1e-15)
    scene.reset(keyframes="long")
    np.testing.assert_array_equal(agent.qpos[0, :4], [1.0, 0.0, 0.0, 0.0])
    half_turn = np.array([[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]])  # pi rad about x: beyond 1.5
    before = agent.qpos.copy()
    with pytest.raises(ra.StateError, match=r"ball joint 'shoulder' turned 3\.14159 rad .* beyond its limit 1\.5 rad"):
        agent.reset(qpos=half_turn)
    np.testing.assert_array_equal(agent.qpos, before)  # nothing changed
    scene.close()
    bad = type("TurnedBall", (cls,), {"keyframes": {"over": ra.Keyframe(qpos={"shoulder": (0.0, 1.0, 0.0, 0.0)})}})
    with pytest.raises(ra.ConfigError, match=r"TurnedBall.keyframes\['over'\]: ball joint 'shoulder' turned 3\.14159"):
        bad.check()


def test_a_base_pose_on_a_fixed_root_robot_is_not_ignored_in_silence() -> None:
    """A keyframe's ``base_pos`` / ``base_quat`` move a free root; a robot bolted to its
    mount ignores them, and the class check says so (a warning: a legged robot's variant
    hung up by its root keeps the keyframes written for it standing)."""
    from robot_agents.robots.panda.panda import Panda

    for base in ({"base_pos": (0.0, 0.0, 1.0)}, {"base_quat": (0.0, 0.0, 0.0, 1.0)}):
        raised = type("RaisedPanda", (Panda,), {"keyframes": {"up": ra.Keyframe(qpos={"panda_joint1": 0.0}, **base)}})
        with pytest.warns(RuntimeWarning, match=r"RaisedPanda.keyframes\['up'\]: base_pos .* they are ignored"):
            raised.check()


def test_a_keyframe_carries_a_root_velocity_checked_like_its_speeds() -> None:
    """``base_vel`` (MuJoCo's free-joint velocity) is six finite numbers; a fixed root
    ignores it with a warning; a speed no robot reaches is refused at the class check,
    where a reset would refuse it only when used."""
    from robot_agents.limits import MAX_SPEED
    from robot_agents.robots.panda.panda import Panda

    assert ra.Keyframe().base_vel == (0.0,) * 6
    with pytest.raises(ra.ConfigError, match=r"Keyframe.base_vel: expected 6 values, got 3"):
        ra.Keyframe(base_vel=(1.0, 0.0, 0.0))
    moving = type("MovingPanda", (Panda,), {"keyframes": {"up": ra.Keyframe(base_vel=(0.0, 0.0, 1.0, 0, 0, 0))}})
    with pytest.warns(RuntimeWarning, match=r"MovingPanda.keyframes\['up'\]: base_vel .* root is fixed: it is ignored"):
        checked = moving.check()
    np.testing.assert_array_equal(checked.keyframes["up"].base_vel, np.zeros(6))
    fast = type("FastPanda", (Panda,), {"keyframes": {"fast": ra.Keyframe(qvel={"panda_joint1": 2 * MAX_SPEED})}})
    with pytest.raises(
        ra.ConfigError, match=r"FastPanda.keyframes\['fast'\]: expected speeds below 10000 .* got up to 2e\+04"
    ):
        fast.check()
