"""Segmentation ids: one id per MuJoCo body, so a pixel names the robot link or scene
object it shows.

The id of a pixel is the id of the body owning the geom (or site) seen there:
``-1`` means background (nothing within the far plane), ``0`` is the world body (the
floor and other world geoms), every other id below ``nbody`` is a robot link or a scene
object. MuJoCo's deformables belong to no one body: a flex (MuJoCo reports the flex's
id) and a skin (the skin's id) read the id of the body they move with when all their
vertices move with one (a flex's vertex or interpolation-node bodies, a skin's bones),
else an id of their own after the bodies: ``nbody``, ``nbody + 1``, ... for such flexes
in model order, then such skins. :func:`segmentation_id_map` names them all.
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
FLEX = "flex"
SKIN = "skin"


@checked_keywords
@dataclass(frozen=True)
class SegmentationEntry:
    """What a segmentation id stands for.

    Attributes:
        name: the body's full name in the scene (``"panda-0/panda_link3"``, ``"cube"``,
            ``"world"``).
        kind: ``"robot_link"``, ``"object"`` (a scene body that is no robot's),
            ``"world"`` (body 0: floor and static world geoms), or ``"flex"`` /
            ``"skin"`` (a deformable that moves with several bodies; its name is the
            flex's / skin's, or ``"flex 3"`` / ``"skin 0"`` by index when unnamed).
        robot: the robot id (``"panda-0"``) for robot links and for deformables whose
            bodies are all one robot's, else ``None``.
        link: the link name within its robot (``"panda_link3"``), else ``None``.
    """

    name: str
    kind: str
    robot: str | None = None
    link: str | None = None


def _owner(name: str, robot_prefixes: Mapping[str, str]) -> str | None:
    return next((rid for rid, prefix in robot_prefixes.items() if name.startswith(prefix)), None)


def _single_body(bodies: npt.NDArray[np.int32]) -> int | None:
    """The one body of ``bodies`` (ids), or ``None`` when there are several (or none)."""
    unique = np.unique(bodies)
    return int(unique[0]) if unique.size == 1 else None


def flex_bodies(model: mujoco.MjModel, flex: int) -> npt.NDArray[np.int32]:
    """Ids of the bodies flex ``flex``'s vertices move with: its interpolation nodes'
    bodies for an interpolated flex (``dof="trilinear"`` ...), else its vertices'."""
    if int(model.flex_interp[flex]) != 0:
        start, count = int(model.flex_nodeadr[flex]), int(model.flex_nodenum[flex])
        return np.asarray(model.flex_nodebodyid[start : start + count])
    start, count = int(model.flex_vertadr[flex]), int(model.flex_vertnum[flex])
    return np.asarray(model.flex_vertbodyid[start : start + count])


def skin_bodies(model: mujoco.MjModel, skin: int) -> npt.NDArray[np.int32]:
    """Ids of the bodies skin ``skin`` is bound to (its bones)."""
    start, count = int(model.skin_boneadr[skin]), int(model.skin_bonenum[skin])
    return np.asarray(model.skin_bonebodyid[start : start + count])


@dataclass(frozen=True)
class DeformableIds:
    """Segmentation ids of a model's flexes and skins (see the module docstring).

    Attributes:
        flex: id of each flex, shape ``(nflex,)``.
        skin: id of each skin, shape ``(nskin,)``.
        own: ``(id, kind, index)`` of the deformables with an id of their own, in id order.
    """

    flex: npt.NDArray[np.int64]
    skin: npt.NDArray[np.int64]
    own: tuple[tuple[int, str, int], ...]


def deformable_ids(model: mujoco.MjModel) -> DeformableIds:
    """The segmentation id of every flex and skin of ``model``."""
    own: list[tuple[int, str, int]] = []
    ids: dict[str, list[int]] = {FLEX: [], SKIN: []}
    for kind, count, bodies_of in ((FLEX, model.nflex, flex_bodies), (SKIN, model.nskin, skin_bodies)):
        for index in range(count):
            body = _single_body(bodies_of(model, index))
            if body is None:
                body = model.nbody + len(own)
                own.append((body, kind, index))
            ids[kind].append(body)
    return DeformableIds(np.array(ids[FLEX], dtype=np.int64), np.array(ids[SKIN], dtype=np.int64), tuple(own))


def max_segmentation_id(model: mujoco.MjModel) -> int:
    """The largest segmentation id ``model``'s images can hold (at least 0)."""
    return max(int(model.nbody) - 1 + len(deformable_ids(model).own), 0)


def segmentation_id_map(model: mujoco.MjModel, robot_prefixes: Mapping[str, str]) -> dict[int, SegmentationEntry]:
    """Every segmentation id of ``model`` -> what it is. ``robot_prefixes`` maps robot id
    -> name prefix (``{"panda-0": "panda-0/"}``)."""
    entries: dict[int, SegmentationEntry] = {0: SegmentationEntry("world", WORLD_KIND)}
    for body in range(1, model.nbody):
        name = model.body(body).name
        owner = _owner(name, robot_prefixes)
        if owner is None:
            entries[body] = SegmentationEntry(name, OBJECT)
        else:
            entries[body] = SegmentationEntry(name, ROBOT_LINK, owner, name[len(robot_prefixes[owner]) :])
    for segment, kind, index in deformable_ids(model).own:
        bodies = flex_bodies(model, index) if kind == FLEX else skin_bodies(model, index)
        owners = {_owner(model.body(int(b)).name, robot_prefixes) if b > 0 else None for b in bodies}
        robot = owners.pop() if len(owners) == 1 else None
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_FLEX if kind == FLEX else mujoco.mjtObj.mjOBJ_SKIN, index)
        name = name or f"{kind} {index}"
        entries[segment] = SegmentationEntry(name, kind, robot)
    return entries


