"""The command line: list, info and the demo (the main job)."""

from __future__ import annotations

import contextlib
import io
import math
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest
from PIL import Image

import robot_agents
from robot_agents.cli import main, show_note
from robot_agents.media.label import LABEL_BACKGROUND
from robot_agents.robots.catalog import BUILTIN_PIECES


def run(*argv: str) -> tuple[int, str]:
    out = io.StringIO()
    code = main(list(argv), out=out)
    return code, out.getvalue()


def test_list_shows_every_robot_with_dof_and_modes() -> None:
    code, text = run("list")
    assert code == 0
    rows = {line.split()[0]: line.split()[1] for line in text.splitlines()[2:]}
    assert set(rows) == set(robot_agents.list_agents())
    assert (
        rows.items()
        >= {
            "allegro_hand_right": "16",
            "allegro_hand_left": "16",
            "allegro_hand_right_touch": "16",
            "anymal_c": "12",
            "floating_panda_gripper": "8",
            "panda": "9",
            "panda_stick": "7",
            "panda_touch": "9",
            "panda_wristcam": "9",
            "unitree_h1": "19",
            "unitree_go2": "12",
        }.items()
    )
    assert "pd_joint_target_delta_pos" in text


def test_info_shows_joints_keyframes_modes() -> None:
    code, text = run("info", "panda")
    assert code == 0
    assert "panda_joint4         -3.0718  -0.0698" in text
    assert "rest: qpos = [0.0000, 0.3927" in text
    assert "pd_joint_delta_pos (default)  8" in text
    assert "pd_joint_pos_vel              15" in text
    assert "sensors: none" in text
    assert "changed as read" not in text


def test_info_says_when_a_model_file_is_changed_as_read() -> None:
    code, text = run("info", "allegro_hand_left")
    assert code == 0
    assert "allegro_hand_right.xml (changed as read by AllegroHandLeft.edit_model)" in text


def test_a_directory_named_like_a_uid_does_not_hide_the_robot(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "spot").mkdir()  # e.g. a folder of videos of the robot
    (tmp_path / "panda").write_text("notes")  # a file without a model suffix
    monkeypatch.chdir(tmp_path)
    for uid in ("spot", "panda"):
        code, text = run("info", uid)
        assert code == 0 and "keyframes" in text.lower(), text


def test_info_lists_cameras_and_touch_sensors() -> None:
    _, text = run("info", "panda_wristcam")
    assert "camera hand_camera on panda_hand: 128x128, fovy 90.0 deg, near 0.01 m, far 10 m" in text
    _, text = run("info", "panda_touch")
    assert "touch left_pad_touch on box site on panda_leftfinger (normal force, N)" in text
    assert "touch right_pad_touch on box site on panda_rightfinger" in text


def test_unknown_uid_is_a_clean_error(capsys: pytest.CaptureFixture[str]) -> None:
    code, _ = run("info", "pamda")
    assert code == 2
    assert "Did you mean 'panda'" in capsys.readouterr().err


@pytest.mark.parametrize(("uid", "width"), [("panda", 320), ("floating_panda_gripper", 320), ("panda_wristcam", 560)])
def test_demo_writes_a_gif_and_reaches_keyframes(tmp_path: Path, uid: str, width: int) -> None:
    """The GIF shows the scene (320 x 240) and, beside it, each robot camera at 240 px high."""
    output = tmp_path / "demo.gif"
    code, text = run("demo", uid, "--output", str(output), "--seconds", "1.0")
    assert code == 0, text
    assert output.is_file()
    with Image.open(output) as image:
        assert image.n_frames >= 10
        assert image.size == (width, 240)
        first = np.asarray(image.convert("RGB")).astype(int)
    # With robot cameras, each panel carries its camera's name on a dark strip at its top left.
    on_strip = np.abs(first[1, 1::320] - LABEL_BACKGROUND).max(axis=-1) < 12
    assert list(on_strip) == ([True, True] if uid == "panda_wristcam" else [False])
    assert "state finite     True" in text
    errors = [float(line.split("within")[1].split()[0]) for line in text.splitlines() if line.startswith("keyframe")]
    assert errors and max(errors) < 0.01


