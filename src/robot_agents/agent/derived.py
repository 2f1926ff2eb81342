"""What a robot that declares little gets derived from its model: its parts (a serial
chain is an arm, two fingers at its end a gripper), the motors among its drives, body pairs already touching at its
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
from robot_agents.parts.declaration import Arm, Body, EndEffector, Gripper, Part

#: Source label of derived drives (see :func:`robot_agents.actuators.spec.apply_actuators`).
DERIVED_SOURCE = "derived gains"


def joint_actuator(model: mujoco.MjModel, joint: str) -> int | None:
    """The id of the first actuator that drives joint ``joint`` (its full name) directly,
    or ``None``."""
    joint_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
    return next(
        (
            a
            for a in range(getattr(model, "nactuator", model.nu))
            if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)
            and model.actuator_trnid[a, 0] == joint_id
        ),
        None,
    )


def torque_only(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive is an affine actuator without stiffness or damping (a motor)."""
    out = []
    for drive in drives:
        if drive.kind is not DriveKind.AFFINE or drive.source.startswith(DERIVED_SOURCE):
            continue
        actuator = joint_actuator(model, drive.joint)
        bias = model.actuator_biasprm[actuator] if actuator is not None else None
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
            actuator = joint_actuator(model, drive.joint)
            damping = -float(model.actuator_biasprm[actuator, 2]) if actuator is not None else 0.0
        if not damping > 0.0:
            out.append(drive.joint)
    return out


def infer_parts(model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str]) -> tuple[Part, ...]:
    """Parts of a robot that declares none: its driven joints as one arm when they form
    a serial chain (each joint's body below the previous one's), with the chain's last
    body as the end effector; otherwise one ``Body`` part over all of them.

    Two fingers at the chain's end are a ``Gripper`` (see :func:`infer_gripper`): the
    arm is the chain above them, its end effector ``"ee"`` on the fingers' common parent
    (the hand), at the midpoint of the fingers' centres of mass when closed."""
    if not driven:
        return ()
    found = infer_gripper(model, index, driven)
    if found is not None:
        gripper, hand, tcp, count = found
        arm_joints = list(driven[: len(driven) - count])
        if not arm_joints:
            return (gripper,)
        bodies = [int(model.jnt_bodyid[index.joint(j, "infer_parts").id]) for j in arm_joints]
        if _serial(index, bodies) and int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, hand)) in (
            index.subtree_bodies(bodies[-1])
        ):
            arm = Arm(
                name="arm",
                joints=tuple(re.escape(j) for j in arm_joints),
                end_effectors=(EndEffector(hand, name="ee", pos=tcp),),
            )
            return (arm, gripper)
    joints = [index.joint(j, "infer_parts") for j in driven]
    bodies = [int(model.jnt_bodyid[j.id]) for j in joints]
    patterns = tuple(re.escape(j) for j in driven)
    if not _serial(index, bodies):
        return (Body(name="body", joints=patterns),)
    tip = bodies[-1]
    while True:
        children = [b for b in range(tip + 1, model.nbody) if int(model.body_parentid[b]) == tip]
        if len(children) != 1:
            break
        tip = children[0]
    link = model.body(tip).name[len(index.prefix) :]
    return (Arm(name="arm", joints=patterns, end_effectors=(EndEffector(link, name="ee"),)),)


def _serial(index: RobotIndex, bodies: Sequence[int]) -> bool:
    """Each body below the previous one."""
    return all(b in index.subtree_bodies(a) for a, b in itertools.pairwise(bodies))


#: Least change of the distance between two fingers over their joints' ranges for them
#: to count as a gripper (m).
MIN_FINGER_STROKE = 1e-3
#: How far past ``closed`` a derived gripper may command its fingers, as a share of its
#: stroke (so that a grasp keeps pressing when the fingers stop on an object).
DERIVED_SQUEEZE = 0.1


