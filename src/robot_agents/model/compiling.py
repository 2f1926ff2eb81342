"""Compile an ``MjSpec`` with MuJoCo's messages kept in the library.

MuJoCo reports compiler warnings by printing them and appending them to
``MUJOCO_LOG.TXT`` in the working directory. :func:`compile_spec` routes them to
Python's ``warnings`` instead (nothing is written to the user's directory) and drops
the one about attaching pieces without a name prefix, which the library does on
purpose (composed robots keep their upstream joint and body names; the library never
saves composed models to XML).
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager

import mujoco

from robot_agents.errors import ModelError

#: Warnings the library causes on purpose and does not pass on: pieces attached without
#: a prefix, and a robot file's physics options (time step, integrator, solver) and
#: keyframes giving way to the scene's when the robot is attached into a scene.
EXPECTED = ("Attaching a spec with an empty prefix", "Attach conflict")


@contextmanager
def mujoco_messages(where: str) -> Iterator[None]:
    """Route MuJoCo's warnings raised inside the block to Python's ``warnings``."""
    messages: list[str] = []
    if not hasattr(mujoco, "set_mju_user_warning"):  # older MuJoCo: its own handler stays
        with warnings.catch_warnings():
            for text in EXPECTED:
                warnings.filterwarnings("ignore", message=text)
            yield
        return
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(messages.append)
    try:
        with warnings.catch_warnings():
            for text in EXPECTED:
                warnings.filterwarnings("ignore", message=text)
            yield
    finally:
        mujoco.set_mju_user_warning(previous)
        for message in messages:
            if not message.startswith(EXPECTED):
                warnings.warn(f"{where}: MuJoCo: {message}", RuntimeWarning, stacklevel=3)


def compile_spec(spec: mujoco.MjSpec, where: str) -> mujoco.MjModel:
    """Compile ``spec``; compiler errors raise :class:`ModelError` naming ``where``."""
    try:
        with mujoco_messages(where):
            return spec.compile()
    except ValueError as err:
        raise ModelError(f"{where}: MuJoCo could not compile the model: {err}") from None
