"""Headless rendering backends: EGL first, OSMesa as fallback, and a clear error naming
the missing library when neither works. Failures are simulated with fake probes."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents import gl_backend

HEADLESS: dict[str, str] = {}
NO_EGL = "EGL: libEGL.so.1 could not be loaded (libEGL.so.1: cannot open shared object file); install it: apt-get install libegl1"
NO_OSMESA = "OSMesa: libOSMesa.so could not be loaded (libOSMesa.so.8: cannot open shared object file); install it: apt-get install libosmesa6"


def probes(
    pyopengl: str | None = None, egl: str | None = None, osmesa: str | None = None
) -> dict[str, Callable[[], str | None]]:
    return {"pyopengl": lambda: pyopengl, "egl": lambda: egl, "osmesa": lambda: osmesa}


def test_egl_is_preferred_when_it_works() -> None:
    choice = gl_backend.select_backend(HEADLESS, "linux", probes())
    assert choice.backend == "egl" and not choice.problems and not choice.headless_failed


def test_osmesa_is_the_fallback() -> None:
    choice = gl_backend.select_backend(HEADLESS, "linux", probes(egl=NO_EGL))
    assert choice.backend == "osmesa"
    assert choice.problems == (NO_EGL,) and "after EGL" in choice.reason


def test_neither_backend_gives_an_error_naming_the_libraries() -> None:
    choice = gl_backend.select_backend(HEADLESS, "linux", probes(egl=NO_EGL, osmesa=NO_OSMESA))
    assert choice.backend is None and choice.headless_failed
    message = str(gl_backend.rendering_error("make_renderer", choice))
    for fragment in (
        "no OpenGL backend",
        "libEGL.so.1",
        "apt-get install libegl1",
        "libOSMesa.so",
        "apt-get install libosmesa6",
        "MUJOCO_GL",
    ):
        assert fragment in message, message
    missing_gl = gl_backend.select_backend(
        HEADLESS, "linux", probes(pyopengl="the Python package PyOpenGL is not installed (pip install PyOpenGL)")
    )
    assert missing_gl.headless_failed and "pip install PyOpenGL" in str(gl_backend.rendering_error("x", missing_gl))


def fail_if_called() -> str | None:
    raise AssertionError("no probe runs when the choice is made elsewhere")


def test_user_choice_and_displays_are_respected() -> None:
    never = {"pyopengl": fail_if_called, "egl": fail_if_called, "osmesa": fail_if_called}
    assert gl_backend.select_backend({"MUJOCO_GL": "osmesa"}, "linux", never).backend == "osmesa"
    with_display = gl_backend.select_backend({"DISPLAY": ":0"}, "linux", never)
    assert with_display.backend is None and not with_display.headless_failed
    assert gl_backend.select_backend({}, "darwin", never).backend is None
    assert gl_backend.select_backend({"PYOPENGL_PLATFORM": "osmesa"}, "linux", never).backend == "osmesa"


def test_configure_exports_the_choice_once(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(gl_backend, "_CHOICE", None)
    monkeypatch.setattr(gl_backend, "DEFAULT_PROBES", probes(egl=NO_EGL))
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.delitem(sys.modules, "mujoco")  # as if robot_agents were imported first
    environ: dict[str, str] = {}
    choice = gl_backend.configure(environ)
    assert environ == {"MUJOCO_GL": "osmesa"} and choice.backend == "osmesa"
    assert gl_backend.configure({}) is choice  # cached for the process


def test_configure_after_mujoco_keeps_its_backend(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(gl_backend, "_CHOICE", None)
    environ = {"MUJOCO_GL": "egl"}
    choice = gl_backend.configure(environ)  # mujoco is already imported here
    assert (
        choice.backend == "egl" and "imported before robot_agents" in choice.reason and environ == {"MUJOCO_GL": "egl"}
    )


def test_rendering_without_a_backend_fails_before_any_episode(monkeypatch: pytest.MonkeyPatch) -> None:
    failed = gl_backend.select_backend(HEADLESS, "linux", probes(egl=NO_EGL, osmesa=NO_OSMESA))
    monkeypatch.setattr(gl_backend, "_CHOICE", failed)
    with pytest.raises(ra.RenderError, match=r"libEGL\.so\.1.*libOSMesa\.so"):
        ra.make_env("Empty-v1", robot_uids="panda_wristcam", obs_mode="rgb")
    env = ra.make_env("Empty-v1", robot_uids="panda_wristcam", obs_mode="state")  # state needs no OpenGL
    env.reset(seed=0)
    env.step(np.zeros(8))


def test_a_context_that_cannot_be_created_is_a_render_error(monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(*args: object, **kwargs: object) -> None:
        raise ImportError("Cannot initialize a EGL device display.")

    monkeypatch.setattr(gl_backend, "_CHOICE", gl_backend.BackendChoice("egl", "test"))
    monkeypatch.setattr(mujoco, "Renderer", broken)
    scene = ra.Scene("panda_wristcam")
    scene.reset()
    before = scene.world.get_state()
    quality = (scene.model.vis.quality.offsamples, scene.model.vis.quality.shadowsize)
    with pytest.raises(ra.RenderError) as caught:
        scene.cameras.capture(scene.world)
    message = str(caught.value)
    for fragment in ("MUJOCO_GL='egl'", "Cannot initialize a EGL device display", "libosmesa6", "MUJOCO_GL=osmesa"):
        assert fragment in message, message
    assert np.array_equal(before, scene.world.get_state())  # the simulation is untouched
    assert (scene.model.vis.quality.offsamples, scene.model.vis.quality.shadowsize) == quality


SUBPROCESS = """
import numpy as np
import robot_agents as ra
from robot_agents import gl_backend
choice = gl_backend.current_choice()
assert choice.backend is None and len(choice.problems) == 2, choice
env = ra.make_env("Empty-v1", robot_uids="panda_wristcam")  # state: no OpenGL needed
env.reset(seed=0)
env.step(np.zeros(8))
try:
    ra.make_env("Empty-v1", robot_uids="panda_wristcam", obs_mode="rgb")
