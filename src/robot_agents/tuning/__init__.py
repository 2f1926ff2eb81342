"""Tuning a robot's simulation settings from measurements and analysis: the time-step
sweep (:mod:`.timestep`), torque-limit cycles (:mod:`.cycles`) and self-collision pairs
(:mod:`.collisions`)."""

from robot_agents.tuning.cycles import DriveCycleBound, drive_cycle_bounds
from robot_agents.tuning.timestep import ClaimResult, StepResult, SweepResult, sweep_timestep

__all__ = ["ClaimResult", "DriveCycleBound", "StepResult", "SweepResult", "drive_cycle_bounds", "sweep_timestep"]
