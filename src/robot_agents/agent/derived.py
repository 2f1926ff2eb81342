"""What a robot that declares little gets derived from its model: its parts (a serial
chain is an arm, two fingers, a mimic linkage or one jaw at its end a gripper), the
motors among its drives, body pairs already touching at its default pose, and where a
floating (or floor-crossing) robot rests on the floor."""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import replace

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.actuators.spec import DriveDeclaration, DriveKind
from robot_agents.agent.index import Coupling, JointKind, RobotIndex
from robot_agents.parts.declaration import Arm, Body, EndEffector, Gripper, Hand, Part, Torso

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


def _file_biases(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[tuple[str, np.ndarray]]:
    """Each joint driven by a model file's affine actuator, with that actuator's bias
    parameters (``[b0, -stiffness, -damping, ...]`` in actuator units)."""
    out = []
    for drive in drives:
        if drive.kind is not DriveKind.AFFINE or drive.source.startswith(DERIVED_SOURCE):
            continue
        actuator = joint_actuator(model, drive.joint)
        if actuator is not None:
            out.append((drive.joint, model.actuator_biasprm[actuator]))
    return out


def torque_only(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive is an affine actuator without stiffness or damping (a motor)."""
    return [joint for joint, bias in _file_biases(model, drives) if bias[1] == 0.0 and bias[2] == 0.0]


def velocity_servos(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive is a file's velocity servo (an affine actuator with
    damping and no stiffness: ``<velocity>``, robosuite's mobile bases). Such a drive
    follows velocity targets and cannot hold a position."""
    return [joint for joint, bias in _file_biases(model, drives) if bias[1] == 0.0 and bias[2] != 0.0]


def undamped(model: mujoco.MjModel, drives: Sequence[DriveDeclaration]) -> list[str]:
    """Driven joints whose drive has neither stiffness nor damping once a velocity mode
    relaxes its stiffness: an affine actuator (a file's ``<position>`` without ``kv``, a
    motor) or an explicit PD without damping, on a joint without damping of its own fed
    forward. Such a drive cannot follow velocity targets; MuJoCo's ``pid`` and
    ``dcmotor`` drives take velocity inputs and can, and so can a drive that feeds its
    joint's damping forward (``damping_feedforward``) where the declaration gives that
    damping (a motor's back-EMF declared as ``joint_damping``): it commands ``b qd*``,
    which meets the target where the joint's own damping ``b qd`` balances it (a
    voltage-driven motor's open-loop speed). A model file's own joint damping (a passive
    loss beside a ``<position>`` servo) does not count."""
    out = []
    for drive in drives:
        if drive.kind in (DriveKind.PID, DriveKind.DCMOTOR):
            continue
        damping = drive.damping
        if drive.kind is DriveKind.AFFINE and not drive.source.startswith(DERIVED_SOURCE):
            actuator = joint_actuator(model, drive.joint)
            damping = -float(model.actuator_biasprm[actuator, 2]) if actuator is not None else 0.0
        if drive.damping_feedforward:
            damping += drive.joint_damping
        if not damping > 0.0:
            out.append(drive.joint)
    return out


def infer_parts(
    model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str], grippers: bool = True
) -> tuple[Part, ...]:
    """Parts of a robot that declares none: its driven joints as one arm when they form
    a serial chain (each joint's body below the previous one's), with the chain's last
    body as the end effector; otherwise one ``Body`` part over all of them.

    Two fingers, a mimic linkage or one jaw at the chain's end are a ``Gripper`` (see
    :func:`infer_gripper`): the arm is the chain above them, its end effector ``"ee"`` on
    the hand at the gripper's tool point (two fingers and a linkage: the midpoint of the
    centres of the closed fingers' colliding geometry, :func:`_finger_centre`; one jaw:
    where it meets the fixed jaw). ``grippers=False``: no gripper is looked for (a
    mounted piece brings the robot's gripper)."""
    if not driven:
        return ()
    found = infer_gripper(model, index, driven) if grippers else None
    if found is not None:
        gripper, hand, tcp, count = found
        arm_joints = list(driven[: len(driven) - count])
        if not arm_joints:
            return (gripper,)
        bodies = [int(model.jnt_bodyid[index.joint(j, "infer_parts").id]) for j in arm_joints]
        if _serial(index, bodies) and int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, hand)) in (
            index.subtree_bodies(bodies[-1])
        ):
            torso, arm_joints = _split_lift(index, arm_joints)
            arm = Arm(
                name="arm",
                joints=tuple(re.escape(j) for j in arm_joints),
                end_effectors=(EndEffector(hand, name="ee", pos=tcp),),
            )
            return (arm, *torso, gripper)
    joints = [index.joint(j, "infer_parts") for j in driven]
    bodies = [int(model.jnt_bodyid[j.id]) for j in joints]
    patterns = tuple(re.escape(j) for j in driven)
    if not _serial(index, bodies):
        return (
            _arm_and_hand(model, index, list(driven), bodies)
            or _hand_alone(model, index, list(driven), bodies)
            or (Body(name="body", joints=patterns),)
        )
    tip = bodies[-1]
    while True:
        children = [b for b in range(tip + 1, model.nbody) if int(model.body_parentid[b]) == tip]
        if len(children) != 1:
            break
        tip = children[0]
    link = model.body(tip).name[len(index.prefix) :]
    torso, arm_joints = _split_lift(index, list(driven))
    arm = Arm(name="arm", joints=tuple(re.escape(j) for j in arm_joints), end_effectors=(EndEffector(link, name="ee"),))
    return (arm, *torso)


