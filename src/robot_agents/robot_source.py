"""Name a robot the way a user has it: a registered uid, a model file path (the
two-line robot: uid from the file name), or ``module:Class`` (a class in an importable
module). The command line's ``info``, ``demo`` and ``check``, ``make_env``'s
``robot_uids`` and :class:`~robot_agents.sim.scene.Scene` take all three."""

from __future__ import annotations

import importlib
import math
from pathlib import Path

from robot_agents.agent import Agent
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.model.compose import Attachment
from robot_agents.registry import get_agent, get_piece, list_agents

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


def robot_from_file(
    path: str | Path,
    floating: bool = False,
    up: str = "z",
    gripper: str | None = None,
    at: str | None = None,
    root_body: str | None = None,
    at_axis: str = "z",
) -> type[Agent]:
    """The two-line robot of a model file: everything else derived (see
    :func:`robot_agents.agent.declaration.check`); ``floating`` gives its root a free joint;
    ``up`` (a key of :data:`UP_AXES`) names the file's up axis when it is not z: the robot
    then gets the ``mount_pose`` that turns that axis up (a floating robot's derived
    keyframe and stance follow its mount; a fixed one reaching into the floor is raised to
    rest on it, as with no mount: ``rest_on_floor``). ``gripper``: a built-in piece
    (:func:`~robot_agents.registry.get_piece`) mounted on the file's body or site ``at``,
    under the prefix ``"<gripper>/"`` (the three-line robot: the arm's end effector is
    the piece's ``tcp``); ``at_axis`` (a key of :data:`OUT_AXES`) is the axis of ``at``
    along which the piece points (the frame's z unless the file's flange has the tool
    along another). ``root_body``: the file's top-level body that is the robot, where
    there are several (gym_aloha's two ALOHA arms: ``"vx300s_left"``)."""
    if up not in UP_AXES:
        raise UnknownNameError("robot_from_file", "up axis", str(up), UP_AXES)
    if (gripper is None) != (at is None):
        raise ConfigError(
            f"robot_from_file: a gripper and the body it is mounted at go together; got gripper={gripper!r}, at={at!r}."
        )
    if at_axis not in OUT_AXES:
        raise UnknownNameError("robot_from_file", "axis of the mount frame (at_axis)", str(at_axis), OUT_AXES)
    if at_axis != "z" and gripper is None:
        raise ConfigError(
            f"robot_from_file: at_axis={at_axis!r} points a mounted gripper, and no gripper is mounted (gripper=None)."
        )
    file = Path(path)
    field = "urdf_path" if file.suffix.lower() == ".urdf" else "mjcf_path"
    name = "".join(part.capitalize() for part in file.stem.replace("-", "_").split("_")) or "Robot"
    attributes: dict[str, object] = {"uid": file.stem, field: file}
    if floating:  # (undeclared, a file's free root is fixed with a note)
        attributes["fix_root_link"] = False
    if up != "z":
        attributes["mount_pose"] = (0.0, 0.0, 0.0, *UP_AXES[up])
        attributes["rest_on_floor"] = True  # the mount names the up axis only: a fixed robot still rests on the floor
    if root_body is not None:
        attributes["root_body"] = root_body
    if gripper is not None and at is not None:
        attributes["attachments"] = (
            Attachment(get_piece(gripper), at=at, prefix=f"{gripper}/", quat=OUT_AXES[at_axis]),
        )
        attributes["uid"] = f"{file.stem}+{gripper}"
    return type(name, (Agent,), attributes)


def resolve_robot(
    spec: str,
    floating: bool = False,
    up: str = "z",
    gripper: str | None = None,
    at: str | None = None,
    root_body: str | None = None,
    at_axis: str = "z",
) -> type[Agent]:
    """A robot class from ``spec``: a model file path, ``module:Class``, or a uid (a
    directory or file without a model suffix that happens to share a registered uid's
    name does not hide the uid); ``floating``, ``up``, ``gripper``, ``at``, ``at_axis``
    and ``root_body``: see :func:`robot_from_file` (model files only)."""
    if not isinstance(spec, str) or not spec:
        raise ConfigError(f"resolve_robot: expected a robot uid, a model file path or module:Class, got {spec!r}.")
    path = Path(spec).expanduser()
    registered = spec in list_agents()
    if path.suffix.lower() in MODEL_SUFFIXES or (path.is_file() and not registered):
        return robot_from_file(path, floating, up, gripper, at, root_body, at_axis)
    if floating:
        raise ConfigError(
            f"resolve_robot: floating=True gives a model file's root a free joint, and {spec!r} is a registered uid "
            "or a class (declare fix_root_link = False instead)."
        )
    if up != "z":
        raise ConfigError(
            f"resolve_robot: up={up!r} turns a model file, and {spec!r} is a registered uid or a class "
            "(declare its mount_pose instead)."
        )
    if root_body is not None:
        raise ConfigError(
            f"resolve_robot: root_body={root_body!r} picks a model file's robot, and {spec!r} is a registered uid or a "
            "class (declare its root_body instead)."
        )
    if gripper is not None or at is not None or at_axis != "z":
        raise ConfigError(
            f"resolve_robot: a gripper (gripper={gripper!r}, at={at!r}, at_axis={at_axis!r}) is mounted on a model file, and {spec!r} "
            "is a registered uid or a class (declare its attachments instead)."
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
