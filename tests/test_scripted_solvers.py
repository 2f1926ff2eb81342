"""The scripted solvers of examples/scripted_pick.py solve PickCube-v1, PushCube-v1 and
ReachPose-v1 for every registered robot that has the parts (20 seeds each, at least 18
successes), unless the robot declares why it cannot (``task_limits``) or the solver is
known to fall short on it (:data:`SOLVER_SHORTFALLS`, strict expected failures)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

import robot_agents as ra

ROOT = Path(__file__).resolve().parents[1]
SEEDS, REQUIRED = 20, 18

#: Where the example's PushCube solver, which pushes with the fingers pointing down
#: (leaning 17 deg into the push, or back from it where leaning in would put the arm into
#: itself) from behind the cube, falls short: limits of that one strategy, not of the
#: robots, so they are not the robots' ``task_limits``. Strict: a solver that starts to
#: succeed fails the test until its entry goes. Empty since the push rises where it
#: presses the cube down (Stretch, 9/20 before: its stalled pushes).
SOLVER_SHORTFALLS: dict[tuple[str, str], str] = {
    (task, uid): (
        "ManiSkill's modes command the G1's joints as one part (its action order); the solver "
        "commands an arm part of its own and a one-action gripper (the G1's hands take an action per joint)"
    )
    for task in ("PickCube-v1", "PushCube-v1", "ReachPose-v1")
    for uid in (
        "unitree_g1_simplified_upper_body",
        "unitree_g1_simplified_upper_body_with_head_camera",
        "unitree_g1_simplified_upper_body_right_arm",
    )
}


def load_solver() -> ModuleType:
    spec = importlib.util.spec_from_file_location("scripted_pick", ROOT / "examples" / "scripted_pick.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["scripted_pick"] = module
    spec.loader.exec_module(module)
    return module


solver = load_solver()
CASES = [(task, uid) for task in solver.TASKS for uid in solver.robots_for(task)]


def test_every_robot_with_the_parts_is_covered() -> None:
    covered = {(task, uid) for task, uid in CASES}
    for uid in ("panda", "panda_wristcam", "panda_touch", "floating_panda_gripper", "so100", "koch-v1.1"):
        assert ("PickCube-v1", uid) in covered
    for uid in ra.list_agents():  # every registered robot with an end effector
        tools = [p for p in ra.get_agent(uid).check().parts if isinstance(p, ra.Arm) and p.end_effectors]
        assert (("ReachPose-v1", uid) in covered) == bool(tools), uid
    assert ("ReachPose-v1", "allegro_hand_right") not in covered  # a hand on a fixed mount: nothing to reach with
    assert ("PickCube-v1", "ur_10e") not in covered  # no gripper: the task refuses it
    assert ("PushCube-v1", "ur_10e") in covered  # pushing needs no gripper
    assert set(SOLVER_SHORTFALLS) <= covered


@pytest.mark.parametrize(("task", "uid"), CASES)
def test_scripted_solver_succeeds(task: str, uid: str, request: pytest.FixtureRequest) -> None:
    reason = ra.get_agent(uid).task_limits.get(task)
    if reason:
        pytest.skip(f"{uid} declares it cannot do {task}: {reason}")
    shortfall = SOLVER_SHORTFALLS.get((task, uid))
    if shortfall:
        request.applymarker(pytest.mark.xfail(reason=f"the solver falls short: {shortfall}", strict=True))
    successes, _ = solver.success_rate(task, uid, SEEDS)
    assert successes >= REQUIRED, f"{uid}: {successes}/{SEEDS} {task} episodes succeeded (need {REQUIRED})"


@pytest.mark.parametrize(("task", "uid", "seed"), [("PickCube-v1", "so100", 4), ("PushCube-v1", "so100", 34)])
def test_batched_solver_runs_match_single_runs(task: str, uid: str, seed: int) -> None:
    """Env i of a batch seeded s behaves as a single env seeded s + i, so success over a
    batch is success over seeds (PushCube from seed 34: a miss among successes; seeds
    5-7, the miss before, all succeed since the push start's self-contact rule)."""
    solve = solver.SOLVERS[task]
    batch = ra.make_env(task, robot_uids=uid, num_envs=3).unwrapped
    together = solve(batch, seed)
    alone = [bool(solve(ra.make_env(task, robot_uids=uid).unwrapped, seed + i)[0]) for i in range(3)]
    assert together.tolist() == alone
    assert task == "PickCube-v1" or alone == [True, True, False]


def test_measurement_script_prints_the_table() -> None:
    import subprocess

    result = subprocess.run(
        [
            sys.executable,
            str(ROOT / "examples" / "scripted_pick.py"),
            "--task",
            "ReachPose-v1",
            "--robots",
            "panda",
            "--seeds",
            "2",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-1].startswith("| ReachPose-v1 | panda | 2/2 |")


def test_the_table_reports_robots_it_does_not_run(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Listing every robot, the script skips one that declares the task out of reach and
    reports a robot whose action layout the solver cannot fill (the G1 upper body's one
    25-joint part) as a row, where it stopped with that ActionError before."""
    monkeypatch.setattr(solver, "robots_for", lambda task: ["xlerobot"])
    assert solver.main(["--task", "PickCube-v1", "--seeds", "1"]) == 0
    assert (
        "| PickCube-v1 | xlerobot | not run: the robot declares it cannot do the task | - |" in capsys.readouterr().out
    )
    uid = "unitree_g1_simplified_upper_body"
    with pytest.raises(ra.ActionError):
        solver.success_rate("ReachPose-v1", uid, 1)
    assert solver.main(["--task", "ReachPose-v1", "--robots", uid, "--seeds", "1"]) == 0
    row = capsys.readouterr().out.splitlines()[-1]
    assert row.startswith(
        f"| ReachPose-v1 | {uid} | not run: the solver cannot command it (expected finite raw commands"
    )


def test_the_turns_ik_moves_stretchs_telescope_segments_with_their_leader() -> None:
    """Frame poses at a given ``qpos`` move only the joints it sets; the solver's IK
    finds the three telescope segments that follow ``joint_arm_l0`` (``l1 = l0``,
    ``l2 = l1``, ``l3 = l2``) and moves them with it, so its solution above a cube
    puts the tool where it aimed (the lead segment alone cannot reach it)."""
    env = ra.make_env("PickCube-v1", robot_uids="stretch").unwrapped
    env.reset(seed=2)
    arm = solver.Arm(env)
    agent = env.agent
    lead = list(arm.q_index).index(agent.index.joint("joint_arm_l0", "test").qpos_start)
    found = {agent.joint_names[q] for q, _, column, offset, slope in arm.followers if column == lead}
    assert {name.rsplit("/", 1)[-1] for name in found} == {"joint_arm_l1", "joint_arm_l2", "joint_arm_l3"}
    assert all((offset, slope) == (0.0, 1.0) for _, _, _, offset, slope in arm.followers)
    # the target: the tool with the whole telescope 4 x 4 cm further out (reachable: the
    # lead segment alone cannot move 16 cm, its range is 0-0.13 m)
    out = agent.qpos.copy()
    for q in [arm.q_index[lead]] + [q for q, _, column, _, _ in arm.followers if column == lead]:
        out[:, q] += 0.04
    target = agent.frame_pose(arm.ee, qpos=out)
    solution = arm.solve(target[:, :3], target[:, 3:])
    full = agent.qpos.copy()
    full[:, arm.q_index] = solution
    for q, _, column, offset, slope in arm.followers:
        full[:, q] = offset + slope * solution[:, column]
    reached = agent.frame_pose(arm.ee, qpos=full)
    assert np.linalg.norm(reached[0, :3] - target[0, :3]) < 1e-3, (reached, target)
    env.close()


def test_the_turns_ik_restarts_where_joint_limits_trap_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """WidowX 250 S, PickCube seed 37: from the measured joints the IK ends with the
    shoulder and the wrist at their limits, the tool 14 cm off, and the episode fails;
    a restart from a random configuration reaches the target and the cube is picked."""
    assert solver.success_rate("PickCube-v1", "widowx250s", 1, seed=37)[0] == 1
    solve = solver.Arm.solve
    monkeypatch.setattr(
        solver.Arm,
        "solve",
        lambda self, position, quat, iterations=200, restarts=0, refuse=None: solve(self, position, quat, 200, 0),
    )
    assert solver.success_rate("PickCube-v1", "widowx250s", 1, seed=37)[0] == 0


def test_the_push_rises_where_it_presses_the_cube_down(monkeypatch: pytest.MonkeyPatch) -> None:
    """Stretch, PushCube seed 4: without the rise, the push stalls pressing the cube onto
    the table (the robot's force on it pointing down by more than half its horizontal
    part when the episode ends, the cube short of the goal); with it, the cube slides
    into the goal. (Seed 0 until the Stretch's finger pads became overdamped,
    2026-11-29: without the rise seed 0 now slides too; seeds 4, 5, 6, 8 and 11 of 0-19
    still stall, docs/tasks.md.)"""
    assert solver.success_rate("PushCube-v1", "stretch", 1, seed=4)[0] == 1
    monkeypatch.setattr(solver, "RISE", 0.0)
    env = ra.make_env("PushCube-v1", robot_uids="stretch").unwrapped
    try:
        assert not solver.solve_push(env, 4)[0]
        force = solver.Arm(env).force_on("cube")[0]
        assert -force[2] > 0.5 * np.linalg.norm(force[:2]) > 1.0, force
    finally:
        env.close()


def test_the_push_rises_where_it_drags_on_the_table(monkeypatch: pytest.MonkeyPatch) -> None:
    """WidowX 250 S at its 100 Hz default, PushCube seed 6: without the rise, the
    fingertips (sunk 3 mm into the table's soft contact where the push's height was
    measured) drag on the table to the end of the episode, the cube creeping short of
    the goal, the robot pressing the cube down no more than along; with it, the cube
    slides into the goal (docs/tasks.md, "The WidowX 250 S's dragged pushes")."""
    assert ra.get_agent("widowx250s").sim_freq == 100
    assert solver.success_rate("PushCube-v1", "widowx250s", 1, seed=6)[0] == 1
    monkeypatch.setattr(solver, "RISE", 0.0)
    env = ra.make_env("PushCube-v1", robot_uids="widowx250s").unwrapped
    try:
        assert not solver.solve_push(env, 6)[0]
        arm = solver.Arm(env)
        assert arm.on_table()[0]
        force = arm.force_on("cube")[0]
        assert -force[2] <= 0.5 * np.linalg.norm(force[:2]), force  # not the pressing stall
    finally:
        env.close()


def test_video_records_the_episode_as_rendered(tmp_path: Path) -> None:
    from PIL import Image

    env = ra.make_env("ReachPose-v1", robot_uids="so100", render_mode="rgb_array").unwrapped
    frames: list[np.ndarray] = []
    assert solver.solve_reach(env, 0, frames=frames)[0]
    assert len(frames) == (env.max_episode_steps or 100) + 1  # the reset, then every step
    assert frames[0].shape == (env.render_size[1], env.render_size[0], 3)
    env.close()
    path = tmp_path / "reach.gif"
    assert solver.record_episode("ReachPose-v1", "so100", 0, str(path))
    with Image.open(path) as gif:  # (Pillow merges repeated frames)
        assert gif.n_frames > 10 and gif.size == env.render_size


def test_video_wants_one_task_and_one_robot() -> None:
    with pytest.raises(SystemExit) as exit_info:
        solver.main(["--task", "PickCube-v1", "--robots", "so100", "panda", "--video", "x.gif"])
    assert exit_info.value.code == 2


def test_seeds_below_one_are_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    """``--seeds 0`` is refused by the command line (before, a traceback from the world:
    ``BatchedWorld: expected num_envs ... got 0``), and so is a negative ``--seed``."""
    for argv in (
        ["--task", "PushCube-v1", "--robots", "panda", "--seeds", "0"],
        ["--task", "PickCube-v1", "--robots", "so100", "--seed", "-1", "--video", "x.gif"],
    ):
        with pytest.raises(SystemExit) as exit_info:
            solver.main(argv)
        assert exit_info.value.code == 2
    assert "--seed" in capsys.readouterr().err


def test_the_ramp_takes_the_nearest_turn_of_a_full_turn_joint() -> None:
    """The UR10e's joints span +-2 pi (its elbow +-pi): an IK solution a whole turn away
    on one of them is driven as the same angle near where the joint is; a joint that
    spans less, or a turn that would leave the limits, is left as solved."""
    env = ra.make_env("ReachPose-v1", robot_uids="ur_10e").unwrapped
    try:
        env.reset(seed=0)
        arm = solver.Arm(env)
        assert arm.turns.tolist() == [True, True, False, True, True, True]
        start = np.array([[0.3, -1.0, 1.2, -1.5, -1.6, 0.0]])
        goal = start + np.array([[2.0 * np.pi, -2.0 * np.pi, 2.0 * np.pi, 0.1, 0.0, 0.0]])
        goal[0, 2] = 1.2  # the elbow cannot take a turn (+-pi): keep it in range
        near = arm.nearest_turns(goal, start)
        assert near[0] == pytest.approx([0.3, -1.0, 1.2, -1.4, -1.6, 0.0])
        # 6 rad with the joint at -6: its nearest equivalent, 6 - 4 pi, lies past the -2 pi
        # stop, so the next nearest within the limits, 6 - 2 pi
        at_stop = np.array([[-6.0, -1.0, 1.2, -1.5, -1.6, 0.0]])
        solved = np.array([[6.0, -1.0, 1.2, -1.5, -1.6, 0.0]])
        assert arm.nearest_turns(solved, at_stop)[0, 0] == pytest.approx(6.0 - 2.0 * np.pi)
    finally:
        env.close()
