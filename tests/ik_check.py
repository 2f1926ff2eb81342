"""One IK reachability check for every robot's tests: targets are the tool frame's pose
at random arm configurations (so they are reachable); the solver starts at the scene's
current pose and must land within 1 mm and 1 deg, inside the joint limits."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

import robot_agents as ra
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.kinematics.rotations import rotation_error


def assert_ik_reaches_random_targets(
    scene: ra.Scene,
    arm_joints: Sequence[str],
    frame_name: str,
    count: int,
    seed: int,
    margin: float = 0.0,
    restarts: int = 50,
) -> None:
    """``count`` random configurations of ``arm_joints`` drawn ``margin`` (rad or m)
    inside their limits; every solution within 1 mm / 1 deg of its target and inside
    the limits."""
    agent = scene.agents[0]
    arm = np.array([agent.joint_names.index(name) for name in arm_joints])
    limits = agent.qpos_limits[arm]
    frame = resolve_frame(scene.model, frame_name, agent.prefix)
    solver = IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], limits)
    rng = np.random.default_rng(seed)
    context = np.repeat(scene.world.qpos, count, axis=0)
    configurations = context.copy()
    configurations[:, agent.qpos_adr[arm]] = rng.uniform(
        limits[:, 0] + margin, limits[:, 1] - margin, (count, len(arm))
    )
    targets = agent.kinematics.pose(configurations, frame)
    start = np.repeat(agent.qpos[:, arm], count, axis=0)
    result = solver.solve(context, targets, start, max_iterations=200, restarts=restarts)
    assert result.success.all(), np.flatnonzero(~result.success)
    configurations[:, agent.qpos_adr[arm]] = result.qpos
    reached = agent.kinematics.pose(configurations, frame)
    assert np.max(np.linalg.norm(reached[:, :3] - targets[:, :3], axis=1)) < 1e-3
    assert np.max(np.linalg.norm(rotation_error(reached[:, 3:], targets[:, 3:]), axis=1)) < math.radians(1)
    assert np.all(result.qpos >= limits[:, 0]) and np.all(result.qpos <= limits[:, 1])
