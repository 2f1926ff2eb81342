"""A bound robot's grippers and hands: grasp detection, opening, and which joints
``is_static`` ignores."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.index import RobotIndex
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.parts.declaration import Gripper, Part
from robot_agents.parts.grasp import grasped

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]


class GripperParts:
    """The Gripper and Hand parts of one robot in ``world``."""

    def __init__(
        self,
        world: SimBackend,
        index: RobotIndex,
        parts: Sequence[Part],
        part_joints: Mapping[str, Sequence[str]],
        owner: str,
    ) -> None:
        self.world = world
        self.index = index
        self.owner = owner
        self.parts = {p.name: p for p in parts if isinstance(p, Gripper)}
        self.part_joints = part_joints
        self._state_cache: dict[str, tuple[npt.NDArray[np.int64], FloatArray, FloatArray]] = {}
        gripping = {j for name in self.parts for j in part_joints[name]}
        self._static_dofs = np.array(
            [a for j in index.joints if j.name not in gripping for a in range(j.dof_adr, j.dof_adr + j.nv)],
            dtype=np.int64,
        )

    def part(self, name: str | None) -> Gripper:
        """The gripper or hand ``name`` (default: the first)."""
        if not self.parts:
            raise ConfigError(f"{self.owner}: declares no Gripper or Hand part.")
        if name is None:
            return next(iter(self.parts.values()))
        if name not in self.parts:
            raise UnknownNameError(f"{self.owner}.gripper", "gripper", str(name), self.parts)
        return self.parts[name]

    def is_static(self, threshold: float) -> BoolArray:
        """Per env: every joint except grippers' moves slower than ``threshold``."""
        qvel = self.world.qvel[:, self._static_dofs]
        return np.asarray(np.max(np.abs(qvel), axis=1, initial=0.0) <= threshold)

    def is_grasping(self, body: str, min_force: float, max_angle: float, gripper: str | None) -> BoolArray:
        """Per env: two fingers press on scene body ``body`` from opposing sides."""
        part = self.part(gripper)
        where = f"{self.owner}.is_grasping"
        if not part.finger_links:
            raise ConfigError(f"{where}: gripper {part.name!r} declares no fingers.")
        model = self.world.model
        target = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body) if isinstance(body, str) else -1
        if target < 0:
            raise UnknownNameError(where, "body", str(body), [model.body(b).name for b in range(model.nbody)])
        return grasped(self.world.contact_forces(self.finger_bodies(part, where), target), min_force, max_angle)

    def finger_bodies(self, part: Gripper, where: str) -> list[list[int]]:
        """The bodies of each finger of ``part``: its links and the bodies below them,
        less those below another finger's link (a fixed jaw on the hand holds the moving
        jaw in its subtree, but the moving jaw's contacts are its own)."""
        links = [[self.index.body_id(link, where) for link in finger] for finger in part.finger_links]
        below = [{b for link in finger for b in self.index.subtree_bodies(link)} for finger in links]
        groups = []
        for i, finger in enumerate(links):
            others = {
                b for k, other in enumerate(links) if k != i for link in other if link in below[i] for b in below[k]
            }
            groups.append([b for link in finger for b in self.index.subtree_bodies(link) if b not in others])
        return groups

    def within(self, gripper: str | None, opening: float) -> BoolArray:
        """Per env: every driven joint of the part that moves between ``open`` and
        ``closed`` within the part's tolerance (rad or m) of its position at ``opening``
        (0 closed, 1 open), as Habitat's ``is_gripper_open`` / ``is_gripper_closed``
        check every gripper joint: one finger closed and the other open is neither.
        Passive joints (a linkage's followers) are left out; a part with no driven joint
        that moves is read at its first joint that moves."""
        part = self.part(gripper)
        qpos_adr, opened, closed = self._state_joints(part)
        target = closed + opening * (opened - closed)
        error = np.abs(self.world.qpos[:, qpos_adr] - target)
        return np.asarray(np.all(error <= part.tolerance, axis=1))

    def _state_joints(self, part: Gripper) -> tuple[npt.NDArray[np.int64], FloatArray, FloatArray]:
        """The ``qpos`` addresses of the joints :meth:`within` reads and their ``open``
        and ``closed`` positions (found once per part)."""
        found = self._state_cache.get(part.name)
        if found is None:
            names = self.part_joints[part.name]
            opened, closed = part.positions(len(names))
            model = self.index.model
            joint_actuators = model.actuator_trntype == mujoco.mjtTrn.mjTRN_JOINT
            driven = {int(j) for j in model.actuator_trnid[joint_actuators, 0]}
            keep = [
                k
                for k, name in enumerate(names)
                if opened[k] != closed[k] and self.index.joint(name, self.owner).id in driven
            ]
            if not keep:
                keep = [list(names).index(self._measured_joint(part)[0])]
            adr = np.array([self.index.joint(names[k], self.owner).qpos_adr for k in keep], dtype=np.int64)
            found = (adr, np.array(opened[keep]), np.array(closed[keep]))
            self._state_cache[part.name] = found
        return found

    def opening(self, gripper: str | None) -> FloatArray:
        """Per env, 0 at ``closed`` and 1 at ``open`` (the part's first joint that moves
        between the two: a gripper's leader; a hand's first joint that flexes)."""
        part = self.part(gripper)
        name, opened, closed = self._measured_joint(part)
        joint = self.index.joint(name, "gripper_opening")
        q = self.world.qpos[:, joint.qpos_adr]
        opening: FloatArray = (q - closed) / (opened - closed)
        return opening

    def _measured_joint(self, part: Gripper) -> tuple[str, float, float]:
        """The part's first joint whose ``open`` and ``closed`` positions differ, and those
        positions (rad or m): a hand's first joint may not move between the two (a
        finger's spread)."""
        names = self.part_joints[part.name]
        opened, closed = part.positions(len(names))
        for name, o, c in zip(names, opened, closed, strict=True):
            if o != c:
                return name, float(o), float(c)
        raise ConfigError(f"{self.owner}: {type(part).__name__} {part.name!r} has the same open and closed positions.")
