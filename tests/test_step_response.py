"""Step responses (robot_agents.tuning.step_response, `robot-agents tune`): measured
against the second-order model on a one-joint robot, gains tried without editing the
robot, the Panda's declared drives, and the errors."""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.cli import main
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.tuning.step_response import StepResponse, step_responses

#: A rotor on a vertical axis (no gravity torque) with 0.5 kg*m^2 about it.
ROTOR_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base" pos="0 0 0.5">
  <geom type="box" size="0.05 0.05 0.05" mass="1"/>
  <body name="rotor"><joint name="spin" axis="0 0 1" range="{low} {high}"/>
    <inertial pos="0 0 0" mass="2" diaginertia="0.5 0.5 0.5"/>
    <geom type="box" size="0.2 0.02 0.02" pos="0 0 0.1" contype="0" conaffinity="0"/></body>
</body></worldbody></mujoco>"""

INERTIA = 0.5
STIFFNESS = 100.0
ZETA = 0.2
DAMPING = 2 * ZETA * math.sqrt(STIFFNESS * INERTIA)


def rotor(tmp_path: Path, low: float = -3.0, high: float = 3.0, rest: float = 0.0) -> type[ra.Agent]:
    path = tmp_path / "rotor.xml"
    path.write_text(ROTOR_MJCF.format(low=low, high=high))

    class Rotor(ra.Agent):
        uid = ""
        mjcf_path = path
        sim_freq = 1000
        actuators: ClassVar = (ra.PDActuator(joints="spin", stiffness=STIFFNESS, damping=DAMPING, effort_limit=1e3),)
        keyframes: ClassVar = {"rest": ra.Keyframe(qpos={"spin": rest})}

    return Rotor


def peak_time(response: StepResponse) -> float:
    return float(response.times[int(np.argmax(response.progress))])


def test_a_step_answers_as_the_second_order_model_says(tmp_path: Path) -> None:
    (response,) = step_responses(rotor(tmp_path), step=0.1, seconds=2.0)
    assert response.inertia == pytest.approx(INERTIA, rel=1e-9)
    assert response.damping_ratio == pytest.approx(ZETA, rel=1e-9)
    assert response.start == 0.0 and response.target == pytest.approx(0.1, abs=1e-12)
    omega = math.sqrt(STIFFNESS / INERTIA)
    expected_overshoot = math.exp(-math.pi * ZETA / math.sqrt(1 - ZETA**2))  # 52.7 %
    assert response.predicted_overshoot == pytest.approx(expected_overshoot, rel=1e-12)
    assert response.overshoot == pytest.approx(expected_overshoot, abs=0.01)
    assert peak_time(response) == pytest.approx(math.pi / (omega * math.sqrt(1 - ZETA**2)), abs=2e-3)
    # 10-90 % rise of an underdamped second-order step, from its exact solution
    t = np.linspace(0.0, 0.5, 500_001)
    wd = omega * math.sqrt(1 - ZETA**2)
    exact = 1 - np.exp(-ZETA * omega * t) * (np.cos(wd * t) + ZETA * omega / wd * np.sin(wd * t))
    exact_rise = t[np.argmax(exact >= 0.9)] - t[np.argmax(exact >= 0.1)]
    assert response.rise_time == pytest.approx(exact_rise, abs=2e-3)
    # the envelope exp(-zeta omega t) enters the 2 % band at about 4 / (zeta omega)
    assert response.settling_time is not None and response.settling_time < 4.5 / (ZETA * omega)
    # within the envelope of the ringing at the end (2 s)
    assert abs(response.final_error) < 0.1 * math.exp(-ZETA * omega * 2.0) / math.sqrt(1 - ZETA**2)
    assert response.peak_effort == pytest.approx(STIFFNESS * 0.1, rel=1e-6)  # the step's first push
    assert response.saturated_share == 0.0 and not response.unstable


def test_gains_to_try_change_the_answer_and_not_the_robot(tmp_path: Path) -> None:
    cls = rotor(tmp_path)
    (stiffer,) = step_responses(cls, step=0.1, stiffness=4 * STIFFNESS, damping=2 * DAMPING)
    assert stiffer.stiffness == 4 * STIFFNESS and stiffer.damping == 2 * DAMPING
    assert stiffer.damping_ratio == pytest.approx(ZETA, rel=1e-9)  # same ratio, twice the frequency
    omega = 2 * math.sqrt(STIFFNESS / INERTIA)
    assert peak_time(stiffer) == pytest.approx(math.pi / (omega * math.sqrt(1 - ZETA**2)), abs=2e-3)
    # a limited effort: the drive saturates, ramps instead of ringing as the model does
    (limited,) = step_responses(cls, step=0.1, effort_limit=2.0)
    assert limited.effort_limit == 2.0 and limited.peak_effort == pytest.approx(2.0, rel=1e-9)
    assert limited.saturated_share > 0.05
    free_rise = step_responses(cls, step=0.1)[0].rise_time
    assert limited.rise_time is not None and free_rise is not None and limited.rise_time > 1.5 * free_rise
    # the robot keeps its declaration: a new scene has the declared gains
    scene = ra.Scene(cls)
    assert scene.agents[0].drives.stiffness[0] == STIFFNESS and scene.agents[0].drives.damping[0] == DAMPING
    scene.close()


def test_the_step_turns_where_the_range_leaves_no_room(tmp_path: Path) -> None:
    (response,) = step_responses(rotor(tmp_path, low=-1.0, high=0.05), step=0.1)
    assert response.step == pytest.approx(-0.1, abs=1e-9)
    with pytest.raises(ConfigError, match=r"no room for a step of 0\.1 either way"):
        step_responses(rotor(tmp_path, low=-0.05, high=0.05), step=0.1)


def test_the_pandas_declared_drives_reach_their_steps_without_overshoot() -> None:
    responses = step_responses("panda", "panda_joint[1-7]")
    assert [r.joint for r in responses] == [f"panda_joint{i}" for i in range(1, 8)]
    for response in responses:
        assert abs(response.final_error) < 1e-3, response.line()
        assert response.overshoot < 0.05, response.line()
        assert response.damping_ratio > 1.0 and not response.unstable


def test_bad_arguments_name_what_was_expected(tmp_path: Path) -> None:
    cls = rotor(tmp_path)
    with pytest.raises(UnknownNameError, match="Did you mean 'spin'"):
        step_responses(cls, "spn")
    with pytest.raises(UnknownNameError, match="Did you mean 'rest'"):
        step_responses(cls, keyframe="rset")
    with pytest.raises(ConfigError, match="non-zero step"):
        step_responses(cls, step=0.0)
    with pytest.raises(ConfigError, match="damping to be a finite number"):
        step_responses(cls, damping=-1.0)
    with pytest.raises(ConfigError, match="seconds"):
        step_responses(cls, seconds=math.nan)


def test_the_command_line_prints_a_line_per_joint() -> None:
    out = io.StringIO()
    assert main(["tune", "panda", "--joints", "panda_joint7", "--stiffness", "300", "--damping", "5"], out) == 0
    text = out.getvalue()
    assert "trying stiffness 300, damping 5" in text
    assert text.count("\n") == 2 and "panda_joint7: kp 300 kv 5 " in text
    assert main(["tune", "panda", "--joints", "panda_jiont7"], io.StringIO()) == 2


def test_the_records_go_to_a_csv_table(tmp_path: Path) -> None:
    import csv

    path = tmp_path / "steps.csv"
    out = io.StringIO()
    assert main(["tune", "panda", "--joints", "panda_joint[67]", "--seconds", "0.1", "--csv", str(path)], out) == 0
    rows = list(csv.DictReader(path.open()))
    assert len(rows) == 2 * 50 and {r["joint"] for r in rows} == {"panda_joint6", "panda_joint7"}  # 0.1 s at 500 Hz
    (six,) = step_responses("panda", "panda_joint6", seconds=0.1)
    first = [r for r in rows if r["joint"] == "panda_joint6"]
    assert float(first[-1]["position"]) == six.positions[-1] and float(first[0]["time_s"]) == pytest.approx(0.002)
    assert main(["tune", "panda", "--csv", str(tmp_path / "no" / "steps.csv")], io.StringIO()) == 2


def test_a_csv_path_that_is_a_directory_is_refused_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = io.StringIO()
    assert main(["tune", "panda", "--csv", str(tmp_path)], out) == 2
    assert out.getvalue() == ""  # no step response was run
    assert capsys.readouterr().err == (
        f"robot-agents: error: argument --csv: expected a file name, got the existing directory {str(tmp_path)!r}\n"
    )


def test_a_mimic_follower_is_stepped_through_its_leader() -> None:
    # the WidowX 250 S's right finger follows the left one mirrored (multiplier -1)
    left, right = step_responses("widowx250s", ".*_finger")
    assert (left.joint, right.joint) == ("left_finger", "right_finger")
    assert right.step == pytest.approx(-left.step, abs=1e-6) and abs(left.step) == pytest.approx(0.01, abs=1e-6)
    for response in (left, right):
        assert abs(response.final_error) < 1e-3 * abs(response.step), response.line()


#: Two rotors on vertical axes, the second turning twice as far as the first (a joint
#: equality), only the first driven.
GEARED_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base" pos="0 0 0.5">
  <geom type="box" size="0.05 0.05 0.05" mass="1"/>
  <body name="first"><joint name="lead" axis="0 0 1" range="-3 3"/>
    <inertial pos="0 0 0" mass="2" diaginertia="0.5 0.5 0.5"/></body>
  <body name="second" pos="0.3 0 0"><joint name="follow" axis="0 0 1" range="-6 6"/>
    <inertial pos="0 0 0" mass="1" diaginertia="0.25 0.25 0.25"/></body>
</body></worldbody>
<equality><joint joint1="follow" joint2="lead" polycoef="0 2 0 0 0" solref="0.004 1"/></equality></mujoco>"""


