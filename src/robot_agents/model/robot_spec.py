"""Edit a robot's MjSpec according to its declaration: root joint, gravity
compensation, friction materials and self-collision filtering (actuators are
:mod:`robot_agents.actuators`). Every name is checked; an unknown one lists what is
available."""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Iterable, Mapping, Sequence

import mujoco
import numpy as np

from robot_agents.errors import ModelError, UnknownNameError
from robot_agents.model.compiler import range_limited
from robot_agents.model.dropping import drop_with_dependents
from robot_agents.model.materials import PAD_SOLIMP, PAD_SOLREF, FrictionMaterial, set_contact_softness

#: Name of the free joint added to a free-floating robot's root body.
ROOT_FREE_JOINT = "root_free_joint"


def robot_bodies(spec: mujoco.MjSpec) -> list[mujoco.MjsBody]:
    """Every body of the robot (its single top-level tree), root first."""
    return list(spec.worldbody.find_all(mujoco.mjtObj.mjOBJ_BODY))


def root_body(spec: mujoco.MjSpec, where: str) -> mujoco.MjsBody:
    """The robot's root body; a robot model must have exactly one top-level body."""
    tops: list[mujoco.MjsBody] = []
    body = spec.worldbody.first_body()
    while body is not None:
        tops.append(body)
        body = spec.worldbody.next_body(body)
    if not tops:
        raise ModelError(
            f"{where}: expected the robot model to have a body, got none: its <worldbody> holds no <body> (a file "
            "of assets or defaults for others to include is no robot)."
        )
    if len(tops) != 1:
        raise ModelError(
            f"{where}: expected the robot model to have exactly one top-level body, got {len(tops)}: "
            f"{[b.name for b in tops]}."
        )
    return tops[0]


def _top_bodies(spec: mujoco.MjSpec) -> list[mujoco.MjsBody]:
    tops: list[mujoco.MjsBody] = []
    body = spec.worldbody.first_body()
    while body is not None:
        tops.append(body)
        body = spec.worldbody.next_body(body)
    return tops


def isolate_robot(spec: mujoco.MjSpec, chosen: str | None, where: str) -> list[str]:
    """Keep only the robot in a model file: one top-level body and its subtree.

    A file may carry more than the robot: a floor or an arena as world geoms (dropped:
    the scene has its own floor), or other top-level bodies such as a target marker.
    With several top-level bodies the robot is ``chosen`` (the robot's ``root_body``),
    else the one whose subtree holds the file's actuated joints (or, without
    actuators, the most joints). What refers to a dropped body or world geom (sensors,
    actuators, tendons, equalities, contact pairs, ...) goes with it, and a camera or
    light that targets a dropped body becomes fixed (:mod:`robot_agents.model.dropping`);
    each dropped body and element is named in one warning. An ambiguous file raises
    :class:`ModelError` naming the bodies and the fix.

    Returns the joints the file moved through a mocap body it welds (or connects) to one
    of the robot's bodies, a mocap body that goes with the dropped ones (gymnasium-
    robotics' Fetch and Meta-World's Sawyer move their hand so): the joints from the
    robot's root to each such body, which nothing drives once the weld is gone."""
    world_geoms = list(spec.worldbody.geoms)
    tops = _top_bodies(spec)
    if len(tops) <= 1 and chosen is None:
        report = drop_with_dependents(spec, [], world_geoms)
        if report.dropped or report.fixed:
            warnings.warn(
                f"{where}: dropped the file's world geoms (the scene has its own floor); {report.sentence()}.",
                RuntimeWarning,
                stacklevel=3,
            )
        return []
    names = [b.name for b in tops]
    if chosen is not None:
        _check_names(where, "top-level body (root_body)", [chosen], names)
        keep = next(b for b in tops if b.name == chosen)
    else:
        actuated = {a.target for a in spec.actuators if a.trntype == mujoco.mjtTrn.mjTRN_JOINT}

        def score(body: mujoco.MjsBody) -> tuple[int, int]:
            joints = [j.name for j in body.find_all(mujoco.mjtObj.mjOBJ_JOINT)]
            return (len(actuated & set(joints)), len(joints))

        ranked = sorted(tops, key=score, reverse=True)
        if score(ranked[0]) == score(ranked[1]):
            raise ModelError(
                f"{where}: the model file has {len(tops)} top-level bodies {names} and none stands out as the robot; "
                f"set root_body = {names[0]!r} (or another) on the robot class to choose (robot-agents: "
                f"--root-body {names[0]})."
            )
        keep = ranked[0]
    kept = keep.name
    dropped = [b for b in tops if b is not keep]
    dropped_names = [b.name for b in dropped]
    held = _mocap_held_joints(spec, keep, [b for b in dropped if b.mocap])
    report = drop_with_dependents(spec, dropped, world_geoms)
    extra = report.sentence()
    how = "the root_body chosen" if chosen is not None else "the robot"
    hint = "" if chosen is not None else " (set root_body on the robot class to choose another)"
    warnings.warn(
        f"{where}: kept top-level body {kept!r} as {how} and dropped {dropped_names}{hint}"
        f"{'; ' + extra if extra else ''}.",
        RuntimeWarning,
        stacklevel=3,
    )
    return held


