"""The library's notes, and MuJoCo's warnings passed on as notes: one way.

A note says what the library derived, changed or dropped where the user's input left it
open (a model file's missing limits, a free root fixed, a keyframe moved inside its
limits, ...). Every note is a Python ``RuntimeWarning`` raised with :func:`warnings.warn`:
a program filters or records them with :mod:`warnings`; the command line prints each as
one line, ``robot-agents: note: ...`` (:func:`robot_agents.cli.show_note`). (No other
way: no logger, no print, not gymnasium's logger.)

MuJoCo's own warnings, from its compiler and at run time (``Nan, Inf or huge value in
QACC ... The simulation is unstable``, a full contact buffer), would be printed to stdout
and appended to ``MUJOCO_LOG.TXT`` in the working directory. The library's handler
collects them instead, and :func:`pass_on` raises each as a note, ``<where>: MuJoCo:
<message>``, once MuJoCo's call has returned: inside MuJoCo's callback a raised warning
(a filter set to ``"error"``) would abort the process, since MuJoCo's C code cannot pass a
Python exception on. Compiles collect them for their own call (:func:`mujoco_messages`);
stepping collects them in :data:`RUNTIME` once :func:`install` made the library's handler
MuJoCo's (:class:`~robot_agents.sim.world.BatchedWorld` does; a handler someone else
installed first is left alone, and gets them instead).
"""

from __future__ import annotations

import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

import mujoco

#: Warnings the library causes on purpose and does not pass on: pieces attached without
#: a prefix, and a robot file's physics options (time step, integrator, solver) and
#: keyframes giving way to the scene's when the robot is attached into a scene.
EXPECTED = ("Attaching a spec with an empty prefix", "Attach conflict")

#: MuJoCo's run-time warnings collected since the last :func:`pass_on` of them (appended
#: from any thread that steps; a list's append holds the GIL).
RUNTIME: list[str] = []

#: Held while messages are taken from a list to be passed on.
_TAKING = threading.Lock()

#: This MuJoCo lets a program take its warnings (older ones keep their own handler).
ROUTABLE = hasattr(mujoco, "set_mju_user_warning")


def install() -> None:
    """Make the library's handler MuJoCo's, collecting into :data:`RUNTIME`, unless a
    handler is installed already (the library's, or someone else's: left alone)."""
    if ROUTABLE and mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(RUNTIME.append)


def pass_on(messages: list[str], where: str, stacklevel: int = 2, handled: tuple[str, ...] = ()) -> None:
    """Raise each of MuJoCo's ``messages`` as a note, ``<where>: MuJoCo: <message>``, and
    empty the list (those starting with one of :data:`EXPECTED` or ``handled``, what the
    caller says in its own words, are dropped). ``stacklevel``: as :func:`warnings.warn`'s,
    counted from the caller of this function."""
    with _TAKING:  # two threads' steps pass on each message once
        taken = messages[:]
        del messages[: len(taken)]  # (one appended meanwhile by another thread stays for the next)
    for message in taken:
        if not message.startswith(EXPECTED + handled):
            warnings.warn(f"{where}: MuJoCo: {message}", RuntimeWarning, stacklevel=stacklevel + 1)


@contextmanager
def mujoco_messages(where: str, handled: tuple[str, ...] = ()) -> Iterator[None]:
    """MuJoCo's warnings raised inside the block (a compile, an attach, a parse) passed on
    as notes naming ``where`` when it ends (but those starting with one of ``handled``)."""
    messages: list[str] = []
    previous = mujoco.get_mju_user_warning() if ROUTABLE else None
    if ROUTABLE:
        mujoco.set_mju_user_warning(messages.append)
    try:
        with warnings.catch_warnings():
            for text in EXPECTED:  # (an older MuJoCo, whose own handler stays, may raise them)
                warnings.filterwarnings("ignore", message=text)
            yield
    finally:
        if ROUTABLE:
            mujoco.set_mju_user_warning(previous)
        pass_on(messages, where, stacklevel=3, handled=handled)
