"""Camera throughput: one 128 x 128 wrist camera, RGB and RGB + depth, 1 and 16 envs,
shadows on and off, and what it costs relative to a state-only env step.

For each setting, on ``make_env("Empty-v1", robot_uids="panda_wristcam", ...)`` with the
task camera dropped (only ``hand_camera`` renders):

- ``capture``: ``scene.cameras.capture(...)`` alone (no physics): camera frames/s;
- ``env``: ``env.step(action)`` in obs mode ``rgb`` / ``rgbd`` (physics, controller,
  proprioception, rendering, camera parameters): env steps/s, and frames/s
  (``num_envs`` frames per step);
- ``state``: the same env in obs mode ``state``, timed in alternating blocks with
  ``env`` so machine noise hits both alike; ``cost`` is the camera step's time over
  the state step's, ``render ms`` the extra time per frame.

Last, RGB capture at 1 env with shadows, with our shadow map (8 texels per pixel) and
with MuJoCo's default 4096 x 4096 one, against shadows off.

Usage: ``python benchmarks/render_throughput.py [--rounds 4] [--block 10]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents import gl_backend
from robot_agents.sensors import renderer as sensor_renderer

SIZE = 128


def make(obs_mode: str, num_envs: int, shadows: bool) -> Any:
    configs = {"base_camera": None, "hand_camera": {"width": SIZE, "height": SIZE, "shadows": shadows}}
    env = ra.make_env(
        "Empty-v1",
        robot_uids="panda_wristcam",
        obs_mode=obs_mode,
        num_envs=num_envs,
        sensor_configs=configs,
        max_episode_steps=None,
        control_mode="pd_joint_delta_pos",
    )
    env.reset(seed=0)
    return env.unwrapped


def interleaved(loops: list[Callable[[int], None]], rounds: int, block: int) -> list[float]:
    """Calls/s of each loop, timed in alternating blocks after one warm-up block each."""
    for loop in loops:
        loop(block)
    totals = [0.0] * len(loops)
    for _ in range(rounds):
        for i, loop in enumerate(loops):
            start = time.perf_counter()
            loop(block)
            totals[i] += time.perf_counter() - start
    return [rounds * block / total for total in totals]


def stepper(env: Any, actions: list[np.ndarray]) -> Callable[[int], None]:
    counter = [0]

    def loop(count: int) -> None:
        for _ in range(count):
            env.step(actions[counter[0] % len(actions)])
            counter[0] += 1

    return loop


def capture_rate(env: Any, textures: tuple[str, ...], rounds: int, block: int) -> float:
    """Camera frames/s of ``CameraRig.capture`` alone (all envs, one camera)."""
    rig, world = env.scene.cameras, env.scene.world

    def loop(count: int) -> None:
        for _ in range(count):
            rig.capture(world, textures)

    return interleaved([loop], rounds, block)[0] * env.num_envs


def gl_renderer_name(env: Any) -> str:
    """The OpenGL renderer string of the camera's context (e.g. Mesa's llvmpipe)."""
    try:
        from OpenGL import GL  # type: ignore[import-untyped]

        env.scene.cameras.capture(env.scene.world, env_ids=[0])
        name = GL.glGetString(GL.GL_RENDERER)
        return name.decode() if isinstance(name, bytes) else str(name)
    except Exception as err:  # only informative
        return f"unknown ({type(err).__name__})"


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--rounds", type=int, default=4)
    parser.add_argument("--block", type=int, default=10, help="env steps per timed block")
    parser.add_argument("--num-envs", type=int, nargs="+", default=[1, 16])
    args = parser.parse_args()
    probe = make("rgb", 1, False)
    print(
        f"robot_agents {ra.__version__}, mujoco {mujoco.__version__}, python {platform.python_version()}, "
        f"{os.cpu_count()} cores, MUJOCO_GL={gl_backend.current_choice().backend}, "
        f"OpenGL renderer: {gl_renderer_name(probe)}"
    )
    print(
        f"panda_wristcam, Empty-v1, hand_camera {SIZE}x{SIZE}, {probe.scene.substeps} physics substeps per env step\n"
    )
    probe.close()
    header = (
        f"{'envs':>4} {'mode':<5} {'shadows':<7} {'capture fps':>11} {'env steps/s':>11} {'env fps':>8}"
        f" {'state steps/s':>13} {'cost':>6} {'render ms':>9}"
    )
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(0)
    for num_envs in args.num_envs:
        actions = [rng.uniform(-0.2, 0.2, (num_envs, 8)) for _ in range(16)]
        state = make("state", num_envs, False)
        for mode, textures in (("rgb", ("rgb",)), ("rgbd", ("rgb", "depth"))):
            for shadows in (False, True):
                env = make(mode, num_envs, shadows)
                scale = 4 if shadows else 1  # fewer steps where a step is slow
                rounds, block = args.rounds, max(2, args.block // scale // max(1, num_envs // 4))
                capture = capture_rate(env, textures, rounds, block)
                env_rate, state_rate = interleaved([stepper(env, actions), stepper(state, actions)], rounds, block)
                cost = state_rate / env_rate
                render_ms = (1 / env_rate - 1 / state_rate) / num_envs * 1e3
                print(
                    f"{num_envs:>4} {mode:<5} {'on' if shadows else 'off':<7} {capture:>11.0f} {env_rate:>11.1f}"
                    f" {env_rate * num_envs:>8.0f} {state_rate:>13.0f} {cost:>5.1f}x {render_ms:>9.2f}",
                    flush=True,
                )
                env.close()
        state.close()
    print("\nRGB capture frames/s at 1 env, by shadow map:")
    rates = {}
    for label, texels, shadows in (("shadows off", 8, False), ("ours", 8, True), ("MuJoCo 4096", 10**6, True)):
        sensor_renderer.SHADOW_TEXELS_PER_PIXEL = texels  # read when a camera env makes its renderer
        env = make("rgb", 1, shadows)
        rates[label] = capture_rate(env, ("rgb",), args.rounds, args.block)
        env.close()
    sensor_renderer.SHADOW_TEXELS_PER_PIXEL = 8
    size = sensor_renderer.shadow_size_for(SIZE, SIZE)
    print(
        f"  shadows off {rates['shadows off']:.0f}; on, ours ({size}) {rates['ours']:.0f} "
        f"({rates['shadows off'] / rates['ours']:.1f}x the time); on, MuJoCo's 4096 {rates['MuJoCo 4096']:.0f} "
        f"({rates['shadows off'] / rates['MuJoCo 4096']:.1f}x)"
    )


if __name__ == "__main__":
    main()
