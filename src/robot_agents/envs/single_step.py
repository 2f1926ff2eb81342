"""The planned one-env step of :class:`~robot_agents.envs.base_env.RobotEnv`: one robot
in a task without hooks (no reward, metrics or termination), a float action, and an
active control mode without substep hooks whose parts all have one-env calls: either
joint-position parts with a fused one-env call (:attr:`CombinedController.single_values
<robot_agents.controllers.combined.CombinedController.single_values>`), or parts that
report in ``info`` (end-effector parts: ``ik_success`` ...) through their own one-env
calls (:meth:`CombinedController._plan_single
<robot_agents.controllers.combined.CombinedController._plan_single>`), taken as
``CombinedController.set_action`` takes them.

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
    # the active controller the plan is for, its fused call (None: not that path), the
    # two action shapes it takes, (A,) and (1, A), the observation reading the parts'
    # targets from the drives' row (None: the env's), and for reporting parts (no fused
    # call) what reports their info (None: not that path)
    plan: list[Any] = [None, None, None, None, None, None]
    ndarray, isfinite = np.ndarray, math.isfinite

    def replan(active: CombinedController) -> None:
        fused = reading = report = None
        if not active.needs_substep:  # no substep hooks
            if active._single_sim is not world:  # (what CombinedController.set_action does first)
                active._plan_single(world)
            if not active._reporting:  # info reports nothing: the fused call, where the parts have one
                fused, targets = active.single_values, active.single_targets
                if fused is not None and targets is not None:
                    reading = observation.single_state_reading(list(active.parts.values()), targets)
            elif active._single_plan is not None and not active._checked:
                # the parts' own calls (ControlModes.checked_action has no part's check to
                # make); Agent.step_info is the mode's (a hookless robot has no planar
                # base), CombinedController.step_info its one reporting part's
                reporting = active._reporting
                report = reporting[0].step_info if len(reporting) == 1 else active.step_info
        plan[:] = [active, fused, (active.action_dim,), (1, active.action_dim), reading, report]

    def step(action: Any) -> StepResult | None:
        active = control.active
        if active is not plan[0] or active._single_sim is not world:  # (a part's calls made again: plan again)
            replan(active)
        fused, report = plan[1], plan[5]
        calls = active._single_plan if report is not None else None
        if (fused is None and calls is None) or action.__class__ is not ndarray:
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
        if fused is not None:
            fused(values)  # targets and controls (CombinedController.set_action's one-env path)
        elif calls is not None:  # CombinedController.set_action's one-env path with the parts' own calls
            active._to_raw_single(action if shape == plan[3] else action[None])
            for call in calls:
                call()
            active.drives.write(world.ctrl)
        world._step_single()  # Scene.step -> BatchedWorld.step for one hookless robot
        elapsed, unstable = env.elapsed_steps, world.last_step_unstable
        count = elapsed.item(0) + 1  # (RobotEnv.step's one-env lines from here on)
        elapsed[0] = count
        if env.raise_on_instability and unstable[0]:
            env._raise_unstable(unstable)
        info: dict[str, Any] = {"elapsed_steps": elapsed.copy(), "physics_unstable": unstable.copy()}
        limit = env.max_episode_steps
        if report is not None:  # (RobotEnv.step's one-robot info and observation)
            info.update(report())
            return env._get_obs(), 0.0, False, limit is not None and bool(count >= limit), info
        reading = plan[4]
        obs = reading() if reading is not None and env._get_obs is observe else env._get_obs()
        return obs, 0.0, False, limit is not None and bool(count >= limit), info

    return step
