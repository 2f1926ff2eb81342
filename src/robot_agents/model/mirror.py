"""Mirror a model across its file's xz plane (y -> -y): a left hand from a right one.

A reflection ``M = diag(1, -1, 1)`` of a kinematic tree keeps it a right-handed tree
when every frame ``R`` becomes ``M R M`` (a quaternion ``(w, x, y, z)`` becomes ``(w, -x,
y, -z)``) and every position ``p`` becomes ``M p``. A hinge turning by ``q`` about ``a``
turns, mirrored, by ``-q`` about ``M a``, that is by ``q`` about ``-M a``: so the hinge's
axis becomes ``-M a`` and every joint angle (ranges, keyframes) keeps its meaning. A
slide's axis becomes ``M a``. Boxes, spheres, capsules, cylinders, ellipsoids and planes
are symmetric about their own planes and need nothing more; a mesh is not, and is
refused, as are ball joints (their keyframe quaternions would need mirroring too) and
orientations written other than as quaternions.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from robot_agents.errors import ModelError

#: The reflection y -> -y.
MIRROR = np.array([1.0, -1.0, 1.0])
#: A quaternion (w, x, y, z) of R -> that of M R M.
QUAT_SIGNS = np.array([1.0, -1.0, 1.0, -1.0])
#: Geom types symmetric about their own frame's planes.
SYMMETRIC_GEOMS = frozenset(
    {
        mujoco.mjtGeom.mjGEOM_PLANE,
        mujoco.mjtGeom.mjGEOM_SPHERE,
        mujoco.mjtGeom.mjGEOM_CAPSULE,
        mujoco.mjtGeom.mjGEOM_ELLIPSOID,
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        mujoco.mjtGeom.mjGEOM_BOX,
    }
)


def _quat_only(element: Any, kind: str, where: str) -> None:
    if element.alt.type != mujoco.mjtOrientation.mjORIENTATION_QUAT:
        raise ModelError(
            f"{where}: {kind} {element.name!r} has its orientation written as {element.alt.type.name}; expected a "
            "quaternion to mirror it (write its quat)."
        )


def _mirror_frame(element: Any, kind: str, where: str) -> None:
    """Mirror ``element``'s ``pos`` and ``quat`` (and ``fromto`` where it has one)."""
    _quat_only(element, kind, where)
    element.pos = MIRROR * np.asarray(element.pos)
    element.quat = QUAT_SIGNS * np.asarray(element.quat)
    fromto = getattr(element, "fromto", None)
    if fromto is not None and not np.isnan(fromto[0]):
        element.fromto = np.tile(MIRROR, 2) * np.asarray(fromto)


def mirror_spec(spec: mujoco.MjSpec, where: str) -> None:
    """Mirror ``spec`` in place across its xz plane (y -> -y).

    Bodies, frames, geoms, sites, cameras and lights are mirrored in their parents'
    frames; hinge axes become ``-M a`` (joint angles keep their meaning: the same
    ``qpos`` gives the mirror image), slide axes ``M a``; explicit inertias are
    mirrored (``ipos``, ``iquat``; a full inertia's ``ixy`` and ``iyz`` change sign).
    Names are kept.

    Raises:
        ModelError: a mesh geom, a ball joint, or an orientation not written as a
            quaternion (nothing is changed then).
    """
    for geom in spec.geoms:
        if geom.type not in SYMMETRIC_GEOMS:
            raise ModelError(
                f"{where}: geom {geom.name!r} is a {geom.type.name}, which mirroring would have to reflect; expected "
                f"one of {sorted(t.name for t in SYMMETRIC_GEOMS)}."
            )
    for joint in spec.joints:
        if joint.type == mujoco.mjtJoint.mjJNT_BALL:
            raise ModelError(f"{where}: joint {joint.name!r} is a ball joint; mirroring supports hinges and slides.")
    groups = (
        ("body", spec.bodies[1:]),
        ("frame", spec.frames),
        ("geom", spec.geoms),
        ("site", spec.sites),
        ("camera", spec.cameras),
        ("light", spec.lights),
    )
    for kind, elements in groups:
        for element in elements:
            if kind != "light":
                _quat_only(element, kind, where)
    for body in spec.bodies[1:]:
        if body.explicitinertial and body.ialt.type != mujoco.mjtOrientation.mjORIENTATION_QUAT:
            raise ModelError(
                f"{where}: body {body.name!r} has its inertial frame written as {body.ialt.type.name}; expected a "
                "quaternion to mirror it."
            )
    # checked: now change
    for kind, elements in groups:
        for element in elements:
            if kind == "light":
                element.pos = MIRROR * np.asarray(element.pos)
                element.dir = MIRROR * np.asarray(element.dir)
            else:
                _mirror_frame(element, kind, where)
    for body in spec.bodies[1:]:
        if body.explicitinertial:
            body.ipos = MIRROR * np.asarray(body.ipos)
            body.iquat = QUAT_SIGNS * np.asarray(body.iquat)
            if not np.isnan(body.fullinertia[0]):
                body.fullinertia = np.array([1.0, 1.0, 1.0, -1.0, 1.0, -1.0]) * np.asarray(body.fullinertia)
    for joint in spec.joints:
        joint.pos = MIRROR * np.asarray(joint.pos)
        if joint.type == mujoco.mjtJoint.mjJNT_HINGE:
            joint.axis = -MIRROR * np.asarray(joint.axis)
        elif joint.type == mujoco.mjtJoint.mjJNT_SLIDE:
            joint.axis = MIRROR * np.asarray(joint.axis)


__all__ = ["mirror_spec"]