def test_a_joint_equality_follower_counts_in_what_the_drive_moves(tmp_path: Path) -> None:
    path = tmp_path / "geared.xml"
    path.write_text(GEARED_MJCF)

    class Geared(ra.Agent):
        uid = ""
        mjcf_path = path
        sim_freq = 1000
        actuators: ClassVar = (ra.PDActuator(joints="lead", stiffness=STIFFNESS, damping=DAMPING, effort_limit=1e3),)
        keyframes: ClassVar = {"rest": ra.Keyframe(qpos={"lead": 0.0, "follow": 0.0})}

    (response,) = step_responses(Geared, step=0.1, seconds=2.0)
    inertia = 0.5 + 2**2 * 0.25  # c^T M c with c = (1, 2)
    assert response.coupled == ("lead", "follow")
    assert response.inertia == pytest.approx(inertia, rel=1e-9) and response.stiffness == STIFFNESS
    zeta = DAMPING / (2 * math.sqrt(STIFFNESS * inertia))
    assert response.damping_ratio == pytest.approx(zeta, rel=1e-9)
    omega = math.sqrt(STIFFNESS / inertia)
    assert response.overshoot == pytest.approx(response.predicted_overshoot, abs=0.02)
    assert peak_time(response) == pytest.approx(math.pi / (omega * math.sqrt(1 - zeta**2)), abs=5e-3)
