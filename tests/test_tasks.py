"""The manipulation tasks (ReachPose-v1, PickCube-v1, PushCube-v1): one definition for
every robot, laid out from the robot's own model; seeded randomization with one
random stream per env; success, rewards and observations checked against numbers."""

from __future__ import annotations

import math
import warnings
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import robot_agents as ra
from robot_agents.envs.tasks import table_top_layout
from robot_agents.kinematics.rotations import rotvec_to_quat

TASKS = ("ReachPose-v1", "PickCube-v1", "PushCube-v1")
GRIPPER_ROBOTS = ("panda", "floating_panda_gripper", "so100", "koch-v1.1")


def robots_for(task: str) -> list[str]:
    """Registered robots the task takes: every table-top task needs an end effector,
    PickCube a gripper with fingers too."""
    uids = [u for u in ra.list_agents() if _has_end_effector(u)]
    return [u for u in uids if _has_gripper(u)] if task == "PickCube-v1" else uids


def _has_end_effector(uid: str) -> bool:
    return any(isinstance(p, ra.Arm) and p.end_effectors for p in ra.get_agent(uid).check().parts)


def _has_gripper(uid: str) -> bool:
    return any(isinstance(p, ra.Gripper) and len(p.fingers) >= 2 for p in ra.get_agent(uid).check().parts)


def _is_mobile(uid: str) -> bool:
    return any(isinstance(p, ra.Base) for p in ra.get_agent(uid).check().parts)


FIXED = [u for u in ra.list_agents() if _has_end_effector(u) and not _is_mobile(u)]
MOBILE = [u for u in ra.list_agents() if _has_end_effector(u) and _is_mobile(u)]


def robot_table_contacts(env: Any) -> float:
    """Deepest penetration (m) between the robot and the table or the cube in env 0."""
    model, data = env.model, env.data
    prefix = env.agent.prefix
    deepest = 0.0
    for i in range(data.ncon):
        contact = data.contact[i]
        names = {model.body(int(model.geom_bodyid[g])).name for g in (contact.geom1, contact.geom2)}
        if any(n.startswith(prefix) for n in names) and names & {"table", "cube"}:
            deepest = max(deepest, -float(contact.dist))
    return deepest


# -- layout -------------------------------------------------------------------------------------
def test_layout_numbers_for_the_panda() -> None:
    layout = table_top_layout(ra.get_agent("panda"))
    # Reach: the Panda's datasheet says 855 mm to the flange; + 0.21 m of hand and TCP,
    # measured from the shoulder (z = 0.333 m), sampled: within a few cm below 1.07 m.
    assert 0.9 < layout.reach < 1.07
    # The rest TCP (0.615 m ahead of the base) is above the workspace centre: the robot
    # stands 0.615 m behind it, unturned, on the table top.
    np.testing.assert_allclose(layout.robot_pose, [-0.615, 0.0, layout.table_height, 1, 0, 0, 0], atol=1e-3)
    np.testing.assert_allclose(layout.rest_tcp[:2], [0.0, 0.0], atol=1e-9)
    assert layout.table_height == pytest.approx(0.75 * layout.reach)
    # Cube: half the 8 cm opening (fingers 0.04 m each, pads 0.3 mm proud) -> 4 cm.
    assert layout.gripper is not None
    assert layout.gripper.opening == pytest.approx(0.0806, abs=1e-3)
    assert 2 * layout.cube_half_size == pytest.approx(0.0403, abs=5e-4)
    np.testing.assert_allclose(layout.gripper.approach_axis, [0, 0, 1], atol=1e-6)  # hand z
    np.testing.assert_allclose(layout.gripper.grasp_point, [0, 0, 0], atol=1e-6)  # between the pads
    assert layout.spawn_half_size == pytest.approx(0.1 * layout.reach)


@pytest.mark.parametrize("uid", FIXED)
def test_every_robot_faces_its_workspace_from_its_own_definition(uid: str) -> None:
    """The robot is turned so its rest tool lies ahead (+x) of its shoulder, moved so the
    rest tool is above the workspace centre, and stands on the table without touching it."""
    env = ra.make_env("PushCube-v1", robot_uids=uid, robot_init_qpos_noise=0.0).unwrapped
    layout = env.layout
    env.reset(seed=0)
    tcp = env.agent.tcp_pose[0, :3]
    np.testing.assert_allclose(tcp, layout.rest_tcp, atol=1e-6)
    np.testing.assert_allclose(tcp[:2], [0.0, 0.0], atol=1e-6)
    assert tcp[2] > layout.table_height  # above the table
    assert layout.robot_pose[0] <= 1e-9  # the robot stands behind (or under) the centre
    # table: covers the robot's root and the workspace, top at table_height
    center, half = np.array(layout.table_center), np.array(layout.table_half_size)
    assert center[2] + half[2] == pytest.approx(layout.table_height)
    for point in (
        np.array(layout.robot_pose[:2]),
        np.array([layout.spawn_half_size + 0.3 * layout.reach, layout.spawn_half_size]),
    ):
        assert np.all(np.abs(point - center[:2]) <= half[:2])
    assert robot_table_contacts(env) < 1e-3
    # cube edge: half the gripper's opening, else 4 % of the reach
    expected = 0.5 * layout.gripper.opening if layout.gripper else 0.04 * layout.reach
    assert 2 * layout.cube_half_size == pytest.approx(max(expected, 0.01))
    assert not layout.mobile
    env.close()


