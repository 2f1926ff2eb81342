"""The planned one-env step of :class:`~robot_agents.envs.base_env.RobotEnv`: one robot
in a task without hooks (no reward, metrics or termination), its active control mode's
parts all joint-position parts with a fused one-env call
(:attr:`CombinedController.single_values
<robot_agents.controllers.combined.CombinedController.single_values>`), a float action.

:func:`plain_single_step` makes a call that does what ``RobotEnv.step`` does on that
path (the action's checks, the targets and controls, the physics step, the step count,
``info`` and the observation), in the same order with the same operations, without the
calls between the layers (``Agent.set_action``, ``ControlModes.checked_action``,
``CombinedController.set_action``, ``Scene.step``, ``BatchedWorld.step``,
``Agent.step_info``). It returns ``None``, having changed nothing, for whatever it does
not take (another dtype or shape, a list, a non-finite or overflowing sum, a closed
world, another mode): ``RobotEnv.step`` then takes its general path, which applies the
action or raises as it always did.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from robot_agents.agent import Agent
from robot_agents.sim.world import BatchedWorld

if TYPE_CHECKING:
    from robot_agents.controllers.combined import CombinedController
    from robot_agents.envs.base_env import RobotEnv

#: ``RobotEnv.step``'s five values (observation, reward, terminated, truncated, info).
StepResult = tuple[Any, float, bool, bool, dict[str, Any]]


def plain_single_step(env: RobotEnv) -> Callable[[Any], StepResult | None] | None:
    """``env``'s planned one-env step (module doc), a call of the action; ``None`` where
    ``env`` has more than one env or robot, task hooks, a robot class with its own
    ``set_action``, ``step_info`` or step hooks (a mobile base), or another backend.
    The call plans itself again whenever the robot's active control mode changes."""
    scene = env.scene
    world = scene.world
    agent = env._agent0
    if (
        not (env._single and env._plain_task and env._one_robot)
        or not isinstance(world, BatchedWorld)
        or agent.world is not world
        or not scene._hookless_single
        or type(agent).set_action is not Agent.set_action
        or type(agent).step_info is not Agent.step_info
    ):
        return None
    control = agent.control
    observation = env._observation
    observe = observation.observe  # the env's own observation (a wrapper put in its place is called instead)
    # the active controller the plan is for, its fused call (None: not this path), the
    # two action shapes it takes, (A,) and (1, A), and the observation reading the
    # parts' targets from the drives' row (None: the env's)
    plan: list[Any] = [None, None, None, None, None]
    ndarray, isfinite = np.ndarray, math.isfinite

    def replan(active: CombinedController) -> None:
        fused = reading = None
        if not active.needs_substep and not active._reporting:  # no substep hooks; info reports nothing
            if active._single_sim is not world:  # (what CombinedController.set_action does first)
                active._plan_single(world)
            fused, targets = active.single_values, active.single_targets
            if fused is not None and targets is not None:
                reading = observation.single_state_reading(list(active.parts.values()), targets)
        plan[:] = [active, fused, (active.action_dim,), (1, active.action_dim), reading]

    def step(action: Any) -> StepResult | None:
        active = control.active
        if active is not plan[0]:
            replan(active)
        fused = plan[1]
        if fused is None or action.__class__ is not ndarray:
            return None
        dtype = action.dtype
        if dtype.kind != "f" or dtype.itemsize > 8:  # (long double: rounded first by the general path)
            return None
        shape = action.shape
        if shape == plan[2]:
            values = action.tolist()
        elif shape == plan[3]:
            values = action.tolist()[0]
        else:
            return None
        # ControlModes.checked_action's one-env test (a finite sum: every entry finite;
        # an overflowing one, or NaN / inf, goes to the general path's exact check)
        if not isfinite(sum(values)) or world.closed:
            return None
        fused(values)  # targets and controls (CombinedController.set_action's one-env path)
        world._step_single()  # Scene.step -> BatchedWorld.step for one hookless robot
        elapsed, unstable = env.elapsed_steps, world.last_step_unstable
        count = elapsed.item(0) + 1  # (RobotEnv.step's one-env lines from here on)
        elapsed[0] = count
        if env.raise_on_instability and unstable[0]:
            env._raise_unstable(unstable)
        info: dict[str, Any] = {"elapsed_steps": elapsed.copy(), "physics_unstable": unstable.copy()}
        limit = env.max_episode_steps
        reading = plan[4]
        obs = reading() if reading is not None and env._get_obs is observe else env._get_obs()
        return obs, 0.0, False, limit is not None and bool(count >= limit), info

    return step
