"""Collision checks a reset makes before it commits a random draw: whether the robots'
reset noise puts a robot into the fixed scene (or into itself) deeper than its
noiseless keyframe does, and whether a prop drawn somewhere overlaps a robot.

One :class:`Clearance` per env object: a scratch ``MjData`` of the simulated model,
loaded with one env's state, posed, and run through ``mj_kinematics`` and
``mj_collision`` (nothing is written to the simulation).
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent

FloatArray = npt.NDArray[np.float64]
#: Contact depths by geom pair (m, > 0: penetrating).
Depths = dict[tuple[int, int], float]


class Clearance:
    """Collision checks of ``model`` for the robots ``agents`` (see the module doc).

    A geom is a *robot geom* when its body lies in a robot's subtree, *fixed* when its
    body is welded to the world (the floor, the table, static props; a fixed-base
    robot's base too).
    """

    def __init__(self, model: mujoco.MjModel, agents: Sequence[Agent]) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        bodies = {b for agent in agents for b in agent.index.subtree_bodies(agent.index.root_body_id)}
        body_of = np.asarray(model.geom_bodyid, dtype=np.int64)
        #: Per geom: whether it belongs to a robot.
        self.robot_geom = np.array([int(b) in bodies for b in body_of], dtype=bool)
        #: Per geom: whether its body is welded to the world.
        self.fixed_geom = np.asarray(model.body_weldid, dtype=np.int64)[body_of] == 0
        self._keyframe_depths: dict[bytes, Depths] = {}

    def load(self, source: mujoco.MjData) -> None:
        """Take an env's positions (joints and mocap bodies) into the scratch data."""
        self.data.qpos[:] = source.qpos
        if self.model.nmocap:
            self.data.mocap_pos[:] = source.mocap_pos
            self.data.mocap_quat[:] = source.mocap_quat

    def _collide(self) -> None:
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_collision(self.model, self.data)

    def robot_depths(self) -> Depths:
        """Penetration depth per geom pair, over the contacts of a robot geom with a
        fixed geom or another robot geom, at the loaded positions."""
        self._collide()
        depths: Depths = {}
        robot, fixed, data = self.robot_geom, self.fixed_geom, self.data
        for i in range(data.ncon):
            contact = data.contact[i]
            depth = -float(contact.dist)
            if depth <= 0.0:
                continue
            g1, g2 = int(contact.geom1), int(contact.geom2)
            if not (robot[g1] or robot[g2]) or not ((robot[g1] or fixed[g1]) and (robot[g2] or fixed[g2])):
                continue
            pair = (min(g1, g2), max(g1, g2))
            depths[pair] = max(depths.get(pair, 0.0), depth)
        return depths

    def keyframe_depths(self) -> Depths:
        """:meth:`robot_depths` at the loaded positions, remembered by those positions (a
        reset's noiseless keyframe is the same at every reset: one pass per keyframe)."""
        key = self.data.qpos.tobytes() + (self.data.mocap_pos.tobytes() if self.model.nmocap else b"")
        depths = self._keyframe_depths.get(key)
        if depths is None:
            if len(self._keyframe_depths) >= 64:
                self._keyframe_depths.clear()
            depths = self.robot_depths()
            self._keyframe_depths[key] = depths
        return depths

    def robots_clear(self, qpos: FloatArray, allowed: Depths, tolerance: float) -> bool:
        """Whether, at scene positions ``qpos`` (the mocap bodies as loaded), no robot
        geom pair penetrates deeper than in ``allowed`` (0 where absent) plus
        ``tolerance`` (m)."""
        self.data.qpos[:] = qpos
        return all(depth <= allowed.get(pair, 0.0) + tolerance for pair, depth in self.robot_depths().items())

    def body_clear_of_robots(self, body: int, qpos_adr: npt.NDArray[np.int64], pose: FloatArray) -> bool:
        """Whether free body ``body`` (its joint's ``qpos_adr``), put at ``pose``, has no
        contact with a robot geom at a distance below 0 (the other positions as loaded)."""
        self.data.qpos[qpos_adr] = pose
        self._collide()
        data, model, robot = self.data, self.model, self.robot_geom
        for i in range(data.ncon):
            contact = data.contact[i]
            if contact.dist >= 0.0:
                continue
            g1, g2 = int(contact.geom1), int(contact.geom2)
            b1, b2 = int(model.geom_bodyid[g1]), int(model.geom_bodyid[g2])
            if (b1 == body and robot[g2]) or (b2 == body and robot[g1]):
                return False
        return True