@pytest.mark.parametrize("uid", MOBILE)
def test_mobile_robots_stand_on_the_floor_next_to_the_table(uid: str) -> None:
    """A robot with a Base stands on the floor at its mount, facing the table: the table
    top 0.25 R below its rest tool, the workspace centre under the rest tool or further
    ahead, the table's near edge 0.02 R clear of the circle its low geoms sweep when it
    turns in place, and every cube drawn on the table. Turning the base through a full
    circle at its stance never touches the table."""
    env = ra.make_env("PickCube-v1", robot_uids=uid, robot_init_qpos_noise=0.0).unwrapped
    layout, agent = env.layout, env.agent
    env.reset(seed=0)
    assert layout.mobile and layout.turning_radius > 0.1
    assert layout.robot_pose[2] == pytest.approx(agent.check().mount_pose[2])  # on the floor
    tcp = agent.tcp_pose[0, :3]
    np.testing.assert_allclose(tcp, layout.rest_tcp, atol=1e-6)
    assert layout.table_height == pytest.approx(tcp[2] - 0.25 * layout.reach)
    assert tcp[1] == pytest.approx(0.0, abs=1e-6) and tcp[0] <= 1e-9  # under or behind the centre
    center, half = np.array(layout.table_center), np.array(layout.table_half_size)
    assert center[2] + half[2] == pytest.approx(layout.table_height)
    near_edge = center[0] - half[0]
    axis = agent.base_pos[0, :2]
    assert near_edge - axis[0] == pytest.approx(layout.turning_radius + 0.02 * layout.reach, abs=1e-9)
    nearest_cube = -layout.spawn_half_size - math.sqrt(2.0) * layout.cube_half_size
    assert nearest_cube >= near_edge + 0.02 * layout.reach - 1e-9
    assert abs(center[1]) + layout.spawn_half_size + math.sqrt(2.0) * layout.cube_half_size <= half[1]
    assert robot_table_contacts(env) < 1e-3
    for yaw in np.linspace(-math.pi, math.pi, 73):
        agent.set_base_pose(yaw=yaw)
        mujoco.mj_forward(env.model, env.data)
        assert robot_table_contacts(env) == 0.0, f"{uid} touches the table turned to {yaw:.2f} rad"
    env.close()


def test_small_servo_arm_and_big_arm_get_scaled_scenes() -> None:
    small, big = table_top_layout(ra.get_agent("koch-v1.1")), table_top_layout(ra.get_agent("ur_10e"))
    assert small.reach < 0.4 < 1.2 < big.reach
    assert small.table_half_size[1] / small.reach == pytest.approx(big.table_half_size[1] / big.reach)
    assert 2 * small.cube_half_size < 0.025 < 0.05 < 2 * big.cube_half_size
    # The Koch faces -y of its root: the layout turns it 90 deg about z.
    yaw = 2 * math.atan2(small.robot_pose[6], small.robot_pose[3])
    assert abs(abs(yaw) - math.pi / 2) < 0.05


# -- randomization ------------------------------------------------------------------------------
def cube_and_goal(env: Any) -> tuple[np.ndarray, np.ndarray]:
    u = env.unwrapped
    return u.body_pose("cube").copy(), u.goal_pos.copy()


@pytest.mark.parametrize("task", ["PickCube-v1", "PushCube-v1"])
def test_same_seed_same_cube_and_goal_and_each_env_its_own_stream(task: str) -> None:
    env = ra.make_env(task, robot_uids="panda", num_envs=3)
    env.reset(seed=5)
    first = cube_and_goal(env)
    qpos = env.unwrapped.agent.qpos
    env.reset(seed=5)
    second = cube_and_goal(env)
    np.testing.assert_array_equal(first[0], second[0])
    np.testing.assert_array_equal(first[1], second[1])
    env.reset(seed=6)
    assert not np.array_equal(first[0], cube_and_goal(env)[0])
    assert len({tuple(row) for row in first[0][:, :2]}) == 3  # envs differ
    # env i of the batch draws what a single env seeded 5 + i draws
    single = ra.make_env(task, robot_uids="panda")
    for i in range(3):
        single.reset(seed=5 + i)
        cube, goal = cube_and_goal(single)
        np.testing.assert_array_equal(cube[0], first[0][i])
        np.testing.assert_array_equal(goal[0], first[1][i])
        np.testing.assert_array_equal(single.unwrapped.agent.qpos[0], qpos[i])
    # a partial reset redraws only the envs it resets
    env.reset(seed=5)
    env.reset(options={"env_ids": [1]})
    third = cube_and_goal(env)
    np.testing.assert_array_equal(third[0][[0, 2]], first[0][[0, 2]])
    assert not np.array_equal(third[0][1], first[0][1])


