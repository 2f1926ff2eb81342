"""Model files read once per robot check.

Checking a robot reads its model file and each mounted piece's more than once: the
build, the piece names an inferred robot tells from its own (``_piece_names``), the
robot without its pieces (a file gripper beside a mounted one), the rebuild after a
compile fallback. Inside :func:`one_read_per_file` (one :func:`~robot_agents.agent.
declaration.check` call, pieces' checks included) :func:`load_spec` parses a file once
per compiler settings and hands out copies; outside it, every call reads the file.
Nothing outlives the scope, so a file edited on disk between two checks (a new class
of the same file, a rerun) is read again: only reads within one check, which must
agree with each other anyway, are shared.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

import mujoco

from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.loading import load_model_spec

_LOADED: ContextVar[dict[tuple[Path, CompilerSettings], mujoco.MjSpec] | None] = ContextVar(
    "robot_agents_loaded_specs", default=None
)


@contextmanager
def one_read_per_file() -> Iterator[None]:
    """Share :func:`load_spec`'s reads for the block (nested blocks join the outer one)."""
    if _LOADED.get() is not None:
        yield
        return
    token = _LOADED.set({})
    try:
        yield
    finally:
        _LOADED.reset(token)


def load_spec(path: str | os.PathLike[str], compiler: CompilerSettings) -> mujoco.MjSpec:
    """:func:`~robot_agents.model.loading.load_model_spec`'s spec of ``path`` with
    ``compiler``: a fresh one, to change at will (a copy of the block's first read
    inside :func:`one_read_per_file`; its notes are given at that read)."""
    loaded = _LOADED.get()
    if loaded is None:
        return load_model_spec(path, compiler)
    key = (Path(path).expanduser().resolve(), compiler)
    first = loaded.get(key)
    if first is None:
        first = loaded[key] = load_model_spec(path, compiler)
    return first.copy()
