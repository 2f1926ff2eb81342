"""The one-env step's fast path (benchmarks/overhead_ratio.py) changes no bit: a single
env steps exactly as env 0 of a batch (which takes the general path), and its fused
``state`` observation equals the general concatenation, across robots whose tool frame
is a body, a body with an offset or a site, with touch sensors, wheels or a kinematic
base, in joint and end-effector modes, and after a mode switch."""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.actuators.drives import DriveOverride
from robot_agents.errors import StateError

CASES = [
    ("panda", "pd_joint_delta_pos", "Empty-v1"),
    ("fetch", "pd_joint_vel", "Empty-v1", {"base_dynamics": "kinematic"}),  # a kinematic move and wheels
    ("panda", "pd_ee_delta_pose", "Empty-v1"),
    ("panda", "pd_joint_pos", "PickCube-v1"),  # task observations (the cube) after the robot's
    ("panda_touch", "pd_joint_delta_pos", "Empty-v1"),  # touch sensors
    ("so100", "pd_joint_delta_pos", "Empty-v1"),  # tool frame: a body with an offset
    ("google_robot", "pd_joint_vel", "Empty-v1"),  # tool frame: a site
    ("stretch", "pd_joint_delta_pos", "Empty-v1"),  # wheels turned after each step
    ("spot", "pd_joint_delta_pos", "Empty-v1"),  # a kinematic base
    ("fetch", "pd_joint_delta_pos", "Empty-v1"),  # joints apart in qpos (take / put), a zero joint limit
    ("xarm6_robotiq", "pd_ee_delta_pose", "Empty-v1"),
]


def _bits(value: Any) -> np.ndarray:
    """The exact bytes of an array (-0.0 and 0.0 differ)."""
    array = np.ascontiguousarray(np.asarray(value))
    return array.view(np.uint8)


def _general_obs(env: Any) -> np.ndarray:
    return np.concatenate(env._observation.state_arrays(), axis=1, dtype=np.float32)


@pytest.mark.parametrize("case", CASES, ids=lambda case: "-".join(map(str, case)))
def test_one_env_steps_bit_for_bit_as_env_zero_of_a_batch(case: tuple[Any, ...]) -> None:
    uid, mode, task = case[:3]
    options = case[3] if len(case) > 3 else {}
    single = ra.make_env(task, robot_uids=uid, control_mode=mode, max_episode_steps=None, **options)
    batch = ra.make_env(task, robot_uids=uid, control_mode=mode, num_envs=2, max_episode_steps=None, **options)
    obs1, _ = single.reset(seed=4)
    obs2, _ = batch.reset(seed=[4, 4])
    one, two = single.unwrapped, batch.unwrapped
    assert np.array_equal(_bits(obs1), _bits(obs2[:1]))
    rng = np.random.default_rng(0)
    space = one.single_action_space
    for step in range(25):
        action = rng.uniform(space.low, space.high).astype(np.float32)
        if step == 12:  # a mode switch mid-episode: the observation's plan is rebuilt
            for env in (one, two):
                env.set_control_mode("pd_joint_delta_pos" if mode != "pd_joint_delta_pos" else "pd_joint_pos")
            space = one.single_action_space
            action = (0.1 * rng.uniform(space.low, space.high)).astype(np.float32)
        obs1, reward1, _, _, info1 = single.step(action[None] if step % 2 else action)
        obs2, reward2, _, _, info2 = batch.step(np.repeat(action[None], 2, axis=0))
        assert obs1.shape == (1, obs2.shape[1]) and obs1.dtype == np.float32
        assert np.array_equal(_bits(obs1), _bits(obs2[:1])), f"step {step}: observations differ"
        assert np.array_equal(_bits(obs1), _bits(_general_obs(one))), f"step {step}: fused != general observation"
        assert reward1 == reward2[0]
        assert set(info1) == set(info2)
        for key, value in info1.items():
            if isinstance(value, np.ndarray) and value.shape[:1] == (1,):
                assert np.array_equal(_bits(value), _bits(info2[key][:1])), f"step {step}: info[{key!r}] differs"
    state1, state2 = one.get_state(), two.get_state()
    assert np.array_equal(_bits(state1["physics"][0]), _bits(state2["physics"][0]))
    assert np.array_equal(_bits(state1["physics"][0]), _bits(state2["physics"][1]))
    single.close()
    batch.close()