def _split_lift(index: RobotIndex, chain: list[str]) -> tuple[tuple[Part, ...], list[str]]:
    """A serial chain that starts with one slide and goes on with at least
    :data:`MIN_ARM_JOINTS` hinges: a mobile manipulator's torso lift under its arm
    (gymnasium-robotics' Fetch), a ``Torso`` part of the slide, and the arm
    the hinges. Anything else (a floating gripper's three slides, a telescope) stays
    the arm."""
    kinds = [index.joint(j, "infer_parts").kind for j in chain]
    if len(chain) > MIN_ARM_JOINTS and kinds[0] is JointKind.SLIDE and all(k is JointKind.HINGE for k in kinds[1:]):
        return (Torso(name="torso", joints=(re.escape(chain[0]),)),), chain[1:]
    return (), chain


#: The fewest joints of a serial chain inferred as an arm with a hand at its end, and
#: the most driven joints of one of that hand's fingers (the Allegro's: 4).
MIN_ARM_JOINTS = 3
MAX_FINGER_JOINTS = 5


def _arm_and_hand(
    model: mujoco.MjModel, index: RobotIndex, driven: list[str], bodies: list[int]
) -> tuple[Part, ...] | None:
    """An arm with a hand at its end, or ``None``: the driven joints (model order) from
    the first as far as they form a serial chain (at least :data:`MIN_ARM_JOINTS`) are
    the arm when every other driven joint lies below its last body, on two or more
    branches (fingers: serial, at most :data:`MAX_FINGER_JOINTS` driven joints each):
    those are one ``Hand`` part, ``"hand"``, and the arm's end
    effector ``"ee"`` is the palm, the deepest body above all of them (an arm file with
    a dexterous hand: the mani-skill wheel's ``xarm7_ability_right_hand.urdf``). A
    shorter serial start (one or two joints: a hand file's wrist, the Shadow hand's) is
    a ``Body`` part ``"wrist"`` beside the hand."""
    serial = 1
    while serial < len(bodies) and bodies[serial] in index.subtree_bodies(bodies[serial - 1]):
        serial += 1
    # the longest serial start below whose last body every other driven joint lies (the
    # chain may run on into the first finger: a thumb's joints follow the wrist's)
    count = next(
        (
            n
            for n in range(serial, 0, -1)
            if n < len(bodies) and set(bodies[n:]) <= set(index.subtree_bodies(bodies[n - 1]))
        ),
        0,
    )
    if not count:
        return None
    found = _palm_and_fingers(model, index, bodies[count:])
    if found is None:
        return None
    palm, fingers = found
    hand = _hand(model, index, driven[count:], palm, fingers)
    if hand is None:
        return None
    joints = tuple(re.escape(j) for j in driven[:count])
    if count < MIN_ARM_JOINTS:
        return (hand, Body(name="wrist", joints=joints))
    arm = Arm(
        name="arm", joints=joints, end_effectors=(EndEffector(model.body(palm).name[len(index.prefix) :], name="ee"),)
    )
    return (arm, hand)


def _hand_alone(model: mujoco.MjModel, index: RobotIndex, driven: list[str], bodies: list[int]) -> tuple[Part] | None:
    """A hand without an arm (a fixed or floating hand file: the mani-skill wheel's
    Allegro and Ability hands), or ``None``: every driven joint lies on one of two or
    more short serial fingers below one palm (:func:`_palm_and_fingers`)."""
    found = _palm_and_fingers(model, index, bodies)
    hand = None if found is None else _hand(model, index, driven, *found)
    return None if hand is None else (hand,)


def _palm_and_fingers(
    model: mujoco.MjModel, index: RobotIndex, bodies: list[int]
) -> tuple[int, list[list[int]]] | None:
    """The palm (the deepest body above every one of ``bodies``, the bodies of a hand's
    driven joints, and none of them) and each finger's driven-joint bodies (one list per
    branch below the palm, base to tip), or ``None`` unless there are two or more
    fingers, each a short serial chain (at most :data:`MAX_FINGER_JOINTS` driven
    joints: an arm and a head below a torso, or a gripper on its arm, are not)."""
    palm = bodies[0]
    while not set(bodies) <= set(index.subtree_bodies(palm)) or palm in bodies:
        palm = int(model.body_parentid[palm])
    fingers = []
    for child in (b for b in range(palm + 1, model.nbody) if int(model.body_parentid[b]) == palm):
        below = set(index.subtree_bodies(child))
        chain = [b for b in bodies if b in below]
        if chain:
            fingers.append(chain)
    if len(fingers) < 2 or any(len(f) > MAX_FINGER_JOINTS or not _serial(index, f) for f in fingers):
        return None
    return palm, fingers


#: A hand joint closes to the end of its range that, turned alone from the open pose,
#: brings its finger's tip nearer the palm by at least this share of the tip's distance
#: from the joint: a flexion, which curls the finger in (0.29-1.36 of that distance on the
#: mani-skill wheel's Allegro and Ability hands); a spread (abduction) moves the tip
#: across (0.0 there; the Allegro thumb's rotation 0.13) and stays open.
CURL_SHARE = 0.2


