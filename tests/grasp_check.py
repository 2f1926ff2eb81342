"""One grasp-lift-hold check for the robots' tests: the fingers open around a cube on a
pedestal, close, lift it 10 cm over 1 s and hold it 2 s, then open and let it drop.
Each step is checked with numbers: ``is_grasping``, the finger forces against the
cube's weight, the lift height, the cube staying at the tool."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import pytest

import robot_agents as ra

#: ``act(arm_target, gripper)``: one control step with the arm's part of the action and
#: the gripper's (+1 opens, -1 closes).
Act = Callable[[np.ndarray, float], None]


def assert_grasps_lifts_and_holds(
    scene: ra.Scene,
    act: Act,
    grasp: np.ndarray,
    lift: np.ndarray,
    fingers: Sequence[Sequence[str]],
    cube_mass: float,
    min_force: float,
    after_close: Callable[[], None] | None = None,
    held_at: str | None = None,
) -> None:
    """``grasp`` / ``lift``: the arm's action at the cube and 10 cm above it; ``fingers``:
    the bodies of each of the two fingers (names with the robot's prefix); the cube
    and the pedestal are the scene's props ``cube`` and ``pedestal``. ``min_force``
    (N): each finger's smallest squeeze; ``after_close`` runs robot-specific checks
    once the fingers are closed; ``held_at``: the robot's frame the cube stays at
    (within 1 cm; default: the tool frame)."""
    agent = scene.agents[0]
    for _ in range(10):
        act(grasp, 1.0)
    assert not agent.is_grasping("cube")[0]
    for _ in range(20):  # close for 1 s
        act(grasp, -1.0)
    assert agent.is_grasping("cube")[0]
    if after_close is not None:
        after_close()

    body_ids = [[int(scene.model.body(name).id) for name in finger] for finger in fingers]
    pedestal, cube = int(scene.model.body("pedestal").id), int(scene.model.body("cube").id)
    weight = [0.0, 0.0, cube_mass * 9.81]
    first, second, under = scene.world.contact_forces([*body_ids, [pedestal]], cube)[0]
    assert np.linalg.norm(first) > min_force
    assert np.linalg.norm(first) == pytest.approx(np.linalg.norm(second), rel=0.1)
    np.testing.assert_allclose(first + second + under, weight, atol=0.05)
    start = scene.body_pose("cube")[0, :3]

    for i in range(60):  # lift 10 cm over 1 s, hold 2 s
        blend = min(1.0, (i + 1) / 20)
        act(grasp + blend * (lift - grasp), -1.0)
    cube_pose = scene.body_pose("cube")[0]
    assert cube_pose[2] - start[2] == pytest.approx(0.1, abs=0.01)
    held = agent.tcp_pose[0, :3] if held_at is None else agent.frame_pose(held_at)[0, :3]
    assert np.linalg.norm(cube_pose[:3] - held) < 0.01  # still between the fingers
    assert agent.is_grasping("cube")[0]
    first, second, under = scene.world.contact_forces([*body_ids, [pedestal]], cube)[0]
    assert not np.any(under)
    np.testing.assert_allclose(first + second, weight, atol=0.05)  # the fingers carry it

    for _ in range(10):  # open: the cube drops
        act(lift, 1.0)
    assert not agent.is_grasping("cube")[0]