def test_the_fused_observation_is_a_fresh_array() -> None:
    env = ra.make_env("Empty-v1", robot_uids="panda", max_episode_steps=None)
    first, _ = env.reset(seed=0)
    kept = first.copy()
    second, *_ = env.step(np.zeros(env.unwrapped.single_action_space.shape, dtype=np.float32))
    assert second is not first and not np.shares_memory(first, second)
    assert np.array_equal(first, kept)  # stepping did not write into the returned observation
    assert first.flags.writeable and first.flags.c_contiguous and first.shape == env.observation_space.shape
    env.close()


def test_one_pass_clip_is_exact_unless_a_bound_is_zero() -> None:
    """The controllers clip in one ufunc call only where that is bit-exact."""
    from robot_agents.controllers.base import clip_ufunc, one_pass_clip_exact

    values = np.array([-0.0, 0.0, np.nan, np.inf, -np.inf, 1.0, -1.0, 0.25, -3.0, 5e-324, -5e-324])
    values = np.concatenate([values, np.random.default_rng(0).normal(size=200)])
    for low, high in ((-1.0, 1.0), (-0.3, 0.7), (-np.inf, np.inf), (1e-300, 2.0), (-2.0, -1e-300)):
        bounds = np.full(values.shape, low), np.full(values.shape, high)
        assert one_pass_clip_exact(*bounds)
        assert (
            _bits(clip_ufunc(values, *bounds)).tobytes() == _bits(np.minimum(np.maximum(values, low), high)).tobytes()
        )
    assert not one_pass_clip_exact(np.zeros(3), np.ones(3))  # which zero comes back is unspecified
    assert not one_pass_clip_exact(-np.ones(3), np.array([1.0, 0.0, 1.0]))


def test_one_env_wheel_turning_matches_the_batched_arithmetic_bit_for_bit() -> None:
    """The scalar wheel roll of one env (``MobileBase._wheel_roll_single``) is bit for bit
    the batched one, over random moves, turns across +-pi and mount yaws."""
    env = ra.make_env("Empty-v1", robot_uids="fetch", max_episode_steps=None).unwrapped
    env.reset(seed=0)
    base = env.agent.mobile
    rng = np.random.default_rng(0)
    for k in range(300):
        base._mount_yaw = float(rng.uniform(-np.pi, np.pi))
        start = rng.uniform(-4.0, 4.0, 3)
        end = start + rng.normal(0.0, (0.05, 0.05, 0.3))
        if k % 3 == 0:  # a turn across the +-pi seam
            end[2] = start[2] + rng.choice((-1.0, 1.0)) * (np.pi - 1e-9)
        single = base._wheel_roll_single(start, end)
        batched = base._wheel_roll(np.stack([start, start]), np.stack([end, end]))
        assert single.shape == (1, len(base.wheels)) and np.array_equal(single[0], batched[0]), k
    env.close()


def full_forward_write(world: Any, *args: Any, forward: bool = True) -> None:
    """``write_joint_state`` always followed by ``mj_forward``."""
    type(world).write_joint_state(world, *args, forward=True)


def full_forward_row(world: Any, *args: Any, forward: bool = True) -> None:
    """``write_joint_row`` (the one-env per-step writes) always followed by ``mj_forward``."""
    type(world).write_joint_row(world, *args, forward=True)


def test_pose_only_writes_leave_the_trajectory_and_poses_of_a_full_forward() -> None:
    """Wheels and held legs are written after a step with poses recomputed only
    (``forward=False``: ``mj_kinematics`` and cameras, not ``mj_forward``): the
    trajectory, the observations and the body poses are bit for bit those of a full
    ``mj_forward`` after each write."""
    results = []
    for full in (False, True):
        env = ra.make_env("Empty-v1", robot_uids="stretch", max_episode_steps=None).unwrapped
        world = env.scene.world
        if full:
            world.write_joint_state = functools.partial(full_forward_write, world)
            world.write_joint_row = functools.partial(full_forward_row, world)
        env.reset(seed=2)
        rng = np.random.default_rng(0)
        observations = [env.step(rng.uniform(-1, 1, env.action_space.shape[-1]))[0] for _ in range(30)]
        data = world.datas[0]
        results.append(
            (np.concatenate(observations), env.get_state()["physics"], data.xpos.copy(), data.cam_xpos.copy())
        )
        env.close()
    for fast, full in zip(*results, strict=True):
        assert np.array_equal(fast, full)