def test_pick_cube_draws_within_its_bounds() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="so100", num_envs=64).unwrapped
    env.reset(seed=0)
    layout, half = env.layout, env.layout.cube_half_size
    cube, goal = env.body_pose("cube"), env.goal_pos
    s = layout.spawn_half_size
    assert np.all(np.abs(cube[:, :2]) <= s) and np.all(np.abs(goal[:, :2]) <= s)
    np.testing.assert_allclose(cube[:, 2], layout.table_height + half, atol=1e-9)  # resting on the table
    lift = goal[:, 2] - (layout.table_height + half)
    assert np.all(lift >= 0) and np.all(lift <= 0.2 * layout.reach)
    assert np.all(np.linalg.norm(goal - cube[:, :3], axis=1) > 2 * env.goal_threshold)
    assert np.ptp(cube[:, 0]) > s  # spread over the area
    yaw = 2 * np.arctan2(cube[:, 6], cube[:, 3])
    assert np.all(np.abs(yaw) <= math.pi / 4 + 1e-9) and np.ptp(yaw) > 1.0


def test_push_cube_goal_lies_ahead_of_the_cube() -> None:
    env = ra.make_env("PushCube-v1", robot_uids="ur_10e", num_envs=32).unwrapped
    env.reset(seed=1)
    r = env.layout.reach
    offset = env.goal_pos[:, :2] - env.body_pose("cube")[:, :2]
    assert np.all((offset[:, 0] >= 0.15 * r) & (offset[:, 0] <= 0.25 * r))
    assert np.all(np.abs(offset[:, 1]) <= 0.05 * r)
    np.testing.assert_allclose(env.goal_pos[:, 2], env.layout.table_height)


def test_reach_goals_are_reachable_poses_away_from_the_table() -> None:
    env = ra.make_env("ReachPose-v1", robot_uids="panda", num_envs=16).unwrapped
    env.reset(seed=3)
    goal = env.goal_pose
    np.testing.assert_allclose(np.linalg.norm(goal[:, 3:], axis=1), 1.0)
    assert np.all(goal[:, 2] >= env.layout.table_height + 0.05 * env.layout.reach)
    distance = np.linalg.norm(goal[:, :3] - env.agent.tcp_pose[:, :3], axis=1)
    assert np.all(distance < env.layout.reach) and np.median(distance) > 0.05
    assert env.with_orientation and not ra.make_env("ReachPose-v1", robot_uids="so100").unwrapped.with_orientation


# -- clear starts -------------------------------------------------------------------------------
def deepest_contacts(env: Any) -> dict[tuple[str, str], float]:
    """Deepest penetration (m) per body pair over every env right after a reset
    (``mj_forward`` on a copy of each env's positions)."""
    model = env.model
    data = mujoco.MjData(model)
    deepest: dict[tuple[str, str], float] = {}
    for source in env.scene.world.physics_sources():
        data.qpos[:] = source.qpos
        if model.nmocap:
            data.mocap_pos[:], data.mocap_quat[:] = source.mocap_pos, source.mocap_quat
        mujoco.mj_forward(model, data)
        for contact in data.contact[: data.ncon]:
            a, b = sorted(model.body(int(model.geom_bodyid[g])).name for g in (contact.geom1, contact.geom2))
            deepest[(a, b)] = max(deepest.get((a, b), 0.0), -float(contact.dist))
    return deepest


CLEAR_START_CASES = [(task, uid) for task in TASKS for uid in robots_for(task)] + [
    ("MobilePickCube-v1", uid) for uid in MOBILE if _has_gripper(uid)
]


@pytest.mark.parametrize(("task", "uid"), CLEAR_START_CASES)
def test_resets_start_clear_of_the_table_the_cube_and_the_robot_itself(task: str, uid: str) -> None:
    """Right after 100 seeded resets (with the default reset noise) nothing in the scene
    penetrates anything more than 1 mm: the robot's reset noise is drawn again where it
    would put the robot into the table (the Koch's rest jaw hangs 15 mm over it), the
    cube where it would overlap the robot at its reset pose (the Koch's cube is 22 mm
    tall: about half of its spawn square lies under the jaw). Every robot each task takes."""
    env = ra.make_env(task, robot_uids=uid, num_envs=100).unwrapped
    env.reset(seed=0)
    deep = {pair: round(depth * 1e3, 1) for pair, depth in deepest_contacts(env).items() if depth > 1e-3}
    assert not deep, f"{task} {uid}: penetrations (mm) right after reset: {deep}"
    env.close()


