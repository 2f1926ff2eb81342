"""The fused one-env call of joint-position parts (:meth:`CombinedController._fuse_single`:
every part's targets on Python floats) and the planned one-env env step
(:mod:`robot_agents.envs.single_step`) against the parts' own one-env calls and the
general path: the same bits in every result, through mode switches, resets, restored
states and actions of every dtype, shape and kind; bad actions refused as before, with
nothing changed."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.controllers.combined import CombinedController, _part_targets
from robot_agents.controllers.joint import PDJointPosController
from tests.special_values import edge_cases

JOINT_MODES = ("pd_joint_pos", "pd_joint_delta_pos", "pd_joint_target_delta_pos")
FUSED_ROBOTS = (
    "panda",
    "widowx250s",
    "so100",
    "floating_panda_gripper",
    "koch-v1.1",
    "ur_10e",
    "floating_robotiq_2f_85_gripper",
)


def make(uid: str, mode: str | None = None, **kwargs: Any) -> ra.RobotEnv:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None, **kwargs).unwrapped
    env.reset(seed=3)
    return env  # type: ignore[return-value]


def controllers(env: ra.RobotEnv) -> list[CombinedController]:
    """Every mode's controller of the env's robot, built now."""
    control = env.agent.control
    return [control.controller_for(mode) for mode in control.modes]


def without_fusion(env: ra.RobotEnv) -> ra.RobotEnv:
    """``env`` stepping through the parts' own one-env calls (no planned step, no fused call)."""
    env._planned_step = None
    for controller in controllers(env):
        controller._plan_single(env.scene.world)
        controller.single_values = None
    return env


def general(env: ra.RobotEnv) -> ra.RobotEnv:
    """``env`` on the general path (plans made for this world that have no calls)."""
    env._planned_step = None
    for controller in controllers(env):
        controller._single_sim, controller._single_plan, controller.single_values = env.scene.world, None, None
    return env


def counting(env: ra.RobotEnv) -> list[str]:
    """The modes whose fused call ``env`` makes, one entry per call."""
    calls: list[str] = []
    for controller in controllers(env):
        controller._plan_single(env.scene.world)
        fused = controller.single_values
        if fused is not None:

            def counted(values: list[float], fused: Any = fused, mode: str = controller.mode) -> None:
                calls.append(mode)
                fused(values)

            controller.single_values = counted
    return calls


def snapshot(env: ra.RobotEnv) -> list[bytes]:
    """Every array a step writes, as bytes."""
    out = [env.scene.world.ctrl.tobytes(), env.get_state()["physics"].tobytes(), env.elapsed_steps.tobytes()]
    out += [value.tobytes() for value in env.agent.drives.get_target_state().values()]
    for part in env.agent.controller.parts.values():
        if isinstance(part, PDJointPosController):
            out += [part.target_qpos.tobytes(), part._previous_target.tobytes()]
    return out


def result_bytes(result: tuple[Any, ...]) -> list[Any]:
    obs, reward, terminated, truncated, info = result
    return [obs.tobytes(), obs.dtype, obs.shape, reward, terminated, truncated] + [
        (key, np.asarray(value).tobytes(), np.asarray(value).dtype) for key, value in sorted(info.items())
    ]


def action_kinds(env: ra.RobotEnv, rng: np.random.Generator, i: int) -> Any:
    """An action past the bounds too, of a dtype, shape and kind chosen by ``i``: float32,
    float64, float16, int64, a list, ``(A,)`` and ``(1, A)``, with ``-0.0``, zero and
    bound entries, and huge finite values (whose sum overflows)."""
    space = env.agent.single_action_space
    mid, half = (space.low.astype(np.float64) + space.high) / 2, (space.high.astype(np.float64) - space.low) / 2
    row = mid + half * rng.uniform(-1.5, 1.5, space.shape)
    pick = rng.integers(len(row))
    if i % 5 == 1:
        row[pick] = -0.0
    elif i % 5 == 2:
        row[:] = 0.0
    elif i % 5 == 3:
        row[pick] = space.high[pick]
    if i % 11 == 10:  # (float64 only: a float32 or an int64 cannot hold them)
        row[:] = 1e308
        return row if i % 2 else row[None]
    kind = i % 7
    if kind == 0:
        return row.astype(np.float32)
    if kind == 1:
        return row[None]
    if kind == 2:
        return row.astype(np.float16)
    if kind == 3:
        return np.round(row).astype(np.int64)
    if kind == 4:
        return row.tolist()
    if kind == 5:
        return row.astype(np.float32)[None]
    return row


