"""The command line: list, info and the demo (the main job)."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from robot_agents.cli import main


def run(*argv: str) -> tuple[int, str]:
    out = io.StringIO()
    code = main(list(argv), out=out)
    return code, out.getvalue()


def test_list_shows_every_robot_with_dof_and_modes() -> None:
    code, text = run("list")
    assert code == 0
    rows = {line.split()[0]: line.split()[1] for line in text.splitlines()[2:]}
    assert rows == {
        "floating_panda_gripper": "8",
        "panda": "9",
        "panda_stick": "7",
        "panda_touch": "9",
        "panda_wristcam": "9",
    }
    assert "pd_joint_target_delta_pos" in text


def test_info_shows_joints_keyframes_modes() -> None:
    code, text = run("info", "panda")
    assert code == 0
    assert "panda_joint4         -3.0718  -0.0698" in text
    assert "rest: qpos = [0.0000, 0.3927" in text
    assert "pd_joint_delta_pos (default)  8" in text
    assert "pd_joint_pos_vel              15" in text
    assert "sensors: none" in text


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
    pil = pytest.importorskip("PIL.Image")
    output = tmp_path / "demo.gif"
    code, text = run("demo", uid, "--output", str(output), "--seconds", "1.0")
    assert code == 0, text
    assert output.is_file()
    with pil.open(output) as image:
        assert image.n_frames >= 10
        assert image.size == (width, 240)
    assert "state finite     True" in text
    errors = [float(line.split("within")[1].split()[0]) for line in text.splitlines() if line.startswith("keyframe")]
    assert errors and max(errors) < 0.01
