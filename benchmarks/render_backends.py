"""Do two OpenGL backends render the same camera frames? (e.g. a GPU driver's EGL
against Mesa's software EGL / OSMesa.)

``--save PATH``: renders a fixed set of frames in this process's backend (chosen by
``import robot_agents``, or ``MUJOCO_GL``) and writes them to an ``.npz``, with the
backend and OpenGL renderer names, and the capture rate of each setting. Every frame
comes from a seeded reset and the same 5 zero-action steps, so two machines render the
same physical state (the simulation is CPU MuJoCo either way).

``--compare A B``: per camera and texture, how far ``B``'s frames are from ``A``'s:

- ``segmentation``: the fraction of pixels with the same body id (edges of bodies can
  fall on either side of a pixel centre when the rasterizers differ);
- ``depth`` (metres, on pixels where both see the same body): the median and 99.9th
  percentile of ``|A - B|``, and the largest;
- ``rgb``: the mean absolute difference per channel (0-255) and the fraction of pixels
  with a channel more than 16 apart;
- ``--png DIR`` also writes each camera's RGB of A and B side by side.

Usage::

    python benchmarks/render_backends.py --save gpu.npz          # on the GPU machine
    python benchmarks/render_backends.py --save cpu.npz          # here
    python benchmarks/render_backends.py --compare cpu.npz gpu.npz --png frames/
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

#: (label, task, robot): the cameras of each come from the task and the robot.
SETTINGS = (
    ("pickcube_panda_wristcam", "PickCube-v1", "panda_wristcam"),
    ("empty_fetch", "Empty-v1", "fetch"),
    ("empty_bridge_flat_table", "Empty-v1", "widowx250s_bridgedataset_flat_table"),
    ("pushcube_xarm6_wristcam", "PushCube-v1", "xarm6_nogripper_wristcam"),
)
TEXTURES = ("rgb", "depth", "segmentation")
NUM_ENVS = 2


def save(path: Path, rounds: int) -> None:
    import robot_agents as ra
    from render_throughput import gl_renderer_name  # a script beside this one
    from robot_agents import gl_backend

    arrays: dict[str, np.ndarray] = {}
    rates: dict[str, float] = {}
    renderer = ""
    for label, task, robot in SETTINGS:
        env = ra.make_env(task, robot_uids=robot, num_envs=NUM_ENVS, obs_mode="state", render_mode="rgb_array")
        env.reset(seed=0)
        scene = env.unwrapped.scene
        zero = np.zeros(env.action_space.shape, dtype=np.float32)
        for _ in range(5):
            env.step(zero)
        frames = scene.cameras.capture(scene.world, TEXTURES)
        renderer = renderer or gl_renderer_name(env.unwrapped)
        for camera, textures in frames.items():
            for texture, image in textures.items():
                arrays[f"{label}/{camera}/{texture}"] = np.asarray(image)
        arrays[f"{label}/render/rgb"] = np.asarray(env.render())
        start = time.perf_counter()
        for _ in range(rounds):
            scene.cameras.capture(scene.world, TEXTURES)
        frames_per_capture = NUM_ENVS * len(frames)
        rates[label] = rounds * frames_per_capture / (time.perf_counter() - start)
        env.close()
    meta = {"backend": gl_backend.current_choice().backend, "renderer": renderer, "frames_per_s": rates}
    np.savez_compressed(path, meta=np.array(json.dumps(meta)), **arrays)
    print(json.dumps(meta, indent=1))
    for key, image in arrays.items():
        print(f"{key}: {image.shape} {image.dtype}")


def compare(path_a: Path, path_b: Path, png_dir: Path | None) -> None:
    a, b = np.load(path_a), np.load(path_b)
    for name, data in (("A", a), ("B", b)):
        meta = json.loads(str(data["meta"]))
        rates = ", ".join(f"{k} {v:.0f}" for k, v in meta["frames_per_s"].items())
        print(
            f"{name}: backend {meta['backend']}, renderer {meta['renderer']}; RGB+depth+segmentation frames/s: {rates}"
        )
    keys = sorted(set(a.files) - {"meta"})
    missing = sorted(set(keys) ^ (set(b.files) - {"meta"}))
    if missing:
        print(f"only in one file: {missing}")
    print(f"\n{'camera':<52} {'texture':<12} result")
    for key in keys:
        if key not in b.files:
            continue
        label, camera, texture = key.split("/")
        x, y = a[key], b[key]
        if x.shape != y.shape:
            print(f"{label + '/' + camera:<52} {texture:<12} shapes differ: {x.shape} vs {y.shape}")
            continue
        if texture == "segmentation":
            result = f"same body id on {np.mean(x == y) * 100:.3f}% of pixels"
        elif texture == "depth":
            seg_key = f"{label}/{camera}/segmentation"
            same = (a[seg_key] == b[seg_key]) & (a[seg_key] >= 0)
            diff = np.abs(x.astype(np.float64) - y.astype(np.float64))[same]
            result = (
                f"|A-B| on {diff.size} shared-body pixels: median {np.median(diff) * 1e3:.4f} mm, "
                f"99.9% {np.percentile(diff, 99.9) * 1e3:.3f} mm, max {diff.max() * 1e3:.2f} mm"
            )
        else:
            diff = np.abs(x.astype(np.int16) - y.astype(np.int16))
            result = (
                f"mean |A-B| {diff.mean():.2f} / 255; {np.mean(diff.max(axis=-1) > 16) * 100:.2f}% of pixels > 16 apart"
            )
        print(f"{label + '/' + camera:<52} {texture:<12} {result}")
        if png_dir is not None and texture == "rgb":
            from PIL import Image

            png_dir.mkdir(parents=True, exist_ok=True)
            Image.fromarray(np.concatenate([x[0], y[0]], axis=1)).save(png_dir / f"{label}-{camera}.png")


def main(argv: Any = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--save", type=Path)
    parser.add_argument("--rounds", type=int, default=20, help="captures timed per setting")
    parser.add_argument("--compare", type=Path, nargs=2)
    parser.add_argument("--png", type=Path)
    args = parser.parse_args(argv)
    if args.save:
        save(args.save, args.rounds)
    if args.compare:
        compare(*args.compare, args.png)
    if not args.save and not args.compare:
        parser.error("give --save PATH or --compare A B")


if __name__ == "__main__":
    main()
