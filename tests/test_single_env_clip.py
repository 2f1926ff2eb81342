"""The one-env planned call of a joint-position part with a zero joint limit (Fetch's
body, Stretch's arm, Spot's arm) clips its targets in one pass when the combined
controller's raw entries cannot be ``-0.0``: bit for bit the general path's two-pass
``maximum`` / ``minimum``, with measured positions, previous targets and actions at
``-0.0``, ``0.0``, on the zero bound, past it, and where a sum cancels to zero."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.controllers.joint import PDJointPosController, _has_negative_zero
from tests.special_values import edge_cases

#: (robot, part): parts whose joint limits include a zero bound.
ZERO_BOUND_PARTS = [("fetch", "body"), ("stretch", "arm"), ("spot", "arm")]
MODES = ("pd_joint_pos", "pd_joint_delta_pos", "pd_joint_target_delta_pos")


@pytest.mark.parametrize(("uid", "name"), ZERO_BOUND_PARTS)
@pytest.mark.parametrize("mode", MODES)
def test_one_pass_clip_with_a_zero_bound_matches_the_general_path(uid: str, name: str, mode: str) -> None:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None).unwrapped
    env.reset(seed=0)
    world, combined = env.scene.world, env.agent.controller
    part = combined.parts[name]
    assert isinstance(part, PDJointPosController)
    assert part._clip and not part._one_pass_clip  # a zero bound: the general path clips in two passes
    assert np.any(part._lower_limit == 0.0) or np.any(part._upper_limit == 0.0)
    combined._plan_single(world)
    plan = combined._single_plan
    assert plan is not None
    call = plan[list(combined.parts).index(name)]
    part_slice = combined.slices[name]
    for k, measured, entry, previous, action, start_target in edge_cases(world, combined, name):
        combined._to_raw_single(action)
        call()
        fast = part.target_qpos.copy()
        part.target_qpos = start_target.copy()
        part.apply(combined._raw_single[:, part_slice].copy(), world)
        general = part.target_qpos
        assert fast.tobytes() == general.tobytes(), (k, measured, entry, previous, fast, general)
    env.close()


def test_negative_zero_offsets_or_bounds_keep_the_two_pass_clip() -> None:
    """The one-pass clip needs raw entries that cannot be ``-0.0``: an offset of
    ``-0.0`` (its sum keeps a ``-0.0`` entry) or a ``-0.0`` bound leaves the part on
    the two-pass clip, whose targets then equal the general path's too."""
    assert _has_negative_zero(np.array([1.0, -0.0])) and not _has_negative_zero(np.array([0.0, -1.0, 2.0]))
    env = ra.make_env("Empty-v1", robot_uids="spot", control_mode="pd_joint_delta_pos", max_episode_steps=None)
    env = env.unwrapped
    env.reset(seed=0)
    world, combined = env.scene.world, env.agent.controller
    part = combined.parts["arm"]
    part_slice = combined.slices["arm"]
    combined._offset_row[0, part_slice] = -0.0  # x + -0.0 keeps x: the same raw values, -0.0 kept
    combined._plan_single(world)
    plan = combined._single_plan
    assert plan is not None
    call = plan[list(combined.parts).index("arm")]
    data = world.physics_sources()[0]
    data.qpos[np.asarray(part.binding.qpos_adr)] = -0.0  # -0.0 + -0.0: a -0.0 target on the zero bound
    world.invalidate()
    action = np.zeros((1, combined.action_dim))
    action[0, part_slice] = -0.0
    combined._to_raw_single(action)
    assert np.all(np.signbit(combined._raw_single[0, part_slice]))  # -0.0 entries reach the part
    call()
    fast = part.target_qpos.copy()
    part.apply(combined._raw_single[:, part_slice].copy(), world)
    assert fast.tobytes() == part.target_qpos.tobytes()
    env.close()


def test_the_planned_call_takes_the_one_pass_clip_only_without_negative_zeros(monkeypatch: pytest.MonkeyPatch) -> None:
    """The guard itself (with this NumPy both clips agree even on zeros of opposite signs,
    so equal targets cannot tell them apart): Spot's arm, whose limits have a zero bound,
    clips in one pass (``clip_ufunc``) when its raw entries cannot be ``-0.0``, and in
    two when an offset of ``-0.0`` can carry one."""
    import robot_agents.controllers.joint as joint

    one_pass_calls = []
    clip = joint.clip_ufunc

    def counted(*args: object) -> object:
        one_pass_calls.append(1)
        return clip(*args)

    monkeypatch.setattr(joint, "clip_ufunc", counted)
    for negative_zero_offsets, expected in ((False, 1), (True, 0)):
        env = ra.make_env("Empty-v1", robot_uids="spot", control_mode="pd_joint_delta_pos", max_episode_steps=None)
        env = env.unwrapped
        env.reset(seed=0)
        world, combined = env.scene.world, env.agent.controller
        part_slice = combined.slices["arm"]
        if negative_zero_offsets:
            combined._offset_row[0, part_slice] = -0.0
        combined._plan_single(world)
        plan = combined._single_plan
        assert plan is not None
        call = plan[list(combined.parts).index("arm")]
        combined._to_raw_single(np.zeros((1, combined.action_dim)))
        one_pass_calls.clear()
        call()
        assert len(one_pass_calls) == expected, (negative_zero_offsets, one_pass_calls)
        env.close()
