"""Compile an ``MjSpec`` with MuJoCo's messages kept in the library.

MuJoCo reports compiler warnings by printing them and appending them to
``MUJOCO_LOG.TXT`` in the working directory. :func:`compile_spec` passes them on as
the library's notes instead (:func:`robot_agents.notes.mujoco_messages`: nothing is
written to the user's directory) and drops the one about attaching pieces without a
name prefix, which the library does on purpose (composed robots keep their upstream
joint and body names; the library never saves composed models to XML).
"""

from __future__ import annotations

import mujoco

from robot_agents.errors import ModelError
from robot_agents.notes import mujoco_messages


def compile_spec(spec: mujoco.MjSpec, where: str) -> mujoco.MjModel:
    """Compile ``spec``; compiler errors raise :class:`ModelError` naming ``where``."""
    try:
        with mujoco_messages(where):
            return spec.compile()
    except ValueError as err:
        raise ModelError(f"{where}: MuJoCo could not compile the model: {err}") from None
