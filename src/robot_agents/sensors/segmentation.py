"""Segmentation ids: one id per MuJoCo body, so a pixel names the robot link or scene
object it shows.

The id of a pixel is the id of the body owning the geom (or site) seen there:
``-1`` means background (nothing within the far plane) or a visual that belongs to no
body, ``0`` is the world body (the floor and other world geoms), every other id is a
robot link or a scene object. :func:`segmentation_id_map` names them all.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ModelError
from robot_agents.keywords import checked_keywords

#: Segmentation id of pixels that show nothing.
BACKGROUND_ID = -1
SEGMENTATION_DTYPE = np.int16

ROBOT_LINK = "robot_link"
OBJECT = "object"
WORLD_KIND = "world"


@checked_keywords
@dataclass(frozen=True)
class SegmentationEntry:
    """What a segmentation id stands for.

    Attributes:
        name: the body's full name in the scene (``"panda-0/panda_link3"``, ``"cube"``,
            ``"world"``).
        kind: ``"robot_link"``, ``"object"`` (a scene body that is no robot's) or
            ``"world"`` (body 0: floor and static world geoms).
        robot: the robot id (``"panda-0"``) for robot links, else ``None``.
        link: the link name within its robot (``"panda_link3"``), else ``None``.
    """

    name: str
    kind: str
    robot: str | None = None
    link: str | None = None


def segmentation_id_map(model: mujoco.MjModel, robot_prefixes: Mapping[str, str]) -> dict[int, SegmentationEntry]:
    """Every segmentation id of ``model`` -> what it is. ``robot_prefixes`` maps robot id
    -> name prefix (``{"panda-0": "panda-0/"}``)."""
    entries: dict[int, SegmentationEntry] = {0: SegmentationEntry("world", WORLD_KIND)}
    for body in range(1, model.nbody):
        name = model.body(body).name
        owner = next((rid for rid, prefix in robot_prefixes.items() if name.startswith(prefix)), None)
        if owner is None:
            entries[body] = SegmentationEntry(name, OBJECT)
        else:
            entries[body] = SegmentationEntry(name, ROBOT_LINK, owner, name[len(robot_prefixes[owner]) :])
    return entries


class SegmentationLookup:
    """Turns MuJoCo's per-pixel ``(object id, object type)`` into body ids."""

    def __init__(self, model: mujoco.MjModel) -> None:
        if model.nbody > np.iinfo(SEGMENTATION_DTYPE).max:
            raise ModelError(
                f"SegmentationLookup: the scene has {model.nbody} bodies; int16 segmentation ids hold at most "
                f"{np.iinfo(SEGMENTATION_DTYPE).max}."
            )
        # A trailing -1 makes object id -1 (background) map to -1 by negative indexing.
        self._geom = np.append(model.geom_bodyid, BACKGROUND_ID).astype(SEGMENTATION_DTYPE)
        self._site = np.append(model.site_bodyid, BACKGROUND_ID).astype(SEGMENTATION_DTYPE)
        self._geom_type = int(mujoco.mjtObj.mjOBJ_GEOM)
        self._site_type = int(mujoco.mjtObj.mjOBJ_SITE)

    def body_ids(self, raw: npt.NDArray[np.int32], out: npt.NDArray[np.int16]) -> None:
        """Write body ids of a ``(H, W, 2)`` MuJoCo segmentation image into ``out`` ``(H, W)``."""
        objid, objtype = raw[..., 0], raw[..., 1]
        np.copyto(out, self._geom[objid])
        other = (objtype != self._geom_type) & (objtype != BACKGROUND_ID)  # rare: sites, flexes, skins
        if other.any():
            out[other] = np.where(objtype[other] == self._site_type, self._site[objid[other]], BACKGROUND_ID)