#: Every pose-derived array of MjData (what mj_kinematics and mj_camlight compute), and
#: what the physics derives besides.
DERIVED = (
    "xpos", "xquat", "xmat", "xipos", "ximat", "xanchor", "xaxis", "geom_xpos", "geom_xmat",
    "site_xpos", "site_xmat", "cam_xpos", "cam_xmat", "light_xpos", "light_xdir", "subtree_com",
    "sensordata", "qacc", "qfrc_actuator", "qacc_warmstart",
)  # fmt: skip


def always_synced_step(world: Any, before_substep: Any = None, sync_poses: bool = True) -> None:
    """``BatchedWorld.step`` with the poses always updated after the physics."""
    type(world).step(world, before_substep, sync_poses=True)


@pytest.mark.parametrize(
    ("uid", "num_envs", "options"),
    [
        ("stretch", 1, {}),  # wheels
        ("spot", 1, {}),  # a kinematic base, held legs
        ("fetch", 2, {}),  # wheels, batched
        ("google_robot", 1, {"base_dynamics": "kinematic"}),  # a kinematic move, then the wheels
        ("fetch", 1, {"base_dynamics": "kinematic", "base_refuse_collisions": True}),  # the collision check
    ],
)
def test_a_step_whose_robot_writes_next_skips_no_pose(uid: str, num_envs: int, options: dict[str, Any]) -> None:
    """A robot that writes joint state after the physics (wheels, a kinematic base) lets
    the world leave out its own pose update (``sync_poses=False``): the poses, sensors,
    observations and states are bit for bit those of a world that always updates them."""
    refuse = options.pop("base_refuse_collisions", None)
    results = []
    for synced in (False, True):
        env = ra.make_env("Empty-v1", robot_uids=uid, num_envs=num_envs, max_episode_steps=None, **options).unwrapped
        world = env.scene.world
        if refuse is not None:
            env.agent.set_base_dynamics("kinematic", refuse_collisions=refuse)
        assert env.agent.writes_after_step
        if synced:
            world.step = functools.partial(always_synced_step, world)
        env.reset(seed=1)
        rng = np.random.default_rng(0)
        space = env.action_space
        kept = []
        for _ in range(15):
            kept.append(env.step(rng.uniform(space.low, space.high).astype(np.float32))[0])
            kept.extend(np.stack([getattr(data, name) for data in world.datas]) for name in DERIVED)
        kept.append(env.get_state()["physics"])
        results.append(kept)
        env.close()
    for skipped, synced in zip(*results, strict=True):
        assert np.array_equal(_bits(skipped), _bits(synced))


@pytest.mark.parametrize("uid", ["fetch", "google_robot", "panda", "stretch"])
def test_drive_controls_written_in_place_equal_the_general_sums(uid: str) -> None:
    """``Drives.write`` sums the affine controls in place (into ``ctrl``'s columns, or a
    scratch row put into Google Robot's permuted ones): bit for bit the general path's
    ``P a + V b + E c + d``, with every target kind in use, into a new ``ctrl`` array
    and into a non-contiguous one."""
    env = ra.make_env("Empty-v1", robot_uids=uid, num_envs=2, max_episode_steps=None).unwrapped
    drives = env.agent.drives
    assert drives._affine_views is not None
    rng = np.random.default_rng(0)
    nu = env.scene.world.ctrl.shape[1]
    for uses in ((True, True), (False, False), (True, False)):
        drives.activate(DriveOverride.none(drives.size), *uses)
        targets = drives.targets
        for array in (targets.position, targets.velocity, targets.effort):
            array[...] = rng.normal(size=array.shape)
        targets.velocity[0, 0] = -0.0
        for ctrl_of in (lambda: np.zeros((2, nu)), lambda: np.zeros((2, 2 * nu))[:, ::2]):
            fast, general = ctrl_of(), ctrl_of()
            drives.write(fast)
            views, drives._affine_views = drives._affine_views, None
            try:
                drives.write(general)
            finally:
                drives._affine_views = views
            assert np.array_equal(_bits(np.ascontiguousarray(fast)), _bits(np.ascontiguousarray(general)))
    env.close()