#: The longest finger a derived hand has (m, from its first joint to its tip at the open
#: pose): a dexterous hand's are 0.05-0.2 (the mani-skill wheel's Allegro 0.14); longer
#: branches are legs (a quadruped's, 0.3-0.5, below its trunk) or arms.
MAX_FINGER_LENGTH = 0.25


def _hand(
    model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str], palm: int, fingers: list[list[int]]
) -> Hand | None:
    """A derived ``Hand`` over ``driven`` (its joints, model order): ``open`` the
    default pose, ``closed`` each finger curled in: each joint at the end of its range
    that, the joint turned there alone from the open pose, brings the finger's tip (the
    centre of its deepest colliding body's geoms) nearer the palm's centre (its
    colliding geoms', else its centre of mass) by :data:`CURL_SHARE` of the tip's
    distance from the joint or more, else open (a spread); ``fingers`` the bodies with
    colliding geoms of each branch. ``None`` when a finger is longer than
    :data:`MAX_FINGER_LENGTH`, or fewer than two fingers close (a grasp needs two)."""
    from robot_agents.keyframe import default_qpos  # (keyframe imports the agent package)

    where = "infer_parts"
    data = mujoco.MjData(model)
    ids = [index.joint(j, where).id for j in driven]
    qpos = model.qpos0.copy()
    qpos[index.qpos_adr] = default_qpos(index)
    opened = {j: float(qpos[model.jnt_qposadr[j]]) for j in ids}
    closed = dict(opened)
    followers = [(index.joint(c.follower, where).id, index.joint(c.leader, where).id, c) for c in index.couplings]

    def tip_to_palm(tip: int, joint: int | None = None, value: float = 0.0) -> float:
        """The tip's distance from the palm's centre (m), ``joint`` turned to ``value``."""
        data.qpos[:] = qpos
        if joint is not None:
            data.qpos[model.jnt_qposadr[joint]] = value
            for follower, leader, coupling in followers:
                if leader == joint:
                    data.qpos[model.jnt_qposadr[follower]] = coupling.follow(value)
        mujoco.mj_kinematics(model, data)
        return float(np.linalg.norm(_geoms_centre(model, data, tip) - _geoms_centre(model, data, palm)))

    finger_links, closing = [], 0
    for chain in fingers:
        branch = [b for b in index.subtree_bodies(chain[0]) if colliding_geoms(model, [b])] or [chain[-1]]
        finger_links.append(tuple(model.body(b).name[len(index.prefix) :] for b in branch))
        tip = max(branch, key=lambda b: (_depth(model, b), b))
        on_finger = set(chain)
        finger_joints = [j for j in ids if int(model.jnt_bodyid[j]) in on_finger]  # base to tip
        tip_to_palm(tip)  # (data at the open pose)
        if np.linalg.norm(_geoms_centre(model, data, tip) - data.xanchor[finger_joints[0]]) > MAX_FINGER_LENGTH:
            return None
        for joint in finger_joints:
            if not model.jnt_limited[joint]:
                continue
            at_open = tip_to_palm(tip)  # (and data at the open pose)
            lever = float(np.linalg.norm(_geoms_centre(model, data, tip) - data.xanchor[joint]))
            ends = [float(v) for v in model.jnt_range[joint]]
            distances = [tip_to_palm(tip, joint, v) for v in ends]
            best = int(np.argmin(distances))
            if at_open - distances[best] >= CURL_SHARE * lever:
                closed[joint] = ends[best]
        closing += any(closed[j] != opened[j] for j in finger_joints)
    if closing < 2:
        return None
    return Hand(
        name="hand",
        joints=tuple(re.escape(j) for j in driven),
        open=tuple(opened[j] for j in ids),
        closed=tuple(closed[j] for j in ids),
        fingers=tuple(finger_links),
    )


def _geoms_centre(model: mujoco.MjModel, data: mujoco.MjData, body: int) -> np.ndarray:
    """The centre (m, world) of the box around ``body``'s own colliding geoms at
    ``data``'s pose, else its centre of mass."""
    return _colliding_centre(model, data, [body], body)


def _colliding_centre(model: mujoco.MjModel, data: mujoco.MjData, bodies: Iterable[int], body: int) -> np.ndarray:
    """The centre (world, m) of the box around the colliding geoms of ``bodies``, as
    ``data`` places them; ``body``'s centre of mass when none of them collides."""
    boxes = [world_box(model, data, geom) for geom in colliding_geoms(model, bodies)]
    if not boxes:
        return np.array(data.xipos[body])
    lower = np.min([low for low, _ in boxes], axis=0)
    upper = np.max([high for _, high in boxes], axis=0)
    return np.asarray(0.5 * (lower + upper))


def _depth(model: mujoco.MjModel, body: int) -> int:
    """How many bodies lie between ``body`` and the world."""
    depth = 0
    while body > 0:
        body, depth = int(model.body_parentid[body]), depth + 1
    return depth


def _serial(index: RobotIndex, bodies: Sequence[int]) -> bool:
    """Each body below the previous one."""
    return all(b in index.subtree_bodies(a) for a, b in itertools.pairwise(bodies))


