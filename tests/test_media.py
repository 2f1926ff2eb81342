"""robot_agents.media: GIF (Pillow) and MP4 (imageio-ffmpeg) writers, labels, errors.

Every written file is read back with an independent reader (Pillow for GIF,
imageio for MP4) and compared with the frames that went in.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from PIL import Image

from robot_agents.errors import MediaError
from robot_agents.media import (
    SUPPORTED_SUFFIXES,
    check_output_path,
    draw_label,
    write_gif,
    write_mp4,
    write_video,
)
from robot_agents.media.gif import gif_delay_ms
from robot_agents.media.label import LABEL_BACKGROUND

Frames = list[npt.NDArray[np.uint8]]

PALETTE5 = np.array([[0, 0, 0], [255, 255, 255], [255, 0, 0], [0, 128, 255], [17, 200, 99]], dtype=np.uint8)


def few_colour_frames(count: int = 6, height: int = 30, width: int = 40) -> Frames:
    """Random pictures in five colours, shape (height, width, 3) each; all different."""
    rng = np.random.default_rng(0)
    return [PALETTE5[rng.integers(0, len(PALETTE5), (height, width))] for _ in range(count)]


def gradient_frames(count: int = 4, height: int = 64, width: int = 96) -> Frames:
    """Red rising left to right, green top to bottom, blue falling along the diagonal; scrolling 8 px a frame."""
    y, x = np.mgrid[0:height, 0:width]
    frames = []
    for k in range(count):
        u = (x + 8 * k) % width
        red = np.round(u * 255 / (width - 1))
        green = np.round(y * 255 / (height - 1))
        blue = 255 - np.round((u + y) * 255 / (width + height - 2))
        frames.append(np.stack([red, green, blue], axis=-1).astype(np.uint8))
    return frames


def read_gif(path: Path) -> tuple[Frames, list[int], dict[str, Any]]:
    """The frames (RGB, composited as a viewer shows them), per-frame durations in ms, and the file info."""
    frames, durations = [], []
    with Image.open(path) as image:
        assert image.format == "GIF"
        info = dict(image.info)
        for index in range(image.n_frames):
            image.seek(index)
            frames.append(np.asarray(image.convert("RGB")))
            durations.append(int(image.info["duration"]))
    return frames, durations, info


# --------------------------------------------------------------------------- GIF


def test_gif_few_colours_round_trip_exactly(tmp_path: Path) -> None:
    frames = few_colour_frames()
    path = write_gif(tmp_path / "few.gif", frames, fps=10)
    assert path == tmp_path / "few.gif"
    back, durations, info = read_gif(path)
    assert len(back) == len(frames)
    with Image.open(path) as image:
        assert image.size == (40, 30)  # (width, height)
    assert durations == [100] * len(frames)  # 1 / 10 fps = 100 ms
    assert info["loop"] == 0  # forever
    for original, decoded in zip(frames, back, strict=True):
        np.testing.assert_array_equal(decoded, original)


def test_gif_gradient_within_tolerance(tmp_path: Path) -> None:
    frames = gradient_frames()
    back, durations, _ = read_gif(write_gif(tmp_path / "gradient.gif", np.stack(frames), fps=25))
    assert len(back) == len(frames)
    assert durations == [40] * len(frames)
    for original, decoded in zip(frames, back, strict=True):
        error = np.abs(decoded.astype(int) - original.astype(int))
        assert error.max() <= 24, error.max()  # 256 colours for up to 6144 distinct ones
        assert error.mean() <= 5.0, error.mean()


def test_gif_single_frame(tmp_path: Path) -> None:
    frame = np.full((5, 7, 3), (200, 10, 60), dtype=np.uint8)
    back, durations, _ = read_gif(write_gif(tmp_path / "one.gif", [frame], fps=2))
    assert len(back) == 1
    assert durations == [500]
    np.testing.assert_array_equal(back[0], frame)


def test_gif_identical_frames_are_merged_keeping_the_playing_time(tmp_path: Path) -> None:
    a, b = few_colour_frames(2)
    back, durations, _ = read_gif(write_gif(tmp_path / "still.gif", [a, a, a, b], fps=10))
    assert len(back) == 2
    assert durations == [300, 100]
    np.testing.assert_array_equal(back[0], a)
    np.testing.assert_array_equal(back[1], b)


@pytest.mark.parametrize(("fps", "ms"), [(10, 100), (30, 30), (20.0, 50), (100, 20), (1000, 20), (0.5, 2000)])
def test_gif_delay_is_rounded_to_centiseconds(fps: float, ms: int) -> None:
    assert gif_delay_ms(fps) == ms


# --------------------------------------------------------------------------- MP4


def test_mp4_round_trip(tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="MP4 needs the optional extra: pip install 'robot-agents[video]'")
    iio = pytest.importorskip("imageio.v2")
    # Large flat colour blocks drifting sideways: H.264 keeps them within a few levels.
    frames = []
    for k in range(12):
        frame = np.zeros((48, 64, 3), dtype=np.uint8)
        frame[:, :32] = (200, 40, 40)
        frame[:, 32:] = (30, 160, 220)
        frame[16:32, 2 * k : 2 * k + 16] = (250, 250, 250)
        frames.append(frame)
    path = write_video(tmp_path / "clip.mp4", frames, fps=12)
    assert path.read_bytes()[4:8] == b"ftyp"  # an ISO media (MP4) file
    reader = iio.get_reader(path, format="FFMPEG")
    try:
        meta = reader.get_meta_data()
        back = [np.asarray(frame) for frame in reader]
    finally:
        reader.close()
    assert meta["fps"] == pytest.approx(12.0)
    assert len(back) == len(frames)
    assert back[0].shape == (48, 64, 3)
    for original, decoded in zip(frames, back, strict=True):
        error = np.abs(decoded.astype(int) - original.astype(int))
        assert error.mean() <= 6.0, error.mean()
        # away from edges (chroma is subsampled) the colours are close
        assert np.abs(decoded[2:14, 36:60].astype(int) - [30, 160, 220]).max() <= 12


def test_mp4_odd_sizes_are_padded_to_even(tmp_path: Path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="MP4 needs the optional extra: pip install 'robot-agents[video]'")
    iio = pytest.importorskip("imageio.v2")
    frames = [np.full((15, 21, 3), 128, dtype=np.uint8)] * 3
    back = iio.mimread(write_mp4(tmp_path / "odd.mp4", frames, fps=5), format="FFMPEG")
    assert len(back) == 3
    assert back[0].shape == (16, 22, 3)


@pytest.mark.parametrize("missing", ["imageio_ffmpeg", "imageio"])
def test_mp4_without_the_extra_names_the_pip_command(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, missing: str
) -> None:
    for name in [m for m in sys.modules if m == missing or m.startswith(missing + ".")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, missing, None)  # makes `import missing` raise ImportError
    frames = few_colour_frames(2)
    for call in (
        lambda: write_video(tmp_path / "a.mp4", frames, fps=10),
        lambda: write_mp4(tmp_path / "a.mp4", frames, fps=10),
        lambda: check_output_path(tmp_path / "a.mp4"),
    ):
        with pytest.raises(MediaError, match=r"pip install 'robot-agents\[video\]'") as caught:
            call()
        assert "pip install imageio imageio-ffmpeg" in str(caught.value)
        assert "is not installed" in str(caught.value)
    assert not (tmp_path / "a.mp4").exists()


# -------------------------------------------------------------------- write_video


@pytest.mark.parametrize("name", ["out.gif", "OUT.GIF"])
def test_write_video_picks_gif_from_the_suffix(tmp_path: Path, name: str) -> None:
    path = write_video(tmp_path / name, few_colour_frames(3), fps=10)
    assert path.read_bytes()[:6] == b"GIF89a"


@pytest.mark.parametrize("name", ["out.avi", "out.png", "out", "out.gif.txt"])
def test_unknown_suffix_lists_the_supported_ones(tmp_path: Path, name: str) -> None:
    with pytest.raises(MediaError, match=r"expected a file name ending in \.gif or \.mp4, got") as caught:
        write_video(tmp_path / name, few_colour_frames(1), fps=10)
    assert name in str(caught.value)
    assert not (tmp_path / name).exists()
    assert SUPPORTED_SUFFIXES == (".gif", ".mp4")


def test_output_directory_must_exist(tmp_path: Path) -> None:
    with pytest.raises(MediaError, match=r"expected an existing directory, but .*missing' does not exist"):
        write_video(tmp_path / "missing" / "out.gif", few_colour_frames(1), fps=10)
    (tmp_path / "file").write_text("")
    with pytest.raises(MediaError, match=r"'.*file' is not a directory"):
        check_output_path(tmp_path / "file" / "out.gif")
    (tmp_path / "dir.gif").mkdir()
    with pytest.raises(MediaError, match="expected a file name, got an existing directory"):
        check_output_path(tmp_path / "dir.gif")
    assert check_output_path(str(tmp_path / "fine.gif")) == tmp_path / "fine.gif"


def test_a_file_that_cannot_be_written_is_a_media_error(tmp_path: Path) -> None:
    (tmp_path / "taken.gif").mkdir()  # write_gif itself does not run check_output_path
    with pytest.raises(MediaError, match=r"^write_gif: cannot write '.*taken\.gif': Is a directory\.$"):
        write_gif(tmp_path / "taken.gif", few_colour_frames(1), fps=10)


# ------------------------------------------------------------------------ bad input

GOOD = np.zeros((4, 6, 3), dtype=np.uint8)
BAD_FRAMES: list[tuple[str, Any, str]] = [
    ("empty list", [], r"expected at least one frame, got 0 frames"),
    ("empty array", np.zeros((0, 4, 6, 3), np.uint8), r"expected at least one frame, got 0 frames"),
    ("float frames", [GOOD.astype(np.float32)], r"expected frame 0 of dtype uint8 \(0\.\.255\), got dtype float32"),
    ("int64 frames", [GOOD, GOOD.astype(np.int64)], r"expected frame 1 of dtype uint8 .*, got dtype int64"),
    ("grey frame", [GOOD[:, :, 0]], r"expected frame 0 of shape \(H, W, 3\) with H, W >= 1, got shape \(4, 6\)"),
    ("RGBA frame", [np.zeros((4, 6, 4), np.uint8)], r"expected frame 0 of shape \(H, W, 3\).*got shape \(4, 6, 4\)"),
    (
        "zero-width frame",
        [np.zeros((4, 0, 3), np.uint8)],
        r"expected frame 0 of shape \(H, W, 3\) with H, W >= 1, got shape \(4, 0, 3\)",
    ),
    (
        "inconsistent sizes",
        [GOOD, GOOD, np.zeros((5, 6, 3), np.uint8)],
        r"expected every frame of shape \(4, 6, 3\) like frame 0, got shape \(5, 6, 3\) for frame 2",
    ),
    (
        "single 3-D array",
        GOOD,
        r"expected frames as an array of shape \(N, H, W, 3\) .*got an array of shape \(4, 6, 3\)",
    ),
    ("list of lists", [[[0, 0, 0]]], r"expected frame 0 to be a numpy array .*, got list"),
    ("a number", 3, r"expected frames as a sequence of \(H, W, 3\) uint8 arrays, got int"),
    ("a string", "frames", r"expected frames as a sequence .*, got str"),
]


@pytest.mark.parametrize(("given", "frames", "message"), BAD_FRAMES, ids=[case[0] for case in BAD_FRAMES])
@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_bad_frames_say_what_was_expected_and_given(
    tmp_path: Path, given: str, frames: Any, message: str, suffix: str
) -> None:
    writer = write_gif if suffix == ".gif" else write_mp4
    with pytest.raises(MediaError, match=f"^write_{suffix[1:]}: {message}"):
        writer(tmp_path / f"bad{suffix}", frames, fps=10)
    assert not (tmp_path / f"bad{suffix}").exists()


@pytest.mark.parametrize("fps", [0, -1, float("nan"), float("inf"), True, "10", None])
def test_bad_fps(tmp_path: Path, fps: Any) -> None:
    with pytest.raises(MediaError, match=r"expected fps \(frames per second\) as a finite number > 0, got"):
        write_gif(tmp_path / "a.gif", [GOOD], fps=fps)
    with pytest.raises(MediaError, match=r"expected fps \(frames per second\) as a finite number > 0, got"):
        write_mp4(tmp_path / "a.mp4", [GOOD], fps=fps)


def test_gif_rejects_delays_longer_than_655_seconds(tmp_path: Path) -> None:
    with pytest.raises(MediaError, match="expected fps >= 100/65535"):
        write_gif(tmp_path / "a.gif", [GOOD], fps=0.001)


# ----------------------------------------------------------------------------- labels


def test_draw_label_puts_light_text_on_a_dark_strip_top_left() -> None:
    frame = np.full((60, 120, 3), (90, 200, 90), dtype=np.uint8)
    labelled = draw_label(frame, "hand_camera")
    assert labelled.shape == frame.shape
    assert labelled.dtype == np.uint8
    assert np.all(frame == (90, 200, 90))  # the input is not changed
    changed = np.any(labelled != frame, axis=-1)
    rows, cols = np.nonzero(changed)
    assert rows.min() == 0 and cols.min() == 0  # top-left corner
    assert 8 <= rows.max() + 1 <= 24  # small: one line of the default font
    assert 30 <= cols.max() + 1 <= 110
    strip = labelled[: rows.max() + 1, : cols.max() + 1].reshape(-1, 3).astype(int)
    dark = np.all(strip == LABEL_BACKGROUND, axis=-1).mean()
    bright = np.all(strip >= 200, axis=-1).sum()
    assert dark > 0.5  # mostly background ...
    assert bright >= 20  # ... with white glyphs on it
    assert np.array_equal(labelled[~changed], frame[~changed])


def test_draw_label_is_cut_to_small_frames() -> None:
    frame = np.zeros((5, 8, 3), dtype=np.uint8)
    assert draw_label(frame, "a long camera name").shape == (5, 8, 3)


@pytest.mark.parametrize("frame", [np.zeros((4, 4), np.uint8), np.zeros((4, 4, 3), np.float32), [[0]]])
def test_draw_label_rejects_bad_frames(frame: Any) -> None:
    with pytest.raises(MediaError, match=r"draw_label: expected a frame of shape \(H, W, 3\) and dtype uint8, got"):
        draw_label(frame, "x")
