"""Choose MuJoCo's OpenGL backend for offscreen rendering, before MuJoCo is imported.

MuJoCo reads the ``MUJOCO_GL`` environment variable once, when ``mujoco`` is imported,
and its choice cannot be changed afterwards in the same process (PyOpenGL binds one
platform). So ``import robot_agents`` decides first, in this order:

1. ``MUJOCO_GL`` already set: the user's choice is kept (likewise a headless
   ``PYOPENGL_PLATFORM`` of ``egl`` or ``osmesa``, which MuJoCo's context must match).
2. A display (``DISPLAY`` / ``WAYLAND_DISPLAY``), or not Linux: nothing is set; MuJoCo
   uses its platform default (GLFW, CGL, WGL).
3. Headless Linux: **EGL** if ``libEGL.so.1`` loads and offers at least one EGL device
   (a GPU driver, or Mesa's software device); otherwise **OSMesa** if ``libOSMesa.so``
   loads. Both need PyOpenGL.

If ``mujoco`` was imported first (with ``MUJOCO_GL`` unset, so it bound GLFW) and no
OpenGL binding is loaded yet, the choice is still applied: MuJoCo's small GL-context
module is reloaded under the new ``MUJOCO_GL``. Once PyOpenGL is loaded its platform
is fixed, and the process keeps what it has.

The probes only load the libraries and enumerate EGL devices (about 2 ms); creating a
full context would cost ~0.2 s on every import, even for state-only use. When the
chosen backend still fails to create a context, or when nothing was found,
:func:`rendering_error` builds a :class:`~robot_agents.errors.RenderError` that names
the missing library and the packages that provide it. The result is cached per process
(:func:`current_choice`).

This module must not import ``mujoco``.
"""

from __future__ import annotations

import ctypes
import dataclasses
import importlib
import importlib.util
import os
import sys
from collections.abc import Callable, Mapping, MutableMapping
from dataclasses import dataclass

from robot_agents.errors import RenderError

#: Shared-library names tried for each headless backend, most specific first.
EGL_LIBRARIES = ("libEGL.so.1", "libEGL.so")
OSMESA_LIBRARIES = ("libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so")
#: How to install each backend on Debian / Ubuntu.
INSTALL_HINTS = {
    "egl": "apt-get install libegl1 libgl1-mesa-dri (Mesa's EGL, software rendering without a GPU; "
    "with an NVIDIA GPU its driver provides libEGL)",
    "osmesa": "apt-get install libosmesa6",
    "pyopengl": "pip install PyOpenGL",
}

#: A probe returns ``None`` when its backend looks usable, else what is missing.
Probe = Callable[[], "str | None"]


@dataclass(frozen=True)
class BackendChoice:
    """What ``import robot_agents`` decided.

    Attributes:
        backend: the ``MUJOCO_GL`` value in effect (``"egl"``, ``"osmesa"``, a user's
            value), or ``None`` for MuJoCo's platform default (GLFW with a display).
        reason: why, in words.
        problems: for headless Linux, why each rejected backend was rejected.
    """

    backend: str | None
    reason: str
    problems: tuple[str, ...] = ()

    @property
    def headless_failed(self) -> bool:
        """Headless, and neither EGL nor OSMesa looked usable."""
        return self.backend is None and bool(self.problems)


def _load_first(names: tuple[str, ...]) -> tuple[ctypes.CDLL | None, str]:
    errors = []
    for name in names:
        try:
            return ctypes.CDLL(name), name
        except OSError as err:
            errors.append(str(err))
    return None, "; ".join(errors)


def probe_pyopengl() -> str | None:
    """PyOpenGL, which MuJoCo's EGL and OSMesa contexts are written with."""
    if importlib.util.find_spec("OpenGL") is None:
        return f"the Python package PyOpenGL is not installed ({INSTALL_HINTS['pyopengl']})"
    return None


def probe_egl() -> str | None:
    """``libEGL.so.1`` loads and enumerates at least one EGL device (what MuJoCo's
    headless EGL context needs: ``EGL_EXT_device_enumeration``)."""
    lib, detail = _load_first(EGL_LIBRARIES)
    if lib is None:
        return f"EGL: {EGL_LIBRARIES[0]} could not be loaded ({detail}); install it: {INSTALL_HINTS['egl']}"
    get_proc = lib.eglGetProcAddress
    get_proc.restype = ctypes.c_void_p
    get_proc.argtypes = [ctypes.c_char_p]
    address = get_proc(b"eglQueryDevicesEXT")
    if not address:
        return f"EGL: {detail} has no eglQueryDevicesEXT (no device enumeration); install: {INSTALL_HINTS['egl']}"
    query = ctypes.CFUNCTYPE(
        ctypes.c_uint, ctypes.c_int, ctypes.POINTER(ctypes.c_void_p), ctypes.POINTER(ctypes.c_int)
    )(address)
    devices = (ctypes.c_void_p * 16)()
    count = ctypes.c_int(0)
    if not query(16, devices, ctypes.byref(count)) or count.value < 1:
        return f"EGL: {detail} loaded but offers no EGL device (no GPU driver or Mesa EGL); install: {INSTALL_HINTS['egl']}"
    return None


def probe_osmesa() -> str | None:
    """``libOSMesa.so`` loads and has ``OSMesaCreateContextExt``."""
    lib, detail = _load_first(OSMESA_LIBRARIES)
    if lib is None:
        return f"OSMesa: libOSMesa.so could not be loaded ({detail}); install it: {INSTALL_HINTS['osmesa']}"
    if not hasattr(lib, "OSMesaCreateContextExt"):
        return f"OSMesa: {detail} has no OSMesaCreateContextExt; install: {INSTALL_HINTS['osmesa']}"
    return None


