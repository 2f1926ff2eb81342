"""A robot's class attribute that looks like a declaration and is none (a misspelt name).

A robot is declared by class attributes (:class:`~robot_agents.agent.definition.AgentDefinition`);
one under another name is an ordinary class attribute, which nothing reads: ``keyframe =
{...}`` or ``sensors = (ra.CameraConfig(...),)`` were ignored without a word, the robot
built with its derived keyframe and no camera. :func:`check_attribute_names` refuses an
attribute of the robot's own classes that either

- is a declaration's name misspelt (as close as ``keyframe`` to ``keyframes``:
  :data:`NAME_CUTOFF`), or
- holds what only a declaration takes (``CameraConfig``, ``Keyframe``, ``ControllerConfig``
  entries, ...: :data:`DECLARED_AS`), whatever its name.

Any other attribute of a user's (constants, helpers, methods) is the user's own.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from typing import Any

from robot_agents.actuators.config import ActuatorConfig
from robot_agents.controllers.base import ControllerConfig
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.keyframe import Keyframe
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.compose import Attachment
from robot_agents.model.materials import FrictionMaterial
from robot_agents.parts.declaration import Part
from robot_agents.sensors.camera import CameraConfig
from robot_agents.sensors.touch import TouchSensorConfig

#: How close (difflib's ratio) a name must be to a declaration's to be taken for it
#: misspelt: ``keyframe`` / ``keyframes`` 0.94, ``control_mode`` / ``control_modes`` 0.96,
#: ``actuator`` / ``actuators`` 0.94, ``fix_root`` / ``fix_root_link`` 0.76 (not taken).
NAME_CUTOFF = 0.8

#: What only a declaration holds, and the declarations that take it.
DECLARED_AS: tuple[tuple[type, str], ...] = (
    (CameraConfig, "cameras"),
    (TouchSensorConfig, "touch_sensors"),
    (ActuatorConfig, "actuators"),
    (Part, "parts"),
    (Attachment, "attachments"),
    (Keyframe, "keyframes"),
    (ControllerConfig, "control_modes"),
    (FrictionMaterial, "link_materials or default_material"),
    (CompilerSettings, "compiler"),
)


#: What a class defines that is not data (a method or property; ``callable`` misses these).
_METHODS = (classmethod, staticmethod, property)


def _entries(value: Any) -> list[Any]:
    """``value`` itself, its items (a tuple or list) or its values (a dict), one level
    down again (a mode's parts)."""
    if isinstance(value, Mapping):
        items = list(value.values())
    elif isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        items = list(value)
    else:
        return [value]
    return [entry for item in items for entry in (item.values() if isinstance(item, Mapping) else (item,))]


def _library_attributes(cls: type) -> dict[str, Any]:
    """Every attribute the library's classes in ``cls``'s bases define (the nearest
    first), and those they only annotate (as ``None``)."""
    found: dict[str, Any] = {}
    for klass in cls.__mro__:
        if klass.__module__.startswith("robot_agents.agent") or klass is object:
            for attribute in getattr(klass, "__annotations__", {}):
                found.setdefault(attribute, None)
            for attribute, value in vars(klass).items():
                found.setdefault(attribute, value)
    return found


def check_attribute_names(cls: type, declared: Sequence[str]) -> None:
    """Refuse a class attribute of ``cls`` (or of its bases outside the library) that is
    misspelt from one of ``declared``, holds what only a declaration takes, or hides one
    of the library's methods or properties under plain data (``control_mode = {...}``
    hid :attr:`Agent.control_mode`): :class:`UnknownNameError` or :class:`ConfigError`
    naming the class, the attribute and the declaration meant (see the module's doc)."""
    library = _library_attributes(cls)
    where = f"{cls.__name__} (a class attribute)"
    for klass in cls.__mro__:
        if klass.__module__.startswith("robot_agents.agent") or klass is object:
            continue
        for attribute, value in vars(klass).items():
            if attribute.startswith("_") or callable(value) or isinstance(value, _METHODS):
                continue
            if attribute in library:
                behaviour = library[attribute]
                if attribute not in declared and (callable(behaviour) or isinstance(behaviour, _METHODS)):
                    sort = "property" if isinstance(behaviour, property) else "method"
                    hiding = f"{cls.__name__} (a class attribute hiding the Agent's {sort} {attribute!r})"
                    raise UnknownNameError(hiding, "declaration", attribute, declared)
                continue
            if difflib.get_close_matches(attribute, declared, n=1, cutoff=NAME_CUTOFF):
                raise UnknownNameError(where, "declaration", attribute, declared)
            for kind, declaration in DECLARED_AS:
                if any(isinstance(entry, kind) for entry in _entries(value)):
                    raise ConfigError(
                        f"{cls.__name__}.{attribute}: holds {kind.__name__} entries, and {attribute!r} is no "
                        f"declaration, so nothing would read it; {kind.__name__} entries are declared as "
                        f"{declaration}."
                    )
