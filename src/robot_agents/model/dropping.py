"""Drop the part of a model file that is not the robot, and everything that refers to it.

:func:`~robot_agents.model.robot_spec.isolate_robot` keeps one top-level body (the
robot) and drops the file's world geoms and its other top-level bodies. Elements
elsewhere in the file may name objects inside what is dropped; MuJoCo cannot compile
them once their object is gone. :func:`drop_with_dependents` finds them, to a fixed
point (an actuator on a tendon through a dropped site goes with the tendon):

- sensors whose object or reference object is dropped (``objname``, ``refname``);
- actuators on dropped joints, tendons, sites (``site``, ``refsite``, slider-crank
  sites) or bodies (adhesion);
- tendons that pass through a dropped joint, site or geom (a wrap's ``sidesite`` too);
- equality constraints naming a dropped body, joint, tendon, site or flex;
- contact pairs of dropped geoms, contact excludes of dropped bodies;
- skins bound to, and flexes with vertices or nodes on, dropped bodies;
- custom tuples listing a dropped object.

A camera or light kept with the robot (in the world or on the robot) that only *targets*
a dropped body (``mode="targetbody"`` / ``"targetbodycom"``) stays: it becomes fixed to
its body with the position and orientation it has at the file's initial pose (``qpos0``)
where the whole file compiles, and is dropped otherwise. Keyframes keep fitting the
reduced model: the ``ctrl`` and ``act`` of dropped actuators are cut out here, and
MuJoCo re-maps ``qpos``, ``qvel``, ``mpos`` and ``mquat`` when a body is deleted.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

_O = mujoco.mjtObj
_KIND_NAMES = {
    _O.mjOBJ_BODY: "body",
    _O.mjOBJ_JOINT: "joint",
    _O.mjOBJ_GEOM: "geom",
    _O.mjOBJ_SITE: "site",
    _O.mjOBJ_CAMERA: "camera",
    _O.mjOBJ_LIGHT: "light",
    _O.mjOBJ_TENDON: "tendon",
    _O.mjOBJ_ACTUATOR: "actuator",
    _O.mjOBJ_SENSOR: "sensor",
    _O.mjOBJ_FLEX: "flex",
}
_TARGETING = (mujoco.mjtCamLight.mjCAMLIGHT_TARGETBODY, mujoco.mjtCamLight.mjCAMLIGHT_TARGETBODYCOM)
#: The order dependents are deleted in: what refers to others before them.
_DELETE_ORDER = ("sensor", "equality", "contact pair", "contact exclude", "tuple", "skin", "flex", "actuator", "tendon")

Ref = tuple[Any, str]  # (mjtObj, name)


@dataclass
class DropReport:
    """What :func:`drop_with_dependents` removed or changed besides the dropped subtrees."""

    dropped: list[str] = field(default_factory=list)  # "sensor 's' (on geom 'target')"
    fixed: list[str] = field(default_factory=list)  # "camera 'c' (targeted body 'ball')"

    def sentence(self) -> str:
        parts = []
        if self.dropped:
            parts.append(f"also dropped what refers to them: {', '.join(self.dropped)}")
        if self.fixed:
            parts.append(
                f"fixed {', '.join(self.fixed)} in place, looking where the dropped target was at the file's "
                "initial pose"
            )
        return "; ".join(parts)


def _kind(objtype: Any) -> Any:
    return _O.mjOBJ_BODY if objtype == _O.mjOBJ_XBODY else objtype


def _label(kind: str, element: Any, index: int) -> str:
    return f"{kind} {element.name!r}" if element.name else f"unnamed {kind} #{index}"


def _wrap_refs(tendon: Any) -> list[Ref]:
    refs: list[Ref] = []
    for wrap in tendon.path:
        target = getattr(wrap, "target", None)
        name = target if isinstance(target, str) else getattr(target, "name", "")
        if isinstance(target, mujoco.MjsGeom):
            refs.append((_O.mjOBJ_GEOM, name))
        elif isinstance(target, mujoco.MjsSite) or wrap.type == mujoco.mjtWrap.mjWRAP_SITE:
            refs.append((_O.mjOBJ_SITE, name))
        elif isinstance(target, mujoco.MjsJoint) or wrap.type == mujoco.mjtWrap.mjWRAP_JOINT:
            refs.append((_O.mjOBJ_JOINT, name))
        sidesite = getattr(wrap, "sidesite", None)
        side = sidesite if isinstance(sidesite, str) else getattr(sidesite, "name", "")
        if side:
            refs.append((_O.mjOBJ_SITE, side))
    return refs


def _actuator_refs(actuator: Any) -> list[Ref]:
    trn = mujoco.mjtTrn
    kind = {
        trn.mjTRN_JOINT: _O.mjOBJ_JOINT,
        trn.mjTRN_JOINTINPARENT: _O.mjOBJ_JOINT,
        trn.mjTRN_TENDON: _O.mjOBJ_TENDON,
        trn.mjTRN_SITE: _O.mjOBJ_SITE,
        trn.mjTRN_SLIDERCRANK: _O.mjOBJ_SITE,
        trn.mjTRN_BODY: _O.mjOBJ_BODY,
    }.get(actuator.trntype)
    kinds = [kind] if kind is not None else [_O.mjOBJ_JOINT, _O.mjOBJ_SITE, _O.mjOBJ_BODY]  # another transmission
    refs: list[Ref] = [(k, actuator.target) for k in kinds]
    refs += [(_O.mjOBJ_SITE, name) for name in (actuator.refsite, actuator.slidersite) if name]
    return refs


def _equality_refs(equality: Any) -> list[Ref]:
    eq = mujoco.mjtEq
    names = [n for n in (equality.name1, equality.name2) if n]
    if equality.type in (eq.mjEQ_CONNECT, eq.mjEQ_WELD):
        kind = _O.mjOBJ_SITE if equality.objtype == _O.mjOBJ_SITE else _O.mjOBJ_BODY
    elif equality.type == eq.mjEQ_JOINT:
        kind = _O.mjOBJ_JOINT
    elif equality.type == eq.mjEQ_TENDON:
        kind = _O.mjOBJ_TENDON
    elif equality.type in (eq.mjEQ_FLEX, getattr(eq, "mjEQ_FLEXVERT", None), getattr(eq, "mjEQ_FLEXSTRAIN", None)):
        kind = _O.mjOBJ_FLEX
    else:  # a kind this list does not know: its names are checked against every kind
        return [(k, n) for n in names for k in _KIND_NAMES]
    return [(kind, n) for n in names]


def _sensor_refs(sensor: Any) -> list[Ref]:
    return [
        (_kind(objtype), name)
        for objtype, name in ((sensor.objtype, sensor.objname), (sensor.reftype, sensor.refname))
        if name and objtype != _O.mjOBJ_UNKNOWN
    ]


def _names(values: Any) -> list[str]:
    if isinstance(values, str):
        return [values] if values else []
    return [v for v in values if v] if values is not None else []


def _tuple_refs(entry: Any) -> list[Ref]:
    names = [entry.objname] if isinstance(entry.objname, str) else list(entry.objname)
    return [(_kind(o), n) for o, n in zip(entry.objtype, names, strict=False) if n]


# (kind label, mjtObj of its own names, the spec's list, the objects it refers to)
_Dependent = tuple[str, Any, Callable[[mujoco.MjSpec], Sequence[Any]], Callable[[Any], list[Ref]]]
_DEPENDENTS: tuple[_Dependent, ...] = (
    ("tendon", _O.mjOBJ_TENDON, lambda s: s.tendons, _wrap_refs),
    ("actuator", _O.mjOBJ_ACTUATOR, lambda s: s.actuators, _actuator_refs),
    ("sensor", _O.mjOBJ_SENSOR, lambda s: s.sensors, _sensor_refs),
    ("equality", _O.mjOBJ_EQUALITY, lambda s: s.equalities, _equality_refs),
    (
        "contact pair",
        _O.mjOBJ_PAIR,
        lambda s: s.pairs,
        lambda p: [(_O.mjOBJ_GEOM, p.geomname1), (_O.mjOBJ_GEOM, p.geomname2)],
    ),
    (
        "contact exclude",
        _O.mjOBJ_EXCLUDE,
        lambda s: s.excludes,
        lambda e: [(_O.mjOBJ_BODY, e.bodyname1), (_O.mjOBJ_BODY, e.bodyname2)],
    ),
    ("skin", _O.mjOBJ_SKIN, lambda s: s.skins, lambda k: [(_O.mjOBJ_BODY, n) for n in _names(k.bodyname)]),
    (
        "flex",
        _O.mjOBJ_FLEX,
        lambda s: s.flexes,
        lambda f: [(_O.mjOBJ_BODY, n) for n in [*_names(f.vertbody), *_names(getattr(f, "nodebody", None))]],
    ),
    ("tuple", _O.mjOBJ_TUPLE, lambda s: s.tuples, _tuple_refs),
)


def _subtree_names(bodies: Iterable[mujoco.MjsBody]) -> dict[Any, set[str]]:
    gone: dict[Any, set[str]] = {kind: set() for kind in _KIND_NAMES}
    for body in bodies:
        gone[_O.mjOBJ_BODY].add(body.name)
        for kind in (_O.mjOBJ_BODY, _O.mjOBJ_JOINT, _O.mjOBJ_GEOM, _O.mjOBJ_SITE, _O.mjOBJ_CAMERA, _O.mjOBJ_LIGHT):
            gone[kind].update(e.name for e in body.find_all(kind))
    for names in gone.values():
        names.discard("")
    return gone


def _hit(refs: list[Ref], gone: dict[Any, set[str]]) -> Ref | None:
    return next(((kind, name) for kind, name in refs if name and name in gone.get(kind, ())), None)


def _dependents(spec: mujoco.MjSpec, gone: dict[Any, set[str]]) -> list[tuple[str, Any, str, Ref, int]]:
    """Every element referring to a gone object (a fixed point: what refers to those goes too),
    as (kind label, the element, its label, the reference, its index in the spec's list of
    its kind); ``gone`` gains their names."""
    found: list[tuple[str, Any, str, Ref, int]] = []
    seen: set[tuple[str, int]] = set()
    changed = True
    while changed:
        changed = False
        for label, own, elements, refs in _DEPENDENTS:
            for index, element in enumerate(elements(spec)):
                if (label, index) in seen:
                    continue
                hit = _hit(refs(element), gone)
                if hit is None:
                    continue
                seen.add((label, index))
                found.append((label, element, _label(label, element, index), hit, index))
                if element.name:
                    gone.setdefault(own, set()).add(element.name)
                changed = True
    return found


def _fixed_poses(spec: mujoco.MjSpec, gone_bodies: set[str]) -> dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]:
    """The local pose (pos, and quat or dir) at ``qpos0`` of each named camera and light
    that targets a gone body, from the whole file compiled; empty when it does not compile."""
    wanted = [
        (kind, e.name)
        for kind, elements in (("camera", spec.cameras), ("light", spec.lights))
        for e in elements
        if e.mode in _TARGETING and e.targetbody in gone_bodies and e.name
    ]
    if not wanted:
        return {}
    try:
        model = spec.copy().compile()
    except ValueError as err:  # MuJoCo's compile error: such cameras and lights are dropped instead
        warnings.warn(
            f"cameras / lights {[n for _, n in wanted]} target dropped bodies and the whole file does not compile "
            f"({str(err).splitlines()[0]}): they are dropped with them.",
            RuntimeWarning,
            stacklevel=2,
        )
        return {}
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    poses: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]] = {}
    for kind, name in wanted:
        if kind == "camera":
            cam = model.camera(name).id
            body = model.cam_bodyid[cam]
            rotation = data.xmat[body].reshape(3, 3).T
            quat = np.zeros(4)
            mujoco.mju_mat2Quat(quat, (rotation @ data.cam_xmat[cam].reshape(3, 3)).ravel())
            poses[(kind, name)] = (rotation @ (data.cam_xpos[cam] - data.xpos[body]), quat)
        else:
            light = model.light(name).id
            body = model.light_bodyid[light]
            rotation = data.xmat[body].reshape(3, 3).T
            poses[(kind, name)] = (
                rotation @ (data.light_xpos[light] - data.xpos[body]),
                rotation @ data.light_xdir[light],
            )
    return poses


def drop_with_dependents(
    spec: mujoco.MjSpec, bodies: Sequence[mujoco.MjsBody], world_geoms: Sequence[mujoco.MjsGeom]
) -> DropReport:
    """Delete ``bodies`` (top-level, with their subtrees) and ``world_geoms`` from ``spec``
    with every element that refers to something in them (see the module doc)."""
    report = DropReport()
    gone = _subtree_names(bodies)
    gone[_O.mjOBJ_GEOM].update(g.name for g in world_geoms if g.name)
    found = _dependents(spec, gone)
    report.dropped = [
        f"{text} ({'lists' if label == 'tuple' else 'on'} {_KIND_NAMES.get(ref[0], 'object')} {ref[1]!r})"
        for label, _element, text, ref, _index in found
    ]
    poses = _fixed_poses(spec, gone[_O.mjOBJ_BODY])
    actuators_before = [(a.dyntype, a.actdim) for a in spec.actuators]
    dropped_actuators = {index for label, *_, index in found if label == "actuator"}
    keys_before = [(len(k.ctrl), len(k.act)) for k in spec.keys]

    # The dependents first, while every element still exists (what refers to others
    # before them: sensors before the actuators they read, actuators before their
    # tendons); then the keyframes' ctrl and act cut to the remaining actuators; then the
    # bodies (MuJoCo re-maps the keyframes' qpos, qvel, mpos and mquat) and world geoms.
    for _text, element, _label_text, _ref, _index in sorted(found, key=lambda f: _DELETE_ORDER.index(f[0])):
        spec.delete(element)
    _trim_keys(spec, actuators_before, dropped_actuators, keys_before)
    for body in bodies:
        spec.delete(body)
    for geom in world_geoms:
        spec.delete(geom)
    for kind, elements in (("camera", spec.cameras), ("light", spec.lights)):
        for index, element in enumerate(list(elements)):
            if element.mode not in _TARGETING or element.targetbody not in gone[_O.mjOBJ_BODY]:
                continue
            pose = poses.get((kind, element.name))
            if pose is None or element.frame is not None:
                report.dropped.append(f"{_label(kind, element, index)} (targets body {element.targetbody!r})")
                spec.delete(element)
                continue
            report.fixed.append(f"{_label(kind, element, index)} (targeted body {element.targetbody!r})")
            element.mode = mujoco.mjtCamLight.mjCAMLIGHT_FIXED
            element.targetbody = ""
            element.pos = pose[0]
            if kind == "camera":
                element.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
                element.quat = pose[1]
            else:
                element.dir = pose[1]
    return report


def _trim_keys(
    spec: mujoco.MjSpec,
    actuators_before: list[tuple[Any, int]],
    dropped: set[int],
    keys_before: list[tuple[int, int]],
) -> None:
    """Cut the dropped actuators' entries out of the keyframes' ``ctrl`` and ``act``."""
    if not dropped:
        return
    ctrl_keep = [i for i in range(len(actuators_before)) if i not in dropped]
    act_keep: list[int] = []
    start = 0
    for i, (dyntype, actdim) in enumerate(actuators_before):
        size = actdim if actdim >= 0 else int(dyntype != mujoco.mjtDyn.mjDYN_NONE)
        if i not in dropped:
            act_keep += range(start, start + size)
        start += size
    for key, (nctrl, nact) in zip(spec.keys, keys_before, strict=True):
        ctrl, act = list(key.ctrl), list(key.act)
        if nctrl == len(actuators_before) and len(ctrl) == nctrl and nctrl:
            key.ctrl = [ctrl[i] for i in ctrl_keep]
        if nact == start and len(act) == nact and nact:
            key.act = [act[i] for i in act_keep]
