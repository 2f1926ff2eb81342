"""The one-env step of the mobile robots through the parts' planned calls (the base's
velocities through :meth:`PDBaseVelController.single_apply`, an arm's joint velocities
through :meth:`PDJointVelController.single_apply`, joint positions whose drive columns
lie apart through ``put``; the base's pose read from the live ``qpos`` before and after
the physics) against the general path of one env and env 0 of a batch: the same bits,
with base commands that turn, stand still or are ``-0.0``."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.controllers.base_vel import PDBaseVelController

MOBILE = ("fetch", "google_robot", "stretch", "spot")
MODES = ("pd_joint_pos", "pd_joint_delta_pos", "pd_joint_target_delta_pos", "pd_joint_vel")


def make(uid: str, mode: str, num_envs: int = 1, **options: Any) -> ra.RobotEnv:
    env = ra.make_env(
        "Empty-v1", robot_uids=uid, control_mode=mode, num_envs=num_envs, max_episode_steps=None, **options
    ).unwrapped
    env.reset(seed=[3] * num_envs if num_envs > 1 else 3)
    return env  # type: ignore[return-value]


def actions(env: ra.RobotEnv, count: int) -> list[np.ndarray]:
    """Random actions (past the bounds too: clipped) whose base entries cycle through
    standing still, ``-0.0``, driving straight, turning on the spot both ways, driving
    while turning and the bounds."""
    space = env.agent.single_action_space
    base = env.agent.controller.slices["base"]
    low, high = space.low[base].astype(np.float64), space.high[base].astype(np.float64)
    straight = np.zeros_like(low)
    straight[0] = 0.7 * high[0]
    turn = np.zeros_like(low)
    turn[-1] = 0.9 * high[-1]
    commands = [
        np.zeros_like(low),
        np.full_like(low, -0.0),
        straight,
        turn,
        -turn,
        straight + turn,
        straight - 0.5 * turn,
        high,
        low,
        None,  # random
    ]
    mid, half = (space.low + space.high) / 2, (space.high - space.low) / 2
    rng = np.random.default_rng(5)
    out = []
    for i in range(count):
        row = (mid + half * rng.uniform(-1.3, 1.3, space.shape)).astype(np.float64)
        command = commands[i % len(commands)]
        if command is not None:
            row[base] = command
        out.append(row.astype(np.float32) if i % 3 == 0 else row)
    return out


def state_bytes(value: Any) -> bytes:
    """The exact bytes of a (nested) state: arrays by their bits (-0.0 and 0.0 differ)."""
    if isinstance(value, Mapping):
        return b"{" + b",".join(repr(k).encode() + b":" + state_bytes(v) for k, v in value.items()) + b"}"
    if isinstance(value, (list, tuple)):
        return b"[" + b",".join(state_bytes(v) for v in value) + b"]"
    if isinstance(value, np.ndarray):
        return str(value.dtype).encode() + str(value.shape).encode() + np.ascontiguousarray(value).tobytes()
    return repr(value).encode()


def targets(env: ra.RobotEnv) -> bytes:
    parts = env.agent.controller.parts.values()
    return b"".join(
        np.ascontiguousarray(getattr(part, key)[:1]).tobytes()
        for part in parts
        for key in ("target_qpos", "target_qvel")
        if hasattr(part, key)
    )


@pytest.mark.parametrize("uid", MOBILE)
@pytest.mark.parametrize("mode", MODES)
def test_the_one_env_mobile_path_matches_the_general_path_bit_for_bit(uid: str, mode: str) -> None:
    fast, general = make(uid, mode), make(uid, mode)
    batch = make(uid, mode, num_envs=2)
    # the general path: a plan made for this world that has no calls (as for other backends)
    slow_controller = general.agent.controller
    slow_controller._single_sim, slow_controller._single_plan = general.scene.world, None
    for action in actions(fast, 30):
        obs_fast = fast.step(action)[0]
        obs_slow = general.step(action)[0]
        obs_batch = batch.step(np.repeat(np.atleast_2d(action), 2, axis=0))[0]
        assert obs_fast.tobytes() == obs_slow.tobytes() == obs_batch[:1].tobytes()
        assert fast.scene.world.ctrl.tobytes() == general.scene.world.ctrl.tobytes()
        assert fast.scene.world.ctrl.tobytes() == batch.scene.world.ctrl[:1].tobytes()
        assert fast.scene.world.qpos.tobytes() == batch.scene.world.qpos[:1].tobytes()
        assert targets(fast) == targets(general) == targets(batch)
    plan = fast.agent.controller._single_plan
    assert plan is not None and len(plan) == len(fast.agent.controller.parts)  # the path under test was taken
    assert state_bytes(fast.get_state()) == state_bytes(general.get_state())
    for env in (fast, general, batch):
        env.close()


def test_a_kinematic_base_and_its_wheels_move_alike_on_both_paths() -> None:
    """Fetch with a kinematic base: the move written after the physics, and the wheels."""
    fast = make("fetch", "pd_joint_delta_pos", base_dynamics="kinematic")
    general = make("fetch", "pd_joint_delta_pos", base_dynamics="kinematic")
    slow_controller = general.agent.controller
    slow_controller._single_sim, slow_controller._single_plan = general.scene.world, None
    start = fast.agent.base_pose.copy()
    for action in actions(fast, 20):
        assert fast.step(action)[0].tobytes() == general.step(action)[0].tobytes()
        assert fast.scene.world.qpos.tobytes() == general.scene.world.qpos.tobytes()
        assert fast.scene.world.qvel.tobytes() == general.scene.world.qvel.tobytes()
    assert fast.agent.controller._single_plan is not None
    assert not np.array_equal(fast.agent.base_pose, start)  # it moved
    assert state_bytes(fast.get_state()) == state_bytes(general.get_state())
    fast.close()
    general.close()


def test_kept_velocity_targets_are_not_overwritten_by_later_steps() -> None:
    env = make("fetch", "pd_joint_vel")
    parts = env.agent.controller.parts
    env.step(np.full(env.agent.action_space.shape, 0.5))
    kept = {name: part.target_qvel for name, part in parts.items() if hasattr(part, "target_qvel")}
    copies = {name: t.copy() for name, t in kept.items()}
    assert set(kept) == {"arm", "base"}
    env.step(np.full(env.agent.action_space.shape, -0.5))
    for name, target in kept.items():
        assert np.array_equal(target, copies[name])
        assert not np.array_equal(parts[name].target_qvel, copies[name])  # type: ignore[attr-defined]
    env.close()


def test_the_base_without_a_turn_keeps_a_negative_zero_yaw() -> None:
    """At yaw ``-0.0`` a command without a turn heads along ``-0.0`` (``cos`` 1, ``sin``
    ``-0.0``), as the batched ``_heading`` does: the lateral target of a forward
    command is ``-0.0 * v``; with a turn the heading is ``yaw + w dt / 2``."""
    env = make("stretch", "pd_joint_delta_pos")
    base = env.agent.controller.parts["base"]
    assert isinstance(base, PDBaseVelController)
    qpos = np.zeros((1, env.scene.world.model.nq))
    qpos[0, base._yaw_adr] = -0.0
    raw = np.zeros((1, 2))
    call = base.single_apply(raw, qpos)
    assert call is not None
    for command in ([0.3, 0.0], [0.3, -0.0], [0.3, 0.5], [-0.2, -0.5], [0.0, 0.0]):
        raw[0] = command
        call()
        fast = base.target_qvel.copy()
        base._apply_single(raw.copy(), type("Sim", (), {"qpos": qpos})())  # type: ignore[arg-type]
        assert fast.tobytes() == base.target_qvel.tobytes()
        cos, sin, share = base._heading(qpos[:, base._yaw_adr].repeat(2), raw[:, -1].repeat(2))
        forward = raw[0, 0] * share[0]
        expected = np.array([[cos[0] * forward - sin[0] * 0.0, sin[0] * forward + cos[0] * 0.0, raw[0, -1]]])
        assert fast.tobytes() == expected.tobytes()
    env.close()
