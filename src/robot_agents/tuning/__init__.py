"""Tuning a robot's simulation settings from measurements (the time-step sweep)."""

from robot_agents.tuning.timestep import ClaimResult, StepResult, SweepResult, sweep_timestep

__all__ = ["ClaimResult", "StepResult", "SweepResult", "sweep_timestep"]
