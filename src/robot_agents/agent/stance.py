"""Where a floating robot with derived drives stands, and what its joints carry there.

The robot's driven joints are locked at its default keyframe (MuJoCo ``joint``
equalities with only ``joint1``: each holds its joint at ``polycoef[0]``), it is set 1 mm
above a floor (:func:`robot_agents.agent.derived.resting_base`) and left to settle for
:data:`STANCE_SETTLE_SECONDS` at the scene's physics step. When it comes to rest with only
bodies below its joints on the floor (feet: not its root, which is an arm lying on its
base), each lock's constraint force is the static torque its drive must give to hold the
pose under the robot's weight; each floor contact's normal force and point give the load a
joint carries and its lever. :func:`robot_agents.actuators.gains.stance_gains` turns these
into gains.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent.derived import resting_base
from robot_agents.agent.index import RobotIndex
from robot_agents.agent.joint_state import mounted_pose
from robot_agents.model.compiling import compile_spec
from robot_agents.model.scene import FLOOR_SOLIMP, FLOOR_SOLMIX, FLOOR_SOLREF
from robot_agents.notes import mujoco_messages

#: Seconds the locked robot is given to come to rest on the floor.
STANCE_SETTLE_SECONDS = 1.0
#: At rest: the base's speed (m/s) and angular speed (rad/s) below these at the end.
REST_SPEED = 1e-3
REST_TURN = 1e-2
#: Standard gravity (m/s^2), the scene's.
GRAVITY = 9.81

FloatArray = npt.NDArray[np.float64]

_FLOOR = "robot_agents_stance_floor"
_LOCK = "robot_agents_stance_lock_"


@dataclass(frozen=True)
class Stance:
    """A floating robot at rest on the floor, its driven joints locked at a keyframe.

    Arrays are ``(n,)`` in the order of ``joints``; hinges in N*m and rad, slides in N and m.

    Attributes:
        joints: the driven joints.
        torque: the generalized force each joint's lock gives to hold it (MuJoCo's sign,
            as ``qfrc_actuator``): what the joint's drive must give to hold the pose.
        load: the floor's normal force on the bodies below each joint (N): the share of
            the robot's weight that joint carries (0 for joints above no foot).
        lever: ``sum_i F_i r_i`` over those contacts, ``F_i`` a contact's normal force and
            ``r_i`` its distance from the joint's axis (N*m; 0 for slides): the most the
            load's torque can grow per radian the joint gives.
        reflected: ``sum_i F_i r_i^2 / g`` (kg*m^2; for slides ``sum_i F_i / g``, kg): the
            carried share of the body's mass as seen from the joint, its foot on the floor.
        feet: the bodies touching the floor.
        weight: the robot's weight ``m g`` (N).
        qpos: the robot's settled joint positions ``(nq,)``; ``base``: its settled base pose ``(7,)``.
    """

    joints: tuple[str, ...]
    torque: FloatArray
    load: FloatArray
    lever: FloatArray
    reflected: FloatArray
    feet: tuple[str, ...]
    weight: float
    qpos: FloatArray
    base: FloatArray

    @property
    def legs(self) -> tuple[str, ...]:
        """The joints that carry a share of the weight (a foot below them)."""
        return tuple(j for j, w in zip(self.joints, self.load, strict=True) if w > 0.0)


def find_stance(
    spec: mujoco.MjSpec,
    index: RobotIndex,
    joints: Sequence[str],
    qpos: npt.ArrayLike,
    timestep: float,
    cone: str = "pyramidal",
    where: str = "stance",
    mount_quat: npt.ArrayLike | None = None,
) -> Stance | str:
    """The stance of the floating robot of ``spec`` (its own compiled model indexed by
    ``index``) with ``joints`` locked at ``qpos`` (the robot's ``(nq,)``), settled
    :data:`STANCE_SETTLE_SECONDS` at ``timestep`` (s) on a floor like the scene's; or a
    sentence saying why there is none (nothing or its root on the floor, not at rest).
    ``mount_quat`` ``(4,)``: the orientation of the robot's mount (w, x, y, z), which turns
    it (:func:`~robot_agents.agent.derived.resting_base`). ``spec`` is not modified."""
    model = index.model
    free = index.free_joint
    if free is None:
        return "its root is fixed"
    joint_q = np.asarray(qpos, dtype=np.float64).reshape(-1)
    stand = spec.copy()
    stand.option.timestep = float(timestep)
    stand.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    stand.option.gravity = [0.0, 0.0, -GRAVITY]
    stand.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC if cone == "elliptic" else mujoco.mjtCone.mjCONE_PYRAMIDAL
    stand.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_ACTUATION)
    stand.worldbody.add_geom(
        name=_FLOOR,
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0, 0, 0.05],
        solref=list(FLOOR_SOLREF),
        solimp=[*FLOOR_SOLIMP, 0.5, 2.0],
        solmix=FLOOR_SOLMIX,
    )
    ids = [index.joint(j, where) for j in joints]
    for k, joint in enumerate(ids):
        stand.add_equality(
            name=f"{_LOCK}{k}",
            type=mujoco.mjtEq.mjEQ_JOINT,
            objtype=mujoco.mjtObj.mjOBJ_JOINT,
            name1=model.joint(joint.id).name,
            data=[float(joint_q[joint.qpos_start]), *([0.0] * 11)],
            solref=[2.0 * timestep, 1.0],  # as stiff as the step allows: a soft lock gives under the load
            solimp=[0.99, 0.999, 0.001, 0.5, 2.0],
        )
    locked = compile_spec(stand, where)
    data = mujoco.MjData(locked)
    data.qpos[:] = locked.qpos0
    data.qpos[index.qpos_adr] = joint_q
    base = resting_base(model, index, joint_q, mount_quat)
    if mount_quat is not None:  # the world pose of the base the mount turns (the robot stands at the origin)
        base = mounted_pose(np.array([0.0, 0.0, 0.0, *np.asarray(mount_quat, dtype=np.float64)]), base)
    data.qpos[free.qpos_adr : free.qpos_adr + 7] = base
    with mujoco_messages(where):  # a diverging settle is reported below in its own words too
        for _ in range(round(STANCE_SETTLE_SECONDS / timestep)):
            mujoco.mj_step(locked, data)
    base_v = data.qvel[free.dof_adr : free.dof_adr + 6]  # the locked model adds a geom and equalities: same layout
    if not np.all(np.isfinite(data.qpos)):
        return f"the locked robot's simulation diverged within {STANCE_SETTLE_SECONDS:g} s"
    speed, turn = float(np.linalg.norm(base_v[:3])), float(np.linalg.norm(base_v[3:]))
    if speed > REST_SPEED or turn > REST_TURN:
        return (
            f"its body, joints locked at the keyframe, is not at rest on the floor after {STANCE_SETTLE_SECONDS:g} s "
            f"(base speed {speed:.3g} m/s, turning {turn:.3g} rad/s)"
        )
    floor = mujoco.mj_name2id(locked, mujoco.mjtObj.mjOBJ_GEOM, _FLOOR)
    below = {j.name: set(index.subtree_bodies(int(model.jnt_bodyid[j.id]))) for j in ids}
    legged = set().union(*below.values()) if below else set()
    contacts: list[tuple[int, float, FloatArray]] = []  # (body, normal force, point)
    force = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        if floor not in (contact.geom1, contact.geom2):
            continue
        other = contact.geom2 if contact.geom1 == floor else contact.geom1
        mujoco.mj_contactForce(locked, data, i, force)
        contacts.append((int(locked.geom_bodyid[other]), float(force[0]), contact.pos.copy()))
    if not contacts:
        return "nothing touches the floor"
    off = sorted({locked.body(b).name for b, _, _ in contacts if b not in legged})
    if off:
        return f"it rests on bodies its joints do not move ({', '.join(off)})"
    n = len(ids)
    load, lever, reflected, torque = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    for k, joint in enumerate(ids):
        lid = joint.id
        hinge = int(locked.jnt_type[lid]) == int(mujoco.mjtJoint.mjJNT_HINGE)
        anchor, axis = data.xanchor[lid], data.xaxis[lid]
        for body, normal, point in contacts:
            if body not in below[joint.name]:
                continue
            load[k] += normal
            if hinge:
                arm = point - anchor
                r = float(np.linalg.norm(arm - (arm @ axis) * axis))
                lever[k] += normal * r
                reflected[k] += normal * r * r / GRAVITY
            else:
                reflected[k] += normal / GRAVITY
        eq = mujoco.mj_name2id(locked, mujoco.mjtObj.mjOBJ_EQUALITY, f"{_LOCK}{k}")
        rows = (data.efc_type[: data.nefc] == int(mujoco.mjtConstraint.mjCNSTR_EQUALITY)) & (
            data.efc_id[: data.nefc] == eq
        )
        torque[k] = float(data.efc_force[: data.nefc][rows].sum())
    root = int(model.body_rootid[index.root_body_id])
    weight = float(locked.body_subtreemass[root]) * GRAVITY
    return Stance(
        joints=tuple(j.name for j in ids),
        torque=torque,
        load=load,
        lever=lever,
        reflected=reflected,
        feet=tuple(sorted({locked.body(b).name for b, _, _ in contacts})),
        weight=weight,
        qpos=np.array(data.qpos[index.qpos_adr]),
        base=np.array(data.qpos[free.qpos_adr : free.qpos_adr + 7]),
    )