DEFAULT_PROBES: Mapping[str, Probe] = {"pyopengl": probe_pyopengl, "egl": probe_egl, "osmesa": probe_osmesa}


def select_backend(
    environ: Mapping[str, str], platform: str | None = None, probes: Mapping[str, Probe] | None = None
) -> BackendChoice:
    """Decide the backend (pure: reads ``environ``, runs the probes, sets nothing).

    ``probes`` maps ``"pyopengl"``, ``"egl"``, ``"osmesa"`` to functions returning
    ``None`` (usable) or what is missing; tests pass failing ones.
    """
    platform = sys.platform if platform is None else platform
    chosen = environ.get("MUJOCO_GL", "").strip()
    if chosen:
        return BackendChoice(chosen.lower(), "MUJOCO_GL was set before robot_agents was imported")
    if not platform.startswith("linux"):
        return BackendChoice(None, f"platform {platform!r}: MuJoCo's default OpenGL context")
    if environ.get("DISPLAY") or environ.get("WAYLAND_DISPLAY"):
        return BackendChoice(None, "a display is available: MuJoCo's default (GLFW)")
    platform_gl = environ.get("PYOPENGL_PLATFORM", "").strip().lower()
    if platform_gl in ("egl", "osmesa"):  # MuJoCo's context must match PyOpenGL's platform
        return BackendChoice(platform_gl, f"PYOPENGL_PLATFORM={platform_gl} was set before robot_agents was imported")
    probes = DEFAULT_PROBES if probes is None else probes
    gl = probes["pyopengl"]()
    if gl is not None:
        return BackendChoice(None, "headless Linux", (gl,))
    problems: list[str] = []
    for backend in ("egl", "osmesa"):
        problem = probes[backend]()
        if problem is None:
            fallback = f" (after {problems[0]})" if problems else ""
            return BackendChoice(backend, f"headless Linux: {backend} works{fallback}", tuple(problems))
        problems.append(problem)
    return BackendChoice(None, "headless Linux", tuple(problems))


_CHOICE: BackendChoice | None = None


def configure(environ: MutableMapping[str, str] | None = None) -> BackendChoice:
    """Select the backend once per process and export it as ``MUJOCO_GL`` (called by
    ``import robot_agents``, before MuJoCo is imported). Never raises."""
    global _CHOICE
    if _CHOICE is not None:
        return _CHOICE
    env = os.environ if environ is None else environ
    late = "mujoco" in sys.modules
    if late and (env.get("MUJOCO_GL") or "OpenGL" in sys.modules):
        current = env.get("MUJOCO_GL") or None
        _CHOICE = BackendChoice(current, "mujoco was imported before robot_agents; it keeps the MUJOCO_GL of then")
        return _CHOICE
    choice = select_backend(env)
    if choice.backend is not None and not env.get("MUJOCO_GL"):
        env["MUJOCO_GL"] = choice.backend
        if late:
            problem = reload_mujoco_gl_context()
            note = "; mujoco was imported first: its GL context module was reloaded"
            choice = dataclasses.replace(
                choice, reason=choice.reason + note, problems=choice.problems + ((problem,) if problem else ())
            )
    _CHOICE = choice
    return choice


def reload_mujoco_gl_context() -> str | None:
    """Re-run MuJoCo's backend selection (its ``gl_context`` module, read by
    ``mujoco.Renderer`` when it is created) under the current ``MUJOCO_GL``; returns
    what went wrong, if anything."""
    for name in ("mujoco.rendering.classic.gl_context", "mujoco.gl_context"):  # MuJoCo >= 3.4, then older
        module = sys.modules.get(name)
        if module is not None and hasattr(module, "GLContext"):
            try:
                importlib.reload(module)
            except Exception as err:  # an import error of the backend; reported, never raised
                return f"reloading {name} with MUJOCO_GL={os.environ.get('MUJOCO_GL')!r} failed: {err}"
            return None
    return "no MuJoCo gl_context module to reload"


def current_choice() -> BackendChoice:
    """The cached decision (made now if ``configure`` has not run)."""
    return _CHOICE if _CHOICE is not None else configure()


def rendering_error(where: str, choice: BackendChoice, cause: BaseException | None = None) -> RenderError:
    """A :class:`RenderError` that says what failed, which library is missing and how to
    install it."""
    if choice.headless_failed:
        tried = " ".join(f"{p}." for p in choice.problems)
        return RenderError(
            f"{where}: no OpenGL backend for offscreen rendering (no display, MUJOCO_GL unset). "
            f"Tried EGL, then OSMesa: {tried} Install one of them and restart Python, or set MUJOCO_GL "
            "before importing robot_agents."
        )
    backend = choice.backend or "MuJoCo's default (GLFW)"
    hint = {
        "egl": f"EGL needs libEGL.so.1 and a driver ({INSTALL_HINTS['egl']}); or use OSMesa: "
        f"{INSTALL_HINTS['osmesa']}, and set MUJOCO_GL=osmesa before importing robot_agents",
        "osmesa": f"OSMesa needs libOSMesa.so ({INSTALL_HINTS['osmesa']}); or use EGL: {INSTALL_HINTS['egl']}, "
        "and set MUJOCO_GL=egl before importing robot_agents",
    }.get(choice.backend or "", "without a display set MUJOCO_GL=egl (libEGL.so.1) or MUJOCO_GL=osmesa (libOSMesa.so)")
    detail = f": {type(cause).__name__}: {cause}" if cause is not None else ""
    extra = f" Earlier: {' '.join(choice.problems)}" if choice.problems else ""
    return RenderError(
        f"{where}: MuJoCo could not create an offscreen OpenGL context with MUJOCO_GL={backend!r}{detail}. "
        f"{hint}.{extra}"
    )