def _mocap_held_joints(spec: mujoco.MjSpec, robot: mujoco.MjsBody, mocaps: Sequence[mujoco.MjsBody]) -> list[str]:
    """The joints from ``robot`` (the kept top-level body) down to each of its bodies that
    a weld or connect equality ties to one of ``mocaps``, in the file's joint order."""
    mocap_names = {b.name for b in mocaps}
    inside = {b.name for b in robot.find_all(mujoco.mjtObj.mjOBJ_BODY)} | {robot.name}
    held: set[str] = set()
    for equality in spec.equalities:
        if equality.type not in (mujoco.mjtEq.mjEQ_WELD, mujoco.mjtEq.mjEQ_CONNECT):
            continue
        if equality.objtype != mujoco.mjtObj.mjOBJ_BODY:
            continue
        pair = {equality.name1, equality.name2}
        if not pair & mocap_names:
            continue
        for name in pair & inside:
            body = spec.body(name)
            while body is not None and body.name in inside:
                held.update(
                    j.name
                    for j in body.joints
                    if j.type != mujoco.mjtJoint.mjJNT_FREE and not _base_slide(j, spec.compiler.autolimits)
                )
                body = body.parent if body.name != robot.name else None
    return [j.name for j in spec.joints if j.name in held]


def _base_slide(joint: mujoco.MjsJoint, autolimits: bool) -> bool:
    """An unlimited slide: a planar base's joint, which moves the whole robot rather than
    its hand (gymnasium-robotics' Fetch locks its three with a damping of 1e11)."""
    return joint.type == mujoco.mjtJoint.mjJNT_SLIDE and not range_limited(joint.limited, joint.range, autolimits)


def _check_names(where: str, kind: str, wanted: Iterable[str], available: Sequence[str]) -> None:
    known = set(available)
    for name in wanted:
        if name not in known:
            raise UnknownNameError(where, kind, name, available)


def set_root_joint(spec: mujoco.MjSpec, fix_root_link: bool, where: str, declared: bool = True) -> None:
    """Add a free joint to the root body, or remove one, as ``fix_root_link`` says;
    ``declared``: the robot states ``fix_root_link`` (a file's free root removed by the
    default, ``True``, gets a note: a two-line humanoid or quadruped hung fixed in the air)."""
    root = root_body(spec, where)
    free = [j for j in root.joints if j.type == mujoco.mjtJoint.mjJNT_FREE]
    if fix_root_link:
        for joint in free:
            spec.delete(joint)
        if free:
            _shift_keys(spec, drop=True)
        if free and not declared:
            warnings.warn(
                f"{where}: the file gives root body {root.name!r} a free joint; the robot is fixed to the world "
                "(fix_root_link defaults to True): set fix_root_link = False (robot-agents --floating) to keep it "
                "free, or fix_root_link = True to silence this.",
                RuntimeWarning,
                stacklevel=3,
            )
    elif not free:
        moving = [j.name for j in root.joints]
        if moving:
            raise ModelError(
                f"{where}: a floating robot's root body gets a free joint, but root body {root.name!r} already has "
                f"joint(s) {moving}; keep fix_root_link = True, or give the file a root body without joints."
            )
        root.add_freejoint(name=ROOT_FREE_JOINT)
        _shift_keys(spec, drop=False, root_pose=(*root.pos, *root.quat))


def _shift_keys(spec: mujoco.MjSpec, drop: bool, root_pose: Sequence[float] = ()) -> None:
    """Keep the file's keyframes on their joints when the root's free joint (the first
    7 ``qpos`` and 6 ``qvel``: the root is the first body) is removed (``drop``) or added
    (its ``qpos`` then the root body's pose in the file, its ``qvel`` zero). MuJoCo
    itself would read a keyframe's values from the start of the new vectors."""
    for key in spec.keys:
        qpos, qvel = np.asarray(key.qpos, dtype=np.float64), np.asarray(key.qvel, dtype=np.float64)
        if drop:
            key.qpos = qpos[7:] if qpos.size >= 7 else qpos[:0]
            key.qvel = qvel[6:] if qvel.size >= 6 else qvel[:0]
        else:
            if qpos.size:
                key.qpos = np.concatenate([np.asarray(root_pose, dtype=np.float64), qpos])
            if qvel.size:
                key.qvel = np.concatenate([np.zeros(6), qvel])


