"""Torque-limit cycles (robot_agents.tuning.cycles): the analytic bound against
simulation, on a one-joint robot and on the Panda's wrist."""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import ClassVar

import mujoco
import pytest

import robot_agents as ra
from robot_agents.errors import ConfigError
from robot_agents.tuning.cycles import CYCLE_RATIO, drive_cycle_bounds

#: A wheel on a vertical axis (no gravity torque): a 2 kg disc of 0.1 m radius.
WHEEL_MJCF = """<mujoco><worldbody><body name="base" pos="0 0 0.5">
  <geom type="box" size="0.05 0.05 0.05" mass="1"/>
  <body name="wheel"><joint name="spin" axis="0 0 1"/>
    <geom type="cylinder" size="0.1 0.01" pos="0 0 0.07" mass="2"/></body>
</body></worldbody></mujoco>"""


def wheel_robot(path: Path) -> type[ra.Agent]:
    class Wheel(ra.Agent):
        uid = ""
        mjcf_path = path
        actuators: ClassVar = (
            ra.PDActuator(joints="spin", stiffness=1000.0, damping=100.0, effort_limit=12.0, armature=0.05),
        )

    return Wheel


def settled_speed(cls: type[ra.Agent], sim_freq: int, kick: float, joint_damping: float = 0.0) -> float:
    """Fastest speed of the wheel over its last 10 physics steps, 1 s after a kick of
    ``kick`` rad/s at its target (the drive holding 0)."""
    scene = ra.Scene(cls, sim_freq=sim_freq)
    scene.reset()
    model, data = scene.model, scene.world.physics_sources([0])[0]
    model.dof_damping[0] = joint_damping
    data.qvel[0] = kick
    mujoco.mj_step(model, data, nstep=sim_freq)
    speeds = []
    for _ in range(10):
        mujoco.mj_step(model, data)
        speeds.append(abs(float(data.qvel[0])))
    scene.close()
    return max(speeds)


@pytest.fixture
def wheel_file(tmp_path: Path) -> Path:
    path = tmp_path / "wheel.xml"
    path.write_text(WHEEL_MJCF)
    return path


def test_the_bound_separates_cycling_from_settling_steps(wheel_file: Path) -> None:
    cls = wheel_robot(wheel_file)
    (bound,) = drive_cycle_bounds(cls)
    disc = 0.5 * 2.0 * 0.1**2  # the disc's inertia about its axis
    assert bound.inertia == pytest.approx(0.05 + disc, rel=1e-6)  # armature + link
    assert bound.cycle_free_above == pytest.approx(100.0 / (CYCLE_RATIO * bound.inertia))  # 833 Hz
    assert bound.reachable  # no rated speed declared
    # below the bound the cycle exists: a joint on it stays on it, flipping its drive
    # between the limits every step
    for share in (0.6, 0.8, 0.95):
        below = 20 * math.floor(share * bound.cycle_free_above / 20)  # tried rates under the bound
        assert bound.ratio(below) >= CYCLE_RATIO and bound.amplitude(below) > 0
        assert settled_speed(cls, below, kick=bound.amplitude(below)) == pytest.approx(bound.amplitude(below))
    # a plain kick can land in it too (here at 500 Hz, 0.2 rad/s)
    assert settled_speed(cls, 500, kick=1.0) == pytest.approx(bound.amplitude(500))
    # above the bound no such cycle: the same start and a saturating kick die out
    above = 20 * math.ceil(1.05 * bound.cycle_free_above / 20)  # 880 Hz
    assert bound.amplitude(above) == 0.0
    for kick in (bound.amplitude(below), 1.0, 5.0):
        assert settled_speed(cls, above, kick=kick) < 1e-3  # (the cycle: 0.13 rad/s)


def _kicked_speeds(clamp: str, hz: int) -> list[float]:
    """Joint speeds (rad/s) of 1 s of a kp 1000 / kv 100 drive limited to 12 N*m, holding
    0 on a 0.05 kg*m^2 hinge kicked to 2 rad/s at its target: the clamp is the
    actuator's ``forcerange`` or, with two unclamped actuators for kp and kv, the joint's
    ``actuatorfrcrange`` (the clamp of their sum, PhysX's drive as one force)."""
    if clamp == "actuator":
        joint_limit, actuators = "", '<position joint="j" kp="1000" kv="100" forcelimited="true" forcerange="-12 12"/>'
    else:
        joint_limit = 'actuatorfrclimited="true" actuatorfrcrange="-12 12"'
        actuators = '<position joint="j" kp="1000"/><velocity joint="j" kv="100"/>'
    model = mujoco.MjModel.from_xml_string(
        f"""<mujoco><option timestep="{1.0 / hz}" integrator="implicitfast" gravity="0 0 0"/>
        <worldbody><body><joint name="j" axis="0 0 1" armature="0.05" {joint_limit}/>
        <geom type="sphere" size="0.01" mass="1e-6" contype="0" conaffinity="0"/></body></worldbody>
        <actuator>{actuators}</actuator></mujoco>"""
    )
    data = mujoco.MjData(model)
    data.qvel[0] = 2.0
    speeds = []
    for _ in range(hz):
        mujoco.mj_step(model, data)
        speeds.append(float(data.qvel[0]))
    return speeds