@pytest.mark.parametrize("uid", ["anymal_c", "unitree_go2", "unitree_h1", "koch-v1.1"])
def test_reset_noise_is_drawn_again_where_it_would_put_the_robot_into_the_floor(uid: str) -> None:
    """Empty-v1 too (the rule is the base env's): legs that stand on the floor at the
    keyframe, and the Koch's low jaw, are not pushed into it by the noise (up to 16 mm
    before), and every env still gets noise of its own."""
    env = ra.make_env("Empty-v1", robot_uids=uid, num_envs=100).unwrapped
    env.reset(seed=0)
    deep = {pair: round(depth * 1e3, 1) for pair, depth in deepest_contacts(env).items() if depth > 1e-3}
    assert not deep, f"{uid}: penetrations (mm) right after reset: {deep}"
    qpos = env.agent.qpos
    keyframe = env.agent.keyframe_qpos(env.agent.keyframe_names()[0])
    assert len({tuple(row) for row in qpos}) == 100 and not np.any(np.all(qpos == keyframe, axis=1))
    env.close()


def test_redrawn_resets_keep_one_stream_per_env(monkeypatch: pytest.MonkeyPatch) -> None:
    """With draws made again (the Koch's cube under its jaw, its noise into the table),
    env i of a batch seeded s still draws what a single env seeded s + i draws, and the
    same seed gives the same episode."""
    from robot_agents.envs.clearance import Clearance

    rejected = {"cube": 0, "noise": 0}
    body_clear, robots_clear = Clearance.body_clear_of_robots, Clearance.robots_clear

    def counted_body(self: Clearance, *args: Any) -> bool:
        clear = body_clear(self, *args)
        rejected["cube"] += not clear
        return clear

    def counted_robots(self: Clearance, *args: Any) -> bool:
        clear = robots_clear(self, *args)
        rejected["noise"] += not clear
        return clear

    monkeypatch.setattr(Clearance, "body_clear_of_robots", counted_body)
    monkeypatch.setattr(Clearance, "robots_clear", counted_robots)
    batch = ra.make_env("PickCube-v1", robot_uids="koch-v1.1", num_envs=12).unwrapped
    batch.reset(seed=3)
    cube, goal, qpos = batch.body_pose("cube"), batch.goal_pos.copy(), batch.agent.qpos
    assert rejected["cube"] > 0 and rejected["noise"] > 0  # the redraws happened
    batch.reset(seed=3)
    np.testing.assert_array_equal(batch.body_pose("cube"), cube)
    np.testing.assert_array_equal(batch.agent.qpos, qpos)
    single = ra.make_env("PickCube-v1", robot_uids="koch-v1.1").unwrapped
    for i in range(12):
        single.reset(seed=3 + i)
        np.testing.assert_array_equal(single.body_pose("cube")[0], cube[i])
        np.testing.assert_array_equal(single.goal_pos[0], goal[i])
        np.testing.assert_array_equal(single.agent.qpos[0], qpos[i])


def test_a_prop_drawn_only_inside_the_robot_raises() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="koch-v1.1", robot_init_qpos_noise=0.0).unwrapped
    env.reset(seed=0)
    jaw = env.data.xpos[env.model.body(f"{env.agent.prefix}fixed_jaw").id].copy()
    with pytest.raises(ra.ConfigError, match=r"100 poses of 'cube' drawn in env 0 all overlap the robot"):
        env.draw_clear_pose("cube", 0, lambda rng: [*jaw, 1.0, 0.0, 0.0, 0.0])
    clear = env.draw_cube_pose(0)  # the spawn square has room
    assert abs(clear[2] - env.layout.table_height - env.layout.cube_half_size) < 1e-12


def test_a_goal_region_too_small_for_the_threshold_raises_instead_of_hanging() -> None:
    """PickCube draws its goal again while it lies within two success thresholds of the
    cube: where no goal of the region can lie that far (a gripper opening large for the
    reach makes a large cube and threshold), the reset raises after 100 draws; before,
    it drew forever."""
    env = ra.make_env("PickCube-v1", robot_uids="panda").unwrapped
    env.reset(seed=0)
    env.goal_threshold = env.layout.reach  # no goal of the region lies 2 R from the cube
    with pytest.raises(ra.ConfigError, match=r"100 goals drawn in env 0 all lie within"):
        env.reset(seed=0)
    env.close()


