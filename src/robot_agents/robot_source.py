"""Name a robot the way a user has it: a registered uid, a model file path (the
two-line robot: uid from the file name), or ``module:Class`` (a class in an importable
module). The command line's ``info``, ``demo`` and ``check``, ``make_env``'s
``robot_uids`` and :class:`~robot_agents.sim.scene.Scene` take all three."""

from __future__ import annotations

import functools
import importlib
import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Concatenate, ParamSpec, TypeVar

from robot_agents.agent import Agent
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.keywords import checked_keywords
from robot_agents.model.compose import Attachment
from robot_agents.registry import get_agent, get_piece, is_known_uid
from robot_agents.robots.catalog import BUILTIN_PIECES
from robot_agents.validation import check_bool

MODEL_SUFFIXES = (".urdf", ".xml", ".mjcf")


#: The mount orientation ``(w, x, y, z)`` that stands a file drawn with this axis up:
#: ``"y"`` turns +90 deg about x (the file's +y becomes the world's +z; some URDFs, e.g.
#: pybullet's ``laikago_toes.urdf``), ``"x"`` -90 deg about y (+x becomes +z).
UP_AXES: dict[str, tuple[float, float, float, float]] = {
    "z": (1.0, 0.0, 0.0, 0.0),
    "y": (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0),
    "x": (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0),
}

#: The piece's orientation ``(w, x, y, z)`` in its ``at`` frame that points the piece's z
#: axis (out of its mount: every built-in piece's tool direction) along this axis of that
#: frame: ``"z"`` as the frame is (a ROS ``tool0``), ``"x"`` +90 deg about y (a frame
#: with the tool along x: a ROS-Industrial ``flange``, robosuite's Spot arm's
#: ``right_hand``), ``"y"`` -90 deg about x, and the negated axes.
OUT_AXES: dict[str, tuple[float, float, float, float]] = {
    "z": (1.0, 0.0, 0.0, 0.0),
    "-z": (0.0, 1.0, 0.0, 0.0),
    "x": (math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0),
    "-x": (math.sqrt(0.5), 0.0, -math.sqrt(0.5), 0.0),
    "y": (math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0),
    "-y": (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0),
}


@checked_keywords
@dataclass(frozen=True)
class FileOptions:
    """How a model file becomes a robot: the options :func:`robot_from_file` and
    :func:`resolve_robot` take after the file (the command line's ``--floating``, ``--up``,
    ``--gripper``, ``--at``, ``--root-body`` and ``--at-axis``). This class is their one
    list: both functions take its fields as keywords (``floating`` and the others in this
    order also positionally), with its defaults.

    Attributes:
        floating: the file's root gets a free joint (else it is fixed, with a note when the
            file gives it a free one).
        up: the file's up axis, a key of :data:`UP_AXES`; not ``"z"``: the robot gets the
            ``mount_pose`` that turns that axis up (a floating robot's derived keyframe and
            stance follow its mount; a fixed one reaching into the floor is raised to rest
            on it, as with no mount: ``rest_on_floor``).
        gripper: a built-in piece (:func:`~robot_agents.registry.get_piece`) mounted on the
            file's body or site ``at``, under the prefix ``"<gripper>/"`` (the three-line
            robot: the arm's end effector is the piece's ``tcp``); given with ``at``.
        at: the file's body or site the ``gripper`` is mounted on (a flange).
        root_body: the file's top-level body that is the robot, where there are several
            (gym_aloha's two ALOHA arms: ``"vx300s_left"``).
        at_axis: the axis of ``at`` along which the piece points, a key of
            :data:`OUT_AXES` (the frame's z unless the file's flange has the tool along
            another); only with a ``gripper``.
    """

    floating: bool = field(
        default=False,
        metadata={"does": "gives a model file's root a free joint", "instead": "declare fix_root_link = False"},
    )
    up: str = field(default="z", metadata={"does": "turns a model file", "instead": "declare its mount_pose"})
    gripper: str | None = field(
        default=None, metadata={"does": "is mounted on a model file", "instead": "declare its attachments"}
    )
    at: str | None = field(
        default=None, metadata={"does": "names a model file's mount frame", "instead": "declare its attachments"}
    )
    root_body: str | None = field(
        default=None, metadata={"does": "picks a model file's robot", "instead": "declare its root_body"}
    )
    at_axis: str = field(
        default="z", metadata={"does": "points a gripper mounted on a model file", "instead": "declare its attachments"}
    )

    def check(self, where: str) -> None:
        """Each option of its type and, for the named ones, a name there is
        (:class:`ConfigError` or :class:`UnknownNameError` naming ``where``)."""
        check_bool(self.floating, "floating", where)
        for name in ("gripper", "at", "root_body"):
            value = getattr(self, name)
            if value is not None and (not isinstance(value, str) or not value):
                raise ConfigError(f"{where}: expected {name} to be a non-empty name (str) or None, got {value!r}.")
        if not isinstance(self.up, str) or self.up not in UP_AXES:
            raise UnknownNameError(where, "up axis", str(self.up), UP_AXES)
        if not isinstance(self.at_axis, str) or self.at_axis not in OUT_AXES:
            raise UnknownNameError(where, "axis of the mount frame (at_axis)", str(self.at_axis), OUT_AXES)
        if self.gripper is not None and self.gripper not in BUILTIN_PIECES:  # named before the file loads
            raise UnknownNameError(where, "gripper (a built-in piece)", self.gripper, BUILTIN_PIECES)


_S = TypeVar("_S")
_P = ParamSpec("_P")


