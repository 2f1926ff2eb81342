"""Tests for robot_agents.media.gif.

Two independent decoders check the written files: Pillow (skipped when Pillow is
not installed) and a small strict GIF parser + LZW decoder defined here, which
also checks the file structure (header, loop extension, disposal, changed-rectangle
descriptors, sub-block sizes, code widths).
"""

from __future__ import annotations

import math
import pathlib
import struct
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from robot_agents.media import gif
from robot_agents.media.gif import PALETTE, write_gif

# ------------------------------------------------------------------- reference decoder


def _lzw_decode(data: bytes, min_code_size: int) -> bytes:
    """Strict GIF LZW decoder; raises AssertionError on any malformed stream."""
    clear = 1 << min_code_size
    end = clear + 1
    base: list[bytes] = [bytes([i]) for i in range(clear)] + [b"", b""]
    table = list(base)
    size = min_code_size + 1
    bitpos = 0
    total_bits = len(data) * 8
    prev: int | None = None
    out = bytearray()
    as_int = int.from_bytes(data, "little")
    while True:
        assert bitpos + size <= total_bits, "stream ended without an end code"
        code = (as_int >> bitpos) & ((1 << size) - 1)
        bitpos += size
        if code == clear:
            table = list(base)
            size = min_code_size + 1
            prev = None
            continue
        if code == end:
            break
        if prev is None:
            assert code < clear, f"first code after clear is {code}"
            entry = table[code]
        else:
            if code < len(table):
                entry = table[code]
                new = table[prev] + entry[:1]
            else:
                assert code == len(table), f"code {code} beyond table {len(table)}"
                entry = table[prev] + table[prev][:1]
                new = entry
            if len(table) < 4096:
                table.append(new)
        out += entry
        prev = code
        if len(table) == (1 << size) and size < 12:
            size += 1
    # Only zero padding (less than one byte) may follow the end code.
    assert (total_bits - bitpos) < 8, "data after end code"
    assert as_int >> bitpos == 0, "non-zero padding after end code"
    return bytes(out)


def _read_sub_blocks(raw: bytes, pos: int) -> tuple[bytes, int]:
    chunks: list[bytes] = []
    while True:
        n = raw[pos]
        pos += 1
        if n == 0:
            return b"".join(chunks), pos
        assert n <= 255
        chunks.append(raw[pos : pos + n])
        pos += n


def _parse_gif(raw: bytes) -> dict[str, Any]:
    """Parse a GIF made of one global palette and full/partial frames."""
    assert raw[:6] == b"GIF89a"
    width, height, flags, _bg, _aspect = struct.unpack_from("<HHBBB", raw, 6)
    pos = 13
    assert flags & 0x80, "no global colour table"
    n_colors = 2 ** ((flags & 7) + 1)
    palette = np.frombuffer(raw[pos : pos + 3 * n_colors], np.uint8).reshape(-1, 3)
    pos += 3 * n_colors
    canvas = np.zeros((height, width), dtype=np.uint8)
    frames: list[dict[str, Any]] = []
    loop: int | None = None
    control: dict[str, int] = {}
    while True:
        kind = raw[pos]
        pos += 1
        if kind == 0x3B:
            assert pos == len(raw), "bytes after trailer"
            break
        if kind == 0x21:
            label = raw[pos]
            pos += 1
            body, pos = _read_sub_blocks(raw, pos)
            if label == 0xFF and body.startswith(b"NETSCAPE2.0"):
                assert body[11] == 1
                loop = struct.unpack_from("<H", body, 12)[0]
            elif label == 0xF9:
                packed, delay, _transparent = struct.unpack_from("<BHB", body, 0)
                assert not packed & 1, "unexpected transparency"
                control = {"delay": delay, "disposal": (packed >> 2) & 7}
        elif kind == 0x2C:
            left, top, w, h, packed = struct.unpack_from("<HHHHB", raw, pos)
            pos += 9
            assert packed == 0, "local colour table / interlace not expected"
            min_code_size = raw[pos]
            pos += 1
            data, pos = _read_sub_blocks(raw, pos)
            pixels = _lzw_decode(data, min_code_size)
            assert len(pixels) == w * h
            assert left + w <= width and top + h <= height
            canvas = canvas.copy()
            canvas[top : top + h, left : left + w] = np.frombuffer(pixels, np.uint8).reshape(h, w)
            frames.append({"rect": (left, top, w, h), "rgb": palette[canvas], **control})
            control = {}
        else:
            raise AssertionError(f"unknown block 0x{kind:02x} at {pos - 1}")
    return {"size": (width, height), "loop": loop, "frames": frames}


