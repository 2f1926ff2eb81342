"""A declaration class's constructor that names a misspelt keyword with the close ones.

The public declaration classes (``PDActuator``, ``Keyframe``, ``Arm``, ``CameraConfig``,
...) are dataclasses; Python's own answer to ``ra.PDActuator(joint=("j",), ...)`` is a
``TypeError`` (``__init__() got an unexpected keyword argument 'joint'``) that names
neither the fields there are nor the one meant. :func:`checked_keywords` makes it an
:class:`~robot_agents.errors.UnknownNameError` that does (``PDActuator: unknown field
'joint'. Did you mean 'joints'? Available: ...``), and too many positional arguments or
one given twice a :class:`~robot_agents.errors.ConfigError` listing the fields.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import Any, TypeVar

from robot_agents.errors import ConfigError, UnknownNameError

T = TypeVar("T", bound=type)


def checked_keywords(cls: T) -> T:
    """``cls`` (a dataclass, decorated after ``@dataclass``) with its ``__init__`` checking
    the arguments' names first; a call it accepts runs the dataclass's own, unchanged."""
    init: Callable[..., None] = vars(cls)["__init__"]  # the dataclass's own (each class has one)
    signature = inspect.signature(init)
    fields = [name for name in signature.parameters if name != "self"]

    @functools.wraps(init)
    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        for name in kwargs:
            if name not in signature.parameters or name == "self":
                raise UnknownNameError(cls.__name__, "field", name, fields)
        try:
            signature.bind(self, *args, **kwargs)
        except TypeError as err:  # too many positional arguments, one given twice, or a required one missing
            raise ConfigError(f"{cls.__name__}: {err}; its fields are {', '.join(fields)}.") from None
        init(self, *args, **kwargs)

    cls.__init__ = __init__  # type: ignore[misc]
    return cls
