"""``Arm(task_space=MeasuredTaskSpace())``: an arm declared by hand on a model file gets
the task space a two-line arm gets measured on it, here a user's arm (a written URDF
without actuators) with the built-in Robotiq 2F-85 piece mounted on its flange."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

import robot_agents as ra
from robot_agents.controllers.rules import EE_MODES
from robot_agents.errors import ConfigError
from robot_agents.robots.robotiq.robotiq import Robotiq2F85
from tests.test_derived_task_space import JOINTS, arm_urdf
from tests.test_scripted_solvers import load_solver

ARM_JOINTS = tuple(name for name, *_ in JOINTS)


def composed(tmp_path: Path, task_space: object | None, joints: tuple[str, ...] = ARM_JOINTS) -> type[ra.Agent]:
    """The written six-joint arm (no effort limits in its file) with drives derived for
    50 N*m servos of 0.02 kg*m^2, the 2F-85 on its flange, and one declared arm part."""
    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf(6, effort=0.0))
    arm = ra.Arm(
        name="arm", joints=joints, end_effectors=(ra.EndEffector("gripper_robotiq_tcp"),), task_space=task_space
    )
    return type(
        "ComposedArm",
        (ra.Agent,),
        {
            "uid": "composed_arm",
            "urdf_path": path,
            "actuators": (ra.DerivedActuators(effort_limit=50.0, armature=0.02),),
            "parts": (arm,),
            "attachments": (
                ra.Attachment(Robotiq2F85, at=f"{ARM_JOINTS[-1]}_link", prefix="gripper_", pos=(0.0, 0.0, 0.06)),
            ),
        },
    )


def test_a_declared_arm_gets_its_task_space_measured(tmp_path: Path) -> None:
    checked = composed(tmp_path, ra.MeasuredTaskSpace()).check()
    arm = next(p for p in checked.parts if p.name == "arm")
    assert isinstance(arm, ra.Arm) and isinstance(arm.task_space, ra.TaskSpace)
    assert set(EE_MODES) <= set(checked.modes)
    # at rest the arm and the gripper stand straight up (every joint at zero): the box
    # reaches that high, spans the arm's sweep either way, and a delta action moves a
    # tenth of the reach (the tool's height above the first joint, 0.1 m up, at rest)
    box = arm.task_space.position_bounds
    assert box.upper[2] >= 0.1 + sum(length for *_, length in JOINTS) + 0.06 + 0.15
    assert min(box.upper[0] - box.lower[0], box.upper[1] - box.lower[1]) > 1.6
    assert arm.task_space.max_translation == pytest.approx(0.1 * (box.upper[2] - 0.1), rel=0.1)


def test_without_it_a_declared_arm_keeps_joint_modes_only(tmp_path: Path) -> None:
    checked = composed(tmp_path, None).check()
    assert not set(EE_MODES) & set(checked.modes)


def test_the_composed_arm_reaches_poses(tmp_path: Path) -> None:
    """The scripted ReachPose solver (end-effector deltas) on the composed robot."""
    cls = composed(tmp_path, ra.MeasuredTaskSpace())
    ra.register_agent(cls, override=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            successes, _ = load_solver().success_rate("ReachPose-v1", cls.uid, 20)
    finally:
        ra.unregister_agent(cls.uid)  # (the solver suites list every registered robot)
    assert successes >= 18, successes


def test_an_arm_it_cannot_be_measured_on_says_why(tmp_path: Path) -> None:
    with pytest.raises(
        ConfigError, match=r"parts\['arm'\]: MeasuredTaskSpace\(\) cannot be measured.*'yaw', 'shoulder'"
    ):
        composed(tmp_path, ra.MeasuredTaskSpace(), joints=ARM_JOINTS[:2]).check()


def test_an_arm_without_drive_declarations_gets_derived_drives(tmp_path: Path) -> None:
    """The mounted gripper declares its own actuators; the robot declares none and its
    file has none, so its own joints get derived drives, as the file alone gets them
    (they were left undriven: a silent gripper-only action space, then an error)."""
    cls = type("Undeclared", (composed(tmp_path, ra.MeasuredTaskSpace()),), {"uid": "undeclared_arm", "actuators": ()})
    sources = {d.joint: d.source for d in cls.check().drives}
    assert [sources[j] for j in ARM_JOINTS] == ["derived gains (see robot_agents.actuators.gains)"] * len(ARM_JOINTS)


def test_a_part_left_without_drives_is_refused(tmp_path: Path) -> None:
    """A part none of whose joints the declared actuators drive is an error naming the
    fix (here the flange's roll, split off the arm and left out of the actuators)."""
    arm = ra.Arm(name="arm", joints=ARM_JOINTS[:5], end_effectors=(ra.EndEffector("gripper_robotiq_tcp"),))
    cls = type(
        "Undriven",
        (composed(tmp_path, None),),
        {
            "uid": "undriven_roll",
            "actuators": (ra.DerivedActuators(joints=ARM_JOINTS[:5], effort_limit=50.0),),
            "parts": (arm, ra.Body(name="roll", joints=ARM_JOINTS[5:])),
        },
    )
    with pytest.raises(
        ConfigError, match=r"parts\['roll'\]: none of its joints \['flange_roll'\] has a drive.*DerivedActuators\(\)"
    ):
        cls.check()