def _decode_pillow(path: pathlib.Path) -> tuple[list[npt.NDArray[np.uint8]], list[int]]:
    """Decode with Pillow: full RGB frames and per-frame durations in ms."""
    pytest.importorskip("PIL")
    from PIL import Image, ImageSequence

    frames: list[npt.NDArray[np.uint8]] = []
    durations: list[int] = []
    with Image.open(path) as im:
        assert im.format == "GIF"
        for frame in ImageSequence.Iterator(im):
            frames.append(np.asarray(frame.convert("RGB")).copy())
            durations.append(int(frame.info["duration"]))
    return frames, durations


# ----------------------------------------------------------------------- test frames


def _gradient_scene(n: int, height: int = 48, width: int = 64) -> list[npt.NDArray[np.uint8]]:
    """Smooth shading plus a moving shaded disc: a small 'rendered' animation."""
    yy, xx = np.mgrid[0:height, 0:width].astype(np.float64)
    background = np.stack([40 + 3 * xx, 60 + 2.5 * yy, 200 - 1.5 * xx - yy], axis=-1)
    frames = []
    for i in range(n):
        img = background.copy()
        cx, cy, r = 15 + 4 * i, 24 + 6 * math.sin(i), 9
        d2 = (xx - cx) ** 2 + (yy - cy) ** 2
        inside = d2 < r * r
        shade = 0.3 + 0.7 * np.sqrt(np.clip(1 - d2 / (r * r), 0, 1))
        img[inside] = np.array([230.0, 90.0, 50.0]) * shade[inside][:, None]
        frames.append(np.clip(img, 0, 255).astype(np.uint8))
    return frames


def _expected(frame: npt.NDArray[np.uint8]) -> npt.NDArray[np.uint8]:
    """What the encoder should produce for a frame: dithered palette colours."""
    tmap = gif._threshold_map(frame.shape[0], frame.shape[1])
    return PALETTE[gif._quantize(frame, tmap)]


def _mean_abs_error(a: npt.NDArray[np.uint8], b: npt.NDArray[np.uint8]) -> npt.NDArray[np.float64]:
    """Mean absolute error per channel, shape (3,)."""
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16))
    result: npt.NDArray[np.float64] = diff.reshape(-1, 3).mean(axis=0)
    return result


# ------------------------------------------------------------------------ Pillow tests


def test_pillow_frame_count_duration_and_error(tmp_path: pathlib.Path) -> None:
    frames = _gradient_scene(8)
    path = write_gif(tmp_path / "scene.gif", frames, fps=25)
    decoded, durations = _decode_pillow(path)
    assert len(decoded) == len(frames)
    assert durations == [40] * len(frames)
    for src, out in zip(frames, decoded, strict=True):
        assert out.shape == src.shape
        assert (_mean_abs_error(src, out) < 20).all()
        np.testing.assert_array_equal(out, _expected(src))


@pytest.mark.parametrize(("fps", "duration_ms"), [(30, 30), (10, 100), (12.5, 80), (1, 1000), (200, 20)])
def test_pillow_duration(tmp_path: pathlib.Path, fps: float, duration_ms: int) -> None:
    frames = [np.zeros((4, 5, 3), np.uint8), np.full((4, 5, 3), 255, np.uint8)]
    _, durations = _decode_pillow(write_gif(tmp_path / "d.gif", frames, fps))
    assert durations == [duration_ms, duration_ms]


def test_pillow_exact_palette_colours(tmp_path: pathlib.Path) -> None:
    rng = np.random.default_rng(1)
    black = np.zeros((20, 30, 3), np.uint8)
    white = np.full((20, 30, 3), 255, np.uint8)
    checker = np.where(
        ((np.arange(20)[:, None] + np.arange(30)[None, :]) % 2 == 0)[..., None],
        white,
        black,
    )
    primaries = np.array(
        [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0], [0, 255, 255]],
        np.uint8,
    )
    blocks = primaries[rng.integers(0, len(primaries), (20, 30))]
    grid = PALETTE[rng.integers(0, 252, (20, 30))]  # any colour of the grid
    frames = [black, white, checker, blocks, grid, black]
    decoded, _ = _decode_pillow(write_gif(tmp_path / "exact.gif", frames, 10))
    assert len(decoded) == len(frames)
    for src, out in zip(frames, decoded, strict=True):
        np.testing.assert_array_equal(out, src)