# -- success ------------------------------------------------------------------------------------
def test_pick_cube_success_by_hand() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="panda", num_envs=3, robot_init_qpos_noise=0.0).unwrapped
    env.reset(seed=2)
    threshold = env.goal_threshold
    assert threshold == pytest.approx(1.25 * env.layout.cube_half_size)
    poses = np.tile([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], (3, 1))
    poses[:, :3] = env.goal_pos
    poses[1, 0] += 0.9 * threshold  # near enough
    poses[2, 0] += 1.1 * threshold  # next to it
    env.place_body("cube", poses)
    info = env.evaluate()
    assert info["success"].dtype == bool and info["success"].shape == (3,)
    np.testing.assert_array_equal(info["success"], [True, True, False])
    np.testing.assert_array_equal(info["is_obj_placed"], [True, True, False])
    np.testing.assert_allclose(info["obj_to_goal_dist"], [0.0, 0.9 * threshold, 1.1 * threshold], atol=1e-12)
    assert not info["is_grasped"].any()
    # a moving arm is not done
    env.place_body("cube", np.tile(poses[0], (3, 1)))
    env.agent.reset(qpos=env.agent.qpos, qvel=np.full((3, env.agent.dof), 0.5))
    assert not env.evaluate()["success"].any()


def test_push_cube_success_by_hand() -> None:
    env = ra.make_env("PushCube-v1", robot_uids="xarm6_nogripper", num_envs=4).unwrapped
    env.reset(seed=4)
    half, radius = env.layout.cube_half_size, env.goal_radius
    assert radius == pytest.approx(0.1 * env.layout.reach)
    poses = np.tile([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], (4, 1))
    poses[:, :3] = env.goal_pos + np.array([0.0, 0.0, half])
    poses[1, 1] += 0.9 * radius  # inside the disc
    poses[2, 1] += 1.1 * radius  # outside
    poses[3, 2] += 3 * half  # above the goal, off the table
    env.place_body("cube", poses)
    np.testing.assert_array_equal(env.evaluate()["success"], [True, True, False, False])


def test_reach_pose_success_by_hand() -> None:
    for uid, orientation in (("panda", True), ("so100", False)):
        env = ra.make_env("ReachPose-v1", robot_uids=uid, num_envs=4).unwrapped
        env.reset(seed=0)
        tcp = env.agent.tcp_pose
        threshold = env.position_threshold
        assert threshold == pytest.approx(0.02 * env.layout.reach)
        goal = np.tile(tcp[0], (4, 1))
        goal[:] = tcp
        goal[1, 2] += 0.9 * threshold
        goal[2, 2] += 1.1 * threshold
        turn = rotvec_to_quat(np.array([0.15, 0.0, 0.0]))
        quat = np.empty(4)
        mujoco.mju_mulQuat(quat, turn, tcp[3, 3:])
        goal[3, 3:] = quat  # turned 0.15 rad: fails only where orientation counts
        env.goal_pose[:] = goal
        info = env.evaluate()
        np.testing.assert_array_equal(info["success"], [True, True, False, not orientation])
        np.testing.assert_allclose(info["rotation_error"][3], 0.15, atol=1e-9)


def test_reach_goals_are_not_met_at_the_start() -> None:
    """A ReachPose goal is drawn again while it lies within two success thresholds of the
    tool at the reset (PickCube's rule for its goal and cube): on the SO-100, 2 of 500
    envs (seed 0) started already succeeded, a free success at the first step."""
    env = ra.make_env("ReachPose-v1", robot_uids="so100", num_envs=500).unwrapped
    env.reset(seed=0)
    start = env.agent.tcp_pose[:, :3]
    distance = np.linalg.norm(env.goal_pose[:, :3] - start, axis=1)
    assert distance.min() > 2.0 * env.position_threshold
    assert not env.evaluate()["success"].any()
    env.close()


# -- rewards ------------------------------------------------------------------------------------
@pytest.mark.parametrize("task", TASKS)
def test_rewards_finite_and_bounded_in_every_mode(task: str) -> None:
    rng = np.random.default_rng(0)
    for mode, high in (("normalized_dense", 1.0), ("dense", None), ("sparse", 1.0)):
        env = ra.make_env(task, robot_uids="panda", num_envs=4, reward_mode=mode)
        u = env.unwrapped
        env.reset(seed=1)
        top = high if high is not None else u.max_reward
        for _ in range(10):
            reward = env.step(rng.uniform(-1, 1, env.action_space.shape))[1]
            assert reward.shape == (4,) and np.all(np.isfinite(reward))
            assert np.all(reward >= 0.0) and np.all(reward <= top)
            if mode == "sparse":
                assert set(np.unique(reward)) <= {0.0, 1.0}
        env.close()
    with pytest.raises(ra.ConfigError, match="reward_mode"):
        ra.make_env(task, robot_uids="panda", reward_mode="shaped")


