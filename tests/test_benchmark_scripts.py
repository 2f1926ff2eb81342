"""Every benchmark script still runs (on its smallest setting): the figures in the docs
come from them, and a script that no longer runs cannot be rerun. Not a speed test:
nothing here is timed. Left out: vs_maniskill.py, peer_link_poses.py, peer_joint_drives.py
and task_throughput's peer rows (need mani-skill), public_models.py (downloads a wheel), timestep_sweep.py (the sweep has its
own tests in test_timestep.py)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"

#: script and arguments -> a piece of text its output must contain.
RUNS = {
    ("python_floor.py", "--rounds", "1", "--block", "2"): "of raw const",
    ("overhead_ratio.py", "--robots", "so100", "--rounds", "1", "--block", "2"): "| `so100` | `pd_joint_delta_pos`",
    ("overhead_ratio.py", "--robots", "so100", "--modes", "joint", "--python-only"): "| `so100` |",
    (
        "overhead_ratio.py",
        "--robots",
        "fetch",
        "--modes",
        "joint",
        "--rounds",
        "1",
        "--block",
        "2",
        "--num-envs",
        "3",
    ): ("| `fetch` | `pd_joint_delta_pos`"),
    ("ee_step_split.py", "--robots", "so100:pd_ee_delta_pos", "--rounds", "1", "--block", "2"): (
        "| `so100` | `pd_ee_delta_pos` |"
    ),
    (
        "ee_step_split.py",
        "--robots",
        "panda:pd_ee_delta_pose",
        "--rounds",
        "2",
        "--block",
        "2",
        "--against",
        str(BENCHMARKS.parent / "src"),  # (this checkout against itself: its code loaded again, the general path)
        "--python-only",
    ): "| `panda` | `pd_ee_delta_pose` |",
    ("sim_options.py", "so100", "--blocks", "1", "--steps", "5", "--variants", "visual geoms simulated"): "| yes |",
    ("solver_tolerance.py", "so100", "--tolerances", "1e-8,1e-11"): "| `so100` | 200 | 1e-11 | 0.294 |",
    (
        "solver_tolerance.py",
        "--tolerances",
        "1e-11",
        "--test",
        "tests/test_xlerobot.py::test_each_jaw_grasps_lifts_and_holds_a_cube",
    ): "| declared | 1e-11 | 2 passed",
    ("batch_stepping.py", "--num-envs", "2", "--rounds", "1"): "BatchedWorld",
    ("thread_schedules.py", "--num-envs", "3", "--rounds", "1"): "| 3 | ",
    (
        "core_scaling.py",
        "--robots",
        "so100",
        "--num-envs",
        "2",
        "--threads",
        "1",
        "2",
        "--rounds",
        "1",
        "--block",
        "2",
    ): ("| `so100` | 2 | 2 |"),
    ("render_throughput.py", "--rounds", "1", "--block", "1", "--num-envs", "1"): "capture fps",
    ("default_step_speedup.py", "so100", "--rounds", "1"): "| `so100`",
    ("pose_sync_cost.py",): "| `fetch` |",
    ("legged_contacts.py", "unitree_go2", "--steps", "2"): "| `unitree_go2` | as declared |",
    ("bridge_latency.py", "--robots", "so100", "--rounds", "1", "--block", "2"): "| `so100` | `pd_joint_delta_pos` |",
    ("random_press.py", "so100", "--seeds", "0", "--floor-solref", "0.004", "1"): "so100  (sim_freq 200)",
    ("integrator_claims.py", "floating_panda_gripper", "160"): "| `floating_panda_gripper` | 160 |",
    ("mobile_pick_seeds.py", "spot", "--seeds", "1"): "| `spot` | 1/1 |",
    ("push_forces.py", "so100", "--seeds", "1", "--no-rise", "--all"): "| 0 | True |",
    ("base_odometry.py", "stretch", "--dynamics", "kinematic"): "| `stretch` | kinematic | ",
    ("rated_speed.py", "so100", "--bridge"): "| `so100` | 0.57 | 12 |",
    ("sleep_option.py", "--rounds", "1"): "round trip",
    ("load_time.py", "--rounds", "1"): "| xarm6_robotiq (a fresh subclass) |",
    ("ik_reach.py", "--robots", "so100", "--count", "2", "--jacobians"): "| `so100` (position) | 5 |",
    ("jaw_close.py", "so100", "--seeds", "1", "--rate", "0.05", "--cube-share", "0.5", "--against", "1.5"): "/1: seeds",
    ("jaw_close.py", "so100", "--trace", "0", "--rate", "0.05"): "Moving_Jaw",
    ("pad_press_trace.py", "stretch", "--seconds", "1", "--trace", "0.99", "1"): "| 1.000 |",
    ("collision_pairs.py", "panda_stick", "--rounds", "1", "--steps", "2"): "panda_stick",
    ("simplified_collisions.py", "--steps", "2", "--rounds", "1", "--block", "1"): (
        "| `unitree_h1_simplified` | random (`pd_joint_pos`) | 500 | 29 / 21 |"
    ),
    ("task_throughput.py", "--rounds", "1", "--block", "2", "--batch-block", "1", "--maniskill-python", "/absent"): (
        "ours x1"
    ),
}


def run_script(*command: str, env: dict[str, str] | None = None) -> str:
    """``python COMMAND`` in benchmarks/ (5 min at most); its stdout, once it exits 0."""
    run = subprocess.run(
        [sys.executable, *command], cwd=BENCHMARKS, capture_output=True, text=True, timeout=300, check=False, env=env
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return run.stdout


@pytest.mark.parametrize("command", list(RUNS), ids=[" ".join(c[:1] + c[1:3]) for c in RUNS])
def test_benchmark_script_runs(command: tuple[str, ...]) -> None:
    stdout = run_script(*command)
    assert RUNS[command] in stdout, stdout[-2000:]


def test_render_backends_saves_frames_and_compares_them(tmp_path: Path) -> None:
    """The script's two halves: frames saved in this process's backend, then compared
    with themselves (every texture identical)."""
    frames = tmp_path / "frames.npz"
    script = str(BENCHMARKS / "render_backends.py")
    for args in (["--save", str(frames), "--rounds", "1"], ["--compare", str(frames), str(frames)]):
        stdout = run_script(script, *args)
    rows = [line for line in stdout.splitlines() if "/" in line and "backend" not in line]
    assert len(rows) >= 4 * 4, stdout
    assert all(("100.000%" in r) or ("mean |A-B| 0.00" in r) or ("max 0.00 mm" in r) for r in rows), stdout


def test_friction_drives_lists_a_files_frictional_joints(tmp_path: Path) -> None:
    """The script on a written one-joint wrist with dry friction: both tables, the floor's
    stiffness (0.5 N*m / 0.005 rad = 100 N*m/rad)."""
    from tests.test_two_line_robot import FRICTION_WRIST_MJCF

    path = tmp_path / "wrist.xml"
    path.write_text(FRICTION_WRIST_MJCF)
    stdout = run_script("friction_drives.py", str(path), "--seconds", "1")
    assert "| `wrist` | 0.5 |" in stdout and "| 100 | 0.0050 |" in stdout, stdout
    assert "Step towards the range end" in stdout, stdout


def test_convex_grasp_runs_on_a_written_one_jaw_gripper(tmp_path: Path) -> None:
    """The script on the one-jaw fixture of test_derived_gripper (boxes only: nothing to
    split, so both runs print the same row), and with MuJoCo's default contact declared
    on the jaws; its figures in the docs come from the Z1."""
    from tests.test_derived_gripper import one_jaw, urdf

    path = tmp_path / "one_jaw.urdf"
    path.write_text(urdf(one_jaw()))
    env = {**os.environ, "ROBOT_AGENTS_CACHE": str(tmp_path / "cache")}
    outputs = [
        run_script("convex_grasp.py", str(path), "--edges", "0.01", "--open", "-0.5", "--depth", "0", extra, env=env)
        for extra in ("--plain", "--soft")
    ]
    rows = [line for line in outputs[0].splitlines() if line.startswith(("| no | 10 |", "| yes | 10 |"))]
    assert len(rows) == 2 and rows[0].split("|")[3:] == rows[1].split("|")[3:], outputs[0]
    assert "MuJoCo defaults on the jaws" in outputs[1], outputs[1]
    assert len([line for line in outputs[1].splitlines() if line.startswith("| yes | 10 |")]) == 1, outputs[1]


def test_derived_ee_modes_runs_on_a_written_arm(tmp_path: Path) -> None:
    """The script on the six-joint arm of test_derived_task_space (its figures in the
    docs come from the mani-skill wheel's arms and the Unitree Z1)."""
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "arm6.urdf"
    path.write_text(arm_urdf(6))
    stdout = run_script("derived_ee_modes.py", str(path), "--trials", "3")
    assert "| arm6.urdf | 6 |" in stdout and "| 3/3 |" in stdout, stdout


def test_two_line_tasks_runs_on_a_written_arm(tmp_path: Path) -> None:
    """The script on the six-joint arm of test_derived_task_space (no gripper: PickCube
    names what it lacks); its figures in the docs come from the mani-skill wheel's arms."""
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "arm6.urdf"
    path.write_text(arm_urdf(6))
    stdout = run_script("two_line_tasks.py", str(path), "--seeds", "2")
    row = next(line for line in stdout.splitlines() if line.startswith("| arm6.urdf |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[1].startswith("- (") and "Gripper" in cells[1], row  # PickCube: no gripper
    assert cells[2].endswith("/2") and cells[3].endswith("/2"), row  # PushCube and ReachPose ran


def test_two_line_tasks_states_servos_for_a_known_file(tmp_path: Path) -> None:
    """``--servos`` states the SO-100's STS3215 facts for a file named ``so100.urdf``
    (here the written six-joint arm: ``DerivedActuators()`` takes every joint)."""
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "so100.urdf"
    path.write_text(arm_urdf(6, effort=0.0))
    stdout = run_script("two_line_tasks.py", str(path), "--seeds", "1", "--servos")
    row = next(line for line in stdout.splitlines() if line.startswith("| so100.urdf + servos |"))
    assert row.rstrip().endswith("/1 |"), row  # ReachPose ran


def test_fingerprint_is_the_same_twice_and_compare_names_a_changed_robot(tmp_path: Path) -> None:
    """Two fingerprints of the same robot are identical (determinism: the model and 8
    random-action steps in each mode); ``--compare`` lists exactly the entry that differs."""
    first, second = tmp_path / "a.json", tmp_path / "b.json"
    for path in (first, second):
        assert "hashes of 1 robots" in run_script("fingerprint.py", str(path), "--robots", "so100")
    hashes = json.loads(first.read_text())
    assert "so100/model" in hashes and "so100/pd_joint_delta_pos" in hashes
    assert "identical" in run_script("fingerprint.py", "--compare", str(first), str(second))
    hashes["so100/pd_joint_pos"] = "0" * 16
    second.write_text(json.dumps(hashes))
    stdout = run_script("fingerprint.py", "--compare", str(first), str(second))
    assert "1 differ" in stdout and "so100/pd_joint_pos" in stdout, stdout


def test_jaw_close_ramps_the_command_and_holds_it_where_the_jaw_stalls() -> None:
    """jaw_close.py's gentle close on the SO-100's jaw, which stays where the reset left
    it (nothing is stepped, as a jaw blocked there): opening commands ``open``; each
    closing step moves the command ``rate`` strokes on until it is more than ``lag``
    strokes ahead of the jaw (the lag set to 0.25 strokes past the open command's), then
    holds it at the jaw's position plus ``squeeze`` strokes; opening again starts over."""
    import importlib.util

    import numpy as np

    import robot_agents as ra

    spec = importlib.util.spec_from_file_location("jaw_close", BENCHMARKS / "jaw_close.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    env = ra.make_env("PickCube-v1", robot_uids="so100").unwrapped
    try:
        env.reset(seed=0)
        close = module.GentleClose(env.agent, 1, rate=0.1, lag=0.25, squeeze=0.05)
        jaw = float(env.agent.qpos[0, close.index])
        close.lag = (close.open - jaw) / close.stroke + 0.25
        opening, closing = np.array([True]), np.array([False])
        assert close.next(opening)[0] == close.open
        expected, held = close.open, False
        for _ in range(15):
            if not held and (expected - jaw) / close.stroke > close.lag:
                expected, held = jaw + 0.05 * close.stroke, True
            elif not held:
                low, high = sorted((close.open, close.end))
                expected = min(max(expected + 0.1 * close.stroke, low), high)
            assert close.next(closing)[0] == pytest.approx(expected, abs=1e-12)
        assert held and close.held[0]
        assert close.next(opening)[0] == close.open and not close.held[0]
    finally:
        env.close()


def _overhead_ratio() -> Any:
    """benchmarks/overhead_ratio.py as a module (benchmarks/ importable for its own imports)."""
    import importlib

    if str(BENCHMARKS) not in sys.path:
        sys.path.insert(0, str(BENCHMARKS))
    return importlib.import_module("overhead_ratio")


@pytest.mark.parametrize(
    ("uid", "mode", "num_envs"),
    [
        ("so100", "pd_joint_delta_pos", 1),  # the one-env fast path (_step_single)
        ("so100", "pd_joint_delta_pos", 3),  # the batched path
        ("so100", "pd_joint_target_delta_pos", 1),  # interpolated targets: one mj_step per substep
        ("stretch", "pd_joint_delta_pos", 1),  # wheels written after the physics (mj_forward's stand-in)
    ],
)
def test_python_cost_stand_in_steps_as_a_real_step(uid: str, mode: str, num_envs: int) -> None:
    """overhead_ratio.py's no-physics step (``python_cost``) takes a real step's path:
    simulated time advances by the control step's substeps, no step is flagged unstable
    (an env asked to raise on instability steps on), the joints stay where they were,
    and the real functions are back after the block."""
    import mujoco
    import numpy as np

    import robot_agents as ra

    module = _overhead_ratio()
    step, forward = mujoco.mj_step, mujoco.mj_forward
    env = ra.make_env(
        "Empty-v1",
        robot_uids=uid,
        control_mode=mode,
        num_envs=num_envs,
        num_threads=1,
        max_episode_steps=None,
        raise_on_instability=True,
    ).unwrapped
    try:
        env.reset(seed=0)
        world = env.scene.world
        actions = module.small_actions(env, 4, np.random.default_rng(0))
        control_dt = env.scene.substeps * float(env.model.opt.timestep)
        qpos = world.qpos.copy()
        with module.no_physics():
            for i in range(6):
                before = world.time
                info = env.step(actions[i % 4])[-1]
                assert np.allclose(world.time - before, control_dt, rtol=1e-12, atol=0.0), (world.time, before)
                assert not np.any(info["physics_unstable"]) and not world.last_step_unstable.any()
        assert not world.unstable_steps.any()
        if uid != "stretch":  # (stretch's wheels are turned by the base's motion: none here)
            assert np.array_equal(world.qpos, qpos)
    finally:
        env.close()
    assert mujoco.mj_step is step and mujoco.mj_forward is forward
    assert module.python_cost(uid, mode, np.random.default_rng(0), steps=5, repeats=2, num_envs=num_envs) > 0.0


def test_python_cost_refuses_a_stand_in_that_leaves_time_standing(monkeypatch: pytest.MonkeyPatch) -> None:
    """With an ``mj_step`` that does nothing (the stand-in before 2026-11-29) every step
    is flagged unstable and time stands: python_cost raises instead of reporting."""
    import numpy as np

    module = _overhead_ratio()
    monkeypatch.setattr(module, "stand_in_step", lambda *args: None)
    with pytest.raises(RuntimeError, match="not a real step's path"):
        module.python_cost("so100", "pd_joint_delta_pos", np.random.default_rng(0), steps=3, repeats=1)