#: Joint types a gripper's fingers may move on.
_HINGE_OR_SLIDE = (int(mujoco.mjtJoint.mjJNT_SLIDE), int(mujoco.mjtJoint.mjJNT_HINGE))
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

    When these find none: a linkage, the last driven joint leading two or more undriven
    followers (:func:`_linkage_gripper`), or one jaw, the last driven joint a hinge
    coupled to nothing that turns a jaw against a fixed jaw on its parent
    (:func:`_one_jaw_gripper`); each takes one driven joint.
    Returns the part, the hand's name, the tool point in the hand's frame (m: the closed
    fingers' midpoint, or where one jaw meets the fixed jaw) and how many driven joints
    the gripper takes (1 or 2)."""
    names = list(driven)
    last = index.joint(names[-1], "infer_gripper")
    candidates: list[tuple[list[int], int, dict[int, Coupling]]] = []
    # joints coupled to the last by an active joint equality (a URDF mimic): the index's couplings
    followers = [c for c in index.couplings if c.leader == last.name]
    if followers:
        follower = index.joint(followers[0].follower, "infer_gripper").id
        candidates.append(([last.id, follower], 1, {follower: followers[0]}))
    if len(names) >= 2:
        candidates.append(([index.joint(names[-2], "infer_gripper").id, last.id], 2, {}))
    for ids, count, coupled in candidates:
        found = _gripper_of(model, index, ids, coupled)
        if found is not None:
            gripper, hand, tcp = found
            return _file_squeeze(model, gripper, ids[:count]), hand, tcp, count
    linked = [c for c in index.couplings if last.name in (c.leader, c.follower)]
    later = _linkage_gripper(model, index, names, last.id, followers) if len(followers) >= 2 else None
    if later is None and not linked:
        later = _one_jaw_gripper(model, index, last.id)
    if later is not None:
        gripper, hand, tcp = later
        return _file_squeeze(model, gripper, [last.id]), hand, tcp, 1
    return None


def _file_squeeze(model: mujoco.MjModel, gripper: Gripper, driven: Sequence[int]) -> Gripper:
    """``gripper`` with the squeeze its file's own position servos command: where each of
    its driven joints ``driven`` (ids, in the order of ``gripper.open``) has a model file's
    position actuator whose control range reaches past ``closed`` farther than
    :data:`DERIVED_SQUEEZE` of the stroke, the close commands as far as every one of them
    reaches (the leader's units: a follower's reach over its share of the stroke).

    A file may write its fingers' targets past their travel so that they close with the
    servo's full force: Meta-World 3.1.1's Sawyer (``sawyer_xyz`` files) gives fingers of
    3 and 4 cm travel ``kp`` 400, 100 kg of armature and 1000 N*s/m of damping, and a
    control range of +-1 m. With the derived squeeze (4 mm) its empty gripper took 4.1 s
    to close (opening under 0.05, from the task's reset); with its file's (0.96 m) 0.15
    s. A gripper with any other driven joint (a derived drive has no control range)
    keeps the derived squeeze."""
    open_at, closed_at = gripper.positions(len(gripper.joints))
    span = float(open_at[0] - closed_at[0])
    reach = math.inf
    for k, joint in enumerate(driven):
        actuator = joint_actuator(model, model.joint(joint).name)
        if actuator is None or not _file_position_servo(model, actuator):
            return gripper
        gear = float(model.actuator_gear[actuator, 0])
        targets = model.actuator_ctrlrange[actuator] / gear
        opened, closed = float(open_at[k]), float(closed_at[k])
        past = closed - float(np.min(targets)) if opened > closed else float(np.max(targets)) - closed
        share = abs((opened - closed) / span)
        reach = min(reach, past / share) if share > 0.0 else reach
    if math.isfinite(reach) and reach > gripper.squeeze:
        return replace(gripper, squeeze=reach)
    return gripper


def _file_position_servo(model: mujoco.MjModel, actuator: int) -> bool:
    """Whether ``actuator`` is a position servo with a control range (a file's
    ``<position ctrlrange=...>``: affine, its gain the stiffness its bias takes back,
    a nonzero gear). The library's derived drives set no control range."""
    gain, bias = model.actuator_gainprm[actuator], model.actuator_biasprm[actuator]
    return bool(
        model.actuator_ctrllimited[actuator]
        and int(model.actuator_gaintype[actuator]) == int(mujoco.mjtGain.mjGAIN_FIXED)
        and int(model.actuator_biastype[actuator]) == int(mujoco.mjtBias.mjBIAS_AFFINE)
        and bias[1] < 0.0
        and np.isclose(gain[0], -bias[1])
        and model.actuator_gear[actuator, 0] != 0.0
    )


def _gripper_of(
    model: mujoco.MjModel, index: RobotIndex, ids: list[int], coupled: dict[int, Coupling]
) -> tuple[Gripper, str, tuple[float, float, float]] | None:
    """The gripper of two finger joints ``ids`` (the second may follow the first through
    its ``coupled`` coupling), or ``None`` when they are not two opposing fingers."""
    kinds = {int(model.jnt_type[j]) for j in ids}
    if len(kinds) != 1 or kinds.pop() not in _HINGE_OR_SLIDE:
        return None
    if not all(model.jnt_limited[j] for j in ids):
        return None
    bodies = [int(model.jnt_bodyid[j]) for j in ids]
    parents = {int(model.body_parentid[b]) for b in bodies}
    if len(parents) != 1 or bodies[0] == bodies[1]:
        return None
    hand = parents.pop()
    data = mujoco.MjData(model)

    def spread(values: dict[int, float]) -> float:
        _place(model, data, values, ids[0], coupled)
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
    for follower, coupling in coupled.items():
        opened[follower] = coupling.follow(opened[ids[0]])
        closed[follower] = coupling.follow(closed[ids[0]])
    _place(model, data, closed, ids[0], coupled)
    midpoint = 0.5 * (_finger_centre(model, data, index, bodies[0]) + _finger_centre(model, data, index, bodies[1]))
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
    return gripper, model.body(hand).name[prefix:], _rounded(tcp)


def _finger_centre(model: mujoco.MjModel, data: mujoco.MjData, index: RobotIndex, body: int) -> np.ndarray:
    """The centre (world, m) of the box around a finger's colliding geoms (its body and
    the bodies below it), as ``data`` places them: the middle of its pads, where a
    grasp holds an object; the finger's centre of mass when nothing on it collides."""
    return _colliding_centre(model, data, index.subtree_bodies(body), body)


#: How close to the fixed jaw a one-jaw gripper's moving jaw must close, as a share of
#: its tip's gap when open: the tip of a jaw closes onto the fixed jaw, an elbow or a
#: wrist that turns past its neighbour link does not come that close.
JAW_CLOSED_SHARE = 0.25
#: Points per edge of the grid sampled on a primitive geom's surface (a box's faces, a
#: cylinder's or capsule's side) to measure distances between geometries.
_SURFACE_GRID = 9
#: Positions over a one-jaw gripper's range at which its gap must shrink steadily.
_JAW_SAMPLES = 9
#: How much a one-jaw gripper's gap may grow between two of those positions, as a share
#: of its open gap: a jaw that opens a little past its widest (the SO-100's file: 75.8 mm
#: at 0.9 rad, 72.3 mm at its 1.1 rad stop) still closes steadily; an elbow sweeping its
#: tip past the fixed link does not (its gap grows by more).
JAW_WIDENING_SHARE = 0.1


def _linkage_gripper(
    model: mujoco.MjModel, index: RobotIndex, driven: Sequence[str], leader: int, followers: Sequence[Coupling]
) -> tuple[Gripper, str, tuple[float, float, float]] | None:
    """The linkage gripper of joint ``leader`` (a driven joint) and the undriven joints
    that follow it (``followers``: their couplings, e.g. URDF mimics), or ``None``.

    The hand is the deepest body above every one of these joints' bodies that none of
    them moves; the joints below it must be exactly these. The fingers are the two
    bodies (with collision geometry in their subtrees), below different children of the
    hand, whose centres of mass's distance changes most over the leader's range: with a
    four-bar or any other linkage, the links that carry the pads (a knuckle's centre of
    mass, nearer its hinge, moves less). ``open`` is the
    leader's end where they are farthest apart, each follower's ``open`` / ``closed``
    its coupling's value there. Returns the part, the hand's name and the closed fingers'
    midpoint in the hand's frame (m)."""
    where = "infer_gripper"
    ids = [leader, *sorted(index.joint(c.follower, where).id for c in followers)]
    if any(int(model.jnt_type[j]) not in _HINGE_OR_SLIDE for j in ids) or not model.jnt_limited[leader]:
        return None
    prefix = len(index.prefix)
    if any(model.joint(j).name[prefix:] in driven for j in ids[1:]):
        return None  # a follower with its own drive: not a passive linkage
    coupled = {index.joint(c.follower, where).id: c for c in followers}
    moved = {int(model.jnt_bodyid[j]) for j in ids}
    hand = int(model.body_parentid[model.jnt_bodyid[leader]])
    while hand > 0 and (hand in moved or not moved <= set(index.subtree_bodies(hand))):
        hand = int(model.body_parentid[hand])
    if hand <= 0:
        return None
    below = [b for b in index.subtree_bodies(hand) if b != hand]
    if any(int(model.jnt_bodyid[j.id]) in below and j.id not in ids for j in index.joints):
        return None  # other joints below the hand: ambiguous
    data = mujoco.MjData(model)

    def place(value: float) -> np.ndarray:
        """The bodies' centres of mass (world, m) with the leader at ``value``."""
        _place(model, data, {leader: value}, leader, coupled)
        return np.array(data.xipos, dtype=np.float64)

    def branch(body: int) -> int:
        while int(model.body_parentid[body]) != hand:
            body = int(model.body_parentid[body])
        return body

    solid = [b for b in below if any(colliding_geoms(model, index.subtree_bodies(b)))]
    low, high = (float(v) for v in model.jnt_range[leader])
    at_low, at_high = place(low), place(high)
    best: tuple[float, int, int] | None = None
    for a, b in itertools.combinations(solid, 2):
        if branch(a) == branch(b):
            continue
        change = float(np.linalg.norm(at_high[a] - at_high[b]) - np.linalg.norm(at_low[a] - at_low[b]))
        if best is None or abs(change) > abs(best[0]):
            best = (change, a, b)
    if best is None or abs(best[0]) < MIN_FINGER_STROKE:
        return None
    change, first, second = best
    opened, closed = (high, low) if change > 0 else (low, high)
    place(closed)
    rotation = data.xmat[hand].reshape(3, 3)
    middle = 0.5 * (_finger_centre(model, data, index, first) + _finger_centre(model, data, index, second))
    tcp = rotation.T @ (middle - data.xpos[hand])
    ends = [(opened, closed)] + [(coupled[j].follow(opened), coupled[j].follow(closed)) for j in ids[1:]]
    gripper = Gripper(
        name="gripper",
        joints=tuple(re.escape(model.joint(j).name[prefix:]) for j in ids),
        open=tuple(o for o, _ in ends),
        closed=tuple(c for _, c in ends),
        squeeze=DERIVED_SQUEEZE * abs(opened - closed),
        fingers=tuple(
            tuple(model.body(b).name[prefix:] for b in index.subtree_bodies(finger)) for finger in (first, second)
        ),
    )
    return gripper, model.body(hand).name[prefix:], _rounded(tcp)


def _one_jaw_gripper(
    model: mujoco.MjModel, index: RobotIndex, joint: int
) -> tuple[Gripper, str, tuple[float, float, float]] | None:
    """The one-jaw gripper of hinge ``joint`` (coupled to no other joint), or ``None``:
    a moving jaw (the joint's body and what is fixed to it) that turns against a fixed
    jaw on its parent (the hand: the parent body and what is fixed to it; no other joint
    below it). Both need collision geometry.

    The jaw's tip is the point of its geometry farthest from the hinge's axis; its gap
    is the distance from the tip to the nearest point of the fixed jaw's geometry (mesh
    vertices, points on primitive surfaces). ``closed`` is the end of the range where
    the gap is smallest, ``open`` the other. It is a gripper when the range is less than
    half a turn (a wrist or a flange turns more), the gap shrinks by at least
    :data:`MIN_FINGER_STROKE` to at most :data:`JAW_CLOSED_SHARE` of the open gap, and
    steadily (it grows by less than :data:`MIN_FINGER_STROKE`, or :data:`JAW_WIDENING_SHARE`
    of the open gap, between any two of :data:`_JAW_SAMPLES` positions from open to
    closed), and the closed tip is farther
    from the hand's origin than the hinge (the jaw closes forward, onto a fixed jaw past
    the hinge, not back onto the link it hangs from).
    Returns the part, the hand's name and the point where the closed jaws meet (the
    closed tip and its nearest fixed point's midpoint, moved along the axis to the
    middle of the jaw's width) in the hand's frame (m)."""
    if int(model.jnt_type[joint]) != int(mujoco.mjtJoint.mjJNT_HINGE) or not model.jnt_limited[joint]:
        return None
    if float(np.ptp(model.jnt_range[joint])) >= math.pi:
        return None  # it turns half a turn or more: a wrist or a flange, not a jaw
    mover = int(model.jnt_bodyid[joint])
    hand = int(model.body_parentid[mover])
    if hand <= 0:
        return None
    moving = index.subtree_bodies(mover)
    fixed = [b for b in index.subtree_bodies(hand) if b not in moving]
    if any(int(model.jnt_bodyid[j.id]) in moving + fixed[1:] and j.id != joint for j in index.joints):
        return None  # another joint on the jaw or beside it: not one jaw
    moving_geoms, fixed_geoms = colliding_geoms(model, moving), colliding_geoms(model, fixed)
    if not moving_geoms or not fixed_geoms:
        return None
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    mujoco.mj_kinematics(model, data)
    jaw = _world_points(model, data, moving_geoms)
    axis, anchor = data.xaxis[joint].copy(), data.xanchor[joint].copy()
    arm = jaw - anchor
    radius = np.linalg.norm(arm - np.outer(arm @ axis, axis), axis=1)
    rotation = data.xmat[mover].reshape(3, 3)
    far = int(np.argmax(radius))
    tip_local = rotation.T @ (jaw[far] - data.xpos[mover])
    along = arm @ axis
    centring = 0.5 * (along.min() + along.max()) - along[far]  # from the tip to the middle of the jaw's width (m)
    fixed_points = _world_points(model, data, fixed_geoms)  # the joint does not move them

    def gap(value: float) -> tuple[float, np.ndarray, np.ndarray]:
        """The tip's distance to the fixed jaw (m), the tip and its nearest fixed point."""
        data.qpos[model.jnt_qposadr[joint]] = value
        mujoco.mj_kinematics(model, data)
        tip = data.xpos[mover] + data.xmat[mover].reshape(3, 3) @ tip_local
        distances = np.linalg.norm(fixed_points - tip, axis=1)
        nearest = int(np.argmin(distances))
        return float(distances[nearest]), tip, fixed_points[nearest]

    low, high = (float(v) for v in model.jnt_range[joint])
    (gap_low, *_), (gap_high, *_) = gap(low), gap(high)
    opened, closed = (low, high) if gap_low > gap_high else (high, low)
    gap_open, gap_closed = max(gap_low, gap_high), min(gap_low, gap_high)
    if gap_open - gap_closed < MIN_FINGER_STROKE or gap_closed > JAW_CLOSED_SHARE * gap_open:
        return None
    gaps = [gap(float(v))[0] for v in np.linspace(opened, closed, _JAW_SAMPLES)]
    slack = max(MIN_FINGER_STROKE, JAW_WIDENING_SHARE * gap_open)
    if any(later > earlier + slack for earlier, later in itertools.pairwise(gaps)):
        return None  # the tip does not close steadily onto the fixed jaw
    _, tip, nearest = gap(closed)
    origin = data.xpos[hand]
    if np.linalg.norm(tip - origin) <= np.linalg.norm(data.xanchor[joint] - origin):
        return None  # the jaw folds back onto the link it hangs from: an elbow, not a jaw
    hand_rotation = data.xmat[hand].reshape(3, 3)
    tcp = hand_rotation.T @ (0.5 * (tip + nearest) + centring * data.xaxis[joint] - origin)
    prefix = len(index.prefix)
    gripper = Gripper(
        name="gripper",
        joints=(re.escape(model.joint(joint).name[prefix:]),),
        open=(opened,),
        closed=(closed,),
        squeeze=DERIVED_SQUEEZE * abs(opened - closed),
        fingers=(tuple(model.body(b).name[prefix:] for b in moving), tuple(model.body(b).name[prefix:] for b in fixed)),
    )
    return gripper, model.body(hand).name[prefix:], _rounded(tcp)


def _place(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    values: Mapping[int, float],
    leader: int,
    coupled: Mapping[int, Coupling],
) -> None:
    """``data`` at the model's reference pose with the joints ``values`` (joint id ->
    rad or m) set and each ``coupled`` follower (joint id -> its coupling) where its
    coupling puts it for ``leader``'s value; body poses and centres of mass computed."""
    data.qpos[:] = model.qpos0
    for joint, value in values.items():
        data.qpos[model.jnt_qposadr[joint]] = value
    if leader in values:
        for follower, coupling in coupled.items():
            data.qpos[model.jnt_qposadr[follower]] = coupling.follow(values[leader])
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)


def _rounded(point: np.ndarray) -> tuple[float, float, float]:
    """A point (m) rounded to the nanometre."""
    return (round(float(point[0]), 9), round(float(point[1]), 9), round(float(point[2]), 9))


def random_configurations(
    model: mujoco.MjModel,
    index: RobotIndex,
    joints: Sequence[str],
    reference: np.ndarray,
    count: int,
    where: str,
    seed: int = 0,
) -> np.ndarray:
    """``(count, nq)`` copies of ``reference`` (the model's ``qpos``) with each hinge and
    slide of ``joints`` drawn uniformly within its limits (``seed``, in the order given:
    the same draws every time), ``±pi`` for an unlimited hinge; an unlimited slide
    keeps its reference value, and so does a ball joint. ``where``: the caller, for
    messages."""
    rng = np.random.default_rng(seed)
    out = np.tile(reference, (count, 1))
    for name in joints:
        joint = index.joint(name, where)
        j = joint.id
        if joint.kind not in (JointKind.HINGE, JointKind.SLIDE):
            continue  # a ball joint's range is an angle, not a qpos entry's
        if model.jnt_limited[j]:
            low, high = model.jnt_range[j]
        elif joint.kind is JointKind.HINGE:
            low, high = -np.pi, np.pi
        else:
            continue
        out[:, model.jnt_qposadr[j]] = rng.uniform(low, high, count)
    return out


def colliding_geoms(model: mujoco.MjModel, bodies: Iterable[int]) -> list[int]:
    """The geoms of ``bodies`` (body ids) that collide (a nonzero ``contype`` or
    ``conaffinity``), in model order."""
    chosen = set(bodies)
    return [
        g
        for g in range(model.ngeom)
        if int(model.geom_bodyid[g]) in chosen and (model.geom_contype[g] or model.geom_conaffinity[g])
    ]


def geom_box(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A geom's bounding box (MuJoCo's ``geom_aabb``, in the geom's frame) as ``data``
    places it: its centre in the world ``(3,)`` (m), the rotation of its axes ``(3, 3)``
    and its half sizes ``(3,)`` (m)."""
    rotation = data.geom_xmat[geom].reshape(3, 3)
    return data.geom_xpos[geom] + rotation @ model.geom_aabb[geom, :3], rotation, model.geom_aabb[geom, 3:]


def world_box(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> tuple[np.ndarray, np.ndarray]:
    """The world axis-aligned box (lower, upper corners, m) around a geom's
    :func:`geom_box` as ``data`` places it."""
    centre, rotation, half = geom_box(model, data, geom)
    extent = np.abs(rotation) @ half
    return centre - extent, centre + extent


def _world_points(model: mujoco.MjModel, data: mujoco.MjData, geoms: Sequence[int]) -> np.ndarray:
    """Points on the surfaces of ``geoms`` in the world (m, ``(n, 3)``) after kinematics."""
    out = [data.geom_xpos[g] + _surface_points(model, g) @ data.geom_xmat[g].reshape(3, 3).T for g in geoms]
    return np.concatenate(out) if out else np.zeros((0, 3))


def _surface_points(model: mujoco.MjModel, geom: int) -> np.ndarray:
    """Points on the surface of ``geom`` in its own frame (m, ``(n, 3)``): a mesh's
    vertices; a grid of :data:`_SURFACE_GRID` points per edge on a box's faces and on a
    sphere's, capsule's, cylinder's or ellipsoid's surface; the corners and face grids
    of the bounding box of anything else."""
    kind = int(model.geom_type[geom])
    size = model.geom_size[geom]
    if kind == int(mujoco.mjtGeom.mjGEOM_MESH):
        mesh = int(model.geom_dataid[geom])
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        return np.asarray(model.mesh_vert[start : start + count], dtype=np.float64)
    n = _SURFACE_GRID
    t = np.linspace(-1.0, 1.0, n)
    angles = np.linspace(0.0, 2.0 * math.pi, 2 * n, endpoint=False)
    ring = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    if kind in (int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_ELLIPSOID)):
        polar = np.linspace(0.0, math.pi, n)
        unit = np.array([(math.sin(p) * c, math.sin(p) * s, math.cos(p)) for p in polar for c, s in ring])
        scale = size[:3] if kind == int(mujoco.mjtGeom.mjGEOM_ELLIPSOID) else np.full(3, size[0])
        return np.asarray(unit * scale, dtype=np.float64)
    if kind in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)):
        radius, half = float(size[0]), float(size[1])
        side = np.array([(radius * c, radius * s, half * z) for z in t for c, s in ring])
        if kind == int(mujoco.mjtGeom.mjGEOM_CAPSULE):
            polar = np.linspace(0.0, math.pi / 2, n)
            cap = np.array(
                [
                    (radius * math.sin(p) * c, radius * math.sin(p) * s, radius * math.cos(p))
                    for p in polar
                    for c, s in ring
                ]
            )
            lift = np.array([0.0, 0.0, half])
            ends = [cap + lift, cap * (1.0, 1.0, -1.0) - lift]
        else:
            disk = np.array([(radius * r * c, radius * r * s, 0.0) for r in np.linspace(0.0, 1.0, n) for c, s in ring])
            lift = np.array([0.0, 0.0, half])
            ends = [disk + lift, disk - lift]
        return np.concatenate([side, *ends])
    if kind == int(mujoco.mjtGeom.mjGEOM_BOX):
        centre, half_size = np.zeros(3), np.asarray(size[:3], dtype=np.float64)
    else:
        centre, half_size = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
    grid = np.array([(u, v) for u in t for v in t])
    faces = []
    for k in range(3):
        others = [i for i in range(3) if i != k]
        for sign in (-1.0, 1.0):
            face = np.zeros((len(grid), 3))
            face[:, k] = sign
            face[:, others] = grid
            faces.append(face)
    return centre + np.concatenate(faces) * half_size


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
    return float(world_box(model, data, geom)[0][2])


def resting_base(
    model: mujoco.MjModel,
    index: RobotIndex,
    qpos: np.ndarray,
    mount_quat: npt.ArrayLike | None = None,
    key: int = 0,
) -> np.ndarray:
    """A floating robot's base pose ``(7,)`` at ``qpos`` that puts its lowest colliding
    geom 1 mm above the floor (z = 0), at the origin, in the file's root orientation
    (:func:`file_root_orientation`; ``key``: of the file's keyframe at that place, from 0).

    ``mount_quat`` ``(4,)`` (w, x, y, z): the orientation of the mount the base pose is
    relative to (a scene composes mount and base, :meth:`JointState.keyframe_base`). The
    lowest point is then found with the robot turned by the mount (a file drawn y-up
    stands upright under a mount turned +90 deg about x), and the returned position is in
    the mount's frame, so that the composed base still rests 1 mm above the floor. A fixed
    robot's (no free joint) is the world position of the mount at the origin, turned by
    ``mount_quat``, that rests it 1 mm above the floor."""
    data = mujoco.MjData(model)
    data.qpos[index.qpos_adr] = qpos
    free = index.free_joint
    quat = np.array([1.0, 0.0, 0.0, 0.0])
    turned = mount_quat is not None and not np.array_equal(np.asarray(mount_quat, dtype=np.float64), quat)
    if free is not None:
        quat = file_root_orientation(model, free.qpos_adr, key)
        data.qpos[free.qpos_adr : free.qpos_adr + 7] = (0.0, 0.0, 0.0, *quat)
        if turned:
            mujoco.mju_mulQuat(data.qpos[free.qpos_adr + 3 : free.qpos_adr + 7], np.asarray(mount_quat, float), quat)
    mujoco.mj_kinematics(model, data)
    if turned and free is None:  # a fixed robot's geoms as its turned mount places them
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, np.asarray(mount_quat, dtype=np.float64))
        turn = rotation.reshape(3, 3)
        data.geom_xpos[:] = data.geom_xpos @ turn.T
        data.geom_xmat[:] = (turn @ data.geom_xmat.reshape(-1, 3, 3)).reshape(-1, 9)
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
    position = np.array([0.0, 0.0, height])
    if turned and free is not None:  # (0, 0, height) in the world, written in the mount's frame
        inverse = np.empty(4)
        mujoco.mju_negQuat(inverse, np.asarray(mount_quat, float))
        mujoco.mju_rotVecQuat(position, np.array([0.0, 0.0, height]), inverse)
    return np.array([*position, *quat])


def file_root_orientation(model: mujoco.MjModel, qpos_adr: int, key: int = 0) -> np.ndarray:
    """The unit quaternion ``(w, x, y, z)`` a model file gives its free root: its
    keyframe's at place ``key`` (from 0; the first by default), else the compiled
    reference (``qpos0``: the root body's ``quat`` / ``euler`` composed with the free
    joint's own reference)."""
    source = model.key_qpos[key] if model.nkey > key else model.qpos0
    quat = np.array(source[qpos_adr + 3 : qpos_adr + 7], dtype=np.float64)
    norm = float(np.linalg.norm(quat))
    return quat / norm if np.isfinite(norm) and norm > 1e-9 else np.array([1.0, 0.0, 0.0, 0.0])