def test_a_joint_level_clamp_cycles_as_the_actuators_does() -> None:
    """MuJoCo leaves a clamped force's velocity derivative out of ``implicitfast`` for the
    joint's ``actuatorfrcrange`` too: kv * dt / m = 20 at 100 Hz, so both flip between the
    limits (dv = 12 * 0.01 / 0.05 = 2.4 rad/s a step) until the spring's share moves the
    joint out, bit for bit the same; at 1 kHz (kv * dt / m = 2) neither stays on it. Moving
    the drive's torque limit to the joint does not lift the bound (docs/benchmarks.md)."""
    for clamp in ("actuator", "joint"):
        slow = _kicked_speeds(clamp, 100)
        assert slow[:5] == pytest.approx([-0.4, 2.0, -0.4, 2.0, -0.4])
        assert abs(slow[-1]) < 1e-3  # it does leave the cycle: the target is held still
    assert _kicked_speeds("actuator", 100) == _kicked_speeds("joint", 100)
    for clamp in ("actuator", "joint"):
        fast = _kicked_speeds(clamp, 1000)
        assert fast[:5] == pytest.approx([1.76, 1.52, 1.28, 1.04, 0.8])  # braked at the limit, 0.24 a step
        assert _sign_changes(fast[:100]) == 1 < 4 == _sign_changes(_kicked_speeds(clamp, 100)[:10])


def _sign_changes(speeds: list[float]) -> int:
    return sum(1 for a, b in itertools.pairwise(speeds) if a * b < 0.0)


def test_joint_damping_is_implicit_and_lowers_the_bound(wheel_file: Path) -> None:
    cls = wheel_robot(wheel_file)
    (bound,) = drive_cycle_bounds(cls)
    damped = type(bound)(**{**vars(bound), "joint_damping": 20.0})
    assert damped.cycle_free_above == pytest.approx((100.0 - 2 * 20.0) / (2 * bound.inertia))  # 500 Hz
    rate = 20 * math.floor(0.8 * bound.cycle_free_above / 20)  # cycles without the joint's damping
    assert bound.amplitude(rate) > 0 and damped.amplitude(rate) == 0.0
    assert settled_speed(cls, rate, kick=bound.amplitude(rate), joint_damping=20.0) < 1e-6
    assert type(bound)(**{**vars(bound), "joint_damping": 50.0}).cycle_free_above == 0.0  # never


def test_panda_wrist_bound_lies_between_the_steps_where_the_sweep_sees_it_cycle_and_not() -> None:
    """The sweep's settle claim sees joint 7 cycling at 400 Hz (0.16 rad/s with seed 2) and
    not at 500 Hz (docs/timestep-sweep.md)."""
    bounds = {b.joint: b for b in drive_cycle_bounds("panda")}
    wrist = bounds["panda_joint7"]
    assert 400 < wrist.cycle_free_above < 500
    assert wrist.amplitude(500) == 0.0
    assert wrist.amplitude(400) == pytest.approx(12.0 / (2 * 400 * wrist.inertia))
    assert 0.1 < wrist.amplitude(400) < 0.2
    assert max(b.cycle_free_above for b in bounds.values()) == wrist.cycle_free_above


def test_drives_without_a_force_limit_are_not_listed() -> None:
    """The floating Panda gripper's mount drives have no effort limit (a fixture): only
    its fingers can cycle."""
    joints = {b.joint for b in drive_cycle_bounds("floating_panda_gripper")}
    assert joints == {"panda_finger_joint1", "panda_finger_joint2"}


def test_bad_input_is_a_clean_error() -> None:
    with pytest.raises(ConfigError, match="drive_cycle_bounds"):
        drive_cycle_bounds(int)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="samples"):
        drive_cycle_bounds("panda", samples=-1)