def test_pillow_identical_frame_decodes_identically(tmp_path: pathlib.Path) -> None:
    a, b = _gradient_scene(2)
    frames = [a, a.copy(), b, b.copy(), b.copy(), a]
    path = write_gif(tmp_path / "same.gif", frames, fps=20)
    decoded, durations = _decode_pillow(path)
    assert len(decoded) == 6
    assert durations == [50] * 6
    np.testing.assert_array_equal(decoded[1], decoded[0])
    np.testing.assert_array_equal(decoded[3], decoded[2])
    np.testing.assert_array_equal(decoded[4], decoded[2])
    np.testing.assert_array_equal(decoded[5], decoded[0])


def test_pillow_noise_round_trip_with_dictionary_resets(tmp_path: pathlib.Path) -> None:
    rng = np.random.default_rng(7)
    noise = rng.integers(0, 256, (160, 200, 3), dtype=np.uint8)  # 32000 pixels
    noise2 = noise.copy()
    noise2[10:150, 20:190] = rng.integers(0, 256, (140, 170, 3), dtype=np.uint8)
    frames = [noise, noise2]
    # The noise really makes the encoder reset its dictionary several times.
    codes = gif._lzw_codes(gif._quantize(noise, gif._threshold_map(160, 200)).tobytes())
    assert sum(1 for c in codes if c & 0xFFF == 256) >= 5
    decoded, _ = _decode_pillow(write_gif(tmp_path / "noise.gif", frames, fps=5))
    assert len(decoded) == 2
    for src, out in zip(frames, decoded, strict=True):
        assert (_mean_abs_error(src, out) < 20).all()
        np.testing.assert_array_equal(out, _expected(src))


def test_pillow_all_code_width_boundaries(tmp_path: pathlib.Path) -> None:
    """1 x n images for many n, so the stream ends at every code-width change."""
    rng = np.random.default_rng(3)
    colours = PALETTE[rng.integers(0, 252, 5000)]
    widened_end = 0
    lengths = [*range(1, 1200), *range(4000, 4700, 7)]
    for n in lengths:
        row = colours[None, :n]
        codes = gif._lzw_codes(gif._quantize(row, gif._threshold_map(1, n)).tobytes())
        widened_end += (codes[-1] >> 12) != (codes[-2] >> 12)
        decoded, _ = _decode_pillow(write_gif(tmp_path / "row.gif", [row], fps=10))
        np.testing.assert_array_equal(decoded[0], row, err_msg=f"n={n}")
    assert widened_end >= 2  # the end code was read one bit wider at least twice


# --------------------------------------------------------------- reference-decoder tests


def test_structure_loop_disposal_and_changed_rectangles(tmp_path: pathlib.Path) -> None:
    frames = _gradient_scene(5)
    frames.insert(3, frames[2].copy())  # an unchanged frame
    path = write_gif(str(tmp_path / "s.gif"), frames, fps=30)
    assert isinstance(path, pathlib.Path)
    assert path == tmp_path / "s.gif"
    parsed = _parse_gif(path.read_bytes())
    assert parsed["size"] == (64, 48)
    assert parsed["loop"] == 0
    out = parsed["frames"]
    assert len(out) == len(frames)
    assert [f["delay"] for f in out] == [3] * len(frames)
    assert [f["disposal"] for f in out] == [1] * len(frames)
    assert out[0]["rect"] == (0, 0, 64, 48)
    assert out[3]["rect"] == (0, 0, 1, 1)
    for i in range(1, len(frames)):
        changed = (_expected(frames[i]) != _expected(frames[i - 1])).any(axis=2)
        if not changed.any():
            assert out[i]["rect"] == (0, 0, 1, 1)
            continue
        rows = np.flatnonzero(changed.any(axis=1))
        cols = np.flatnonzero(changed.any(axis=0))
        rect = (cols[0], rows[0], cols[-1] - cols[0] + 1, rows[-1] - rows[0] + 1)
        assert out[i]["rect"] == tuple(int(v) for v in rect)
        assert out[i]["rect"][2] < 64  # only part of the frame was encoded
    for src, f in zip(frames, out, strict=True):
        np.testing.assert_array_equal(f["rgb"], _expected(src))
        assert (_mean_abs_error(src, f["rgb"]) < 20).all()