def test_one_env_wheel_write_matches_the_general_write_bit_for_bit() -> None:
    """The wheel angles and speeds the one-env after-step writes
    (``MobileBase._turn_wheels_single``, its roll written out on Python floats, through
    ``BatchedWorld.write_joint_row``) are bit for bit those of the general path's
    ``_turn_wheels`` (one env, through ``write_joint_state``) and of a batch's row, over
    random moves, turns across +-pi, mount yaws and control periods; read back from the
    simulation's own ``qpos`` / ``qvel``."""
    env = ra.make_env("Empty-v1", robot_uids="fetch", max_episode_steps=None).unwrapped
    env.reset(seed=0)
    base, world = env.agent.mobile, env.scene.world
    assert base._write_rows  # the one-env row write is the path under test
    data = world.physics_sources()[0]

    def written() -> tuple[np.ndarray, np.ndarray]:
        return data.qpos[base._wheel_qadr].copy(), data.qvel[base._wheel_dadr].copy()

    rng = np.random.default_rng(1)
    nq = world.model.nq
    for k in range(200):
        base._mount_yaw = float(rng.uniform(-np.pi, np.pi))
        base._mount_cos, base._mount_sin = np.cos(base._mount_yaw), np.sin(base._mount_yaw)
        start_row = rng.uniform(-4.0, 4.0, nq)
        start = start_row[base._planar_adr]
        end = start + rng.normal(0.0, (0.05, 0.05, 0.3))
        if k % 3 == 0:  # a turn across the +-pi seam
            end[2] = start[2] + rng.choice((-1.0, 1.0)) * (np.pi - 1e-9)
        dt = float(rng.choice((0.05, 0.01, 1 / 30)))
        world.write_joint_state(np.array([0]), base._planar_adr, end[None], base._planar_dofs, np.zeros((1, 3)))
        data.qpos[base._wheel_qadr] = data.qvel[base._wheel_dadr] = np.nan
        base._turn_wheels_single(start_row.tolist(), dt)
        fast_q, fast_v = written()
        data.qpos[base._wheel_qadr] = data.qvel[base._wheel_dadr] = np.nan
        base._turn_wheels(start[None], end[None], start_row[base._wheel_qadr][None], dt)
        general_q, general_v = written()
        rolled = base._wheel_roll(np.stack([start, start]), np.stack([end, end]))[:1]
        batch_q, batch_v = (start_row[base._wheel_qadr][None] + rolled)[0], (rolled / dt)[0]
        for fast, general, batch in ((fast_q, general_q, batch_q), (fast_v, general_v, batch_v)):
            assert _bits(fast).tobytes() == _bits(general).tobytes() == _bits(batch).tobytes(), k
    env.close()


_WRITTEN = ("qpos", "qvel", "qacc_warmstart", "ctrl", "xpos", "xquat", "xmat", "geom_xpos", "site_xpos",
            "cam_xpos", "cam_xmat", "light_xpos", "light_xdir", "qacc", "qfrc_bias", "sensordata", "act")  # fmt: skip