def test_success_earns_the_largest_reward() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="panda", num_envs=2, robot_init_qpos_noise=0.0, reward_mode="dense")
    u = env.unwrapped
    env.reset(seed=0)
    poses = np.tile([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], (2, 1))
    poses[:, :3] = u.goal_pos
    u.place_body("cube", poses)
    info = u.evaluate()
    np.testing.assert_allclose(u.compute_reward(info), [5.0, 5.0])
    # Away from everything, the dense reward is the reaching term alone: 1 - tanh(d / 0.2 R).
    poses[1, :3] = [0.0, 0.0, u.layout.table_height + u.layout.cube_half_size]
    u.place_body("cube", poses[1:], [1])
    info = u.evaluate()
    d = np.linalg.norm(u.agent.tcp_pose[1, :3] - u.body_pose("cube")[1, :3])
    assert u.compute_reward(info)[1] == pytest.approx(1.0 - math.tanh(d / (0.2 * u.layout.reach)))
    # At the goal with the arm moving at 0.3 rad/s (too fast to count as still): the
    # reaching term plus ManiSkill's static term 1 - tanh(5 * |arm qvel|), no success.
    poses[0, :3] = u.goal_pos[0]
    u.place_body("cube", poses[:1], [0])
    qvel = np.zeros_like(u.agent.qvel[:1])
    qvel[0, :2] = (0.18, 0.24)  # |arm qvel| = 0.3 rad/s
    u.agent.reset(qpos=u.agent.qpos[0], qvel=qvel[0], env_ids=[0])
    info = u.evaluate()
    assert not info["success"][0] and info["is_obj_placed"][0] and not info["is_grasped"][0]
    d = np.linalg.norm(u.agent.tcp_pose[0, :3] - u.body_pose("cube")[0, :3])
    expected = 1.0 - math.tanh(d / (0.2 * u.layout.reach)) + 1.0 - math.tanh(5.0 * 0.3)
    assert u.compute_reward(info)[0] == pytest.approx(expected, rel=1e-12)


# -- API ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("task", TASKS)
def test_check_env_and_every_obs_mode(task: str) -> None:
    env = ra.make_env(task, robot_uids="panda_wristcam", render_mode="rgb_array", render_size=(64, 48))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=False)
    env.close()
    for mode in ("state_dict", "sensor_data", "rgb", "depth", "rgbd", "segmentation", "pointcloud"):
        env = ra.make_env(task, robot_uids="panda_wristcam", obs_mode=mode, num_envs=2)
        obs, _ = env.reset(seed=0)
        assert env.observation_space.contains(obs), mode
        obs, _, _, _, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs), mode
        assert info["success"].shape == (2,) and info["success"].dtype == bool
        if mode not in ("state_dict", "pointcloud"):
            assert "base_camera" in obs["sensor_data"]
        if mode != "state_dict":
            assert "obj_pose" not in obs["extra"]  # camera modes see the goal, not the object
        env.close()


