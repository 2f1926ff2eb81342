"""A bound robot's legs: which of its bodies are feet, and whether it stands or has
fallen (``is_standing`` / ``is_fallen``), for robots whose legs carry a free base."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import RobotIndex
from robot_agents.errors import ConfigError
from robot_agents.parts.declaration import Legs, Part

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int64]

#: Default largest tilt (rad) of a standing robot's base from upright: 20 deg (the
#: threshold ManiSkill's quadrupeds use for "standing").
STANDING_TILT = math.radians(20.0)


def standing_legs(
    parts: Sequence[Part], part_joints: Mapping[str, Sequence[str]], fix_root_link: bool
) -> tuple[str, ...]:
    """The joints of legs that carry the robot: its ``Legs`` parts that are not held,
    when its root is free (empty for a fixed root, which rests on its mount, and for
    held legs, which ride a kinematic base: ``spot``)."""
    if fix_root_link:
        return ()
    return tuple(j for p in parts if isinstance(p, Legs) and not p.held for j in part_joints[p.name])


def foot_bodies(model: mujoco.MjModel, leg_joint_ids: Sequence[int]) -> set[int]:
    """Bodies of ``model`` that are feet: each distal leg link (moved by a leg joint
    that no other leg joint's body descends from) and every body below it."""
    leg_bodies = {int(model.jnt_bodyid[j]) for j in leg_joint_ids}

    def ancestors(body: int) -> list[int]:
        chain = []
        while body > 0:
            body = int(model.body_parentid[body])
            chain.append(body)
        return chain

    proximal = {a for b in leg_bodies for a in ancestors(b) if a in leg_bodies}
    distal = leg_bodies - proximal
    return {b for b in range(model.nbody) if b in distal or distal.intersection(ancestors(b))}


class LegParts:
    """The legs of one robot in ``world`` that carry its free base (none for other robots)."""

    def __init__(
        self,
        world: SimBackend,
        index: RobotIndex,
        parts: Sequence[Part],
        part_joints: Mapping[str, Sequence[str]],
        fix_root_link: bool,
        owner: str,
    ) -> None:
        self.world = world
        self.index = index
        self.owner = owner
        model = index.model
        self.joints = standing_legs(parts, part_joints, fix_root_link)
        self.feet = foot_bodies(model, [index.joint(j, owner).id for j in self.joints])
        tree = int(model.body_rootid[index.root_body_id])
        self._robot = np.asarray(model.body_rootid == tree)  # (nbody,) the robot's bodies
        foot = np.zeros(model.nbody, dtype=bool)
        foot[sorted(self.feet)] = True
        self._not_foot = self._robot & ~foot  # robot bodies that must not touch the world

    def _require(self, where: str) -> None:
        if not self.joints:
            raise ConfigError(
                f"{where}: {self.owner} has no legs carrying a free base (a free root and a Legs part "
                "that is not held); it cannot stand or fall."
            )

    def off_feet(self, env: int, where: str) -> IntArray:
        """Bodies of the robot other than its feet that touch something outside it in env
        ``env`` (ids, sorted; empty while it stands on its feet alone)."""
        self._require(where)
        return self._off_feet(self.world.physics_sources([env])[0])

    def _off_feet(self, data: mujoco.MjData) -> IntArray:
        n = data.ncon
        bodies = self.index.model.geom_bodyid
        b1, b2 = bodies[data.contact.geom1[:n]], bodies[data.contact.geom2[:n]]
        hits = np.concatenate((b1[self._not_foot[b1] & ~self._robot[b2]], b2[self._not_foot[b2] & ~self._robot[b1]]))
        return np.unique(hits).astype(np.int64)

    def is_fallen(self, where: str) -> BoolArray:
        """Per env: a body of the robot other than a foot touches something outside it."""
        self._require(where)
        datas = self.world.physics_sources(range(self.world.num_envs))
        return np.array([self._off_feet(data).size > 0 for data in datas], dtype=bool)

    def is_standing(self, max_tilt: float, where: str) -> BoolArray:
        """Per env: the base's up axis within ``max_tilt`` (rad) of the world's, and not
        fallen (only the feet touch anything outside the robot)."""
        self._require(where)
        quat = self.world.body_poses(self.index.root_body_id)[:, 0, 3:]
        x, y = quat[:, 1], quat[:, 2]
        up_z = 1.0 - 2.0 * (x * x + y * y)  # the z component of the base's z axis in the world
        upright = up_z >= math.cos(max_tilt)
        return np.asarray(upright & ~self.is_fallen(where))
