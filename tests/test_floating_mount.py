"""The floating grippers' ``pd_ee_pose`` box covers every tool position their mount
reaches, and no more than it (robot_agents.robots.floating_mount.reachable_box)."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.robots.floating_mount import SLIDE_TRAVEL

UIDS = ("floating_panda_gripper", "floating_robotiq_2f_85_gripper")
#: How close (m) the box's faces are to the farthest sampled tool points.
TIGHTNESS = 0.005  # measured gaps: at most 1.9 mm (Franka Hand), 0.66 mm (2F-85)


def bounds(agent: ra.Agent) -> tuple[np.ndarray, np.ndarray]:
    box = type(agent).parts[0].task_space.position_bounds
    return np.asarray(box.lower), np.asarray(box.upper)


@pytest.mark.parametrize("uid", UIDS)
def test_the_tool_offset_is_the_models(uid: str) -> None:
    scene = ra.Scene(uid)
    scene.reset()
    agent = scene.agents[0]
    q = np.asarray(agent.keyframe_qpos("rest"), dtype=np.float64).copy()
    q[:6] = 0.0
    offset = float(np.linalg.norm(agent.frame_pose("tcp", q, relative_to="root")[0, :3]))
    lower, upper = bounds(agent)
    np.testing.assert_allclose(upper, SLIDE_TRAVEL + offset, atol=1e-9)
    np.testing.assert_allclose(lower, -(SLIDE_TRAVEL + offset), atol=1e-9)


@pytest.mark.parametrize("uid", UIDS)
def test_every_reachable_tool_position_is_inside_and_the_box_is_tight(uid: str) -> None:
    scene = ra.Scene(uid)
    scene.reset()
    agent = scene.agents[0]
    rest = np.asarray(agent.keyframe_qpos("rest"), dtype=np.float64)
    low, high = scene.model.jnt_range[:6].T  # the mount's slides then hinges
    rng = np.random.default_rng(0)
    n = 4000
    q = np.tile(rest, (n, 1))
    q[:, :6] = rng.uniform(low, high, size=(n, 6))
    # and the corners with the tool turned along each axis: the faces' points
    signs = rng.choice([-1.0, 1.0], size=(n // 4, 3))
    q[: n // 4, :3] = signs * high[:3]
    points = np.vstack([agent.frame_pose("tcp", row, relative_to="root")[0, :3] for row in q])
    lower, upper = bounds(agent)
    assert np.all(points >= lower - 1e-9) and np.all(points <= upper + 1e-9)
    # tight: on every face some sampled point lies within TIGHTNESS of it
    assert np.all(upper - points.max(axis=0) < TIGHTNESS), (upper, points.max(axis=0))
    assert np.all(points.min(axis=0) - lower < TIGHTNESS), (lower, points.min(axis=0))
    # the old +-1 m box missed some of them
    assert np.any(np.abs(points) > SLIDE_TRAVEL)
