"""The time-step sweep (robot_agents.tuning.timestep), per-robot default steps
(``AgentDefinition.sim_freq``) and the Panda wrist's torque-limit oscillation."""

from __future__ import annotations

import io
from typing import ClassVar

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.cli import cmd_check
from robot_agents.errors import ConfigError
from robot_agents.robots.panda.panda import Panda
from robot_agents.robots.servo_arms.so100 import SO100
from robot_agents.sim.scene import DEFAULT_SIM_FREQ, Scene
from robot_agents.tuning.timestep import CLAIMS, SETTLE_SPEED, measure_step, sweep_timestep


def settled_speed(cls: type[ra.Agent], mode: str, sim_freq: int, seconds: float = 10.0) -> tuple[float, str]:
    """Fastest joint speed after ``seconds`` of random actions then 1 s of holding still."""
    scene = Scene(cls, control_modes=mode, sim_freq=sim_freq)
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    space = agent.action_space
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(rng.uniform(space.low, space.high))
        scene.step()
    for _ in range(scene.control_freq):
        agent.set_action(hold_action(agent))
        scene.step()
    speeds = np.abs(agent.qvel[0])
    name = agent.joint_names[int(np.argmax(speeds))]
    scene.close()
    return float(speeds.max()), name


def test_panda_wrist_settles_after_random_actions() -> None:
    """Without the wrist's rotor inertia (armature 0), joint 7 (12 N*m limit, kv = 100,
    about 0.05 kg*m^2) is left in a bang-bang cycle between its torque limits, 0.26 rad/s
    after 10 s of random pd_joint_delta_pos actions and 1 s of holding still: MuJoCo
    integrates the drive's damping implicitly only while the force is inside its range."""
    speed, joint = settled_speed(Panda, "pd_joint_delta_pos", 500)
    assert speed < SETTLE_SPEED, f"{joint} still moves at {speed:.3f} rad/s"


def test_panda_wrist_oscillates_without_armature() -> None:
    """The same motion without the armature shows the cycle (the test above can fail)."""

    class BarePanda(Panda):
        uid = ""
        actuators = (Panda.actuators[0].__class__(**{**vars(Panda.actuators[0]), "armature": None}),)
        keyframes: ClassVar = Panda.keyframes

    speed, joint = settled_speed(BarePanda, "pd_joint_delta_pos", 500)
    assert speed > 0.1 and joint.endswith("panda_joint7")


def test_measure_step_reports_every_claim() -> None:
    result = measure_step(SO100, 500)
    assert [c.name for c in result.claims] == list(CLAIMS)
    assert result.passed, result.claims
    tracking = result.claim("ee_tracking")
    assert tracking is not None and tracking.value < 0.05


def test_sweep_finds_a_failing_coarse_step_and_a_passing_fine_one() -> None:
    """At 40 Hz (two substeps per 20 Hz action) the SO-100's claims fail; at 500 Hz they hold."""
    result = sweep_timestep("so100", substeps=(2, 25), stop_after=None)
    by_freq = {s.sim_freq: s for s in result.steps}
    assert not by_freq[40].passed
    assert by_freq[500].passed
    assert result.largest_passing == 500
    assert "| 40 | 25 |" in result.table()


def test_sweep_rejects_bad_input() -> None:
    with pytest.raises(ConfigError):
        sweep_timestep("so100", substeps=(0,))
    with pytest.raises(ConfigError):
        sweep_timestep(int)  # type: ignore[arg-type]


def test_check_sweep_prints_the_table(monkeypatch: pytest.MonkeyPatch) -> None:
    import robot_agents.tuning.timestep as timestep

    monkeypatch.setattr(timestep, "DEFAULT_SUBSTEPS", (25,))
    real = timestep.sweep_timestep
    monkeypatch.setattr(timestep, "sweep_timestep", lambda cls, stop_after=None: real(cls, substeps=(25,)))
    out = io.StringIO()
    code = cmd_check("so100", out, sweep=True)
    text = out.getvalue()
    assert code == 0 and "| 500 | 2 |" in text and "sim_freq 500 Hz" in text


def test_declared_sim_freq_is_the_default_and_an_explicit_one_wins() -> None:
    class Fast(SO100):
        uid = ""
        sim_freq = 200

    assert Scene(Fast).sim_freq == 200
    assert Scene(Fast, sim_freq=1000).sim_freq == 1000
    assert Scene(SO100).sim_freq == (SO100.sim_freq or DEFAULT_SIM_FREQ)
    assert Scene([Fast, Panda]).sim_freq == max(200, Panda.sim_freq or DEFAULT_SIM_FREQ)


def test_bad_declared_sim_freq_is_a_clean_error() -> None:
    class Bad(SO100):
        uid = ""
        sim_freq = 0

    with pytest.raises(ConfigError, match="sim_freq"):
        Bad.validate_definition()
