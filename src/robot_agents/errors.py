"""The library's exceptions.

Every error raised for bad user input derives from :class:`RobotAgentsError` and
says *where* it happened, *what* was expected, *what* was given and, for name
look-ups, *what* is available (with the closest names first).
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping


class RobotAgentsError(Exception):
    """Base class of every exception raised by robot_agents."""


class UnknownNameError(RobotAgentsError, KeyError):
    """A name (robot uid, control mode, keyframe, joint, ...) that does not exist."""

    def __init__(
        self, where: str, kind: str, given: str, available: Iterable[str], aliases: Mapping[str, str] | None = None
    ) -> None:
        """``aliases``: other names of available ones (alias -> name), listed and
        suggested beside them (``'home' (= 'default')``)."""
        self.where = where
        self.kind = kind
        self.given = given
        self.aliases = dict(aliases or {})
        self.available = sorted([*available, *self.aliases])
        self.suggestions = close_names(given, self.available) if isinstance(given, str) else []
        super().__init__(self.message)

    @property
    def message(self) -> str:
        hint = did_you_mean(self.given, self.available)
        avail = (
            ", ".join(repr(a) + (f" (= {self.aliases[a]!r})" if a in self.aliases else "") for a in self.available)
            if self.available
            else "(none)"
        )
        return f"{self.where}: unknown {self.kind} {self.given!r}.{hint} Available: {avail}."

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self.message


class RegistryError(RobotAgentsError):
    """Registering a uid that is taken, or a class that is not an Agent."""


class ActionError(RobotAgentsError, ValueError):
    """An action of the wrong shape, dtype, or with non-finite values."""


class StateError(RobotAgentsError, ValueError):
    """A state, qpos, qvel or keyframe of the wrong size or with bad values."""


class ModelError(RobotAgentsError):
    """A robot or scene model file that is missing, malformed or unsupported."""


class MediaError(RobotAgentsError, ValueError):
    """Frames or settings a video / image writer cannot use."""


class ConfigError(RobotAgentsError, ValueError):
    """An invalid robot, controller or environment configuration."""


class PhysicsError(RobotAgentsError, RuntimeError):
    """The simulation became unstable (MuJoCo reset an env) and the env was asked to raise."""


class RenderError(RobotAgentsError, RuntimeError):
    """Offscreen rendering is unavailable: no usable OpenGL backend (EGL / OSMesa)."""


def did_you_mean(given: object, available: Iterable[str]) -> str:
    """`` Did you mean 'a', 'b'?`` naming the names in ``available`` closest to ``given``
    (:func:`close_names`; empty when none is close or ``given`` is not a string): the
    hint every message about a name not among the choices ends with."""
    names = close_names(given, available) if isinstance(given, str) else []
    return f" Did you mean {', '.join(repr(s) for s in names)}?" if names else ""


def close_names(given: str, available: Iterable[str], n: int = 3) -> list[str]:
    """The up to ``n`` names in ``available`` closest to ``given`` (best first)."""
    names = list(available)
    lowered = given.lower()
    same = [a for a in names if a.lower() == lowered]  # only the case differs: the closest
    matches = difflib.get_close_matches(given, names, n=n, cutoff=0.5)
    if not matches:  # a part of a name or the other way round, the nearest in length first
        matches = sorted(
            (a for a in names if lowered in a.lower() or a.lower() in lowered), key=lambda a: abs(len(a) - len(given))
        )
    return list(dict.fromkeys(same + matches))[:n]
