"""``DerivedActuators``: derived PD gains on the joints it claims, taking the limits,
armature and friction it states into account (a file that leaves out what a datasheet
gives), beside drives declared outright."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.actuators.gains import CLAMPED_DAMPING_SHARE, DEFAULT_BANDWIDTH_HZ
from robot_agents.checks import check_random_actions
from robot_agents.errors import ConfigError, RobotAgentsError
from robot_agents.sim.scene import DEFAULT_SIM_FREQ
from tests.conftest import PENDULUM_MJCF
from tests.test_derived_gripper import slide_fingers, urdf
from tests.test_derived_task_space import arm_urdf

ARMATURE = 0.02  # kg*m^2: a servo's reflected rotor inertia, which a URDF cannot carry


def arm_class(tmp_path: Path, effort: float = 0.0, **attrs: object) -> type[ra.Agent]:
    """The six-joint written arm (``arm_urdf``: bare links), its file's effort limits
    ``effort`` N*m (0: none), with ``attrs`` as class attributes."""
    path = tmp_path / f"arm_{effort:g}.urdf"
    path.write_text(arm_urdf(6, motor=1e-4, effort=effort))
    return type("StatedArm", (ra.Agent,), {"uid": "stated_arm", "urdf_path": path, **attrs})


def test_limits_stated_in_python_equal_limits_in_the_file(tmp_path: Path) -> None:
    """An effort limit stated with ``DerivedActuators`` gives the drives a file with that
    limit gets, bit for bit (the same gains, the same clamp)."""
    in_file = arm_class(tmp_path, effort=5.0).check()
    stated = arm_class(tmp_path, actuators=(ra.DerivedActuators(effort_limit=5.0),)).check()
    assert in_file.derived_gains == stated.derived_gains
    assert [d.effort_limit for d in stated.drives] == [5.0] * 6
    unlimited = arm_class(tmp_path).check()
    assert unlimited.derived_gains != stated.derived_gains  # the clamp's damping bound applies only with a limit


def test_stated_armature_and_limits_reach_the_model_and_the_gains(tmp_path: Path) -> None:
    """The armature adds to every inertia the gains come from (at 10 Hz, ``kp >=
    armature * omega^2``), the effort limit bounds each drive and keeps its damping
    within the clamped bound ``kv dt / I <= 1`` at the smallest inertia (at least the
    armature), and the velocity limit bounds the velocity modes."""
    cls = arm_class(
        tmp_path,
        actuators=(ra.DerivedActuators(effort_limit=5.0, velocity_limit=2.0, armature=ARMATURE, friction=0.01),),
    )
    checked = cls.check()
    model = checked.index.model
    dofs = [model.jnt_dofadr[model.joint(d.joint).id] for d in checked.drives]
    np.testing.assert_array_equal(model.dof_armature[dofs], ARMATURE)
    np.testing.assert_array_equal(model.dof_frictionloss[dofs], 0.01)
    omega = 2.0 * math.pi * DEFAULT_BANDWIDTH_HZ
    dt = 1.0 / DEFAULT_SIM_FREQ
    assert checked.derived_gains is not None
    for drive in checked.drives:
        kp, kv, limit = checked.derived_gains[drive.joint]
        assert kp >= ARMATURE * omega**2, (drive.joint, kp)
        assert limit == drive.effort_limit == 5.0
        assert drive.velocity_limit == 2.0
        assert kv > 0.0
    arm = ra.Scene(cls, control_modes="pd_joint_vel", floor=False).agents[0].controller.parts["main"]
    np.testing.assert_array_equal(arm.raw_high, 2.0)
    least = checked.index.model.dof_armature[dofs]  # the inertia never falls below the armature
    for drive in checked.drives:
        assert checked.derived_gains[drive.joint][1] * dt <= 2.0 * CLAMPED_DAMPING_SHARE * least[0] * 10.0


def test_one_joint_declared_outright_and_the_rest_derived(tmp_path: Path) -> None:
    """``PDActuator`` on one joint and ``DerivedActuators()`` on the rest: the declared
    joint keeps its gains; every other joint gets exactly what the all-derived robot
    gives it (gains over the same configurations of all the driven joints)."""
    declared = ra.PDActuator(joints="flange_roll", stiffness=7.0, damping=0.3, effort_limit=100.0)
    mixed = arm_class(tmp_path, effort=100.0, actuators=(declared, ra.DerivedActuators())).check()
    derived = arm_class(tmp_path, effort=100.0).check()
    assert mixed.derived_gains is not None and derived.derived_gains is not None
    assert set(mixed.derived_gains) == {d.joint for d in derived.drives} - {"flange_roll"}
    for joint, gains in mixed.derived_gains.items():
        assert gains == derived.derived_gains[joint], joint
    model = mixed.index.model
    flange = model.actuator("flange_roll")
    assert (flange.gainprm[0], -flange.biasprm[1], -flange.biasprm[2]) == (7.0, 7.0, 0.3)
    result = check_random_actions(
        arm_class(tmp_path, effort=100.0, uid="mixed_arm", actuators=(declared, ra.DerivedActuators())), seconds=2.0
    )
    assert result.passed, result.detail


def test_a_stated_effort_sets_how_hard_derived_fingers_press(tmp_path: Path) -> None:
    """A gripper the file implies keeps being found with stated drives, and its sliding
    fingers press with the stated effort a full stroke out (``grip_gains``: kp =
    effort / stroke, 15 N over 0.04 m), not the file's 20 N."""
    path = tmp_path / "hand.urdf"
    path.write_text(urdf(slide_fingers(mimic=True)))
    attrs = {"uid": "stated_hand", "urdf_path": path}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        plain = type("Hand", (ra.Agent,), attrs).check()
        stated = type("Hand", (ra.Agent,), {**attrs, "actuators": (ra.DerivedActuators(effort_limit=15.0),)}).check()
    assert [type(p).__name__ for p in stated.parts] == [type(p).__name__ for p in plain.parts] == ["Arm", "Gripper"]
    assert stated.derived_gains is not None and plain.derived_gains is not None
    kp_plain, kp_stated = plain.derived_gains["left_joint"][0], stated.derived_gains["left_joint"][0]
    assert kp_plain == pytest.approx(20.0 / 0.04)
    assert kp_stated == pytest.approx(15.0 / 0.04)
    assert stated.derived_gains["left_joint"][2] == 15.0
    assert stated.derived_pads == plain.derived_pads != ()


