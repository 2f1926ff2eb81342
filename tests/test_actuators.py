"""Drives declared once per robot: a file's own actuators adopted or replaced (never
duplicated), MuJoCo's pid and dcmotor, explicit-PD motors, effort control, and the
errors of bad declarations. Checked against numbers."""

from __future__ import annotations

import warnings
from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

import robot_agents as ra
from tests.conftest import PENDULUM_MJCF

GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"

# The pendulum with position servos of its own: a named one (kp 100) on the shoulder
# and an unnamed one (kp 50) on the elbow.
SERVO_PENDULUM = PENDULUM_MJCF.replace(
    "</mujoco>",
    """  <actuator>
    <position name="shoulder_servo" joint="shoulder" kp="100" kv="10"/>
    <position joint="elbow" kp="50" kv="5"/>
  </actuator>
</mujoco>""",
)


def robot(path: Path, **attrs: object) -> type[ra.Agent]:
    base: dict[str, object] = {
        "uid": "servo_pendulum",
        "mjcf_path": path,
        "keyframes": {"down": ra.Keyframe(qpos={".*": 0.0})},
        "control_modes": ra.joint_control_modes(ra.JointGroup(("shoulder", "elbow"))),
    }
    base.update(attrs)
    return type("ServoPendulum", (ra.Agent,), base)


@pytest.fixture
def servo_file(tmp_path: Path) -> Path:
    path = tmp_path / "servo_pendulum.xml"
    path.write_text(SERVO_PENDULUM)
    return path


@pytest.fixture
def plain_file(tmp_path: Path) -> Path:
    path = tmp_path / "pendulum.xml"
    path.write_text(PENDULUM_MJCF)
    return path


def settle(cls: type[ra.Agent], target: list[float], steps: int = 60, mode: str = "pd_joint_pos") -> ra.Scene:
    scene = ra.Scene(cls, control_modes=mode)
    scene.reset()
    for _ in range(steps):
        scene.agents[0].set_action(target)
        scene.step()
    return scene


def test_file_position_actuators_are_adopted_and_track_targets(servo_file: Path) -> None:
    scene = settle(robot(servo_file), [0.5, -0.3])
    agent = scene.agents[0]
    assert scene.model.nu == 2  # adopted, not duplicated beside ours
    assert scene.model.actuator(0).name.endswith("shoulder_servo")
    np.testing.assert_allclose(agent.qpos[0], [0.5, -0.3], atol=0.01)
    # The file's gains are the declared ones: kp 100 and 50.
    np.testing.assert_allclose(agent.drives.declared_stiffness, [100.0, 50.0])
    np.testing.assert_allclose(scene.model.actuator_gainprm[:, 0], [100.0, 50.0])


def test_declared_drive_on_a_file_actuated_joint_needs_a_decision(servo_file: Path) -> None:
    pd = ra.PDActuator(joints="shoulder|elbow", stiffness=300.0, damping=30.0)
    with pytest.raises(ra.ConfigError) as err:
        ra.Scene(robot(servo_file, actuators=(pd,)))
    message = str(err.value)
    assert "already drives" in message and "FileActuators('shoulder')" in message
    assert "replace_file_actuators = True" in message
    # Replaced: only ours remain, with our gains, and they track.
    scene = settle(robot(servo_file, actuators=(pd,), replace_file_actuators=True), [0.5, -0.3])
    assert scene.model.nu == 2
    np.testing.assert_allclose(scene.model.actuator_gainprm[:, 0], [300.0, 300.0])
    np.testing.assert_allclose(scene.agents[0].qpos[0], [0.5, -0.3], atol=0.01)
    # Mixed: adopt the file's shoulder servo, replace nothing else (elbow stays the file's).
    mixed = robot(servo_file, actuators=(ra.FileActuators(joints="shoulder"),))
    assert ra.Scene(mixed).model.nu == 2


