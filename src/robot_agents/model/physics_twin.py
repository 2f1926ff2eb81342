"""The simulated twin of a compiled scene: the same model without its visual-only geoms.

A geom that takes part in no contact (``contype = conaffinity = 0``) still costs every
physics step: ``mj_kinematics`` computes its world pose at each of them, and a robot
that looks like itself has many (the Panda 36 of its 65 geoms). They change nothing the
physics computes, so the scene steps a twin without them and draws the full model
(:attr:`robot_agents.sim.scene.Scene.render_model`). On 18 of the 22 built-in robots
this makes the physics step 8-22 % faster, with the same trajectory bit for bit
(docs/benchmarks.md, "Visual geoms out of the physics step").

A visual-only geom stays in the twin when anything that acts on the physics names it:
a contact pair, a tendon wrapping around it, a sensor, a fluid interaction, or when it
gives its body mass (a body without an explicit inertial takes its mass and inertia
from its geoms, visual ones included, unless they are massless). The twin is checked
against the full model after compiling: the counts, bodies (pose, mass, inertia),
joints, DoFs, actuators, sites, cameras, equalities, sensors, tendons, keyframes, the
physics options and the mean inertia equal, contact pairs and sensors naming the same
geoms, or there is no twin.
"""

from __future__ import annotations

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ModelError
from robot_agents.model.compiling import compile_spec

IntArray = npt.NDArray[np.int64]

#: What must be equal, array for array, between the full model and its twin (the
#: physics besides geoms; checked after compiling, so a stripped geom that mattered
#: leaves the model without a twin rather than simulating something else).
SAME_FIELDS = (
    "body_parentid",
    "body_pos",
    "body_quat",
    "body_ipos",
    "body_iquat",
    "body_mass",
    "body_inertia",
    "body_gravcomp",
    "jnt_type",
    "jnt_qposadr",
    "jnt_range",
    "jnt_stiffness",
    "dof_armature",
    "dof_damping",
    "dof_frictionloss",
    "actuator_trnid",
    "actuator_gainprm",
    "actuator_biasprm",
    "actuator_forcerange",
    "site_pos",
    "site_bodyid",
    "cam_pos",
    "cam_bodyid",
    "eq_data",
    "sensor_type",
    "sensor_objtype",
    "sensor_reftype",
    "tendon_num",
    "key_qpos",
    "qpos0",
)
#: Physics options that must be equal (``MjOption`` fields).
SAME_OPTIONS = (
    "timestep",
    "integrator",
    "cone",
    "jacobian",
    "solver",
    "iterations",
    "tolerance",
    "impratio",
    "gravity",
    "wind",
    "density",
    "viscosity",
    "disableflags",
    "enableflags",
)
#: Counts that must be equal.
SAME_SIZES = ("nq", "nv", "nu", "na", "nbody", "njnt", "nsite", "ncam", "nlight", "nsensor", "neq", "ntendon", "nkey")


def visual_only_geoms(model: mujoco.MjModel) -> set[int]:
    """Geom ids of ``model`` that collide with nothing and that nothing acting on the
    physics names (contact pairs, tendon wraps, sensors, fluid forces)."""
    candidates = {
        g
        for g in range(model.ngeom)
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0 and model.geom_fluid[g, 0] == 0
    }
    named = set(model.pair_geom1.tolist()) | set(model.pair_geom2.tolist())
    wrapping = (int(mujoco.mjtWrap.mjWRAP_SPHERE), int(mujoco.mjtWrap.mjWRAP_CYLINDER))
    named |= {int(i) for t, i in zip(model.wrap_type, model.wrap_objid, strict=True) if int(t) in wrapping}
    geom = int(mujoco.mjtObj.mjOBJ_GEOM)
    for types, ids in ((model.sensor_objtype, model.sensor_objid), (model.sensor_reftype, model.sensor_refid)):
        named |= {int(i) for t, i in zip(types, ids, strict=True) if int(t) == geom}
    return candidates - named


def copy_spec(spec: mujoco.MjSpec) -> mujoco.MjSpec:
    """``spec.copy()`` with each material's texture slots restored (MuJoCo 4.0's copy
    garbles them, and the copy then fails to compile)."""
    copy = spec.copy()
    for source, target in zip(spec.materials, copy.materials, strict=True):
        names = list(source.textures)
        target.textures = names + [""] * (int(mujoco.mjtTextureRole.mjNTEXROLE) - len(names))
    return copy


