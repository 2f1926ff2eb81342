"""What a robot that declares little gets derived from its model: its parts (a serial
chain is an arm), the motors among its drives, body pairs already touching at its
default pose, and where a floating (or floor-crossing) robot rests on the floor."""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.actuators.spec import DriveDeclaration, DriveKind
from robot_agents.agent.index import RobotIndex
from robot_agents.parts.declaration import Arm, Body, EndEffector, Part

#: Source label of derived drives (see :func:`robot_agents.actuators.spec.apply_actuators`).
DERIVED_SOURCE = "derived gains"


def torque_only(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive is an affine actuator without stiffness or damping (a motor)."""
    out = []
    for drive in drives:
        if drive.kind is not DriveKind.AFFINE or drive.source.startswith(DERIVED_SOURCE):
            continue
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, drive.joint)
        actuators = [
            a
            for a in range(getattr(model, "nactuator", model.nu))
            if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT) and model.actuator_trnid[a, 0] == joint
        ]
        bias = model.actuator_biasprm[actuators[0]] if actuators else None
        if bias is not None and bias[1] == 0.0 and bias[2] == 0.0:  # no stiffness, no damping: a motor
            out.append(drive.joint)
    return out


def undamped(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive has neither stiffness nor damping once a velocity mode
    relaxes its stiffness: an affine actuator (a file's ``<position>`` without ``kv``, a
    motor) or an explicit PD without damping. Such a drive cannot follow velocity
    targets; MuJoCo's ``pid`` and ``dcmotor`` drives take velocity inputs and can."""
    out = []
    for drive in drives:
        if drive.kind in (DriveKind.PID, DriveKind.DCMOTOR):
            continue
        damping = drive.damping
        if drive.kind is DriveKind.AFFINE and not drive.source.startswith(DERIVED_SOURCE):
            joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, drive.joint)
            actuator = next(
                (
                    a
                    for a in range(getattr(model, "nactuator", model.nu))
                    if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)
                    and model.actuator_trnid[a, 0] == joint
                ),
                None,
            )
            damping = -float(model.actuator_biasprm[actuator, 2]) if actuator is not None else 0.0
        if not damping > 0.0:
            out.append(drive.joint)
    return out


def infer_parts(model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str]) -> tuple[Part, ...]:
    """Parts of a robot that declares none: its driven joints as one arm when they form
    a serial chain (each joint's body below the previous one's), with the chain's last
    body as the end effector; otherwise one ``Body`` part over all of them."""
    if not driven:
        return ()
    joints = [index.joint(j, "infer_parts") for j in driven]
    bodies = [int(model.jnt_bodyid[j.id]) for j in joints]
    serial = all(b in index.subtree_bodies(a) for a, b in itertools.pairwise(bodies))
    patterns = tuple(re.escape(j) for j in driven)
    if not serial:
        return (Body(name="body", joints=patterns),)
    tip = bodies[-1]
    while True:
        children = [b for b in range(tip + 1, model.nbody) if int(model.body_parentid[b]) == tip]
        if len(children) != 1:
            break
        tip = children[0]
    link = model.body(tip).name[len(index.prefix) :]
    return (Arm(name="arm", joints=patterns, end_effectors=(EndEffector(link, name="ee"),)),)


def self_contacts(model: mujoco.MjModel, index: RobotIndex, qpos: np.ndarray) -> tuple[tuple[str, str], ...]:
    """Pairs of the robot's bodies (names) whose geoms touch at joint positions ``qpos``."""
    data = mujoco.MjData(model)
    data.qpos[index.qpos_adr] = qpos
    mujoco.mj_forward(model, data)
    pairs: dict[tuple[str, str], None] = {}
    for i in range(data.ncon):
        contact = data.contact[i]
        first, second = int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])
        if first and second and first != second:
            names = sorted((model.body(first).name, model.body(second).name))
            pairs[(names[0], names[1])] = None
    return tuple(pairs)


def lowest_point(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> float:
    """World z (m) of the lowest point of ``geom`` after kinematics (exact for spheres,
    capsules, cylinders, boxes, ellipsoids and meshes; the bounding box otherwise)."""
    kind = int(model.geom_type[geom])
    z = float(data.geom_xpos[geom, 2])
    rotation = data.geom_xmat[geom].reshape(3, 3)
    size = model.geom_size[geom]
    axis_z = abs(float(rotation[2, 2]))
    if kind == int(mujoco.mjtGeom.mjGEOM_SPHERE):
        return z - float(size[0])
    if kind == int(mujoco.mjtGeom.mjGEOM_CAPSULE):
        return z - axis_z * float(size[1]) - float(size[0])
    if kind == int(mujoco.mjtGeom.mjGEOM_CYLINDER):
        return z - axis_z * float(size[1]) - float(size[0]) * math.sqrt(max(0.0, 1.0 - axis_z**2))
    if kind == int(mujoco.mjtGeom.mjGEOM_BOX):
        return z - float(np.abs(rotation[2]) @ size)
    if kind == int(mujoco.mjtGeom.mjGEOM_ELLIPSOID):
        return z - float(np.linalg.norm(rotation[2] * size))
    if kind == int(mujoco.mjtGeom.mjGEOM_MESH):
        mesh = int(model.geom_dataid[geom])
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        vertices = model.mesh_vert[start : start + count]
        return z + float(np.min(vertices @ rotation[2]))
    center, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
    return z + float(rotation[2] @ center) - float(np.abs(rotation[2]) @ half)


def resting_base(model: mujoco.MjModel, index: RobotIndex, qpos: np.ndarray) -> np.ndarray:
    """A floating robot's base pose ``(7,)`` at ``qpos`` that puts its lowest colliding
    geom 1 mm above the floor (z = 0), at the origin, in the file's root orientation
    (:func:`file_root_orientation`)."""
    data = mujoco.MjData(model)
    data.qpos[index.qpos_adr] = qpos
    free = index.free_joint
    quat = np.array([1.0, 0.0, 0.0, 0.0])
    if free is not None:
        quat = file_root_orientation(model, free.qpos_adr)
        data.qpos[free.qpos_adr : free.qpos_adr + 7] = (0.0, 0.0, 0.0, *quat)
    mujoco.mj_kinematics(model, data)
    lowest = min(
        (
            lowest_point(model, data, g)
            for g in range(model.ngeom)
            if (model.geom_contype[g] or model.geom_conaffinity[g])
            and int(model.geom_type[g]) != int(mujoco.mjtGeom.mjGEOM_PLANE)
        ),
        default=np.inf,
    )
    height = 0.0 if not np.isfinite(lowest) else 0.001 - lowest
    return np.array([0.0, 0.0, height, *quat])


def file_root_orientation(model: mujoco.MjModel, qpos_adr: int) -> np.ndarray:
    """The unit quaternion ``(w, x, y, z)`` a model file gives its free root: its first
    keyframe's, else the compiled reference (``qpos0``: the root body's ``quat`` /
    ``euler`` composed with the free joint's own reference)."""
    source = model.key_qpos[0] if model.nkey > 0 else model.qpos0
    quat = np.array(source[qpos_adr + 3 : qpos_adr + 7], dtype=np.float64)
    norm = float(np.linalg.norm(quat))
    return quat / norm if np.isfinite(norm) and norm > 1e-9 else np.array([1.0, 0.0, 0.0, 0.0])