class SegmentationLookup:
    """Turns MuJoCo's per-pixel ``(object id, object type)`` into segmentation ids."""

    def __init__(self, model: mujoco.MjModel) -> None:
        deformables = deformable_ids(model)
        largest = max_segmentation_id(model)
        if largest > np.iinfo(SEGMENTATION_DTYPE).max:
            raise ModelError(
                f"SegmentationLookup: the scene has {model.nbody} bodies and {len(deformables.own)} flexes / skins "
                f"spanning several bodies; int16 segmentation ids hold at most {np.iinfo(SEGMENTATION_DTYPE).max}."
            )
        # A trailing -1 makes object id -1 (background) map to -1 by negative indexing.
        self._geom = np.append(model.geom_bodyid, BACKGROUND_ID).astype(SEGMENTATION_DTYPE)
        self._other = {
            int(mujoco.mjtObj.mjOBJ_SITE): np.append(model.site_bodyid, BACKGROUND_ID).astype(SEGMENTATION_DTYPE),
            int(mujoco.mjtObj.mjOBJ_FLEX): np.append(deformables.flex, BACKGROUND_ID).astype(SEGMENTATION_DTYPE),
            int(mujoco.mjtObj.mjOBJ_SKIN): np.append(deformables.skin, BACKGROUND_ID).astype(SEGMENTATION_DTYPE),
        }
        self._geom_type = int(mujoco.mjtObj.mjOBJ_GEOM)

    def body_ids(self, raw: npt.NDArray[np.int32], out: npt.NDArray[np.int16]) -> None:
        """Write segmentation ids of a ``(H, W, 2)`` MuJoCo segmentation image into ``out`` ``(H, W)``."""
        objid, objtype = raw[..., 0], raw[..., 1]
        other = (objtype != self._geom_type) & (objtype != BACKGROUND_ID)  # rare: sites, flexes, skins
        if not other.any():
            np.copyto(out, self._geom[objid])
        else:  # another kind's id may exceed the geoms'
            np.copyto(out, self._geom[np.where(other, BACKGROUND_ID, objid)])
            for kind, table in self._other.items():
                pixels = other & (objtype == kind)
                if pixels.any():
                    out[pixels] = table[objid[pixels]]