def set_gravity_compensation(spec: mujoco.MjSpec, bodies: bool | Sequence[str], where: str) -> None:
    """Cancel gravity on the given bodies (``True``: every robot body) via ``gravcomp``."""
    all_bodies = robot_bodies(spec)
    if bodies is True:
        chosen = {b.name for b in all_bodies}
    elif bodies is False:
        chosen = set()
    else:
        _check_names(where, "body (gravity_compensation)", bodies, [b.name for b in all_bodies])
        chosen = set(bodies)
    for body in all_bodies:
        body.gravcomp = 1.0 if body.name in chosen else 0.0


def set_materials(
    spec: mujoco.MjSpec, materials: Mapping[str, FrictionMaterial], default: FrictionMaterial | None, where: str
) -> None:
    """Set the contact material (friction, and contact softness where the material
    gives it) of every colliding geom, per body name (``default`` for the rest)."""
    all_bodies = robot_bodies(spec)
    _check_names(where, "body (link_materials)", materials, [b.name for b in all_bodies])
    for body in all_bodies:
        material = materials.get(body.name, default)
        if material is None:
            continue
        for geom in body.geoms:
            if geom.contype or geom.conaffinity:
                material.apply(geom)


def keep_collisions(spec: mujoco.MjSpec, links: Sequence[str] | None, where: str) -> None:
    """Let only the geoms of the bodies ``links`` collide (``None``: every body's, the
    file as it is): every other body's colliding geoms become visual-only
    (``contype = conaffinity = 0``); they keep their shape and mass and are still drawn.
    A contact ``<pair>`` of the file still acts (MuJoCo's explicit pairs ignore
    ``contype``)."""
    if links is None:
        return
    all_bodies = robot_bodies(spec)
    _check_names(where, "body (collision_links)", links, [b.name for b in all_bodies])
    kept = set(links)
    for body in all_bodies:
        if body.name in kept:
            continue
        for geom in body.geoms:
            geom.contype = 0
            geom.conaffinity = 0


def set_pad_contact(spec: mujoco.MjSpec, bodies: Iterable[str], where: str) -> None:
    """Give the colliding geoms of ``bodies`` (a derived gripper's fingers) stiff pad
    contact: ``priority`` :data:`~robot_agents.model.materials.STIFF_PRIORITY` with
    :data:`~robot_agents.model.materials.PAD_SOLREF` and
    :data:`~robot_agents.model.materials.PAD_SOLIMP`; their friction stays the file's."""
    names = set(bodies)
    _check_names(where, "body (gripper fingers)", names, [b.name for b in robot_bodies(spec)])
    for body in robot_bodies(spec):
        if body.name not in names:
            continue
        for geom in body.geoms:
            if geom.contype or geom.conaffinity:
                set_contact_softness(geom, PAD_SOLREF, PAD_SOLIMP)


#: The joint stops a robot with derived drives gets (MuJoCo's ``solreflimit``: 5 ms, as
#: the built-in Unitree H1's and ANYbotics ANYmal C's stops, ``robots/unitree/assets/h1.xml``;
#: MuJoCo raises it to two physics steps where that is longer). MuJoCo's default 20 ms
#: let a light joint driven into its stop pass it by half a radian (the two-line
#: Panda's joint 5 under random position+velocity targets: 0.51 rad; 0.12 with these).
STOP_SOLREF = (0.005, 1.0)


def set_stiff_stops(spec: mujoco.MjSpec) -> None:
    """Give every limited hinge and slide joint of the robot :data:`STOP_SOLREF`."""
    kinds = (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
    for body in robot_bodies(spec):
        for joint in body.joints:
            if joint.type in kinds and joint.limited != mujoco.mjtLimited.mjLIMITED_FALSE:
                joint.solref_limit = list(STOP_SOLREF)


def set_self_collisions(
    spec: mujoco.MjSpec, disable_all: bool, exclusions: Iterable[tuple[str, str]], where: str
) -> None:
    """Filter contacts between the robot's own bodies: all pairs, or the listed ones.

    MuJoCo ignores contacts between a moving body and its parent, but not between a
    body and a parent welded to the world; so the root body's children are always
    excluded from touching the root (the first joint's housing overlaps both).
    """
    names = [b.name for b in robot_bodies(spec)]
    pairs: list[tuple[str, str]]
    if disable_all:
        pairs = list(itertools.combinations(names, 2))
    else:
        pairs = list(exclusions)
        _check_names(where, "body (self_collision_exclusions)", [n for pair in pairs for n in pair], names)
        root = root_body(spec, where)
        child = root.first_body()
        while child is not None:
            if (root.name, child.name) not in pairs and (child.name, root.name) not in pairs:
                pairs.append((root.name, child.name))
            child = root.next_body(child)
    for first, second in pairs:
        spec.add_exclude(bodyname1=first, bodyname2=second)
