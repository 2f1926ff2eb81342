"""Names to addresses: a robot's joints, bodies, sites and couplings in a compiled model,
resolved once when the robot is bound (or checked).

Multi-DoF joints are first-class: a ball joint has 4 ``qpos`` entries (a unit
quaternion ``w, x, y, z``) and 3 ``qvel`` entries, so a robot's ``qpos`` vector
``(nq,)`` and ``qvel`` vector ``(nv,)`` can differ in length. The free joint of a
floating robot's root is kept apart (:attr:`RobotIndex.free_joint`): its pose is the
robot's base pose, not part of its joint vector.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ModelError, UnknownNameError
from robot_agents.indexing import index_selector

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


class JointKind(Enum):
    HINGE = "hinge"
    SLIDE = "slide"
    BALL = "ball"
    FREE = "free"


_KINDS = {
    mujoco.mjtJoint.mjJNT_HINGE: JointKind.HINGE,
    mujoco.mjtJoint.mjJNT_SLIDE: JointKind.SLIDE,
    mujoco.mjtJoint.mjJNT_BALL: JointKind.BALL,
    mujoco.mjtJoint.mjJNT_FREE: JointKind.FREE,
}
#: qpos and qvel sizes of each joint kind.
JOINT_SIZES = {JointKind.HINGE: (1, 1), JointKind.SLIDE: (1, 1), JointKind.BALL: (4, 3), JointKind.FREE: (7, 6)}


@dataclass(frozen=True)
class JointInfo:
    """One joint of the robot.

    Attributes:
        name: without the scene prefix.
        id: index in the compiled model.
        kind: hinge, slide, ball or free.
        qpos_adr, dof_adr: first index in the model's ``qpos`` / ``qvel``.
        qpos_start, dof_start: first index in the robot's own joint vectors.
        limited, range: the joint's limits (rad or m; for a ball joint the largest
            rotation angle, rad).
    """

    name: str
    id: int
    kind: JointKind
    qpos_adr: int
    dof_adr: int
    qpos_start: int
    dof_start: int
    limited: bool
    range: tuple[float, float]

    @property
    def nq(self) -> int:
        return JOINT_SIZES[self.kind][0]

    @property
    def nv(self) -> int:
        return JOINT_SIZES[self.kind][1]


@dataclass(frozen=True)
class Coupling:
    """A joint equality inside the robot: ``follower = sum_k coef[k] * leader**k``."""

    follower: str
    leader: str
    coef: tuple[float, ...]

    def follow(self, leader_value: float) -> float:
        return float(sum(c * leader_value**k for k, c in enumerate(self.coef)))


class RobotIndex:
    """The robot with name prefix ``prefix`` in ``model``, resolved once.

    Attributes:
        joints: every joint except the root's free joint, in model order.
        free_joint: the root's free joint, if the robot floats.
        qpos_adr / dof_adr: model addresses of the robot's joint vectors, ``(nq,)`` / ``(nv,)``.
        qpos_limits: ``(nq, 2)`` per ``qpos`` entry (``(-inf, inf)`` where unlimited or a quaternion entry).
        quaternion_joints: the ball joints.
        couplings: joint equalities between two of the robot's joints (mimic joints, linkages).
        root_body_id: the robot's root body.
    """

    def __init__(self, model: mujoco.MjModel, prefix: str, owner: str) -> None:
        self.model = model
        self.prefix = prefix
        self.owner = owner
        ids = [j for j in range(model.njnt) if model.joint(j).name.startswith(prefix)]
        joints: list[JointInfo] = []
        free: JointInfo | None = None
        qpos_start = dof_start = 0
        for j in ids:
            kind = _KINDS[mujoco.mjtJoint(model.jnt_type[j])]
            info = JointInfo(
                name=model.joint(j).name[len(prefix) :],
                id=int(j),
                kind=kind,
                qpos_adr=int(model.jnt_qposadr[j]),
                dof_adr=int(model.jnt_dofadr[j]),
                qpos_start=qpos_start,
                dof_start=dof_start,
                limited=bool(model.jnt_limited[j]),
                range=(float(model.jnt_range[j, 0]), float(model.jnt_range[j, 1])),
            )
            if kind is JointKind.FREE:
                if free is not None or model.body_parentid[model.jnt_bodyid[j]] != 0:
                    raise ModelError(f"{owner}: only the root body may have a free joint; found {info.name!r}.")
                free = info
                continue
            joints.append(info)
            qpos_start += info.nq
            dof_start += info.nv
        if not joints and free is None:
            raise ModelError(
                f"{owner}: no joint{f' with prefix {prefix!r}' if prefix else ''} in the compiled model: nothing a "
                "robot could move (a fixed object, a table or a stage, is part of a scene: a ra.Prop, or a robot "
                "with fix_root_link=False moves its root on a free joint)."
            )
        self.joints: tuple[JointInfo, ...] = tuple(joints)
        self.free_joint = free
        self.joint_names: tuple[str, ...] = tuple(j.name for j in joints)
        self._by_name = {j.name: j for j in joints}
        self.qpos_adr: IntArray = np.array([j.qpos_adr + k for j in joints for k in range(j.nq)], dtype=np.int64)
        self.dof_adr: IntArray = np.array([j.dof_adr + k for j in joints for k in range(j.nv)], dtype=np.int64)
        self.qpos_sel = index_selector(self.qpos_adr)
        self.dof_sel = index_selector(self.dof_adr)
        limits = np.tile([-np.inf, np.inf], (len(self.qpos_adr), 1))
        for info in joints:
            if info.limited and info.kind in (JointKind.HINGE, JointKind.SLIDE):
                limits[info.qpos_start] = info.range
        self.qpos_limits: FloatArray = limits
        self.quaternion_joints = tuple(j for j in joints if j.kind is JointKind.BALL)
        self.root_body_id = int(model.jnt_bodyid[free.id]) if free is not None else self._find_root_body()
        self.couplings = self._couplings()

    # -- sizes ----------------------------------------------------------------------------
    @property
    def nq(self) -> int:
        return len(self.qpos_adr)

    @property
    def nv(self) -> int:
        return len(self.dof_adr)

    def joint(self, name: str, where: str) -> JointInfo:
        try:
            return self._by_name[name]
        except KeyError:
            raise UnknownNameError(where, "joint", name, self.joint_names) from None

    # -- bodies and sites -----------------------------------------------------------------
    def _find_root_body(self) -> int:
        model = self.model
        for body in range(1, model.nbody):
            if model.body_parentid[body] == 0 and model.body(body).name.startswith(self.prefix):
                return body
        raise ModelError(f"{self.owner}: no root body with prefix {self.prefix!r} in the compiled model.")

    @property
    def body_names(self) -> list[str]:
        model, prefix = self.model, self.prefix
        return [model.body(b).name[len(prefix) :] for b in range(model.nbody) if model.body(b).name.startswith(prefix)]

    def body_id(self, name: str, where: str) -> int:
        body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, self.prefix + name)
        if body < 0:
            raise UnknownNameError(where, "body", name, self.body_names)
        return int(body)

    def subtree_bodies(self, body: int) -> list[int]:
        """``body`` and every body below it."""
        parent = self.model.body_parentid
        out = [body]
        for b in range(body + 1, self.model.nbody):
            if int(parent[b]) in out:
                out.append(b)
        return out

    # -- couplings ------------------------------------------------------------------------
    def _couplings(self) -> tuple[Coupling, ...]:
        model = self.model
        by_id = {j.id: j.name for j in self.joints}
        out = []
        for eq in range(model.neq):
            if int(model.eq_type[eq]) != int(mujoco.mjtEq.mjEQ_JOINT) or not model.eq_active0[eq]:
                continue  # (an inactive equality couples nothing, as IK and the derived gripper read it)
            follower, leader = int(model.eq_obj1id[eq]), int(model.eq_obj2id[eq])
            if follower in by_id and leader in by_id:
                out.append(Coupling(by_id[follower], by_id[leader], tuple(float(c) for c in model.eq_data[eq, :5])))
        return tuple(out)