def test_reference_decoder_noise_and_array_input(tmp_path: pathlib.Path) -> None:
    rng = np.random.default_rng(11)
    frames = rng.integers(0, 256, (3, 90, 110, 3), dtype=np.uint8)
    frames[1] = frames[0]
    parsed = _parse_gif(write_gif(tmp_path / "n.gif", frames, fps=50).read_bytes())
    out = parsed["frames"]
    assert len(out) == 3
    assert out[1]["rect"] == (0, 0, 1, 1)
    for src, f in zip(frames, out, strict=True):
        np.testing.assert_array_equal(f["rgb"], _expected(src))


def test_lzw_round_trip_many_lengths() -> None:
    rng = np.random.default_rng(5)
    for alphabet in (1, 2, 7, 256):
        data = rng.integers(0, alphabet, 9000, dtype=np.uint8).tobytes()
        for n in [*range(1, 600, 3), 1023, 1024, 1025, 4095, 4096, 4097, 9000]:
            packed = gif._pack_codes(gif._lzw_codes(data[:n]))
            assert _lzw_decode(packed, 8) == data[:n]


def test_sub_blocks_at_most_255_bytes() -> None:
    rng = np.random.default_rng(2)
    block = gif._lzw_image_data(rng.integers(0, 252, (50, 60), dtype=np.uint8))
    assert block[0] == 8
    payload, end = _read_sub_blocks(block, 1)
    assert end == len(block)
    assert len(payload) > 255 * 3
    sizes = []
    pos = 1
    while block[pos]:
        sizes.append(block[pos])
        pos += block[pos] + 1
    assert all(s == 255 for s in sizes[:-1]) and 0 < sizes[-1] <= 255


def test_palette() -> None:
    assert PALETTE.shape == (256, 3)
    assert PALETTE.dtype == np.uint8
    assert len({tuple(c) for c in PALETTE[:252]}) == 252
    with pytest.raises(ValueError, match="read-only"):
        PALETTE[0, 0] = 1


# ----------------------------------------------------------------------------- errors

_OK = np.zeros((4, 5, 3), np.uint8)


@pytest.mark.parametrize(
    ("frames", "match"),
    [
        ([], "expected at least one frame, got 0"),
        (np.zeros((0, 4, 5, 3), np.uint8), "expected at least one frame, got 0"),
        (
            np.zeros((4, 5, 3), np.uint8),
            r"expected frames .*\(N, H, W, 3\).* got .*\(4, 5, 3\)",
        ),
        (
            [np.zeros((4, 5), np.uint8)],
            r"expected frame 0 .*\(H, W, 3\).* got shape \(4, 5\)",
        ),
        (
            [_OK, np.zeros((4, 5, 4), np.uint8)],
            r"expected frame 1 .* got shape \(4, 5, 4\)",
        ),
        (
            [np.zeros((4, 5, 3), np.float32)],
            "expected frame 0 to have dtype uint8, got dtype float32",
        ),
        ([_OK.tolist()], "expected frame 0 .*numpy array.* got list"),
        (
            [np.zeros((0, 5, 3), np.uint8)],
            r"between 1 and 65535 .* got shape \(0, 5, 3\)",
        ),
        (
            [_OK, _OK, np.zeros((5, 4, 3), np.uint8)],
            r"expected all frames to have shape \(4, 5, 3\).* got shape \(5, 4, 3\) for frame 2",
        ),
        (None, "expected frames .* got NoneType"),
    ],
)
def test_bad_frames(tmp_path: pathlib.Path, frames: Any, match: str) -> None:
    path = tmp_path / "bad.gif"
    with pytest.raises(ValueError, match=match):
        write_gif(path, frames, fps=10)
    assert not path.exists()


@pytest.mark.parametrize("fps", [0, -1, -0.5, math.nan, math.inf, -math.inf, "30", None, True])
def test_bad_fps(tmp_path: pathlib.Path, fps: Any) -> None:
    path = tmp_path / "bad.gif"
    with pytest.raises(ValueError, match="expected fps to be a positive finite number, got"):
        write_gif(path, [_OK], fps=fps)
    assert not path.exists()


def test_fps_too_small_for_gif_delay(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ValueError, match=r"expected fps >= 100/65535.* got 0\.001"):
        write_gif(tmp_path / "slow.gif", [_OK], fps=0.001)
    parsed = _parse_gif(write_gif(tmp_path / "ok.gif", [_OK], fps=np.float64(0.002)).read_bytes())
    assert parsed["frames"][0]["delay"] == 50000
