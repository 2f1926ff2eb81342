"""Joint (and body) name patterns: regular expressions that must each match a name.

A declaration names joints by pattern (``"panda_joint[1-7]"``, ``".*_finger_joint"``):
the whole name must match (``re.fullmatch``). Every pattern must match at least one
name and, where a declaration claims joints exclusively, no name may be claimed twice;
errors list what is available.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from robot_agents.errors import ConfigError, UnknownNameError

#: One pattern or several; a plain name is a pattern that matches itself.
Patterns = str | tuple[str, ...]


def as_patterns(value: Patterns | Sequence[str], where: str) -> tuple[str, ...]:
    """``value`` as a non-empty tuple of valid regular expressions."""
    try:
        patterns = (value,) if isinstance(value, str) else tuple(value)
    except TypeError:  # not a sequence (a number, None)
        patterns = ()
    if not patterns or not all(isinstance(p, str) and p for p in patterns):
        raise ConfigError(f"{where}: expected a joint name pattern or a tuple of them, got {value!r}.")
    for pattern in patterns:
        try:
            re.compile(pattern)
        except re.error as err:
            raise ConfigError(f"{where}: {pattern!r} is not a valid regular expression ({err}).") from None
    return patterns


def match(patterns: Patterns | Sequence[str], names: Sequence[str], where: str, kind: str = "joint") -> list[int]:
    """Indices into ``names`` matched by any of ``patterns`` (full match), in ``names`` order.

    Raises:
        UnknownNameError: a pattern matches nothing (the message lists ``names``).
    """
    chosen: set[int] = set()
    for pattern in as_patterns(patterns, where):
        compiled = re.compile(pattern)
        hits = [i for i, name in enumerate(names) if compiled.fullmatch(name)]
        if not hits:
            raise UnknownNameError(where, f"{kind} (pattern)", pattern, names)
        chosen.update(hits)
    return sorted(chosen)


def claim(
    groups: Sequence[tuple[str, Patterns | Sequence[str]]], names: Sequence[str], where: str, kind: str = "joint"
) -> list[list[int]]:
    """Resolve several labelled pattern groups that claim names exclusively.

    Returns the matched indices of each group; raises :class:`ConfigError` when two
    groups claim the same name (naming both)."""
    owner: dict[int, str] = {}
    result: list[list[int]] = []
    for label, patterns in groups:
        hits = match(patterns, names, f"{where} {label}", kind)
        for i in hits:
            if i in owner:
                raise ConfigError(f"{where}: {kind} {names[i]!r} is claimed by both {owner[i]} and {label}.")
            owner[i] = label
        result.append(hits)
    return result


def prefixed(patterns: Patterns | Sequence[str], prefix: str) -> tuple[str, ...]:
    """Patterns for the same names after a ``prefix`` was put in front of them."""
    if not prefix:
        return as_patterns(patterns, "prefixed")
    return tuple(re.escape(prefix) + f"(?:{p})" for p in as_patterns(patterns, "prefixed"))
