"""A scene left where the time-step sweep's random-action claim leaves it, for tests
that look at what happens next (the settle hold, contacts pressed by the actions)."""

from __future__ import annotations

import robot_agents as ra
from robot_agents.checks import run_random_actions
from robot_agents.sim.scene import Scene
from robot_agents.tuning.claims import RANDOM_SECONDS


def after_random_actions(
    cls: type[ra.Agent], mode: str, sim_freq: int, seed: int = 0, seconds: float = RANDOM_SECONDS
) -> Scene:
    """A reset scene of ``cls`` in ``mode`` at ``sim_freq`` after ``seconds`` of uniform
    random actions drawn with ``seed`` (the sweep's random claim: 10 s)."""
    scene = Scene(cls, control_modes=mode, sim_freq=sim_freq)
    scene.reset()
    run_random_actions(scene, seconds, seed)
    return scene