def _same_physics(full: mujoco.MjModel, twin: mujoco.MjModel) -> bool:
    if any(getattr(full, n) != getattr(twin, n) for n in SAME_SIZES):
        return False
    if full.stat.meaninertia != twin.stat.meaninertia:  # scales the solver's tolerance
        return False
    if not all(np.array_equal(getattr(full.opt, f), getattr(twin.opt, f)) for f in SAME_OPTIONS):
        return False
    if not all(np.array_equal(getattr(full, f), getattr(twin, f)) for f in SAME_FIELDS):
        return False
    return _same_references(full, twin)


def _same_references(full: mujoco.MjModel, twin: mujoco.MjModel) -> bool:
    """Sensors and contact pairs name the same objects (geoms by name: their ids move)."""
    geom = int(mujoco.mjtObj.mjOBJ_GEOM)

    def named(model: mujoco.MjModel, objtype: int, objid: int) -> object:
        return model.geom(objid).name if objtype == geom and objid >= 0 else objid

    for types, ids in (("sensor_objtype", "sensor_objid"), ("sensor_reftype", "sensor_refid")):
        for t, a, b in zip(getattr(full, types), getattr(full, ids), getattr(twin, ids), strict=True):
            if named(full, int(t), int(a)) != named(twin, int(t), int(b)):
                return False
    if full.npair != twin.npair:
        return False
    pairs = zip(full.pair_geom1, full.pair_geom2, twin.pair_geom1, twin.pair_geom2, strict=True)
    return all(
        full.geom(int(a)).name == twin.geom(int(c)).name and full.geom(int(b)).name == twin.geom(int(d)).name
        for a, b, c, d in pairs
    )


def _strip(spec: mujoco.MjSpec, full: mujoco.MjModel, geoms: set[int]) -> mujoco.MjModel | None:
    copy = copy_spec(spec)
    specs = list(copy.geoms)
    if len(specs) != full.ngeom:
        return None
    for g in sorted(geoms):
        element = specs[g]
        # the spec's geoms are listed in the compiled order; check before deleting
        if int(element.type) != int(full.geom_type[g]) or element.name != full.geom(g).name:
            return None
        copy.delete(element)
    try:
        twin = compile_spec(copy, "physics_twin")
    except ModelError:
        return None
    twin.opt.timestep = full.opt.timestep
    return twin


def geoms_giving_mass(spec: mujoco.MjSpec, full: mujoco.MjModel, geoms: set[int]) -> set[int]:
    """Those of ``geoms`` that give their body mass: the body takes its inertial from its
    geoms (no explicit inertial, or the compiler's ``inertiafromgeom="true"``), the geom's
    group is within the compiler's ``inertiagrouprange``, and its mass (given, or density
    times volume) is not zero."""
    compiler = spec.compiler
    always = compiler.inertiafromgeom == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    low, high = (int(v) for v in compiler.inertiagrouprange)
    bodies, elements = list(spec.bodies), list(spec.geoms)
    if len(bodies) != full.nbody or len(elements) != full.ngeom:
        return set(geoms)
    giving = set()
    for g in geoms:
        element = elements[g]
        from_geoms = always or not bodies[int(full.geom_bodyid[g])].explicitinertial
        massless = element.mass == 0 if not np.isnan(element.mass) else element.density == 0
        if from_geoms and low <= int(element.group) <= high and not massless:
            giving.add(g)
    return giving


def physics_twin(spec: mujoco.MjSpec, full: mujoco.MjModel) -> mujoco.MjModel | None:
    """``full`` (compiled from ``spec``) without its visual-only geoms, or ``None`` when
    it has none to leave out (or the twin would differ in anything but geoms).

    Geoms that give their body mass are kept."""
    visual = visual_only_geoms(full)
    geoms = visual - geoms_giving_mass(spec, full, visual)
    if not geoms:
        return None
    twin = _strip(spec, full, geoms)
    if twin is None or not _same_physics(full, twin):
        return None
    return twin


def shared_geoms(full: mujoco.MjModel, twin: mujoco.MjModel) -> IntArray:
    """For each geom of ``twin``, its id in ``full`` (the twin keeps the full model's
    order: each is the next geom of ``full`` on the same body with the same type, name,
    size and pose). Raises ``ValueError`` when ``twin`` is not ``full`` less some geoms."""
    ids = np.empty(twin.ngeom, dtype=np.int64)
    j = 0
    for i in range(twin.ngeom):
        while j < full.ngeom and not (
            full.geom_bodyid[j] == twin.geom_bodyid[i]
            and full.geom_type[j] == twin.geom_type[i]
            and full.geom(j).name == twin.geom(i).name
            and np.array_equal(full.geom_size[j], twin.geom_size[i])
            and np.array_equal(full.geom_pos[j], twin.geom_pos[i])
        ):
            j += 1
        if j == full.ngeom:
            raise ValueError(f"shared_geoms: geom {i} of the twin has no match in the full model.")
        ids[i] = j
        j += 1
    return ids
