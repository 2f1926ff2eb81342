"""Compose robot models from pieces: attach one model onto another at a named site or
body, with a name prefix (an arm plus a gripper, a hand or a camera housing; a floating
mount plus a gripper). Uses ``MjSpec`` attachment, so the child's joints, actuators,
equalities and default classes come along, renamed with the prefix.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from robot_agents.errors import ConfigError, ModelError, UnknownNameError
from robot_agents.keywords import checked_keywords
from robot_agents.notes import mujoco_messages
from robot_agents.validation import check_quat, check_vector


@checked_keywords
@dataclass(frozen=True)
class Attachment:
    """A piece (another :class:`~robot_agents.agent.Agent` class, usually unregistered)
    mounted on this robot.

    Attributes:
        piece: the class whose model, actuators, parts, sensors and default keyframe
            the piece brings.
        at: the body or site of the parent model it is fixed to.
        prefix: put in front of every name of the piece (``""``: names as they are,
            which must then not clash with the parent's).
        pos, quat: the piece's root pose in the ``at`` frame (m; ``w, x, y, z``).
    """

    piece: Any
    at: str
    prefix: str = ""
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        from robot_agents.agent.agent import Agent

        if not (isinstance(self.piece, type) and issubclass(self.piece, Agent)):
            raise ConfigError(f"Attachment: expected an Agent subclass as the piece, got {self.piece!r}.")
        if not isinstance(self.at, str) or not self.at:
            raise ConfigError(
                f"Attachment({self.piece.__name__}): expected 'at' to name a body or site, got {self.at!r}."
            )
        where = f"Attachment({self.piece.__name__})"
        object.__setattr__(self, "pos", check_vector(self.pos, 3, "(x, y, z) (m)", f"{where}.pos"))
        object.__setattr__(self, "quat", check_quat(self.quat, f"{where}.quat"))


def attach(parent: mujoco.MjSpec, child: mujoco.MjSpec, attachment: Attachment, where: str) -> None:
    """Fix ``child``'s root body onto ``parent`` at ``attachment.at`` (a body, else a site)."""
    root = child.worldbody.first_body()
    if root is None:
        raise ModelError(f"{where}: the piece {attachment.piece.__name__} has no body to attach.")
    for joint in list(root.joints):
        if joint.type == mujoco.mjtJoint.mjJNT_FREE:
            child.delete(joint)  # a mounted piece is fixed to its parent
    pos, quat = np.array(attachment.pos), np.array(attachment.quat)
    body = parent.body(attachment.at)
    if body is None:
        site = parent.site(attachment.at)
        if site is None:
            names = [b.name for b in parent.bodies if b.name] + [s.name for s in parent.sites if s.name]
            raise UnknownNameError(
                f"{where} Attachment({attachment.piece.__name__})", "body or site", attachment.at, names
            )
        body = site.parent
        site_pos, site_quat = np.array(site.pos, dtype=np.float64), np.array(site.quat, dtype=np.float64)
        mujoco.mju_normalize4(site_quat)
        rotated = np.empty(3)
        mujoco.mju_rotVecQuat(rotated, pos, site_quat)
        composed = np.empty(4)
        mujoco.mju_mulQuat(composed, site_quat, quat)
        pos, quat = site_pos + rotated, composed
    _check_name_clashes(parent, child, attachment, where)
    frame = body.add_frame(pos=list(pos), quat=list(quat))
    try:
        with mujoco_messages(where):
            frame.attach_body(root, attachment.prefix, "")
    except ValueError as err:
        raise ModelError(f"{where}: attaching {attachment.piece.__name__} at {attachment.at!r} failed: {err}") from None


#: The named elements of a model that share one name space per kind when a piece is attached.
_NAMED_KINDS = ("bodies", "joints", "geoms", "sites", "cameras", "actuators", "sensors", "tendons", "equalities")


def _check_name_clashes(parent: mujoco.MjSpec, child: mujoco.MjSpec, attachment: Attachment, where: str) -> None:
    """Raise :class:`ConfigError` when a name of the piece (after its prefix) is taken in
    ``parent`` by an element of the same kind (MuJoCo's compiler would refuse it with
    only "repeated name"), naming the clashes and the way out (a prefix)."""
    clashes = []
    for kind in _NAMED_KINDS:
        taken = {element.name for element in getattr(parent, kind) if element.name}
        for element in getattr(child, kind):
            if kind == "bodies" and element == child.worldbody:
                continue  # the piece's world body is not attached
            name = attachment.prefix + element.name if element.name else ""
            if name and name in taken:
                clashes.append(f"{kind[:-1] if kind != 'bodies' else 'body'} {name!r}")
    if clashes:
        shown = ", ".join(clashes[:5]) + (f" and {len(clashes) - 5} more" if len(clashes) > 5 else "")
        raise ConfigError(
            f"{where} Attachment({attachment.piece.__name__}, at={attachment.at!r}): the piece's names clash with "
            f"the robot's: {shown}; give the attachment a prefix (Attachment(..., prefix='gripper_'))."
        )