def test_gymnasium_humanoid_motors_are_adopted() -> None:
    class Humanoid(ra.Agent):
        uid = "gym_humanoid"
        mjcf_path = GYM_ASSETS / "humanoid.xml"
        fix_root_link = False
        keyframes = {"stand": ra.Keyframe(base_pos=(0.0, 0.0, 1.4))}  # joints: the model's pose, within limits
        control_modes = {
            "torque": ra.JointEffortConfig(
                joint_names=("right_hip_y", "right_knee", "left_elbow"), normalize_action=False
            )
        }

    with warnings.catch_warnings():  # MuJoCo >= 4 warns that the file's RK4 yields to the scene's options
        warnings.simplefilter("ignore")
        scene = ra.Scene(Humanoid)
    agent = scene.agents[0]
    assert scene.model.nu == 17 and agent.drives.size == 17  # one actuator per motor, none added
    assert {scene.model.actuator(i).name.split("/")[-1] for i in range(17)} >= {"right_hip_y", "left_elbow"}
    # Effort limits from the file: ctrlrange 0.4 x gear (300, 200, 25).
    np.testing.assert_allclose(agent.single_action_space.high, [120.0, 80.0, 10.0])
    scene.reset()
    agent.set_action(np.array([-60.0, 40.0, 5.0], dtype=np.float32))
    ctrl = scene.world.ctrl[
        0, agent.drives.ctrl_adr[agent.drives.columns(["right_hip_y", "right_knee", "left_elbow"], "t")]
    ]
    np.testing.assert_allclose(ctrl, [-60.0 / 300, 40.0 / 200, 5.0 / 25])  # ctrl = effort / gear
    # A position mode needs stiffness the motors do not have: a clear error.
    Positional = type(
        "Positional", (Humanoid,), {"control_modes": ra.joint_control_modes(ra.JointGroup(("right_knee",)))}
    )
    with pytest.raises(ra.ConfigError, match=r"'right_knee', but its drive .* has no stiffness"):
        ra.Scene(Positional)


def test_gymnasium_ant_has_one_control_per_joint() -> None:
    class Ant(ra.Agent):
        uid = "gym_ant"
        mjcf_path = GYM_ASSETS / "ant.xml"
        fix_root_link = False
        keyframes = {"stand": ra.Keyframe(base_pos=(0.0, 0.0, 0.75))}
        control_modes = {"torque": ra.JointEffortConfig(joint_names=("hip_1", "ankle_1"))}

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        scene = ra.Scene(Ant)
    assert scene.model.nu == 8  # 8 motors for 8 joints, not 16


@pytest.mark.skipif(not hasattr(mujoco.MjSpec().add_actuator(), "set_to_pid"), reason="MuJoCo < 3.15 has no pid")
def test_pid_removes_the_gravity_sag_of_a_pd(plain_file: Path) -> None:
    pd = settle(
        robot(
            plain_file,
            gravity_compensation=False,
            actuators=(ra.PDActuator(joints=".*", stiffness=200.0, damping=20.0),),
        ),
        [0.5, -0.3],
    )
    pid_cls = robot(
        plain_file,
        gravity_compensation=False,
        actuators=(
            ra.PIDActuator(joints=".*", stiffness=200.0, damping=20.0, integral_gain=2000.0, integral_limit=50.0),
        ),
    )
    pid = settle(pid_cls, [0.5, -0.3])
    pd_error = float(np.max(np.abs(pd.agents[0].qpos[0] - [0.5, -0.3])))
    pid_error = float(np.max(np.abs(pid.agents[0].qpos[0] - [0.5, -0.3])))
    assert pd_error > 5e-3  # gravity pulls a pure PD off its target
    assert pid_error < 1e-4  # the integral term cancels it
    assert pid.model.nu == 4  # a pid actuator takes two controls: position and velocity targets