except ra.RenderError as err:
    print(err)
"""


def test_broken_libraries_end_to_end(tmp_path: Path) -> None:
    """A fresh process whose libEGL and libOSMesa cannot load (garbage files first on the
    library path): import works, state envs work, camera envs raise a RenderError."""
    for name in (*gl_backend.EGL_LIBRARIES, *gl_backend.OSMESA_LIBRARIES):
        (tmp_path / name).write_text("not a shared library")
    env = {
        k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY")
    }
    env["LD_LIBRARY_PATH"] = str(tmp_path)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(ra.__file__).parents[1]), env.get("PYTHONPATH", "")])
    result = subprocess.run([sys.executable, "-c", SUBPROCESS], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    message = result.stdout
    for fragment in (
        "no OpenGL backend",
        "libEGL.so.1 could not be loaded",
        "apt-get install libegl1",
        "libOSMesa.so could not be loaded",
        "apt-get install libosmesa6",
    ):
        assert fragment in message, message


MUJOCO_FIRST = """
import mujoco  # before robot_agents, with MUJOCO_GL unset: MuJoCo binds GLFW, which needs a display
import robot_agents as ra
from robot_agents import gl_backend
choice = gl_backend.current_choice()
assert choice.backend in ("egl", "osmesa") and "reloaded" in choice.reason, choice
env = ra.make_env("Empty-v1", robot_uids="panda_wristcam", obs_mode="rgb", sensor_configs={"base_camera": None})
obs, _ = env.reset(seed=0)
print(obs["sensor_data"]["hand_camera"]["rgb"].shape, obs["sensor_data"]["hand_camera"]["rgb"].std() > 5)
"""


def test_importing_mujoco_first_still_renders_headless() -> None:
    env = {
        k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY")
    }
    env["PYTHONPATH"] = os.pathsep.join([str(Path(ra.__file__).parents[1]), env.get("PYTHONPATH", "")])
    result = subprocess.run([sys.executable, "-c", MUJOCO_FIRST], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "(1, 128, 128, 3) True"