def test_task_observations() -> None:
    env = ra.make_env("PickCube-v1", robot_uids="so100", obs_mode="state_dict", num_envs=2)
    obs, _ = env.reset(seed=0)
    u = env.unwrapped
    extra = obs["extra"]
    np.testing.assert_allclose(extra["goal_pos"], u.goal_pos, rtol=1e-6)
    np.testing.assert_allclose(extra["obj_pose"], u.body_pose("cube"), rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(extra["tcp_to_obj_pos"], u.body_pose("cube")[:, :3] - u.agent.tcp_pose[:, :3], atol=1e-6)
    flat = ra.make_env("PickCube-v1", robot_uids="so100").reset(seed=0)[0]
    assert flat.shape == (1, int(sum(np.prod(v.shape[1:]) for v in _leaves(obs))))  # the same values, flat


def _leaves(tree: Any) -> list[np.ndarray]:
    if isinstance(tree, dict):
        return [leaf for value in tree.values() for leaf in _leaves(value)]
    return [np.asarray(tree)]


def test_tasks_are_registered_with_gymnasium_and_say_what_a_robot_lacks() -> None:
    for task in TASKS:
        env = gym.make(f"robot_agents/{task}", robot_uids="panda")
        assert isinstance(env.unwrapped, ra.RobotEnv)
        env.close()
    assert set(GRIPPER_ROBOTS) <= set(robots_for("PickCube-v1"))
    for uid in set(robots_for("ReachPose-v1")) - set(robots_for("PickCube-v1")):
        with pytest.raises(ra.ConfigError, match="no Gripper or Hand part"):
            ra.make_env("PickCube-v1", robot_uids=uid)
    for uid in set(ra.list_agents()) - set(robots_for("ReachPose-v1")):  # legged robots without a tool
        for task in TASKS:
            with pytest.raises(ra.ConfigError, match=r"no end effector|no Gripper or Hand part"):
                ra.make_env(task, robot_uids=uid)
    with pytest.raises(ra.ConfigError, match="one robot"):
        ra.make_env("PickCube-v1", robot_uids=("panda", "panda"))


def test_default_episode_lengths() -> None:
    for task in TASKS:
        env = ra.make_env(task, robot_uids="panda")
        assert env.unwrapped.max_episode_steps == 100
        env.close()


def test_readme_tasks_block_runs() -> None:
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", readme, flags=re.S) if "PickCube-v1" in b)
    namespace: dict[str, Any] = {}
    exec(compile(block, "README tasks block", "exec"), namespace)
    assert namespace["info"]["success"].shape == (4,)
    assert np.all((namespace["reward"] >= 0) & (namespace["reward"] <= 1))


def test_task_classes_take_num_envs_second_like_every_env() -> None:
    from robot_agents.envs.tasks import PickCubeEnv

    env = PickCubeEnv("panda", 3, reward_mode="sparse")
    assert env.num_envs == 3 and env.reward_mode == "sparse"
    env.close()


def test_the_fingertips_reach_covers_the_whole_stroke() -> None:
    """The Robotiq 2F-85's pads swing past their open reach while closing: driven from
    open to closed, the lowest point of the pads' boxes along the approach axis never
    passes ``tip_reach`` below the grasp point, and it passes the open reach by more
    than 1 cm on the way (the descent must keep the whole stroke above the table)."""
    from robot_agents.agent.derived import geom_box
    from robot_agents.envs.tasks.layout import table_top_layout, tool_arm
    from robot_agents.kinematics.rotations import quat_to_matrix

    uid = "floating_robotiq_2f_85_gripper"
    geometry = table_top_layout(ra.get_agent(uid)).gripper
    assert geometry is not None
    scene = ra.Scene(uid, control_modes="pd_joint_pos", floor=False)
    agent = scene.agents[0]
    model, data = scene.model, scene.world.datas[0]
    pads = [g for g in range(model.ngeom) if model.body(model.geom_bodyid[g]).name.endswith("_pad")]
    assert len(pads) >= 2
    tcp = tool_arm(agent, "test").end_effectors[0].name

    def reach() -> float:
        tool = agent.frame_pose(tcp)[0]
        rotation = quat_to_matrix(tool[None, 3:])[0]
        grasp, approach = (
            tool[:3] + rotation @ np.array(geometry.grasp_point),
            rotation @ np.array(geometry.approach_axis),
        )
        farthest = -np.inf
        for g in pads:
            centre, axes, half = geom_box(model, data, g)
            farthest = max(farthest, float((centre - grasp) @ approach + half @ np.abs(axes.T @ approach)))
        return farthest

    scene.reset()
    action = np.zeros((1, agent.action_space.shape[-1]))
    action[0, agent.controller.slices["gripper"]] = 1.0  # open
    for _ in range(20):
        agent.set_action(action)
        scene.step()
    reaches = [reach()]
    action[0, agent.controller.slices["gripper"]] = -1.0  # close, step by step
    for _ in range(20):
        agent.set_action(action)
        scene.step()
        reaches.append(reach())
    assert max(reaches) <= geometry.tip_reach + 1e-3, (max(reaches), geometry.tip_reach)
    assert max(reaches) > reaches[0] + 0.01, reaches


@pytest.mark.parametrize("task", list(ra.envs.TASKS))
def test_every_registered_task_is_bit_identical_for_the_same_seed_and_actions(task: str) -> None:
    """Two envs made alike, reset with one seed and given the same actions observe,
    earn and end identically bit for bit, through the next (unseeded) reset too."""
    uid = "fetch" if task == "MobilePickCube-v1" else "panda"

    def run() -> list[Any]:
        env = ra.make_env(task, robot_uids=uid, num_envs=2)
        obs, _ = env.reset(seed=7)
        out = [obs]
        rng = np.random.default_rng(1)
        for _ in range(6):
            obs, reward, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
            out += [obs, reward, terminated, truncated]
        out.append(env.reset()[0])
        env.close()
        return out

    first, second = run(), run()
    assert not np.array_equal(first[0], first[-5])  # the observations change: something to compare
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("obs_mode", ["state", "state_dict", "rgbd", "pointcloud"])
@pytest.mark.parametrize("task", list(ra.envs.TASKS))
def test_gymnasium_check_env_passes_on_every_registered_task(task: str, obs_mode: str) -> None:
    """Gymnasium's own checker, warnings as errors, on every ``robot_agents/...`` id
    (made with ``gymnasium.make``) in state and camera observation modes."""
    uid = "fetch" if task == "MobilePickCube-v1" else "panda"
    env = gym.make(f"robot_agents/{task}", robot_uids=uid, obs_mode=obs_mode)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=True)
    env.close()