@pytest.mark.skipif(not hasattr(mujoco.MjSpec().add_actuator(), "set_to_dcmotor"), reason="MuJoCo < 3.15")
def test_dcmotor_tracks_position_targets(plain_file: Path) -> None:
    drive = ra.DCMotorActuator(joints=".*", motor_constant=0.5, resistance=1.0, stiffness=100.0, damping=5.0)
    scene = settle(robot(plain_file, actuators=(drive,)), [0.5, -0.3], steps=100)
    np.testing.assert_allclose(scene.agents[0].qpos[0], [0.5, -0.3], atol=0.01)
    assert not np.any(scene.world.instability_counts())


def test_motor_under_explicit_pd(plain_file: Path) -> None:
    drive = ra.MotorActuator(joints=".*", stiffness=200.0, damping=2.0, effort_limit=50.0)
    scene = ra.Scene(robot(plain_file, actuators=(drive,)), num_envs=2, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    assert agent.needs_substep  # the loop is closed before every substep
    agent.set_action([2.5, -2.5])
    scene.step()
    assert np.all(np.abs(scene.world.ctrl) <= 50.0 + 1e-12)  # the effort limit holds
    for _ in range(60):
        agent.set_action([0.5, -0.3])
        scene.step()
    np.testing.assert_allclose(agent.qpos, [[0.5, -0.3]] * 2, atol=0.01)


def test_velocity_servo_tracks_velocity(plain_file: Path) -> None:
    drive = ra.VelocityActuator(joints=".*", damping=20.0)
    cls = robot(
        plain_file, actuators=(drive,), control_modes={"vel": ra.PDJointVelConfig(joint_names=("shoulder", "elbow"))}
    )
    scene = settle(cls, [0.5, 0.0], steps=10, mode="vel")
    np.testing.assert_allclose(scene.agents[0].qvel[0], [0.5, 0.0], atol=0.02)  # normalized: 0.5 rad/s
    position = ra.joint_control_modes(ra.JointGroup(("shoulder", "elbow")))["pd_joint_pos"]
    with pytest.raises(ra.ConfigError, match="no stiffness"):
        ra.Scene(robot(plain_file, actuators=(drive,), control_modes={"pos": position}))


def test_declaration_errors_name_what_is_available(plain_file: Path) -> None:
    with pytest.raises(ra.UnknownNameError, match=r"unknown joint \(pattern\) 'elbw'.*Did you mean 'elbow'"):
        ra.Scene(robot(plain_file, actuators=(ra.PDActuator(joints=("shoulder", "elbw"), stiffness=1.0),)))
    twice = (ra.PDActuator(joints="shoulder", stiffness=1.0), ra.PDActuator(joints=".*", stiffness=2.0))
    with pytest.raises(ra.ConfigError, match="joint 'shoulder' is claimed by both PDActuator"):
        ra.Scene(robot(plain_file, actuators=twice))
    with pytest.raises(ra.ConfigError, match="stiffness: expected finite values >= 0"):
        ra.PDActuator(joints=".*", stiffness=-1.0)
    with pytest.raises(ra.ConfigError, match="not a valid regular expression"):
        ra.PDActuator(joints="(", stiffness=1.0)
    undriven = robot(plain_file, actuators=(ra.PDActuator(joints="shoulder", stiffness=1.0),))
    with pytest.raises(ra.ConfigError, match="joint 'elbow' has no drive"):
        ra.Scene(undriven)


def test_armature_and_friction_reach_the_joints(plain_file: Path) -> None:
    drive = ra.PDActuator(joints=".*", stiffness=100.0, armature=(0.2, 0.1), friction=0.5)
    scene = ra.Scene(robot(plain_file, actuators=(drive,)))
    np.testing.assert_allclose(scene.model.dof_armature, [0.2, 0.1])
    np.testing.assert_allclose(scene.model.dof_frictionloss, [0.5, 0.5])


def test_joint_damping_acts_beyond_the_effort_limit(tmp_path: Path) -> None:
    """A drive's back-EMF as joint damping (``joint_damping``, the joint's
    ``dof_damping``) bounds a saturated joint's speed to effort limit / damping: a
    2 rad jump of a turntable under kp 100 N*m/rad and a 2 N*m limit with
    2 N*m*s/rad peaks at 1.0 rad/s. The same damping as the PD drive's ``damping`` is
    clamped with its force, and the joint ran at 10.6 rad/s (the drive gives full effort
    until kp (q* - q) - kv qd falls below it)."""
    path = tmp_path / "turntable.xml"
    path.write_text(
        '<mujoco><compiler angle="radian"/><worldbody><body name="base"><geom type="box" size="0.05 0.05 0.05" mass="1"/>'
        '<body name="table"><joint name="turn" axis="0 0 1" range="-3 3"/>'
        '<geom type="box" size="0.2 0.02 0.02" pos="0 0 0.1" mass="1"/></body></body></worldbody></mujoco>'
    )

    def peak(**gains: float) -> float:
        drive = ra.PDActuator(joints="turn", stiffness=100.0, effort_limit=2.0, armature=0.05, **gains)
        attributes = {"uid": "", "mjcf_path": path, "actuators": (drive,)}
        scene = ra.Scene(
            type("Turntable", (ra.Agent,), attributes), control_modes="pd_joint_pos", sim_freq=500, control_freq=500
        )
        scene.reset()
        agent, fastest = scene.agents[0], 0.0
        for _ in range(1500):  # 3 s
            agent.set_action(agent.controller.parts["main"].from_raw(np.array([2.0])))
            scene.step()
            fastest = max(fastest, abs(float(agent.qvel[0, 0])))
        assert agent.qpos[0, 0] == pytest.approx(2.0, abs=1e-3)  # it got there
        np.testing.assert_array_equal(scene.model.dof_damping, [gains.get("joint_damping", 0.0)])
        scene.close()
        return fastest

    assert peak(damping=0.0, joint_damping=2.0) == pytest.approx(1.0, abs=0.01)
    assert peak(damping=2.0) > 10.0
    with pytest.raises(ra.ConfigError, match=r"joint_damping: expected finite values >= 0"):
        ra.PDActuator(joints=".*", stiffness=1.0, joint_damping=-1.0)


def test_joint_damping_fed_forward_follows_velocity_targets(tmp_path: Path) -> None:
    """A PD drive without damping of its own, on a joint whose damping is fed forward
    (a voltage-driven motor's back-EMF as ``joint_damping``), keeps ``pd_joint_vel``:
    it commands ``b qd*``, and the turntable settles at its 1.5 rad/s target. Without the
    feedforward nothing would follow the target, and the mode is left out."""
    path = tmp_path / "turntable.xml"
    path.write_text(
        '<mujoco><compiler angle="radian"/><worldbody><body name="base"><geom type="box" size="0.05 0.05 0.05" mass="1"/>'
        '<body name="table"><joint name="turn" axis="0 0 1"/>'
        '<geom type="box" size="0.2 0.02 0.02" pos="0 0 0.1" mass="1"/></body></body></worldbody></mujoco>'
    )

    def turntable(feedforward: bool) -> type[ra.Agent]:
        drive = ra.PDActuator(
            joints="turn",
            stiffness=100.0,
            damping=0.0,
            joint_damping=2.0,
            effort_limit=4.0,
            velocity_limit=2.0,
            armature=0.05,
            damping_feedforward=feedforward,
        )
        return type("Turntable", (ra.Agent,), {"uid": "", "mjcf_path": path, "actuators": (drive,)})

    assert "pd_joint_vel" not in turntable(False).modes()
    scene = ra.Scene(turntable(True), control_modes="pd_joint_vel", sim_freq=500, control_freq=50)
    scene.reset()
    agent = scene.agents[0]
    for _ in range(50):  # 1 s; the time constant is (I + armature) / b, about 0.04 s
        agent.set_action(agent.controller.parts["main"].from_raw(np.array([1.5])))
        scene.step()
    assert agent.qvel[0, 0] == pytest.approx(1.5, rel=1e-6)
    np.testing.assert_array_equal(agent.drives.damping, [0.0])
    scene.close()
