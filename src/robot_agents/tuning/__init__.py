"""Tuning a robot's simulation settings from measurements and analysis: the time-step
sweep (:mod:`.timestep`; the claims it measures: :mod:`.claims`), torque-limit cycles (:mod:`.cycles`), self-collision pairs
(:mod:`.collisions`) and drives' step responses (:mod:`.step_response`)."""

from robot_agents.tuning.claims import ClaimResult, StepResult, measure_step, scene_setup
from robot_agents.tuning.cycles import DriveCycleBound, drive_cycle_bounds
from robot_agents.tuning.step_response import StepResponse, step_responses
from robot_agents.tuning.timestep import SweepResult, sweep_timestep

__all__ = [
    "ClaimResult",
    "DriveCycleBound",
    "StepResponse",
    "StepResult",
    "SweepResult",
    "drive_cycle_bounds",
    "measure_step",
    "scene_setup",
    "step_responses",
    "sweep_timestep",
]