@pytest.mark.parametrize("uid", FUSED_ROBOTS)
def test_the_planned_step_matches_the_parts_calls_and_the_general_path(uid: str) -> None:
    envs = [make(uid, "pd_joint_delta_pos") for _ in range(3)]
    calls = counting(envs[0])
    without_fusion(envs[1])
    general(envs[2])
    modes = [m for m in (*JOINT_MODES, "pd_ee_delta_pos", "pd_joint_vel") if m in envs[0].agent.control.modes]
    rng = np.random.default_rng(5)
    saved: list[dict[str, Any]] = []
    for i in range(150):
        if i % 25 == 24:  # a mode switch (an end-effector or velocity mode too, then back)
            for env in envs:
                env.set_control_mode(modes[(i // 25) % len(modes)])
        if i == 40:
            saved = [env.get_state() for env in envs]
        if i == 90:
            for env in envs:
                env.reset(seed=11)
        if i == 120:  # back to the state of step 40 (its mode too), then on
            for env, state in zip(envs, saved, strict=True):
                env.set_state(state)
        action = action_kinds(envs[0], rng, i)
        results = [env.step(action) for env in envs]
        reference = result_bytes(results[2])
        for env, result in zip(envs, results, strict=True):
            assert result_bytes(result) == reference, (uid, i, env.agent.control_mode)
            assert snapshot(env) == snapshot(envs[2]), (uid, i, env.agent.control_mode)
    fused_modes = set(calls)
    assert len(calls) > 40 and fused_modes <= set(JOINT_MODES), fused_modes  # the path under test was taken
    for env in envs:
        env.close()


#: (robot, end-effector modes): an arm with every mode, arms with position modes only or
#: with a tool frame, a floating mount (mode switches go through the robot's own modes).
EE_ROBOTS = [
    ("panda", ("pd_ee_delta_pose", "pd_ee_delta_pos", "pd_ee_pose", "pd_ee_target_delta_pose")),
    ("so100", ("pd_ee_delta_pos", "pd_ee_target_delta_pos")),
    ("widowx250s", ("pd_ee_delta_pose", "pd_ee_target_delta_pos")),
    ("xarm6_robotiq", ("pd_ee_delta_pose", "pd_ee_pose")),
    ("floating_robotiq_2f_85_gripper", ("pd_ee_delta_pose", "pd_ee_pose")),
]


@pytest.mark.parametrize(("uid", "modes"), EE_ROBOTS)
def test_the_planned_step_of_end_effector_modes_matches_the_parts_calls_and_the_general_path(
    uid: str, modes: tuple[str, ...]
) -> None:
    """End-effector parts (which report ``ik_success`` ... in ``info``) step through the
    planned step with their own one-env calls: the same bits as through the parts' calls
    on ``RobotEnv.step``'s path and the general path, in observations, infos, controls,
    physics and the controllers' states (IK targets and results), through mode switches,
    a reset and a restored state."""
    envs = [make(uid, modes[0]) for _ in range(3)]
    without_fusion(envs[1])
    general(envs[2])
    world = envs[0].scene.world
    general_steps = [0]
    world_step = world.step

    def counted(*args: Any, **kwargs: Any) -> None:  # the general path's Scene.step calls it
        general_steps[0] += 1
        world_step(*args, **kwargs)

    world.step = counted  # type: ignore[method-assign]
    rng = np.random.default_rng(7)
    saved: list[dict[str, Any]] = []
    steps = 100
    for i in range(steps):
        if i % 20 == 19:
            for env in envs:
                env.set_control_mode(modes[(i // 20 + 1) % len(modes)])
        if i == 30:
            saved = [env.get_state() for env in envs]
        if i == 50:
            for env in envs:
                env.reset(seed=11)
        if i == 70:
            for env, state in zip(envs, saved, strict=True):
                env.set_state(state)
        action = action_kinds(envs[0], rng, i)
        if i % 3 == 0:  # small moves too, which IK meets
            action = np.asarray(action, dtype=np.float64) * 0.05
        results = [env.step(action) for env in envs]
        reference = result_bytes(results[2])
        assert "ik_success" in results[2][4], (uid, i)
        for env, result in zip(envs, results, strict=True):
            assert result_bytes(result) == reference, (uid, i, env.agent.control_mode)
            assert snapshot(env) == snapshot(envs[2]), (uid, i, env.agent.control_mode)
            state = env.agent.controller.get_state()
            expected = envs[2].agent.controller.get_state()
            assert {
                (part, key): value.tobytes() for part, values in state.items() for key, value in values.items()
            } == {(part, key): value.tobytes() for part, values in expected.items() for key, value in values.items()}
    # the path under test was taken: the general path only for what the planned step
    # leaves to it (integer arrays, lists, overflowing sums: 23 of the 100 actions)
    assert general_steps[0] < steps // 3, general_steps[0]
    for env in envs:
        env.close()


@pytest.mark.parametrize("uid", FUSED_ROBOTS)
def test_results_of_the_planned_step_are_not_overwritten_by_later_steps(uid: str) -> None:
    env = make(uid, "pd_joint_target_delta_pos")
    assert env._planned_step is not None
    obs, _, _, _, info = env.step(np.full(env.agent.single_action_space.shape, 0.5, dtype=np.float32))
    parts = {name: p.target_qpos for name, p in env.agent.controller.parts.items()}  # type: ignore[attr-defined]
    kept = (obs.copy(), {k: v.copy() for k, v in info.items()}, {k: v.copy() for k, v in parts.items()})
    env.step(np.full(env.agent.single_action_space.shape, -0.5, dtype=np.float32))
    assert obs.tobytes() == kept[0].tobytes()
    assert all(info[k].tobytes() == v.tobytes() for k, v in kept[1].items())
    assert all(parts[k].tobytes() == v.tobytes() for k, v in kept[2].items())
    for name, part in env.agent.controller.parts.items():
        assert part.target_qpos is not parts[name]  # type: ignore[attr-defined]
        assert part._previous_target is parts[name]  # type: ignore[attr-defined]
    env.close()


def bad_actions(dim: int) -> list[Any]:
    nan, inf = np.zeros(dim, dtype=np.float32), np.zeros((1, dim))
    nan[1], inf[0, 2] = np.nan, -np.inf
    return [
        nan,
        inf,
        np.zeros(dim + 1, dtype=np.float32),
        np.zeros((2, dim)),
        np.zeros((1, dim, 1)),
        np.zeros(dim, dtype=bool),
        np.array(["a"] * dim),
        np.zeros(dim, dtype=np.complex128),
        [0.0] * (dim - 1),
        None,
        "up",
    ]


@pytest.mark.parametrize("uid", ["panda", "so100"])
def test_bad_actions_are_refused_as_on_the_general_path_and_change_nothing(uid: str) -> None:
    planned, reference = make(uid), general(make(uid))
    planned.step(np.zeros(planned.agent.single_action_space.shape, dtype=np.float32))
    reference.step(np.zeros(planned.agent.single_action_space.shape, dtype=np.float32))
    before = snapshot(planned)
    assert before == snapshot(reference)
    for action in bad_actions(planned.agent.controller.action_dim):
        with pytest.raises(ra.ActionError) as raised:
            planned.step(action)
        with pytest.raises(ra.ActionError) as expected:
            reference.step(action)
        assert str(raised.value) == str(expected.value)
        assert snapshot(planned) == before
    planned.close()
    with pytest.raises(ra.StateError) as closed:
        planned.step(np.zeros(planned.agent.single_action_space.shape, dtype=np.float32))
    reference.close()
    with pytest.raises(ra.StateError) as closed_reference:
        reference.step(np.zeros(planned.agent.single_action_space.shape, dtype=np.float32))
    assert str(closed.value) == str(closed_reference.value)


def test_the_planned_step_is_made_only_where_it_applies() -> None:
    env = make("panda")
    assert env._planned_step is not None
    env.close()
    for uid, kwargs in (
        ("panda", {"num_envs": 2}),  # several envs
        (("panda", "so100"), {}),  # several robots
        ("fetch", {}),  # a mobile base: step hooks
    ):
        env = make(uid, **kwargs)  # type: ignore[arg-type]
        assert env._planned_step is None, uid
        env.close()
    task = ra.make_env("PickCube-v1", robot_uids="panda").unwrapped  # a task with reward and metrics
    assert task._planned_step is None  # type: ignore[attr-defined]
    task.close()
    # modes without a fused call: end-effector, velocity, and an action clip with a zero bound
    for uid, mode in (("panda", "pd_ee_delta_pose"), ("panda", "pd_joint_vel"), ("koch-v1.1", "pd_joint_pos")):
        env = make(uid, mode)
        env.step(np.zeros(env.agent.single_action_space.shape))
        assert env.agent.controller._single_plan is not None and env.agent.controller.single_values is None
        env.close()


#: (robot, part, modes): plain arms, a mimic gripper, a plain gripper, zero-bound parts.
PARTS = [
    ("panda", "arm"),
    ("widowx250s", "gripper"),
    ("so100", "gripper"),
    ("fetch", "body"),
    ("stretch", "arm"),
    ("spot", "arm"),
]


@pytest.mark.parametrize(("uid", "name"), PARTS)
@pytest.mark.parametrize("mode", JOINT_MODES)
def test_a_parts_fused_targets_match_its_planned_call(uid: str, name: str, mode: str) -> None:
    """:func:`_part_targets` (Python floats) against the part's own one-env call
    (NumPy), with measured positions, previous targets and action entries at ``-0.0``,
    ``0.0``, the smallest subnormals, on the bounds, past them and cancelling to zero."""
    env = make(uid, mode)
    world, combined = env.scene.world, env.agent.controller
    part = combined.parts[name]
    assert isinstance(part, PDJointPosController)
    combined._plan_single(world)
    plan = combined._single_plan
    assert plan is not None
    call = plan[list(combined.parts).index(name)]
    terms = part.single_terms(combined._never_negative_zero(name))
    assert terms is not None
    part_slice = combined.slices[name]
    fused = _part_targets(part_slice, combined.entry_constants()[part_slice], terms, part)
    assert fused is not None
    data = world.physics_sources()[0]
    for k, measured, entry, previous, action, _ in edge_cases(world, combined, name):
        values = fused(action[0].tolist(), data.qpos.tolist())
        combined._to_raw_single(action)
        call()
        assert np.array(values)[None].tobytes() == part.target_qpos.tobytes(), (k, measured, entry, previous)
    env.close()


def test_a_negative_zero_offset_leaves_a_zero_bound_part_unfused() -> None:
    """Spot's arm (a zero joint limit) with an offset of ``-0.0``: its call clips in two
    passes, so it has no fused terms (its comparisons would not be that clip)."""
    env = make("spot", "pd_joint_delta_pos")
    combined = env.agent.controller
    part = combined.parts["arm"]
    assert isinstance(part, PDJointPosController)
    assert part.single_terms(True) is not None
    combined._offset_row[0, combined.slices["arm"]] = -0.0
    assert not combined._never_negative_zero("arm") and part.single_terms(False) is None
    env.close()


def test_an_observation_put_in_the_envs_place_is_still_called() -> None:
    """The planned step reads the parts' targets from the drives' row only while the env
    observes with its own observation: a callable put in ``_get_obs``'s place (a
    profiler's wrapper) is called instead, and gives the same row here."""
    env, reference = make("panda"), general(make("panda"))
    calls = []
    own = env._get_obs

    def wrapped() -> Any:
        calls.append(1)
        return own()

    env._get_obs = wrapped
    for i in range(5):
        action = np.full(env.agent.single_action_space.shape, 0.1 * i, dtype=np.float32)
        assert result_bytes(env.step(action)) == result_bytes(reference.step(action))
    assert len(calls) == 5
    env.close()
    reference.close()


def test_an_offset_tool_frames_one_env_observation_is_the_batched_concatenation() -> None:
    """The SO-100's jaw (a tool frame offset from its body): the planned one-env row
    against :meth:`StateObservation._flat_state` (the pieces of ``state_arrays``, the tool
    pose from ``RobotFrames.measured_pose``), step after step."""
    env = make("so100")
    rng = np.random.default_rng(2)
    for _ in range(30):
        obs = env.step(rng.uniform(-1, 1, env.agent.single_action_space.shape).astype(np.float32))[0]
        assert obs.tobytes() == env._observation._flat_state().tobytes()
    env.close()


def test_the_fused_call_of_each_robot_in_a_scene_of_two_matches_the_general_path() -> None:
    """Two robots in one env (no planned env step): each robot's
    ``CombinedController.set_action`` takes its fused call (integer actions too: a scene of
    several robots validates each robot's action into float64 first); the same bits as the
    general path."""
    fused, reference = make(("panda", "widowx250s")), make(("panda", "widowx250s"))  # type: ignore[arg-type]
    assert fused._planned_step is None
    calls = []
    for agent, other in zip(fused.agents, reference.agents, strict=True):
        for mode in agent.control.modes:
            controller, slow = agent.control.controller_for(mode), other.control.controller_for(mode)
            controller._plan_single(fused.scene.world)
            slow._single_sim, slow._single_plan, slow.single_values = reference.scene.world, None, None
            call = controller.single_values
            if call is not None:

                def counted(values: list[float], call: Any = call) -> None:
                    calls.append(1)
                    call(values)

                controller.single_values = counted
    rng = np.random.default_rng(4)
    for i in range(40):
        action = {}
        for rid, agent in zip(fused.scene.robot_ids, fused.agents, strict=True):
            row = rng.uniform(-1.5, 1.5, agent.single_action_space.shape)
            action[rid] = np.round(row).astype(np.int64) if i % 3 == 0 else row.astype(np.float32)
        assert result_bytes(fused.step(action)) == result_bytes(reference.step(action))
        assert fused.get_state()["physics"].tobytes() == reference.get_state()["physics"].tobytes()
    assert len(calls) == 2 * 40  # both robots, every step
    fused.close()
    reference.close()
