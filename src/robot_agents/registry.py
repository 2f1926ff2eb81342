"""Robots registered by string id."""

from __future__ import annotations

from typing import TYPE_CHECKING, TypeVar

from robot_agents.errors import RegistryError, UnknownNameError

if TYPE_CHECKING:
    from robot_agents.agent import Agent

AgentT = TypeVar("AgentT", bound="type[Agent]")

_REGISTRY: dict[str, type[Agent]] = {}


def register_agent(uid: str | None = None, *, override: bool = False):  # type: ignore[no-untyped-def]
    """Class decorator that registers an :class:`~robot_agents.agent.Agent` subclass.

    Args:
        uid: the id to register under; defaults to the class attribute ``uid``.
        override: replace an agent already registered under that id.

    Raises:
        RegistryError: the id is taken (and ``override`` is false), or the class is not
            an Agent subclass, or it has no uid.
    """

    def decorator(cls: AgentT) -> AgentT:
        from robot_agents.agent import Agent

        if not (isinstance(cls, type) and issubclass(cls, Agent)):
            raise RegistryError(f"register_agent: expected a subclass of robot_agents.Agent, got {cls!r}.")
        key = uid if uid is not None else getattr(cls, "uid", None)
        if not isinstance(key, str) or not key:
            raise RegistryError(
                f"register_agent({cls.__name__}): expected a non-empty string uid (argument or class attribute), got {key!r}."
            )
        if key in _REGISTRY and not override and _REGISTRY[key] is not cls:
            raise RegistryError(
                f"register_agent({cls.__name__}): uid {key!r} is already registered to "
                f"{_REGISTRY[key].__module__}.{_REGISTRY[key].__qualname__}; pass override=True to replace it."
            )
        cls.validate_definition()
        if uid is not None and cls.uid != uid:
            cls.uid = uid
        _REGISTRY[key] = cls
        return cls

    return decorator


def get_agent(uid: str) -> type[Agent]:
    """The agent class registered under ``uid``.

    Raises:
        UnknownNameError: no agent has that uid; the message lists close matches.
    """
    _ensure_builtin_robots()
    try:
        return _REGISTRY[uid]
    except KeyError:
        raise UnknownNameError("get_agent", "robot uid", str(uid), _REGISTRY) from None


def list_agents() -> list[str]:
    """Registered robot uids, sorted."""
    _ensure_builtin_robots()
    return sorted(_REGISTRY)


def unregister_agent(uid: str) -> type[Agent]:
    """Remove ``uid`` from the registry and return its class."""
    _ensure_builtin_robots()
    try:
        return _REGISTRY.pop(uid)
    except KeyError:
        raise UnknownNameError("unregister_agent", "robot uid", str(uid), _REGISTRY) from None


def _ensure_builtin_robots() -> None:
    import robot_agents.robots  # noqa: F401  (registers the built-in zoo on first import)
