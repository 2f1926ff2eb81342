"""The one-env step's own paths (joint-position parts through
:meth:`PDJointPosController.single_apply`, the one-row finiteness test, live views of
the simulation) against the general path: the same bits, arrays safe to keep, bad
actions refused with nothing changed."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra

JOINT_MODES = ("pd_joint_pos", "pd_joint_delta_pos", "pd_joint_target_delta_pos")


def make(uid: str, mode: str) -> ra.RobotEnv:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None).unwrapped
    env.reset(seed=3)
    return env  # type: ignore[return-value]


def actions(env: ra.RobotEnv, count: int) -> list[np.ndarray]:
    """Actions past the bounds too (clipped), of several dtypes and both shapes."""
    space = env.agent.single_action_space
    mid, half = (space.low + space.high) / 2, (space.high - space.low) / 2
    rng = np.random.default_rng(7)
    out = []
    for i in range(count):
        row = mid + half * rng.uniform(-1.5, 1.5, space.shape)
        kind = i % 4
        if kind == 0:
            out.append(row.astype(np.float32))
        elif kind == 1:
            out.append(row.astype(np.float64)[None])
        elif kind == 2:
            out.append(row.astype(np.float16))
        else:
            out.append(np.round(row).astype(np.int64))
    return out


@pytest.mark.parametrize("uid", ["panda", "widowx250s", "so100", "floating_robotiq_2f_85_gripper"])
@pytest.mark.parametrize("mode", JOINT_MODES)
def test_the_one_env_joint_path_matches_the_general_path_bit_for_bit(uid: str, mode: str) -> None:
    fast, general = make(uid, mode), make(uid, mode)
    # the general path: a plan made for this world that has no calls (as for other backends)
    slow_controller = general.agent.controller
    slow_controller._single_sim, slow_controller._single_plan = general.scene.world, None
    for action in actions(fast, 24):
        obs_fast = fast.step(action)[0]
        obs_slow = general.step(action)[0]
        assert obs_fast.tobytes() == obs_slow.tobytes()
        assert fast.scene.world.ctrl.tobytes() == general.scene.world.ctrl.tobytes()
        for name, part in fast.agent.controller.parts.items():
            other = general.agent.controller.parts[name]
            assert part.target_qpos.tobytes() == other.target_qpos.tobytes()  # type: ignore[attr-defined]
    assert fast.agent.controller._single_plan is not None  # the path under test was taken
    assert np.array_equal(fast.get_state()["physics"], general.get_state()["physics"])
    fast.close()
    general.close()


def test_kept_observations_and_targets_are_not_overwritten_by_later_steps() -> None:
    env = make("panda", "pd_joint_target_delta_pos")
    parts = env.agent.controller.parts
    obs = env.step(env.action_space.sample())[0]
    targets = {name: part.target_qpos for name, part in parts.items()}  # type: ignore[attr-defined]
    kept_obs, kept_targets = obs.copy(), {name: t.copy() for name, t in targets.items()}
    new_obs = env.step(np.ones(env.agent.action_space.shape, dtype=np.float32))[0]
    assert np.array_equal(obs, kept_obs) and not np.array_equal(new_obs, kept_obs)
    for name, part in parts.items():
        assert np.array_equal(targets[name], kept_targets[name])
        assert not np.array_equal(part.target_qpos, kept_targets[name])  # type: ignore[attr-defined]
    env.close()


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_one_env_action_is_refused_and_changes_nothing(dtype: type, bad: float) -> None:
    env = make("panda", "pd_joint_delta_pos")
    env.step(np.zeros(8))
    ctrl, targets = env.scene.world.ctrl.copy(), env.agent.drives.get_target_state()
    for action in (np.zeros(8, dtype=dtype), np.zeros((1, 8), dtype=dtype)):
        action[..., 3] = bad
        with pytest.raises(
            ra.ActionError, match=r"expected finite values, got NaN or inf at \(env, index\) \[\[0, 3\]\]"
        ):
            env.step(action)
        assert np.array_equal(env.scene.world.ctrl, ctrl)
        for key, value in env.agent.drives.get_target_state().items():
            assert np.array_equal(value, targets[key])
    env.close()


def test_huge_finite_one_env_actions_overflow_the_sum_and_are_clipped() -> None:
    env = make("panda", "pd_joint_pos")
    hold = env.agent.qpos[0, :8].copy()
    env.step(np.full(8, 1e308))  # the sum overflows: the exact test passes it
    high = env.agent.controller.parts["arm"].raw_high
    assert np.array_equal(env.agent.controller.parts["arm"].target_qpos[0], high)  # type: ignore[attr-defined]
    assert not np.array_equal(hold[:7], high)
    env.close()


def test_live_view_follows_one_env_and_is_read_only() -> None:
    env = make("panda", "pd_joint_delta_pos")
    world = env.scene.world
    view = world.live_view("qpos")
    assert view is not None and view.shape == (1, world.model.nq) and not view.flags.writeable
    before = view.copy()
    env.step(np.ones(8))
    assert np.array_equal(view, world.qpos) and not np.array_equal(view, before)
    env.close()
    batched = ra.make_env("Empty-v1", robot_uids="panda", num_envs=2).unwrapped
    assert batched.scene.world.live_view("qpos") is None  # type: ignore[attr-defined]
    batched.close()


def test_the_instability_tests_dot_is_the_sum_matmul_computes() -> None:
    """``BatchedWorld._step_single`` reads ``qvel.dot(qvel)`` where the batched step reads
    ``qvel @ qvel``: the same bits (huge values overflow alike)."""
    rng = np.random.default_rng(11)
    for n in range(1, 80):
        for _ in range(40):
            qvel = rng.standard_normal(n) * 10.0 ** rng.uniform(-10, 160)
            with np.errstate(over="ignore"):
                assert (qvel @ qvel).tobytes() == qvel.dot(qvel).tobytes()


def test_a_mimic_entry_times_its_multipliers_as_a_float_is_the_broadcast_product() -> None:
    """:meth:`PDJointPosController.single_apply` multiplies a mimic's one action entry,
    read as a Python float, into its ``(1, n)`` multiplier row where the general path
    broadcasts ``(1, 1) * (1, n)``: the same bits (signed zeros, subnormals, huge values)."""
    rng = np.random.default_rng(5)
    specials = [0.0, -0.0, 5e-324, -5e-324, 1e308, -1e308, 1.0, -1.0]
    for n in range(1, 6):
        for _ in range(200):
            multipliers = (rng.standard_normal(n) * 10.0 ** rng.uniform(-3, 3, n))[None]
            multipliers[0, rng.integers(n)] = rng.choice([1.0, -1.0, 0.0, -0.0])
            row = np.empty((1, 3))
            for value in [*specials, *(rng.standard_normal(4) * 10.0 ** rng.uniform(-300, 300, 4))]:
                row[0, 1] = value
                entry = row[:, 1:2]
                with np.errstate(over="ignore"):
                    assert (multipliers * entry.item(0)).tobytes() == (entry * multipliers).tobytes()


def test_the_one_env_empty_step_returns_new_values_and_truncates_at_its_limit() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_joint_delta_pos", max_episode_steps=3).unwrapped
    env.reset(seed=0)
    kept = []
    for step in range(1, 5):
        obs, reward, terminated, truncated, info = env.step(np.zeros(8))
        assert type(reward) is float and reward == 0.0 and terminated is False
        assert type(truncated) is bool and truncated is (step >= 3)
        assert sorted(info) == ["elapsed_steps", "physics_unstable"]
        assert info["elapsed_steps"].dtype == np.int64 and info["elapsed_steps"].tolist() == [step]
        assert info["physics_unstable"].tolist() == [False]
        assert info["elapsed_steps"] is not env.elapsed_steps
        assert info["physics_unstable"] is not env.scene.world.last_step_unstable
        kept.append((obs, info))
    assert [i["elapsed_steps"].tolist() for _, i in kept] == [[1], [2], [3], [4]]  # not overwritten later
    assert len({id(o) for o, _ in kept}) == 4
    env.close()
    ee = ra.make_env("Empty-v1", robot_uids="panda", control_mode="pd_ee_delta_pose", max_episode_steps=None).unwrapped
    ee.reset(seed=0)
    info = ee.step(np.zeros(ee.action_space.shape[-1]))[4]
    assert {"ik_success", "ik_position_error", "ik_rotation_error"} <= set(info)
    assert info["ik_success"].shape == (1,)
    ee.close()


@pytest.mark.parametrize("kind", ["body", "site"])
def test_a_shift_only_tool_offset_writes_the_quaternion_the_product_gives(kind: str) -> None:
    """``pose_entries`` with an offset whose rotation is the identity (the SO-100's jaw)
    writes the frame's own quaternion where no component is zero or not finite: the same
    bits as ``mju_mulQuat`` by the identity, which it still calls otherwise (a zero's sign,
    NaN from inf * 0)."""
    import mujoco

    from robot_agents.envs.state_obs import pose_entries
    from robot_agents.kinematics.forward import FrameKind, FrameRef

    model = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body name="b"><freejoint/><geom size="0.1"/><site name="s"/></body></worldbody></mujoco>'
    )
    data = mujoco.MjData(model)
    offset = (0.00705, -0.09548, 0.0, 1.0, 0.0, 0.0, 0.0)
    frame = FrameRef(FrameKind.BODY if kind == "body" else FrameKind.SITE, 1 if kind == "body" else 0, "x", offset)
    (call,) = pose_entries(frame, data)
    rng = np.random.default_rng(13)
    specials = [0.0, -0.0, np.inf, -np.inf, np.nan, 1e308, -1e308, 5e-324]
    for trial in range(600):
        quat = rng.standard_normal(4)
        for k in rng.choice(4, size=trial % 3, replace=False):
            quat[k] = rng.choice(specials)
        if kind == "body":
            data.xquat[1], data.xpos[1] = quat, rng.standard_normal(3)
            measured, position = data.xquat[1].copy(), data.xpos[1].copy()
        else:
            if not np.isfinite(quat).all() or not quat.any() or np.abs(quat).max() > 1e100:
                continue
            quat /= np.linalg.norm(quat)
            mujoco.mju_quat2Mat(data.site_xmat[0], quat)
            data.site_xpos[0] = rng.standard_normal(3)
            measured, position = np.empty(4), data.site_xpos[0].copy()
            mujoco.mju_mat2Quat(measured, data.site_xmat[0])
        expected_position, expected_quat, shifted = np.empty(3), np.empty(4), np.empty(3)
        mujoco.mju_rotVecQuat(shifted, np.array(offset[:3]), measured)
        np.add(position, shifted, out=expected_position)
        mujoco.mju_mulQuat(expected_quat, measured, np.array(offset[3:]))
        got_position, got_quat = call()
        assert got_position.tobytes() == expected_position[None].tobytes()
        assert got_quat.tobytes() == expected_quat[None].tobytes(), (quat, got_quat, expected_quat)