def _taking(
    options: Callable[_P, FileOptions],
) -> Callable[[Callable[[_S, FileOptions], type[Agent]]], Callable[Concatenate[_S, _P], type[Agent]]]:
    """``func(source, options)`` called as ``func(source, <the fields of options as
    arguments>)``: the options' one signature is :class:`FileOptions`'s (its
    ``inspect.signature`` and ``help`` show them too)."""

    accepted = inspect.signature(options)

    def decorate(func: Callable[[_S, FileOptions], type[Agent]]) -> Callable[Concatenate[_S, _P], type[Agent]]:
        where = func.__name__

        @functools.wraps(func)
        def call(source: _S, /, *args: _P.args, **kwargs: _P.kwargs) -> type[Agent]:
            for name in kwargs:  # a misspelt option is named with the close ones, not a TypeError
                if name not in accepted.parameters:
                    raise UnknownNameError(where, "option", name, accepted.parameters)
            try:
                accepted.bind(*args, **kwargs)
            except TypeError as err:  # too many positional options, or one given twice
                raise ConfigError(
                    f"{where}: {err}; the options after the {first.name} are {', '.join(accepted.parameters)}, got "
                    f"{args!r} and {kwargs!r}."
                ) from None
            return func(source, options(*args, **kwargs))

        first = next(iter(inspect.signature(func).parameters.values()))
        call.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
            [first.replace(kind=inspect.Parameter.POSITIONAL_ONLY), *accepted.parameters.values()],
            return_annotation=inspect.signature(func).return_annotation,
        )
        return call

    return decorate


def _file_robot(path: str | Path, options: FileOptions, where: str) -> type[Agent]:
    """The robot class of the model file ``path`` with ``options`` (checked here; errors
    name ``where``)."""
    options.check(where)
    gripper, at, at_axis = options.gripper, options.at, options.at_axis
    if (gripper is None) != (at is None):
        raise ConfigError(
            f"{where}: a gripper and the body it is mounted at go together; got gripper={gripper!r}, at={at!r} "
            "(at: the file's body or site the gripper is mounted on, its flange; --at on the command line)."
        )
    if at_axis != "z" and gripper is None:
        raise ConfigError(
            f"{where}: at_axis={at_axis!r} points a mounted gripper, and no gripper is mounted (gripper=None)."
        )
    if not isinstance(path, (str, Path)) or not str(path):
        raise ConfigError(f"{where}: expected a model file path (str or pathlib.Path), got {path!r}.")
    file = Path(path)
    field_name = "urdf_path" if file.suffix.lower() == ".urdf" else "mjcf_path"
    name = "".join(part.capitalize() for part in file.stem.replace("-", "_").split("_")) or "Robot"
    attributes: dict[str, object] = {"uid": file.stem, field_name: file}
    if options.floating:  # (undeclared, a file's free root is fixed with a note)
        attributes["fix_root_link"] = False
    if options.up != "z":
        attributes["mount_pose"] = (0.0, 0.0, 0.0, *UP_AXES[options.up])
        attributes["rest_on_floor"] = True  # the mount names the up axis only: a fixed robot still rests on the floor
    if options.root_body is not None:
        attributes["root_body"] = options.root_body
    if gripper is not None and at is not None:
        attributes["attachments"] = (
            Attachment(get_piece(gripper), at=at, prefix=f"{gripper}/", quat=OUT_AXES[at_axis]),
        )
        attributes["uid"] = f"{file.stem}+{gripper}"
    return type(name, (Agent,), attributes)


@_taking(FileOptions)
def robot_from_file(path: str | Path, options: FileOptions) -> type[Agent]:
    """The two-line robot of a model file: everything else derived (see
    :func:`robot_agents.agent.declaration.check`). The options after ``path`` are
    :class:`FileOptions`' fields: ``floating=False, up="z", gripper=None, at=None,
    root_body=None, at_axis="z"`` (e.g. ``robot_from_file("ur5.urdf", gripper="robotiq_2f85",
    at="tool0")``, ``robot_from_file("ant.xml", floating=True)``).

    Raises:
        ConfigError: an option of the wrong type, or a gripper without ``at`` (or the other
            way round), or an ``at_axis`` without a gripper.
        UnknownNameError: an ``up``, ``at_axis`` or ``gripper`` that does not exist.
    """
    return _file_robot(path, options, "robot_from_file")


@_taking(FileOptions)
def resolve_robot(spec: str, options: FileOptions) -> type[Agent]:
    """A robot class from ``spec``: a model file path, ``module:Class``, or a uid (a
    directory or file without a model suffix that happens to share a registered uid's
    name does not hide the uid). The options after ``spec`` (model files only) are
    :class:`FileOptions`' fields, as :func:`robot_from_file` takes them.

    Raises:
        ConfigError: ``spec`` is not a non-empty string, an option is given for a
            registered uid or a class, or ``module:Class`` names no Agent subclass.
        UnknownNameError: no registered robot has the uid ``spec`` (close names listed).
    """
    if not isinstance(spec, str) or not spec:
        raise ConfigError(f"resolve_robot: expected a robot uid, a model file path or module:Class, got {spec!r}.")
    path = Path(spec).expanduser()
    registered = is_known_uid(spec)
    if path.suffix.lower() in MODEL_SUFFIXES or (path.is_file() and not registered):
        return _file_robot(path, options, "resolve_robot")
    options.check("resolve_robot")
    for option in fields(options):
        value = getattr(options, option.name)
        if value != option.default:
            raise ConfigError(
                f"resolve_robot: {option.name}={value!r} {option.metadata['does']}, and {spec!r} is a registered uid "
                f"or a class ({option.metadata['instead']} instead)."
            )
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