@pytest.mark.parametrize("uid", ["so100", "panda"])
def test_the_closed_point_lies_on_both_closed_fingers(uid: str) -> None:
    """Driven closed, each finger's colliding geoms come within 1 cm of ``closed_point``
    (MuJoCo's geom distances from a probe sphere there), and the nearest of them lies
    ``closed_clearance`` from the grasp point (within 2 mm). The Panda's fingers close
    on the grasp point (within 1 mm); the SO-100's moving jaw closes on its fixed jaw,
    beside it across the approach axis (1.4 cm from it: less than the cube's half edge,
    so the push solver keeps the grasp point for both)."""
    from robot_agents.agent.derived import colliding_geoms
    from robot_agents.envs.tasks.layout import tool_arm
    from robot_agents.kinematics.rotations import quat_to_matrix
    from robot_agents.model.scene import Prop
    from tests.test_scripted_solvers import load_solver

    layout = table_top_layout(ra.get_agent(uid))
    geometry = layout.gripper
    assert geometry is not None and geometry.closed_point is not None
    scene = ra.Scene(
        uid, control_modes="pd_joint_pos", floor=False, props=[Prop("probe", "sphere", (1e-4,), mass=1e-3)]
    )
    agent = scene.agents[0]
    model = scene.model
    scene.reset()
    action = np.zeros((1, agent.action_space.shape[-1]))
    action[0, agent.controller.slices["gripper"]] = -1.0  # close
    for _ in range(40):
        agent.set_action(action)
        scene.step()
    data = mujoco.MjData(model)
    data.qpos[:] = scene.world.qpos[0]
    tool = agent.frame_pose(tool_arm(agent, "test").end_effectors[0].name)[0]
    rotation = quat_to_matrix(tool[None, 3:])[0]
    probe = model.body("probe")
    adr = int(model.jnt_qposadr[probe.jntadr[0]])
    probe_geom = model.geom("probe").id
    fingers = [
        colliding_geoms(
            model, {b for link in finger for b in agent.index.subtree_bodies(agent.index.body_id(link, "t"))}
        )
        for finger in agent.gripper().finger_links[:2]
    ]

    def gaps(point_in_tool: Any) -> list[float]:
        data.qpos[adr : adr + 3] = tool[:3] + rotation @ np.asarray(point_in_tool)
        mujoco.mj_kinematics(model, data)
        fromto = np.zeros(6)
        return [min(mujoco.mj_geomDistance(model, data, probe_geom, g, 1.0, fromto) for g in f) for f in fingers]

    assert max(gaps(geometry.closed_point)) < 0.01, gaps(geometry.closed_point)
    assert min(gaps(geometry.grasp_point)) == pytest.approx(geometry.closed_clearance, abs=0.002)
    approach = np.array(geometry.approach_axis)
    aside = np.array(geometry.closed_point) - np.array(geometry.grasp_point)
    aside -= approach * float(aside @ approach)
    if uid == "panda":
        assert np.linalg.norm(aside) < 0.001 and geometry.closed_clearance < 0.001, (aside, geometry.closed_clearance)
    else:
        assert np.linalg.norm(aside) > 0.5 * layout.cube_half_size and geometry.closed_clearance > 0.01
    assert geometry.closed_clearance < layout.cube_half_size  # the built-in robots push as before
    np.testing.assert_array_equal(load_solver().push_point(geometry, layout.cube_half_size), geometry.grasp_point)


def test_the_push_aims_the_closed_jaws_where_the_grasp_point_is_clear_of_them() -> None:
    """Where the grasp point lies farther than half the cube's edge from every closed
    finger, the push point moves to where the closed fingers are, across the approach
    axis only (the descent finds the table's height itself); nearer, it stays."""
    from robot_agents.envs.tasks.layout import GripperGeometry
    from tests.test_scripted_solvers import load_solver

    push_point = load_solver().push_point
    geometry = GripperGeometry(
        opening=0.07,
        grasp_point=(0.0, 0.0, 0.1),
        closing_axis=(1.0, 0.0, 0.0),
        approach_axis=(0.0, 0.0, 1.0),
        closed_point=(0.02, 0.001, 0.09),
        closed_clearance=0.025,
    )
    np.testing.assert_allclose(push_point(geometry, 0.0175), [0.02, 0.001, 0.1], atol=1e-15)
    np.testing.assert_array_equal(push_point(geometry, 0.03), [0.0, 0.0, 0.1])
