"""The batched simulation: one compiled model, ``num_envs`` independent MjData."""

from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, DEFAULT_SIM_FREQ, Scene
from robot_agents.sim.world import BatchedWorld

__all__ = ["DEFAULT_CONTROL_FREQ", "DEFAULT_SIM_FREQ", "BatchedWorld", "Scene"]