@pytest.mark.parametrize("forward", [True, False])
def test_one_env_row_write_writes_as_write_joint_state(forward: bool) -> None:
    """``BatchedWorld.write_joint_row`` (the per-step writes of wheels, a kinematic base
    and held legs at one env) leaves every MjData array it touches, the derived ones
    included, bit for bit as ``write_joint_state`` of env 0 does, in two identical
    simulations; with several envs it raises and writes nothing."""
    envs = [ra.make_env("Empty-v1", robot_uids="spot", max_episode_steps=None).unwrapped for _ in range(2)]
    rng = np.random.default_rng(3)
    action = rng.uniform(-1.0, 1.0, envs[0].action_space.shape)
    for env in envs:
        env.reset(seed=0)
        env.step(action)
    legs, dofs = envs[0].agent._held_qpos, envs[0].agent._held_dof
    assert len(legs) > 0 and envs[0].agent._held_rows and envs[0].agent.mobile._write_rows
    for k in range(5):
        qpos = rng.uniform(-0.5, 0.5, len(legs))
        qvel = rng.normal(0.0, 1.0, len(dofs))
        ctrl = rng.normal(0.0, 1.0, envs[0].scene.world.ctrl.shape)
        for env in envs:
            env.scene.world.ctrl[...] = ctrl  # copied into the controls by both writes
            env.scene.world.physics_sources()[0].qacc_warmstart[:] = 1.5  # cleared by both
            env.scene.world.qpos  # noqa: B018 (the read cache filled: both writes clear it)
        envs[0].scene.world.write_joint_state(np.array([0]), legs, qpos[None], dofs, qvel[None], forward=forward)
        envs[1].scene.world.write_joint_row(legs, qpos, dofs, qvel, forward=forward)
        general, fast = (env.scene.world.physics_sources()[0] for env in envs)
        for name in _WRITTEN:
            assert _bits(getattr(fast, name)).tobytes() == _bits(getattr(general, name)).tobytes(), (k, name)
        assert _bits(envs[1].scene.world.qpos).tobytes() == _bits(envs[0].scene.world.qpos).tobytes()
    for env in envs:
        env.close()
    batch = ra.make_env("Empty-v1", robot_uids="spot", num_envs=2, max_episode_steps=None).unwrapped
    world = batch.scene.world
    assert not batch.agent._held_rows and not batch.agent.mobile._write_rows
    before = world.get_state()
    with pytest.raises(StateError, match="write_joint_row: expected a world of one env, got 2 envs"):
        world.write_joint_row(legs, np.zeros(len(legs)), dofs, np.zeros(len(dofs)))
    after = world.get_state()
    assert np.array_equal(before, after)
    batch.close()
    # One env: a row that is not one value per address is refused before anything is
    # written (a valid qpos row with a short qvel row left the qpos written before).
    single = ra.make_env("Empty-v1", robot_uids="spot", max_episode_steps=None).unwrapped
    world = single.scene.world
    before = world.get_state()
    with pytest.raises(StateError, match=r"expected qpos of shape \(12,\) and qvel of shape \(12,\)"):
        world.write_joint_row(legs, np.full(len(legs), 0.3), dofs, np.zeros(len(dofs) - 1))
    with pytest.raises(StateError, match="one value per address"):
        world.write_joint_row(legs, np.full((1, len(legs)), 0.3), dofs, np.zeros(len(dofs)))
    assert np.array_equal(world.get_state(), before)
    single.close()


def test_moves_each_step_follows_the_base_dynamics() -> None:
    """The per-step flag :attr:`MobileBase.moves_each_step` (kept with the dynamics)
    follows ``set_base_dynamics`` and ``set_state``: a base without wheels moves each
    step only while kinematic; one with wheels always (they turn)."""
    env = ra.make_env("Empty-v1", robot_uids="spot", max_episode_steps=None).unwrapped
    env.reset(seed=0)
    agent = env.agent
    assert agent.mobile.dynamics == "kinematic" and agent.writes_after_step
    saved = env.get_state()
    agent.set_base_dynamics("dynamic")
    assert agent.mobile.dynamics == "dynamic" and not agent.writes_after_step
    env.set_state(saved)
    assert agent.mobile.dynamics == "kinematic" and agent.writes_after_step
    env.close()
    env = ra.make_env("Empty-v1", robot_uids="fetch", max_episode_steps=None).unwrapped
    env.reset(seed=0)
    for dynamics in ("kinematic", "dynamic"):
        env.agent.set_base_dynamics(dynamics)
        assert env.agent.writes_after_step
    env.close()


@pytest.mark.parametrize("task", ["Empty-v1", "PickCube-v1"])
def test_a_site_tool_frames_quaternion_is_refreshed_each_step(task: str) -> None:
    """Google Robot's tool frame is a site, whose quaternion MuJoCo does not store: the
    one-env observation computes it each step into a buffer (``Refreshed``), copied into
    the planned row (Empty) or joined with the task's extras (PickCube): the general
    concatenation's values every step, and a quaternion that follows the arm."""
    env = ra.make_env(task, robot_uids="google_robot", max_episode_steps=None).unwrapped
    env.reset(seed=0)
    assert (env._observation._out is None) == (task != "Empty-v1")
    rng = np.random.default_rng(0)
    quats = []
    for _ in range(6):
        obs = env.step(rng.uniform(-1.0, 1.0, env.action_space.shape).astype(np.float32))[0]
        assert _bits(obs).tobytes() == _bits(_general_obs(env)).tobytes()
        quats.append(env.agent.tcp_pose[0, 3:].astype(np.float32))
    assert not np.array_equal(quats[0], quats[-1])  # the arm turned the site
    env.close()