def test_demo_writes_an_mp4(tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="MP4 needs the optional extra: pip install 'robot-agents[video]'")
    iio = pytest.importorskip("imageio.v2")
    output = tmp_path / "demo.mp4"
    code, text = run("demo", "panda_stick", "-o", str(output), "--seconds", "0.5")
    assert code == 0, text
    frames = iio.mimread(output, format="FFMPEG")
    assert f"video            {output} ({len(frames)} frames)" in text
    assert frames[0].shape == (240, 320, 3)


# ------------------------------------------------ arguments checked before simulating


@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make any call of the demo fail the test: bad arguments must be caught before it."""

    def run_demo(*args: object, **kwargs: object) -> None:
        raise AssertionError("the demo ran although its arguments were bad")

    monkeypatch.setattr("robot_agents.demo.run_demo", run_demo)


def run_fast(*argv: str) -> tuple[int, str, str]:
    """Run the CLI, check it returned within a second; return (status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stderr(err):
        code = main(list(argv), out=out)
    assert time.perf_counter() - start < 1.0
    return code, out.getvalue(), err.getvalue()


@pytest.mark.usefixtures("no_simulation")
@pytest.mark.parametrize("seconds", ["0", "-1", "nan", "inf", "abc", "61", "1e9", ""])
def test_demo_rejects_bad_seconds_before_simulating(tmp_path: Path, seconds: str) -> None:
    code, out, err = run_fast("demo", "panda", "-o", str(tmp_path / "x.gif"), f"--seconds={seconds}")
    assert code == 2
    assert out == ""
    assert err == (
        "robot-agents: error: argument --seconds: expected a number of simulated seconds per pose, "
        f"> 0 and <= 60, got {seconds!r}\n"
    )
    assert not (tmp_path / "x.gif").exists()


@pytest.mark.usefixtures("no_simulation")
@pytest.mark.parametrize("seconds", ["0", "-1", "nan", "61", "1e-300", "0.049", "1e9"])
def test_check_rejects_bad_seconds_naming_what_they_are(seconds: str) -> None:
    """At least one control step: before, 1e-300 s (no step at all) ran no random action
    and the check passed."""
    code, out, err = run_fast("check", "panda", f"--seconds={seconds}")
    assert (code, out) == (2, "")
    assert err == (
        "robot-agents: error: argument --seconds: expected a number of seconds of random actions per mode, "
        f">= 0.05 (one control step at 20 Hz, the checks' control rate) and <= 60, got {seconds!r}\n"
    )


@pytest.mark.parametrize("seconds", ["0.05", "60"])
def test_check_takes_seconds_from_one_control_step(monkeypatch: pytest.MonkeyPatch, seconds: str) -> None:
    asked: list[float] = []

    def run_checks(cls: object, random_seconds: float) -> list[object]:
        asked.append(random_seconds)
        return []

    monkeypatch.setattr("robot_agents.checks.run_checks", run_checks)
    code, _, err = run_fast("check", "panda", f"--seconds={seconds}")
    assert (code, err, asked) == (0, "", [float(seconds)])


@pytest.mark.parametrize("seconds", [1e-300, 0.049, math.nan, math.inf])
def test_random_actions_check_refuses_less_than_a_control_step(seconds: float) -> None:
    from robot_agents.checks import check_random_actions

    with pytest.raises(robot_agents.ConfigError, match=r"check_random_actions: expected seconds covering .* got"):
        check_random_actions(robot_agents.get_agent("panda"), seconds=seconds)


@pytest.mark.parametrize("substeps", ["1001", "10,2000", "99999999999999999999", "0", "0,10", "ten", ""])
def test_check_bounds_the_sweeps_substeps(monkeypatch: pytest.MonkeyPatch, substeps: str) -> None:
    """Each count from 1 to 1000 (20 kHz at 20 Hz control), said in one line before the
    robot loads; before, a huge count was taken and the sweep ran at its step."""

    def sweep_timestep(*args: object, **kwargs: object) -> None:
        raise AssertionError("the sweep ran although its --substeps were bad")

    monkeypatch.setattr("robot_agents.tuning.timestep.sweep_timestep", sweep_timestep)
    code, out, err = run_fast("check", "/nonexistent/robot.urdf", "--sweep", f"--substeps={substeps}")
    assert (code, out) == (2, "")
    assert err == (
        "robot-agents: error: argument --substeps: expected whole numbers from 1 to 1000 separated by commas "
        f"(e.g. 10,20,50,100; 1000 is 20 kHz at 20 Hz control), got {substeps!r}\n"
    )


def test_check_sweeps_up_to_a_thousand_substeps(monkeypatch: pytest.MonkeyPatch) -> None:
    asked: list[object] = []

    def sweep_timestep(cls: object, substeps: object, stop_after: object) -> None:
        asked.append(substeps)
        raise robot_agents.ConfigError("stop here")

    monkeypatch.setattr("robot_agents.tuning.timestep.sweep_timestep", sweep_timestep)
    code, _, err = run_fast("check", "panda", "--sweep", "--substeps=1,1000")
    assert (code, err, asked) == (2, "robot-agents: error: stop here\n", [(1, 1000)])


def test_substeps_without_sweep_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    def run_checks(*args: object, **kwargs: object) -> None:
        raise AssertionError("the checks ran, the --substeps asked for ignored")

    monkeypatch.setattr("robot_agents.checks.run_checks", run_checks)
    code, out, err = run_fast("check", "panda", "--substeps", "10,20")
    assert (code, out) == (2, "")
    assert err == "robot-agents: error: argument --substeps: chooses the steps of the time-step sweep; add --sweep\n"


@pytest.mark.parametrize("spec", ["panda", "robot_agents.robots.panda.panda:Panda"])
def test_floating_is_refused_for_a_registered_robot(spec: str) -> None:
    # a model file's option, as --up and --gripper are; "root: fixed" was printed before
    code, out, err = run_fast("info", spec, "--floating")
    assert (code, out) == (2, "")
    assert err.startswith("robot-agents: error: resolve_robot: floating=True gives a model file's root a free joint")
    assert err.count("\n") == 1


def test_a_compile_error_of_a_model_file_is_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "bad.xml"
    bad.write_text(
        '<mujoco><worldbody><body name="a"><joint name="j"/><geom type="box" size="0 0 0"/></body></worldbody></mujoco>'
    )
    code, _, err = run_fast("info", str(bad))
    assert code == 2
    assert err.count("\n") == 1  # MuJoCo's message names the element on a second line
    assert "must be positive in geom; Element name '', id 0, line 1" in err


@pytest.mark.usefixtures("no_simulation")
@pytest.mark.parametrize("name", ["x.avi", "x.png", "x", ""])
def test_demo_rejects_an_unsupported_output_suffix(tmp_path: Path, name: str) -> None:
    # "": an empty --output is refused, not replaced by the default panda_demo.gif
    code, _, err = run_fast("demo", "panda", "-o", str(tmp_path / name) if name else "")
    assert code == 2
    assert err.count("\n") == 1  # one line, no traceback
    assert err.startswith("robot-agents: error: video output ")
    assert "expected a file name ending in .gif or .mp4" in err


@pytest.mark.usefixtures("no_simulation")
def test_the_commands_own_arguments_are_checked_before_the_robot_loads(tmp_path: Path) -> None:
    # a missing model file would be reported by loading it: the argument's fault comes first
    missing = str(tmp_path / "no_such_arm.urdf")
    for argv, message in (
        (("demo", missing, "-o", str(tmp_path / "x.avi")), "expected a file name ending in .gif or .mp4"),
        (("demo", missing, "--seconds", "0"), "argument --seconds"),
        (("check", missing, "--seconds", "-1"), "argument --seconds"),
        (("check", missing, "--sweep", "--substeps", "x"), "--substeps"),
    ):
        code, _, err = run_fast(*argv)
        assert code == 2 and message in err and "does not exist" not in err, (argv, err)
    assert "does not exist" in run_fast("demo", missing, "-o", str(tmp_path / "x.gif"))[2]


@pytest.mark.usefixtures("no_simulation")
def test_demo_rejects_a_missing_output_directory(tmp_path: Path) -> None:
    code, _, err = run_fast("demo", "panda", "--output", str(tmp_path / "no" / "such" / "dir" / "x.gif"))
    assert code == 2
    assert err.count("\n") == 1
    assert f"expected an existing directory, but {str(tmp_path / 'no' / 'such' / 'dir')!r} does not exist" in err


@pytest.mark.parametrize(
    ("spec", "name"),
    [("koch-v1.1", "koch-v1.1_demo.gif"), ("panda", "panda_demo.gif"), ("pendulum", "pendulum_demo.gif")],
)
def test_demo_names_its_default_video_after_the_robot(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, pendulum_file: Path, spec: str, name: str
) -> None:
    written: list[Path] = []

    def run_demo(cls: object, output: Path, seconds_per_pose: float) -> object:
        written.append(output)
        return type("Summary", (), {"finite": True, "lines": lambda self: []})()

    monkeypatch.setattr("robot_agents.demo.run_demo", run_demo)
    monkeypatch.chdir(tmp_path)
    code, _, err = run_fast("demo", str(pendulum_file) if spec == "pendulum" else spec)
    assert (code, err) == (0, "")
    assert written == [Path(name)]  # 'koch-v1_demo.gif' before: the uid's '.1' was taken for a suffix


def test_demo_reports_a_video_that_cannot_be_written(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    def disk_full(*args: object, **kwargs: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", disk_full)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["demo", "panda", "-o", str(tmp_path / "x.gif"), "--seconds", "0.1"], out=io.StringIO())
    assert code == 2
    assert err.getvalue() == (
        f"robot-agents: error: write_gif: cannot write {str(tmp_path / 'x.gif')!r}: No space left on device.\n"
    )


def test_a_demo_that_fails_midway_closes_its_scene_and_renderers(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    from robot_agents.demo import run_demo
    from robot_agents.sim.scene import Scene

    closed: list[str] = []
    scene_close, renderer_close = Scene.close, mujoco.Renderer.close

    def closing_scene(self: Scene) -> None:
        closed.append("scene")
        scene_close(self)

    def closing_renderer(self: mujoco.Renderer) -> None:
        closed.append("renderer")
        renderer_close(self)

    def disk_full(*args: object, **kwargs: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Scene, "close", closing_scene)
    monkeypatch.setattr(mujoco.Renderer, "close", closing_renderer)
    monkeypatch.setattr(Image.Image, "save", disk_full)
    with pytest.raises(robot_agents.MediaError, match="No space left on device"):
        run_demo("panda_wristcam", tmp_path / "x.gif", seconds_per_pose=0.1)
    assert closed.count("scene") == 1 and "renderer" in closed  # the scene's, the framing view's, the robot's cameras'


@pytest.mark.usefixtures("no_simulation")
def test_demo_mp4_without_the_video_extra_says_how_to_install(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # as if not installed
    code, _, err = run_fast("demo", "panda", "-o", str(tmp_path / "x.mp4"))
    assert code == 2
    assert err.count("\n") == 1
    assert "pip install 'robot-agents[video]'" in err


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        main(["--version"])
    assert caught.value.code == 0
    assert capsys.readouterr().out == f"robot-agents {robot_agents.__version__}\n"


def test_bad_arguments_fail_fast_from_the_shell(tmp_path: Path) -> None:
    """As a user runs it: exit status 2, one line on stderr, no traceback, well under the time of a demo."""
    src = str(Path(robot_agents.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", "")}
    command = [sys.executable, "-m", "robot_agents.cli", "demo", "panda", "--seconds", "abc"]
    result = subprocess.run(command, capture_output=True, text=True, env=env, cwd=tmp_path, timeout=60)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.strip().splitlines() == [
        "robot-agents: error: argument --seconds: expected a number of simulated seconds per pose, "
        "> 0 and <= 60, got 'abc'"
    ]
    version = subprocess.run(
        [sys.executable, "-m", "robot_agents.cli", "--version"], capture_output=True, text=True, env=env, timeout=60
    )
    assert version.returncode == 0
    assert version.stdout == f"robot-agents {robot_agents.__version__}\n"


def test_a_reader_that_stops_reading_gets_no_traceback(tmp_path: Path) -> None:
    """robot-agents info panda | head -1: the pipe closes before the output is written."""
    src = str(Path(robot_agents.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", "")}
    command = [sys.executable, "-m", "robot_agents.cli", "info", "panda"]
    with subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=tmp_path, text=True
    ) as process:
        assert process.stdout is not None and process.stderr is not None
        process.stdout.close()  # as head does once it has its lines
        err = process.stderr.read()
        code = process.wait(timeout=60)
    assert "Traceback" not in err and "BrokenPipeError" not in err, err
    assert err == "" and code == 1


def test_ctrl_c_stops_a_long_command_without_a_traceback(tmp_path: Path) -> None:
    src = str(Path(robot_agents.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", "")}
    env["PYTHONUNBUFFERED"] = "1"  # each line as it is written
    command = [sys.executable, "-m", "robot_agents.cli", "check", "panda", "--seconds", "60"]
    with subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, cwd=tmp_path, text=True
    ) as process:
        assert process.stdout is not None and process.stderr is not None
        assert process.stdout.readline().startswith("panda: ")  # the robot is loaded, the checks to come
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
    assert (process.returncode, err) == (130, "robot-agents: interrupted\n")


UNSTABLE_MODULE = """
import robot_agents as ra

class StiffPendulum(ra.Agent):
    uid = "stiff_pendulum"
    mjcf_path = {path!r}
    actuators = (ra.PDActuator(joints=".*", stiffness=1e7, damping=1.0),)
"""


def test_check_passes_for_a_builtin_and_a_model_file(tmp_path: Path) -> None:
    from tests.conftest import TWO_LINK_URDF

    code, text = run("check", "panda", "--seconds", "0.5")
    assert code == 0, text
    assert "5 passed, 0 failed" in text and "total mass: 17.452 kg" in text
    assert "geoms simulated: 29 of 65 in its scene, floor included (the other 36 only drawn" in text
    urdf = tmp_path / "two_link.urdf"
    urdf.write_text(TWO_LINK_URDF)
    code, text = run("check", str(urdf), "--seconds", "0.5")
    assert code == 0, text
    assert "drive: derived gains" in text and "parts: arm (joint_a, joint_b)" in text
    code, text = run("info", str(urdf))
    assert code == 0 and "end effectors: ee (tool)" in text


def test_check_fails_with_numbers_for_unstable_gains(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from tests.conftest import PENDULUM_MJCF

    model = tmp_path / "pendulum.xml"
    model.write_text(PENDULUM_MJCF)
    (tmp_path / "stiff_robot.py").write_text(UNSTABLE_MODULE.format(path=str(model)))
    monkeypatch.syspath_prepend(str(tmp_path))
    code, text = run("check", "stiff_robot:StiffPendulum", "--seconds", "0.5")
    assert code == 1
    assert "[FAIL] PD drives stable at the physics step" in text and "at elbow (kp 1e+07" in text
    assert "unstable: ['pd_joint_" in text


def test_info_takes_a_class_whose_docstring_is_blank(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pendulum_file: Path
) -> None:
    module = f'import robot_agents as ra\n\nclass Blank(ra.Agent):\n    """\n    """\n    mjcf_path = {str(pendulum_file)!r}\n'
    (tmp_path / "blank_doc.py").write_text(module)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, text = run("info", "blank_doc:Blank")  # an IndexError traceback before
    assert code == 0 and text.startswith("blank_doc:Blank: Blank\n")


def test_pd_stability_is_checked_at_the_robots_own_step() -> None:
    from robot_agents.checks import check_pd_stability

    assert robot_agents.get_agent("fetch").sim_freq == 160
    assert "dt 0.00625 s" in check_pd_stability(robot_agents.get_agent("fetch")).detail
    assert "dt 0.002 s" in check_pd_stability(robot_agents.get_agent("panda")).detail  # the library's 500 Hz
    assert "dt 0.001 s" in check_pd_stability(robot_agents.get_agent("panda"), timestep=0.001).detail


def test_robot_forms_are_checked_before_anything_runs() -> None:
    code = main(["check", "no_such_module:Robot"])
    assert code == 2
    code = main(["info", "/nonexistent/robot.urdf"])
    assert code == 2


def test_check_sweeps_the_substeps_asked_for(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``--substeps`` widens the sweep past its default 1 kHz (here 1 and 2 kHz at 20 Hz
    control); a bad list is refused before anything runs."""
    from tests.conftest import TWO_LINK_URDF

    urdf = tmp_path / "two_link.urdf"
    urdf.write_text(TWO_LINK_URDF)
    code, text = run("check", str(urdf), "--sweep", "--substeps", "100,50")
    assert code == 0, text
    rows = [line for line in text.splitlines() if line.startswith("| 1000 |") or line.startswith("| 2000 |")]
    assert len(rows) == 2 and "| 500 |" not in text
    for bad in ("0,10", "ten", ""):
        assert main(["check", str(urdf), "--sweep", "--substeps", bad]) == 2
        assert "--substeps: expected whole numbers from 1 to 1000" in capsys.readouterr().err


def test_demo_holds_keyframes_in_a_mode_without_absolute_joint_targets(tmp_path: Path, pendulum_file: Path) -> None:
    """A robot without ``pd_joint_pos`` is reset to each keyframe and held there with
    the hold action of its mode: with asymmetric normalized delta bounds an all-zero
    action would step every joint by the middle of its range (here 0.05 rad a step)."""
    from robot_agents.demo import run_demo
    from tests.conftest import make_pendulum_class

    delta = robot_agents.PDJointPosConfig(joint_names=("shoulder", "elbow"), lower=-0.05, upper=0.15, use_delta=True)
    cls = make_pendulum_class(pendulum_file, uid="test_demo_delta_pendulum", control_modes={"delta": delta})
    summary = run_demo(cls, tmp_path / "demo.gif", seconds_per_pose=1.0, size=(160, 120))
    assert summary.control_mode == "delta" and summary.finite
    assert summary.max_abs_qvel < 0.01, summary.lines()  # 0.35 rad/s with an all-zero action


@pytest.mark.parametrize("effort", [0.0, 40.0])
def test_info_says_when_a_file_gives_no_effort_limits(tmp_path: Path, effort: float) -> None:
    """Derived drives without an effort limit (a URDF's ``effort="0"``) get a line naming
    the joints and how to state the motors'; a file with limits gets none."""
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf(3, effort=effort))
    code, text = run("info", str(path))
    assert code == 0, text
    line = "  no effort limit for yaw, shoulder, elbow: the model file gives none"
    assert (line in text) == (effort == 0.0), text
    assert ("ra.DerivedActuators(effort_limit=" in text) == (effort == 0.0)


def test_a_model_file_takes_a_builtin_gripper(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``--gripper NAME --at LINK``: the file's arm with a built-in piece on its flange,
    its end effector the piece's tcp; refused with the reason where it cannot be."""
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf(6))
    code, text = run("info", str(path), "--gripper", "robotiq_2f85", "--at", "flange_roll_link")
    assert code == 0, text
    assert "  + Robotiq2F85 (robotiq_2f85.xml) as 'robotiq_2f85/'" in text
    assert "end effectors: ee (robotiq_2f85/robotiq_tcp)" in text
    assert "parts: arm (yaw, shoulder, elbow, forearm_roll, wrist, flange_roll); robotiq_2f85_gripper (" in text
    # a flange with the tool along x (a ROS-Industrial `flange`): the piece turned onto it
    turned = run("info", str(path), "--gripper", "robotiq_2f85", "--at", "flange_roll_link", "--at-axis", "x")
    assert turned == (0, text), turned
    for argv, message in (
        (("--gripper", "franka_hand"), "a gripper and the body it is mounted at go together"),
        (("--gripper", "franka_hand", "--at", "flange_rol_link"), "Did you mean 'flange_roll_link',"),
    ):
        assert run("info", str(path), *argv)[0] == 2
        assert message in capsys.readouterr().err
    assert run("info", "panda", "--gripper", "franka_hand", "--at", "panda_link8")[0] == 2
    assert "is a registered uid or a class (declare its attachments instead)" in capsys.readouterr().err


def test_every_builtin_piece_names_its_tcp() -> None:
    from robot_agents.agent.declaration import composition
    from robot_agents.registry import get_piece
    from robot_agents.robots.catalog import BUILTIN_PIECES

    for name in BUILTIN_PIECES:
        piece = get_piece(name)
        assert piece.tcp is not None, name
        # a body of the piece's file or of a piece it mounts (the WidowX gripper's bar and fingers)
        files = [piece, *(inner for _, inner in composition(piece).pieces)]
        models = [mujoco.MjModel.from_xml_path(str(cls.model_path())) for cls in files]
        assert any(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, piece.tcp) >= 0 for model in models), name
    with pytest.raises(robot_agents.UnknownNameError, match=r"get_piece.*'robotiq'.*robotiq_2f85"):
        get_piece("robotiq")


def test_the_librarys_notes_are_one_line_each_on_stderr(tmp_path: Path) -> None:
    """A note the library raises while a command runs (here: a file's free joint fixed)
    reaches the user as ``robot-agents: note: ...``, one line, without Python's source
    location and code line (which named the library's internals)."""
    model = tmp_path / "free.xml"
    model.write_text(
        '<mujoco><worldbody><body name="b" pos="0 0 0.5"><freejoint/><geom size="0.1"/>'
        '<body name="c"><joint name="j" range="-1 1"/><geom size="0.05" pos="0.2 0 0"/></body>'
        "</body></worldbody></mujoco>"
    )
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["info", str(model)], out=out)
    assert code == 0 and out.getvalue().startswith(f"{model}: Free")
    lines = err.getvalue().splitlines()
    assert len(lines) == 1 and lines[0].startswith("robot-agents: note: Free (")
    assert "free joint" in lines[0] and "Warning" not in lines[0] and ".py:" not in lines[0]
    assert warnings.showwarning is not show_note  # put back after the command


def test_show_note_names_a_warning_that_is_not_a_note() -> None:
    err = io.StringIO()
    show_note(DeprecationWarning("old"), DeprecationWarning, "x.py", 1, file=err)
    show_note(RuntimeWarning("derived"), RuntimeWarning, "x.py", 1, file=err)
    assert err.getvalue() == "robot-agents: DeprecationWarning: old\nrobot-agents: note: derived\n"


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (
            ["lst"],
            "argument command: invalid choice: 'lst' (choose from 'list', 'info', 'check', 'tune', 'demo'). Did you mean 'list'?",
        ),
        (
            ["info", "panda", "--gripper", "robotiq"],
            "argument --gripper: invalid choice: 'robotiq' (choose from "
            + ", ".join(repr(name) for name in sorted(BUILTIN_PIECES))
            + "). Did you mean 'robotiq_2f85'?",
        ),
        (
            ["check", "arm.urdf", "--up", "Y"],
            "argument --up: invalid choice: 'Y' (choose from 'x', 'y', 'z'). Did you mean 'y'?",
        ),
        (["info", "panda", "--up", "q"], "argument --up: invalid choice: 'q' (choose from 'x', 'y', 'z')\n"),
    ],
)
def test_a_choice_the_command_line_does_not_have_names_the_close_one(
    argv: list[str], expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """argparse's refusal of a command or a flag's value outside its choices ends with the
    close ones, as the library's errors do (it listed the choices only)."""
    with pytest.raises(SystemExit) as caught:
        main(argv)
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert expected in err and "Traceback" not in err
