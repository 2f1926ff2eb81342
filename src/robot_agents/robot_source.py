"""Name a robot the way a user has it: a registered uid, a model file path (the
two-line robot: uid from the file name), or ``module:Class`` (a class in an importable
module). The command line's ``info``, ``demo`` and ``check``, ``make_env``'s
``robot_uids`` and :class:`~robot_agents.sim.scene.Scene` take all three."""

from __future__ import annotations

import importlib
from pathlib import Path

from robot_agents.agent import Agent
from robot_agents.errors import ConfigError
from robot_agents.registry import get_agent, list_agents

MODEL_SUFFIXES = (".urdf", ".xml", ".mjcf")


def robot_from_file(path: str | Path, floating: bool = False) -> type[Agent]:
    """The two-line robot of a model file: everything else derived (see
    :func:`robot_agents.agent.declaration.check`); ``floating`` gives its root a free joint."""
    file = Path(path)
    field = "urdf_path" if file.suffix.lower() == ".urdf" else "mjcf_path"
    name = "".join(part.capitalize() for part in file.stem.replace("-", "_").split("_")) or "Robot"
    return type(name, (Agent,), {"uid": file.stem, field: file, "fix_root_link": not floating})


def resolve_robot(spec: str, floating: bool = False) -> type[Agent]:
    """A robot class from ``spec``: a model file path, ``module:Class``, or a uid (a
    directory or file without a model suffix that happens to share a registered uid's
    name does not hide the uid)."""
    if not isinstance(spec, str) or not spec:
        raise ConfigError(f"resolve_robot: expected a robot uid, a model file path or module:Class, got {spec!r}.")
    path = Path(spec).expanduser()
    registered = spec in list_agents()
    if path.suffix.lower() in MODEL_SUFFIXES or (path.is_file() and not registered):
        return robot_from_file(path, floating)
    if ":" in spec and not registered:
        module_name, _, class_name = spec.partition(":")
        try:
            module = importlib.import_module(module_name)
        except ImportError as err:
            raise ConfigError(f"resolve_robot: cannot import module {module_name!r} of {spec!r}: {err}.") from None
        cls = getattr(module, class_name, None)
        if not (isinstance(cls, type) and issubclass(cls, Agent)):
            available = [n for n, v in vars(module).items() if isinstance(v, type) and issubclass(v, Agent)]
            raise ConfigError(
                f"resolve_robot: {spec!r} is not an Agent subclass in {module_name!r}; robot classes there: {available}."
            )
        return cls
    return get_agent(spec)
