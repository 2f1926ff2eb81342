"""Contacts of a configuration before it is simulated: how deep geoms of two sets press
into each other at a given ``qpos``, on a scratch ``MjData`` (the simulation is not
touched). Resets use it to redraw random starts that would begin inside something: a
robot's noisy reset pose in the table, a cube drawn under a resting gripper."""

from __future__ import annotations

import mujoco
import numpy as np
import numpy.typing as npt

BoolArray = npt.NDArray[np.bool_]


class StartContacts:
    """Penetration checks on one scratch ``MjData`` of ``model``."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self._data = mujoco.MjData(model)
        #: Geoms of bodies welded to the world (the floor, a table): ``(ngeom,)``.
        self.static_geoms: BoolArray = np.asarray(model.body_weldid[model.geom_bodyid] == 0)

    def body_geoms(self, bodies: npt.ArrayLike) -> BoolArray:
        """Geoms of ``bodies`` (ids), as a ``(ngeom,)`` mask."""
        return np.isin(self.model.geom_bodyid, np.asarray(bodies, dtype=np.int64))

    def deepest(self, qpos: npt.ArrayLike, first: BoolArray, second: BoolArray) -> float:
        """The deepest penetration (m, ``>= 0``; 0 when none) between a geom of ``first``
        and a geom of ``second`` (masks ``(ngeom,)``; a geom may be in both: a robot's
        own links) at ``qpos`` ``(nq,)``: MuJoCo's kinematics and collision detection,
        the pairs its filters keep (excluded and parent-child pairs never collide)."""
        model, data = self.model, self._data
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        mujoco.mj_collision(model, data)
        if data.ncon == 0:
            return 0.0
        contacts = data.contact
        g1, g2 = contacts.geom1, contacts.geom2
        hit = (first[g1] & second[g2]) | (first[g2] & second[g1])
        if not hit.any():
            return 0.0
        return max(0.0, -float(contacts.dist[hit].min()))
