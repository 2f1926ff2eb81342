"""Island sleeping (``sleep=True``): props at rest stop being simulated, the robot never
sleeps, and state round trips stay exact (the sleep state is saved)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra

SLEEP = int(mujoco.mjtEnableBit.mjENBL_SLEEP)


def pick_cube(sleep: bool = True) -> ra.RobotEnv:
    env = ra.make_env(
        "PickCube-v1", robot_uids="panda", control_mode="pd_joint_delta_pos", max_episode_steps=None, sleep=sleep
    )
    env.reset(seed=0)
    return env.unwrapped  # type: ignore[no-any-return]


def actions(count: int) -> list[np.ndarray]:
    rng = np.random.default_rng(0)
    moving = [rng.uniform(-0.1, 0.1, 8).astype(np.float32) for _ in range(count // 2)]
    return moving + [np.zeros(8, np.float32)] * (count - count // 2)


def run(env: ra.RobotEnv, sequence: list[np.ndarray]) -> np.ndarray:
    for action in sequence:
        env.step(action)
    return np.asarray(env.get_state()["physics"]).copy()


def cube_asleep(env: ra.RobotEnv) -> bool:
    data = env.scene.world.physics_sources([0])[0]
    tree = int(env.model.body_treeid[env.model.body("cube").id])
    return not bool(data.tree_awake[tree])


def test_sleeping_is_on_for_the_tasks_and_off_elsewhere_by_default() -> None:
    assert not ra.make_env("Empty-v1", robot_uids="panda").unwrapped.model.opt.enableflags & SLEEP
    assert not ra.Scene("panda").model.opt.enableflags & SLEEP
    assert ra.make_env("PickCube-v1", robot_uids="panda").unwrapped.model.opt.enableflags & SLEEP
    assert not pick_cube(sleep=False).model.opt.enableflags & SLEEP
    env = pick_cube()
    assert env.model.opt.enableflags & SLEEP
    run(env, actions(200))
    assert cube_asleep(env)  # the cube at rest on the table sleeps
    with pytest.raises(ra.ConfigError, match="sleep"):
        ra.make_env("PickCube-v1", robot_uids="panda", sleep="yes")


def test_the_robot_never_sleeps() -> None:
    env = pick_cube()
    run(env, [np.zeros(8, np.float32)] * 100)
    before = env.agent.qpos.copy()
    run(env, [np.full(8, 0.5, np.float32)] * 3)
    assert np.max(np.abs(env.agent.qpos - before)) > 0.05


def test_state_round_trips_stay_exact_with_sleeping_props() -> None:
    env = pick_cube()
    sequence, nudge = actions(200), actions(60)
    start = env.get_state()  # the cube awake
    first = run(env, sequence)
    assert cube_asleep(env)
    middle = env.get_state()
    env.set_state(start)  # back to an awake cube from a sleeping one
    assert np.array_equal(run(env, sequence), first)
    later = run(env, nudge)
    env.set_state(middle)
    assert np.array_equal(run(env, nudge), later)
    # the same seed and actions in a fresh env: the same trajectory
    assert np.array_equal(run(pick_cube(), sequence), first)


def test_a_sleeping_state_restored_in_a_fresh_env_continues_exactly() -> None:
    """The fresh env's cube is awake; the saved one's sleeps (MuJoCo's integration state
    alone would wake it: the continuation would differ)."""
    still = [np.zeros(8, np.float32)] * 50
    env = pick_cube()
    run(env, [np.zeros(8, np.float32)] * 150)
    assert cube_asleep(env)
    saved = env.get_state()
    original = run(env, still)
    fresh = pick_cube()
    assert not cube_asleep(fresh)
    fresh.set_state(saved)
    assert cube_asleep(fresh)
    assert np.array_equal(run(fresh, still), original)


def test_a_bad_sleep_state_is_refused_before_anything_changes() -> None:
    env = pick_cube()
    run(env, actions(20))
    state = env.get_state()
    bad = {**state, "sleep": np.asarray(state["sleep"])[:, :-1]}
    before = env.get_state()
    with pytest.raises(ra.StateError, match="sleep state"):
        env.set_state(bad)
    after = env.get_state()
    assert np.array_equal(after["physics"], before["physics"]) and np.array_equal(after["sleep"], before["sleep"])


@pytest.mark.parametrize(
    ("column", "value", "fragment"),
    [
        (None, 7, r"tree_asleep entries in \[-11, 1\], got 7 at tree_asleep\[0\] in env 0"),
        (2, 2, r"tree_awake entries in \[0, 1\], got 2"),
        (4, -2, r"body_awake entries in \[-1, 1\], got -2"),
        (-1, 99, r"nv_awake entries in \[0, 15\], got 99"),
        (0, 1, r"permutation of the sleeping trees \[0\], got \[1\]"),
    ],
)
def test_an_out_of_range_sleep_state_is_refused_and_the_env_goes_on(
    column: int | None, value: int, fragment: str
) -> None:
    """Values of the right shape and type but outside what MuJoCo's sleep arrays hold
    (an index past the trees, a tree's sleep cycle through an awake tree) are refused
    before anything is written: they crashed the next step (mujoco.FatalError), and
    a good state could not be restored after them."""
    env = pick_cube()
    run(env, [np.zeros(8, np.float32)] * 150)
    assert cube_asleep(env)  # tree 0 (the cube) sleeps: its cycle is itself
    good = env.get_state()
    bad = {**good, "sleep": np.array(good["sleep"], copy=True)}
    if column is None:
        bad["sleep"][:] = value
    else:
        bad["sleep"][0, column] = value
    with pytest.raises(ra.StateError, match=fragment):
        env.set_state(bad)
    after = env.get_state()
    assert np.array_equal(after["physics"], good["physics"]) and np.array_equal(after["sleep"], good["sleep"])
    still = [np.zeros(8, np.float32)] * 5
    expected = run(env, still)
    env.set_state(good)
    assert np.array_equal(run(env, still), expected)