#: conftest's pendulum with a position servo of its own on the shoulder, none on the elbow.
FILE_DRIVES_SHOULDER = PENDULUM_MJCF.replace(
    "</mujoco>", '<actuator><position name="shoulder_servo" joint="shoulder" kp="50" kv="2"/></actuator></mujoco>'
)


def test_a_file_driving_some_joints_gets_the_rest_derived(tmp_path: Path) -> None:
    path = tmp_path / "half.xml"
    path.write_text(FILE_DRIVES_SHOULDER)
    cls = type("Half", (ra.Agent,), {"uid": "half", "mjcf_path": path, "actuators": (ra.DerivedActuators(),)})
    checked = cls.check()
    sources = {d.joint: d.source for d in checked.drives}
    assert sources["shoulder"].startswith("the model file")
    assert sources["elbow"].startswith("derived gains (DerivedActuators()")
    assert checked.derived_gains is not None and set(checked.derived_gains) == {"elbow"}
    assert checked.derived_gains["elbow"][0] > 0.0
    assert check_random_actions(cls, seconds=2.0).passed


@pytest.mark.parametrize(
    ("actuators", "expected"),
    [
        ((ra.DerivedActuators(joints="shoulder"),), "already drives with actuator 'shoulder_servo'"),
        ((ra.DerivedActuators(joints="elbow"), ra.PDActuator(joints="elbow", stiffness=5.0)), "is claimed by both"),
        ((ra.DerivedActuators(), ra.DerivedActuators()), "2 DerivedActuators() without joints"),
        ((ra.PDActuator(joints="elbow", stiffness=5.0), ra.DerivedActuators()), "there are none"),
        ((ra.DerivedActuators(joints="wrist"),), "unknown joint"),
    ],
)
def test_derived_actuators_that_cannot_apply_say_why(
    tmp_path: Path, actuators: tuple[ra.ActuatorConfig, ...], expected: str
) -> None:
    path = tmp_path / "half.xml"
    path.write_text(FILE_DRIVES_SHOULDER)
    cls = type("Half", (ra.Agent,), {"uid": "half", "mjcf_path": path, "actuators": actuators})
    with pytest.raises(RobotAgentsError, match=re.escape(expected)):
        cls.check()


def test_a_mimic_follower_gets_no_derived_drive(tmp_path: Path) -> None:
    path = tmp_path / "hand.urdf"
    path.write_text(urdf(slide_fingers(mimic=True)))
    cls = type(
        "Hand", (ra.Agent,), {"uid": "hand", "urdf_path": path, "actuators": (ra.DerivedActuators(joints=".*"),)}
    )
    with pytest.raises(ConfigError, match=r"right_joint.*follows another joint"):
        cls.check()


@pytest.mark.parametrize("field", ["effort_limit", "velocity_limit", "armature", "friction"])
def test_bad_numbers_are_refused(field: str) -> None:
    with pytest.raises(ConfigError, match=f"DerivedActuators.{field}"):
        ra.DerivedActuators(**{field: -1.0})  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=f"DerivedActuators.{field}"):
        ra.DerivedActuators(joints="a", **{field: float("nan")})  # type: ignore[arg-type]


def test_the_rest_is_the_robots_own_joints_not_a_mounted_pieces(tmp_path: Path) -> None:
    """A mounted Robotiq 2F-85 drives its two knuckles and leaves its four linkage hinges
    passive (closed by its loops): ``DerivedActuators()`` takes the arm's own six joints
    only, and the composed robot stays stable under random actions."""
    from robot_agents.robots.robotiq.robotiq import Robotiq2F85

    cls = arm_class(
        tmp_path,
        actuators=(ra.DerivedActuators(effort_limit=50.0, armature=ARMATURE),),
        attachments=(ra.Attachment(Robotiq2F85, at="flange_roll_link", prefix="gripper_", pos=(0.0, 0.0, 0.06)),),
    )
    checked = cls.check()
    sources = {d.joint: d.source for d in checked.drives}
    arm = ["yaw", "shoulder", "elbow", "forearm_roll", "wrist", "flange_roll"]
    assert [j for j, s in sources.items() if s.startswith("derived gains")] == arm
    assert sorted(j for j in sources if j not in arm) == ["gripper_left_driver_joint", "gripper_right_driver_joint"]
    result = check_random_actions(cls, seconds=2.0)
    assert result.passed, result.detail