def infer_gripper(
    model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str]
) -> tuple[Gripper, str, tuple[float, float, float], int] | None:
    """A gripper at the end of ``driven`` (joint names in model order), or ``None``.

    Two fingers: the last driven joint and a joint coupled to it by a joint equality
    (a URDF ``mimic``), or the last two driven joints, of one kind (slide or hinge),
    limited, on sibling bodies (one parent: the hand), whose centres of mass come at
    least :data:`MIN_FINGER_STROKE` closer over their ranges. Each finger's ``open`` is
    the end of its range where the fingers are farthest apart, ``closed`` the other.
    Returns the part, the hand's name, the closed fingers' midpoint in the hand's frame
    (m; the tool point) and how many driven joints the gripper takes (1 or 2)."""
    names = list(driven)
    last = index.joint(names[-1], "infer_gripper")
    candidates: list[tuple[list[int], int, dict[int, np.ndarray]]] = []
    # joints coupled to the last by an active joint equality (a URDF mimic): the index's couplings
    followers = [c for c in index.couplings if c.leader == last.name]
    if followers:
        follower = index.joint(followers[0].follower, "infer_gripper").id
        candidates.append(([last.id, follower], 1, {follower: np.array(followers[0].coef)}))
    if len(names) >= 2:
        candidates.append(([index.joint(names[-2], "infer_gripper").id, last.id], 2, {}))
    for ids, count, coupled in candidates:
        found = _gripper_of(model, index, ids, coupled)
        if found is not None:
            gripper, hand, tcp = found
            return gripper, hand, tcp, count
    return None


def _gripper_of(
    model: mujoco.MjModel, index: RobotIndex, ids: list[int], coupled: dict[int, np.ndarray]
) -> tuple[Gripper, str, tuple[float, float, float]] | None:
    """The gripper of two finger joints ``ids`` (the second may follow the first through
    ``coupled`` polynomials), or ``None`` when they are not two opposing fingers."""
    kinds = {int(model.jnt_type[j]) for j in ids}
    if len(kinds) != 1 or kinds.pop() not in (int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE)):
        return None
    if not all(model.jnt_limited[j] for j in ids):
        return None
    bodies = [int(model.jnt_bodyid[j]) for j in ids]
    parents = {int(model.body_parentid[b]) for b in bodies}
    if len(parents) != 1 or bodies[0] == bodies[1]:
        return None
    hand = parents.pop()
    data = mujoco.MjData(model)
    qpos = model.qpos0.copy()

    def place(values: dict[int, float]) -> None:
        data.qpos[:] = qpos
        for joint, value in values.items():
            data.qpos[model.jnt_qposadr[joint]] = value
            for follower, coef in coupled.items() if joint == ids[0] else ():
                data.qpos[model.jnt_qposadr[follower]] = float(np.polyval(coef[::-1], value))
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)

    def spread(values: dict[int, float]) -> float:
        place(values)
        return float(np.linalg.norm(data.xipos[bodies[0]] - data.xipos[bodies[1]]))

    def middle(joint: int) -> float:
        return float(model.jnt_range[joint].mean())

    ends: dict[int, tuple[float, float]] = {}  # joint -> (open, closed)
    driven_ids = [ids[0]] if coupled else ids
    for joint in driven_ids:
        others = {j: middle(j) for j in driven_ids if j != joint}
        low, high = (float(v) for v in model.jnt_range[joint])
        far_low, far_high = spread({**others, joint: low}), spread({**others, joint: high})
        if abs(far_high - far_low) < MIN_FINGER_STROKE:
            return None
        ends[joint] = (high, low) if far_high > far_low else (low, high)
    opened = {j: ends[j][0] for j in driven_ids}
    closed = {j: ends[j][1] for j in driven_ids}
    for follower, coef in coupled.items():
        opened[follower] = float(np.polyval(coef[::-1], opened[ids[0]]))
        closed[follower] = float(np.polyval(coef[::-1], closed[ids[0]]))
    place(closed)
    midpoint = 0.5 * (data.xipos[bodies[0]] + data.xipos[bodies[1]])
    rotation = data.xmat[hand].reshape(3, 3)
    tcp = rotation.T @ (midpoint - data.xpos[hand])
    prefix = len(index.prefix)
    joint_names = [model.joint(j).name[prefix:] for j in ids]
    stroke = abs(opened[ids[0]] - closed[ids[0]])
    gripper = Gripper(
        name="gripper",
        joints=tuple(re.escape(j) for j in joint_names),
        open=tuple(opened[j] for j in ids),
        closed=tuple(closed[j] for j in ids),
        squeeze=DERIVED_SQUEEZE * stroke,
        fingers=tuple(tuple(model.body(b).name[prefix:] for b in index.subtree_bodies(body)) for body in bodies),
    )
    point = (round(float(tcp[0]), 9), round(float(tcp[1]), 9), round(float(tcp[2]), 9))  # m, to the nanometre
    return gripper, model.body(hand).name[prefix:], point


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
