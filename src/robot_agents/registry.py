"""Robots registered by string id.

User robots register with :func:`register_agent`; built-in ones are listed in
:mod:`robot_agents.robots.catalog` and imported (registered and checked) on first use,
so importing the library loads no robot model.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, TypeVar

from robot_agents.errors import ConfigError, RegistryError, UnknownNameError
from robot_agents.robots.catalog import BUILTIN_ALIASES, BUILTIN_PIECES, BUILTIN_ROBOTS

if TYPE_CHECKING:
    from robot_agents.agent import Agent

AgentT = TypeVar("AgentT", bound="type[Agent]")

_REGISTRY: dict[str, type[Agent]] = {}
#: Built-in uids that were unregistered in this process.
_REMOVED: set[str] = set()


def register_agent(uid: str | type | None = None, *, override: bool = False):  # type: ignore[no-untyped-def]
    """Class decorator that registers an :class:`~robot_agents.agent.Agent` subclass:
    ``@register_agent()``, ``@register_agent("my_uid")``, or bare ``@register_agent``;
    ``register_agent(MyRobot)`` registers a class defined elsewhere (and returns it).

    Args:
        uid: the id to register under; defaults to the class attribute ``uid``. A class
            here is the class to register, under its own ``uid``.
        override: replace an agent already registered under that id.

    Raises:
        RegistryError: the id is taken (and ``override`` is false), or the class is not
            an Agent subclass, or it has no uid.
    """

    def decorator(cls: AgentT) -> AgentT:
        from robot_agents.agent import Agent

        if not (isinstance(cls, type) and issubclass(cls, Agent)):
            raise RegistryError(f"register_agent: expected a subclass of robot_agents.Agent, got {cls!r}.")
        key = uid if isinstance(uid, str) else getattr(cls, "uid", None)
        if not isinstance(key, str) or not key:
            raise RegistryError(
                f"register_agent({cls.__name__}): expected a non-empty string uid (argument or class attribute), got {key!r}."
            )
        if key in _REGISTRY and not override and _REGISTRY[key] is not cls:
            raise RegistryError(
                f"register_agent({cls.__name__}): uid {key!r} is already registered to "
                f"{_REGISTRY[key].__module__}.{_REGISTRY[key].__qualname__}; pass override=True to replace it."
            )
        cls.check()
        if isinstance(uid, str) and cls.uid != uid:
            cls.uid = uid
        _REGISTRY[key] = cls
        _REMOVED.discard(key)
        return cls

    if isinstance(uid, type):  # @register_agent without parentheses, or register_agent(cls)
        return decorator(uid)
    if uid is not None and not isinstance(uid, str):
        raise RegistryError(f"register_agent: expected a uid string or an Agent subclass, got {uid!r}.")
    return decorator


def _builtin(uid: str) -> type[Agent] | None:
    """Import the module of built-in robot ``uid`` (registering it) and return its class."""
    if uid in _REMOVED or uid not in BUILTIN_ROBOTS:
        return None
    module, name = BUILTIN_ROBOTS[uid].split(":")
    cls: type[Agent] = getattr(importlib.import_module(module), name)
    _REGISTRY.setdefault(uid, cls)
    return cls


def _available() -> list[str]:
    return sorted(set(_REGISTRY) | (set(BUILTIN_ROBOTS) - _REMOVED))


def get_agent(uid: str) -> type[Agent]:
    """The agent class registered under ``uid``, or under the uid that ``uid`` is an
    alias of (:data:`~robot_agents.robots.catalog.BUILTIN_ALIASES`: ManiSkill's
    ``googlerobot`` is our ``google_robot``; a robot registered under the alias itself
    comes first).

    Raises:
        UnknownNameError: no agent has that uid; the message lists close matches.
    """
    if isinstance(uid, str):
        found = _REGISTRY.get(uid) or _builtin(uid)
        if found is None and uid in BUILTIN_ALIASES:
            target = BUILTIN_ALIASES[uid]
            found = _REGISTRY.get(target) or _builtin(target)
        if found is not None:
            return found
    raise UnknownNameError("get_agent", "robot uid", str(uid), _available())


def is_known_uid(uid: str) -> bool:
    """Whether :func:`get_agent` finds ``uid``: a registered uid or an alias of one."""
    available = _available()
    return uid in available or BUILTIN_ALIASES.get(uid) in available


def get_piece(name: str) -> type[Agent]:
    """The built-in piece called ``name`` (:data:`~robot_agents.robots.catalog.BUILTIN_PIECES`:
    a gripper or tool to mount with :class:`~robot_agents.model.compose.Attachment`).

    Raises:
        UnknownNameError: no built-in piece has that name; the message lists close matches.
    """
    if not isinstance(name, str) or name not in BUILTIN_PIECES:
        raise UnknownNameError("get_piece", "piece", str(name), sorted(BUILTIN_PIECES))
    module, attribute = BUILTIN_PIECES[name].split(":")
    piece: type[Agent] = getattr(importlib.import_module(module), attribute)
    return piece


def agent_class(robot: object, where: str) -> type[Agent]:
    """``robot`` as an Agent class: a string as the command line reads it
    (:func:`~robot_agents.robot_source.resolve_robot`: a registered uid, a model file
    path, or ``module:Class``), an Agent subclass as it is; :class:`ConfigError`
    (naming ``where``) for anything else."""
    from robot_agents.agent import Agent  # (the agent package imports this module)
    from robot_agents.robot_source import resolve_robot

    cls = resolve_robot(robot) if isinstance(robot, str) else robot
    if not (isinstance(cls, type) and issubclass(cls, Agent)):
        raise ConfigError(
            f"{where}: expected a robot uid, a model file path, module:Class or an Agent subclass, got {robot!r}."
        )
    return cls


def list_agents() -> list[str]:
    """Registered robot uids (built-in and user), sorted."""
    return _available()


def unregister_agent(uid: str) -> type[Agent]:
    """Remove ``uid`` from the registry and return its class."""
    cls = get_agent(uid) if isinstance(uid, str) and uid in _available() else None
    if cls is None:
        raise UnknownNameError("unregister_agent", "robot uid", str(uid), _available())
    _REGISTRY.pop(uid, None)
    if uid in BUILTIN_ROBOTS:
        _REMOVED.add(uid)
    return cls
