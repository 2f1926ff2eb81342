"""Read a robot's URDF or MJCF file into a fresh :class:`mujoco.MjSpec`, without hand
edits where the fix is known.

- Meshes MuJoCo cannot read (``.glb``, ``.gltf``, ``.dae``, ``.ply``) are converted once
  into a cache (:mod:`.meshes`); when no converter is installed a visual-only mesh is
  dropped with one warning that says what to install, a collision mesh is an error.
- ``package://`` URIs resolve next to the file, above it, and in the declared search
  paths (:class:`~robot_agents.model.compiler.CompilerSettings`).
- URDF pieces MuJoCo cannot use or would misread (unknown joint types, a floating joint
  below the root, a link with two ``<inertial>``, a zero-size collision shape) fail
  with a :class:`~robot_agents.errors.ModelError` that names the element, the file,
  the line and the fix; a zero-size visual shape is dropped with a note.
- Fixed links are kept as bodies (``fusestatic="false"``) so tool frames survive.
"""

from __future__ import annotations

import functools
import math
import os
import re
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.parsers import expat

import mujoco
import numpy as np

from robot_agents.errors import ModelError, close_names
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.inertia import combine_inertias
from robot_agents.model.meshes import SUPPORTED_MESH_SUFFIXES, MeshConversionUnavailable, mujoco_reads, readable_mesh
from robot_agents.notes import mujoco_messages

_URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_DEFAULT_SETTINGS = CompilerSettings()


def looked_up(spec: mujoco.MjSpec, name: str, folder: Path) -> Path:
    """Where MuJoCo looks for an asset file written ``name`` (a mesh's, a texture's) whose
    folder is ``folder`` (the model file's folder joined with its ``meshdir`` /
    ``texturedir``): under ``<compiler strippath="true">`` the name's own folders are
    dropped (an absolute path too: only the file's name is kept), then a relative name is
    taken inside ``folder``."""
    path = Path(Path(name).name if spec.strippath else name)
    return path if path.is_absolute() else folder / path


def stripped_note(spec: mujoco.MjSpec, name: str) -> str:
    """Words saying that ``<compiler strippath="true">`` dropped the folders of ``name``
    (empty when it did not: no strippath, or a bare file name)."""
    if not spec.strippath or Path(name).name == name:
        return ""
    return f' (the file\'s <compiler strippath="true"> drops the folders written in {name!r})'


def bake_strippath(spec: mujoco.MjSpec) -> None:
    """Apply ``<compiler strippath="true">`` to every asset file name of ``spec`` (meshes,
    textures with their cube faces, height fields, skins) and turn it off, so that a name
    this library writes (a converted mesh's absolute path) is read as written."""
    for asset in (*spec.meshes, *spec.hfields, *spec.skins, *spec.textures):
        if asset.file:
            asset.file = Path(asset.file).name
    for texture in spec.textures:
        texture.cubefiles = [Path(face).name if face else face for face in texture.cubefiles]
    spec.strippath = False


def load_model_spec(path: str | os.PathLike[str], compiler: CompilerSettings = _DEFAULT_SETTINGS) -> mujoco.MjSpec:
    """Parse a ``.urdf`` or ``.xml``/``.mjcf`` file into a new MjSpec with the declared
    ``compiler`` settings applied.

    Raises:
        ModelError: the file is missing, is not a file, has an unknown suffix, is not
            well-formed XML, uses unsupported URDF pieces, or MuJoCo rejects it.
    """
    file = Path(path).expanduser()
    if not file.exists():
        raise ModelError(f"load_model_spec: model file {str(file)!r} does not exist.")
    if not file.is_file():
        raise ModelError(f"load_model_spec: expected a file, got the directory {str(file)!r}.")
    suffix = file.suffix.lower()
    if suffix == ".urdf":
        spec = _load_urdf(file, compiler)
    elif suffix in (".xml", ".mjcf"):
        spec = _load_mjcf(file, compiler)
    else:
        raise ModelError(f"load_model_spec: expected a model file ending in .urdf, .xml or .mjcf, got {str(file)!r}.")
    compiler.apply(spec)
    name_unnamed(spec)
    _check_finite(spec, file)
    _check_joint_ranges(spec, file)
    _bake_total_mass(spec)
    return spec


def _check_finite(spec: mujoco.MjSpec, file: Path) -> None:
    """Raise :class:`ModelError` for a NaN or infinite number in a body's pose or inertial,
    a joint's pose, axis, range or dynamics, or a geom's pose or size, and for a hinge or
    slide joint's zero axis, naming the element,
    the file and its line: MuJoCo reads ``nan`` and ``inf`` as numbers, and such a file
    failed far from its cause (a NaN origin: "EndEffector 'ee'.pos: expected 3 finite
    numbers"; an infinite mass compiled and blew up)."""
    urdf = file.suffix.lower() == ".urdf"
    checks: list[tuple[str, str, list[tuple[mujoco.MjsElement, str]]]] = []
    bodies = []
    for body in spec.bodies[1:]:
        bodies += [(body, "pos"), (body, "quat")]
        if body.explicitinertial:
            bodies += [(body, "mass"), (body, "ipos"), (body, "inertia")]
    checks.append(("link" if urdf else "body", "link" if urdf else "body", bodies))
    fields = ("pos", "axis", "range", "damping", "armature", "frictionloss", "stiffness")
    checks.append(("joint", "joint", [(joint, field) for joint in spec.joints for field in fields]))
    checks.append(
        ("geom", "link" if urdf else "geom", [(geom, f) for geom in spec.geoms for f in ("pos", "quat", "size")])
    )
    for joint in spec.joints:  # MuJoCo: "axis too small in joint", naming none
        moving = joint.type in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE)
        if moving and np.all(np.isfinite(joint.axis)) and not np.linalg.norm(joint.axis) > 1e-9:
            raise ModelError(
                f"load_model_spec: {_joint_in_file(file, joint.name)} has axis "
                f"{np.asarray(joint.axis).tolist()}; expected a direction (a nonzero axis)."
            )
    for kind, tag, pairs in checks:
        for element, field in pairs:
            values = np.atleast_1d(np.asarray(getattr(element, field), dtype=np.float64))
            if np.all(np.isfinite(values)):
                continue
            name = element.name if kind != "geom" or not urdf else element.parent.name
            text = file.read_text(errors="replace") if file.is_file() else ""
            line = _line_of(text, rf'<{tag}\b[^>]*\bname\s*=\s*["\']{re.escape(name)}["\']') if name else 0
            owner = f"{kind} {element.name!r}" if kind != "geom" or not urdf else f"a shape of link {name!r}"
            if urdf and kind == "link" and field in ("pos", "quat"):
                field += " (its parent joint's <origin>)"
            raise ModelError(
                f"load_model_spec: {owner} in {str(file)!r}{f' (line {line})' if line else ''} has {field} "
                f"{values.tolist()}; expected finite numbers (a NaN or inf in the file: an unexpanded or failed "
                "expression?)."
            )


def _check_joint_ranges(spec: mujoco.MjSpec, file: Path) -> None:
    """Raise :class:`ModelError` for an MJCF joint whose ``range`` is upside down under
    autolimits (``range="1 0"``): MuJoCo reads it as no limit, without a word. A URDF's
    ``lower > upper`` stays pybullet's "no limit"."""
    if file.suffix.lower() == ".urdf" or not spec.compiler.autolimits:
        return
    for joint in spec.joints:
        low, high = (float(v) for v in joint.range)
        if joint.limited == mujoco.mjtLimited.mjLIMITED_AUTO and low > high:
            raise ModelError(
                f"load_model_spec: {_joint_in_file(file, joint.name)} has range {[low, high]}; expected lower <= "
                "upper (MuJoCo would leave the joint unlimited; swap the values, or drop the range for an "
                "unlimited joint)."
            )


def _joint_in_file(file: Path, name: str) -> str:
    """``joint 'name' in 'file' (line N)`` for messages (no line when it is not found)."""
    text = file.read_text(errors="replace") if file.is_file() else ""
    line = _line_of(text, rf'<joint\b[^>]*\bname\s*=\s*["\']{re.escape(name)}["\']')
    return f"joint {name!r} in {str(file)!r}{f' (line {line})' if line else ''}"


def _bake_total_mass(spec: mujoco.MjSpec) -> None:
    """Write a file's ``<compiler settotalmass>`` into its bodies: each body gets the
    mass, centre of mass and principal inertia (kg, m, kg*m^2) the file compiles to, as
    an explicit inertial, and the setting is cleared. MuJoCo scales a model's masses to
    that total when the model itself is compiled; a robot attached into a scene lost it
    (gymnasium's ``half_cheetah.xml``: 21.18 kg in a scene against the file's 14). A file
    that does not compile keeps the setting: its compile error is reported later."""
    if not spec.compiler.settotalmass > 0:
        return
    copy = spec.copy()
    copy.compiler.fusestatic = False  # one compiled body per body of the spec, in its order
    try:
        with warnings.catch_warnings():  # MuJoCo's deprecation of the setting: it is cleared below
            warnings.filterwarnings("ignore", message="compiler attribute 'settotalmass' is deprecated")
            model = copy.compile()
    except ValueError:
        return
    for number, body in enumerate(spec.bodies[1:], start=1):
        body.mass = float(model.body_mass[number])
        body.ipos = model.body_ipos[number].tolist()
        body.iquat = model.body_iquat[number].tolist()
        body.inertia = model.body_inertia[number].tolist()
        body.fullinertia = [math.nan, 0.0, 0.0, 0.0, 0.0, 0.0]  # unset: the principal inertia in its frame (iquat)
        body.explicitinertial = True
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_AUTO  # every body's is explicit
    spec.compiler.settotalmass = -1.0


#: The speeds (rad/s for a hinge, m/s for a slide) from which a URDF's ``<limit
#: velocity>`` is a placeholder, taken as none: over the 105 URDFs of the
#: example-robot-data and mani-skill wheels, the fastest stated joints are legged robots'
#: motors (Unitree G1 53 rad/s, Laikago 52.4, Go2 30.1) and slides 5 m/s (Baxter), while
#: placeholders are 100 (D'Claw, whose XM430 servos turn 4.8 rad/s), 1000 (TriFinger)
#: and 10000 (Baxter's head, the flying arms).
PLACEHOLDER_SPEED = {"hinge": 100.0, "slide": 10.0}


def urdf_velocity_limits(path: str | os.PathLike[str]) -> dict[str, float]:
    """Each joint's speed limit a URDF states (``<limit velocity>``, rad/s or m/s), for the
    joints that give a positive one (a URDF writes ``velocity="0"`` for none, as it writes
    ``effort="0"``) below :data:`PLACEHOLDER_SPEED` (faster ones are taken as none, with a
    note); an empty dict for any other file. MuJoCo's URDF reader keeps the effort limits
    (``actuatorfrcrange``) and drops the speeds: the drives take them from here
    (:func:`robot_agents.actuators.spec.apply_actuators`)."""
    file = Path(path).expanduser()
    if file.suffix.lower() != ".urdf" or not file.is_file():
        return {}
    speeds, placeholders = {}, []
    for name, kind, speed in _urdf_speeds(str(file.resolve()), file.stat().st_mtime_ns):
        if speed < PLACEHOLDER_SPEED[kind]:
            speeds[name] = speed
        else:
            placeholders.append(f"{name} ({speed:g} {'rad/s' if kind == 'hinge' else 'm/s'})")
    if placeholders:
        warnings.warn(
            f"{str(file)!r}: joint speed limits taken as none, too fast for any robot's joint (a placeholder): "
            f"{', '.join(placeholders[:4])}{' ...' if len(placeholders) > 4 else ''}; state the motors' with "
            "actuators = (ra.DerivedActuators(velocity_limit=...),).",
            RuntimeWarning,
            stacklevel=2,
        )
    return speeds


@functools.lru_cache(maxsize=64)
def _urdf_speeds(file: str, _mtime_ns: int) -> tuple[tuple[str, str, float], ...]:
    """(joint, ``"hinge"`` or ``"slide"``, speed) per positive stated speed."""
    speeds = []
    for joint in _parse_xml(Path(file), "robot", "a URDF").findall("joint"):
        limit, kind = joint.find("limit"), joint.get("type")
        try:
            speed = float(limit.get("velocity", "0")) if limit is not None else 0.0
        except ValueError:
            continue  # not a number: MuJoCo's reader reports the file's own faults
        if kind in ("revolute", "continuous", "prismatic") and math.isfinite(speed) and speed > 0:
            speeds.append((joint.get("name", ""), "slide" if kind == "prismatic" else "hinge", speed))
    return tuple(speeds)


def name_unnamed(spec: mujoco.MjSpec) -> None:
    """Give the file's unnamed bodies and joints names: ``body<k>`` and ``joint<k>``, ``k``
    their place among the file's bodies (the world is 0) or joints, unless the file uses
    that name already (then ``_`` is appended until it is free). The library finds a
    robot's root, its end effector, its drives and keyframes by name: MJCF written by
    hand often names only the joints it actuates (gymnasium-robotics' Franka kitchen: an
    unnamed root body failed in every scene)."""
    for elements, stem, first in ((spec.bodies[1:], "body", 1), (spec.joints, "joint", 0)):
        taken = {e.name for e in elements}
        for number, element in enumerate(elements, start=first):
            if element.name:
                continue
            name = f"{stem}{number}"
            while name in taken:
                name += "_"
            element.name = name
            taken.add(name)


def _parse_xml(file: Path, root_tag: str, kind: str) -> ET.Element:
    """The root element of a well-formed XML file whose root is ``<root_tag>``."""
    try:
        root = ET.parse(file).getroot()
    except ET.ParseError as err:
        raise ModelError(f"load_model_spec: {str(file)!r} is not well-formed XML: {err}.") from None
    if root.tag != root_tag:
        raise ModelError(
            f"load_model_spec: expected {kind} file with a <{root_tag}> root in {str(file)!r}, got <{root.tag}>."
        )
    return root


def _line_of(text: str, pattern: str) -> int:
    """1-based line of the first match of ``pattern`` in ``text`` (0 when absent)."""
    match = re.search(pattern, text)
    return text.count("\n", 0, match.start()) + 1 if match else 0


def _load_mjcf(file: Path, compiler: CompilerSettings) -> mujoco.MjSpec:
    _parse_xml(file, "mujoco", "an MJCF")
    try:
        with mujoco_messages(f"load_model_spec: {str(file)!r}"):
            if file.suffix == ".xml":
                spec = mujoco.MjSpec.from_file(str(file))
            else:
                # MuJoCo picks its reader by the name's ending and reads only ".xml" (".mjcf",
                # ".XML": "could not find decoder"): the file's text under that name, in its own
                # folder, where its includes and meshes are found
                named = file.with_name(f"{file.stem}.xml")
                spec = mujoco.MjSpec.from_file(str(named), include={str(named): file.read_bytes()})
    except ValueError as err:
        raise ModelError(f"load_model_spec: MuJoCo rejected {str(file)!r}: {err}") from None
    if compiler.meshdir is not None:
        spec.meshdir = compiler.meshdir
    base = file.parent / (spec.meshdir or "")
    dropped: list[str] = []
    for mesh in list(spec.meshes):
        suffix = Path(mesh.file).suffix.lower() if mesh.file else ""
        if not mesh.file or (suffix in SUPPORTED_MESH_SUFFIXES and suffix != ".stl"):
            continue
        source = looked_up(spec, mesh.file, base)
        if suffix == ".stl" and (not source.is_file() or mujoco_reads(source)):
            continue  # MuJoCo reads it (or finds it where this does not look, or says it is missing)
        if not source.is_file():
            raise ModelError(
                f"load_model_spec: mesh {mesh.file!r} of {str(file)!r} was not found at {str(source)!r}"
                f"{stripped_note(spec, mesh.file)}."
            )
        if spec.strippath:  # the converted mesh's own path must stay as written
            bake_strippath(spec)
        try:
            mesh.file = str(readable_mesh(source))
        except MeshConversionUnavailable as err:
            users = [g for g in spec.geoms if g.meshname == mesh.name]
            if any(g.contype or g.conaffinity for g in users):
                raise ModelError(f"load_model_spec: collision mesh {mesh.name!r} of {str(file)!r}: {err}") from None
            for geom in users:
                spec.delete(geom)
            spec.delete(mesh)
            dropped.append(mesh.file)
    _warn_dropped(file, dropped)
    return spec


def _warn_dropped(file: Path, dropped: list[str]) -> None:
    if dropped:
        from robot_agents.model.meshes import INSTALL_HINT

        warnings.warn(
            f"{str(file)!r}: dropped {len(dropped)} visual mesh(es) MuJoCo cannot read ({', '.join(dropped[:3])}"
            f"{' ...' if len(dropped) > 3 else ''}); to keep them: {INSTALL_HINT}.",
            RuntimeWarning,
            stacklevel=4,
        )


def _merged_inertial(inertials: list[ET.Element], where: str) -> ET.Element:
    """One URDF ``<inertial>`` for several: the total mass at the combined centre of
    mass, the inertias turned into the link's axes and moved there (parallel axes)."""
    masses, centres, tensors = [], [], []
    for inertial in inertials:
        try:
            mass_element, origin, inertia = inertial.find("mass"), inertial.find("origin"), inertial.find("inertia")
            mass = float(mass_element.get("value", "0")) if mass_element is not None else 0.0
            xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
            terms = {k: float(inertia.get(k, "0")) if inertia is not None else 0.0 for k in _INERTIA_TERMS}
        except ValueError as err:
            raise ModelError(f"{where}: an <inertial> has a value that is not a number: {err}.") from None
        if len(xyz) != 3 or len(rpy) != 3:
            raise ModelError(f"{where}: an <inertial>'s origin needs 3 numbers in xyz and rpy.")
        tensor = np.zeros((3, 3))
        for key, (i, j) in zip(_INERTIA_TERMS, _INERTIA_INDEX, strict=True):
            tensor[i, j] = tensor[j, i] = terms[key]
        rotation = _rpy_matrix(rpy)
        masses.append(mass)
        centres.append(np.array(xyz))
        tensors.append(rotation @ tensor @ rotation.T)
    total, centre, combined = combine_inertias(masses, centres, tensors)
    merged = ET.Element("inertial")
    ET.SubElement(merged, "origin", xyz=" ".join(repr(float(v)) for v in centre), rpy="0 0 0")
    ET.SubElement(merged, "mass", value=repr(total))
    ET.SubElement(
        merged,
        "inertia",
        {k: repr(float(combined[i, j])) for k, (i, j) in zip(_INERTIA_TERMS, _INERTIA_INDEX, strict=True)},
    )
    return merged


_INERTIA_TERMS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_INERTIA_INDEX = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def _rpy_matrix(rpy: list[float]) -> np.ndarray:
    """URDF's roll, pitch, yaw (rad, about the fixed x, y, z axes in turn) as a rotation
    matrix: MuJoCo's extrinsic ``"XYZ"`` Euler sequence."""
    quat, matrix = np.zeros(4), np.zeros(9)
    mujoco.mju_euler2Quat(quat, np.asarray(rpy, dtype=np.float64), "XYZ")
    mujoco.mju_quat2Mat(matrix, quat)
    return matrix.reshape(3, 3)


def _check_links(file: Path, root: ET.Element, text: str) -> None:
    """Duplicate inertials (merged, with a note) and zero-size shapes, named with their
    line and fix."""
    weighed: list[str] = []
    states_masses = root.find("link/inertial") is not None
    for link in root.findall("link"):
        name = link.get("name", "?")
        line = _line_of(text, rf'<link\b[^>]*\bname\s*=\s*["\']{re.escape(name)}["\']')
        inertials = link.findall("inertial")
        if not inertials and link.find("collision") is not None:
            weighed.append(f"{name!r} (line {line})")
            if states_masses:  # massless, as URDF has it (MuJoCo's reader would weigh its collision shapes)
                link.insert(0, _massless_inertial())
        if len(inertials) > 1:
            # a link has one: the body they describe together
            merged = _merged_inertial(inertials, f"load_model_spec: link {name!r} in {str(file)!r} (line {line})")
            for inertial in inertials:
                link.remove(inertial)
            link.insert(0, merged)
            warnings.warn(
                f"{str(file)!r}: link {name!r} (line {line}) has {len(inertials)} <inertial> elements; a link has one: "
                "merged into one (total mass, combined centre of mass and inertia). Merge them in the file to "
                "silence this.",
                RuntimeWarning,
                stacklevel=4,
            )
        for kind in ("visual", "collision"):
            for element in list(link.findall(kind)):
                geometry = element.find("geometry")
                shape = geometry[0] if geometry is not None and len(geometry) else None
                if shape is None or not _zero_size(shape):
                    continue
                if kind == "collision":
                    raise ModelError(
                        f"load_model_spec: link {name!r} in {str(file)!r} (line {line}) has a zero-size collision "
                        f"<{shape.tag}> ({dict(shape.attrib)}); give it a size or remove it."
                    )
                link.remove(element)
                warnings.warn(
                    f"{str(file)!r}: dropped a zero-size visual <{shape.tag}> of link {name!r} (line {line}).",
                    RuntimeWarning,
                    stacklevel=4,
                )
    if weighed:
        links = f"{', '.join(weighed[:4])}{' ...' if len(weighed) > 4 else ''}"
        if states_masses:
            message = (
                f"link(s) {links} have collision shapes and no <inertial>: massless, as URDF has it (MuJoCo's reader "
                "would give them the mass of those shapes at water's density, 1000 kg/m^3: the ANYmal C's base "
                "link, 29.4 kg on a 52.1 kg robot). Give each an <inertial> to state its mass."
            )
        else:  # a file stating no mass at all (a kinematic one): massless links would weigh 1 g each
            message = (
                f"the file states no <inertial>: link(s) {links} get the mass and inertia of their collision shapes "
                "at water's density (1000 kg/m^3, MuJoCo's reader's rule). Give each an <inertial> to state its mass."
            )
        warnings.warn(f"{str(file)!r}: {message}", RuntimeWarning, stacklevel=4)


def _massless_inertial() -> ET.Element:
    """A URDF ``<inertial>`` of no mass and no inertia (a link that only carries shapes)."""
    inertial = ET.Element("inertial")
    ET.SubElement(inertial, "mass", value="0")
    ET.SubElement(inertial, "inertia", dict.fromkeys(_INERTIA_TERMS, "0"))
    return inertial


def _zero_size(shape: ET.Element) -> bool:
    def numbers(attribute: str) -> list[float]:
        try:
            return [float(v) for v in shape.get(attribute, "1").split()]
        except ValueError:
            return [1.0]

    if shape.tag == "box":
        return any(v <= 0 for v in numbers("size"))
    if shape.tag == "sphere":
        return any(v <= 0 for v in numbers("radius"))
    if shape.tag == "cylinder":
        return any(v <= 0 for v in numbers("radius") + numbers("length"))
    if shape.tag == "mesh":  # a negative scale mirrors the mesh; a zero one flattens it
        return any(v == 0 for v in numbers("scale"))
    return False


def _load_urdf(file: Path, compiler: CompilerSettings) -> mujoco.MjSpec:
    root = _parse_xml(file, "robot", "a URDF")
    text = file.read_text(errors="replace")
    source_lines = _element_lines(file, root)
    links = [link.get("name", "") for link in root.findall("link")]
    if not links:
        raise ModelError(f"load_model_spec: the URDF {str(file)!r} has no <link>; expected at least one.")
    _check_unique_names(file, root, source_lines)
    children = {child.get("link", "") for child in root.findall("joint/child")}
    roots = [name for name in links if name not in children]
    for joint in root.findall("joint"):
        name = joint.get("name", "?")
        jtype = joint.get("type", "")
        if jtype not in _URDF_JOINT_TYPES:
            raise ModelError(
                f"load_model_spec: joint {name!r} in {str(file)!r} has type {jtype!r}; expected one of {', '.join(_URDF_JOINT_TYPES)}."
            )
        for end in ("parent", "child"):
            end_element = joint.find(end)
            link_name = end_element.get("link", "") if end_element is not None else ""
            if link_name not in links:
                line = _line_of(text, rf'<joint\b[^>]*\bname\s*=\s*["\']{re.escape(name)}["\']')
                raise ModelError(
                    f"load_model_spec: joint {name!r} in {str(file)!r} (line {line}) names {end} link {link_name!r}, "
                    f"which is not in the file;{_did_you_mean(link_name, links)} links: {links}."
                )
        parent = joint.find("parent")
        if jtype == "floating" and parent is not None and parent.get("link") not in roots:
            raise ModelError(
                f"load_model_spec: floating joint {name!r} in {str(file)!r} is below link {parent.get('link')!r}; "
                "MuJoCo supports a free joint only on the root link (set fix_root_link=False instead)."
            )
    _check_links(file, root, text)
    _drop_fixed_mimics(file, root, source_lines)
    dropped: list[str] = []
    for link in root.findall("link"):
        for kind in ("visual", "collision"):
            for element in list(link.findall(kind)):
                for mesh in element.iter("mesh"):
                    filename = mesh.get("filename", "")
                    resolved = _resolve_mesh(file, filename, compiler)
                    try:
                        mesh.set("filename", str(readable_mesh(resolved)))
                    except MeshConversionUnavailable as err:
                        if kind == "collision":
                            raise ModelError(
                                f"load_model_spec: collision mesh of link {link.get('name')!r} in {str(file)!r}: {err}"
                            ) from None
                        link.remove(element)
                        dropped.append(filename)
                    except ModelError as err:
                        raise ModelError(
                            f"load_model_spec: link {link.get('name')!r} in {str(file)!r}: {err}"
                        ) from None
    _warn_dropped(file, dropped)
    # Keep fixed links (tool frames) as bodies, keep visual geoms, use the absolute mesh paths.
    extension = root.find("mujoco")
    if extension is None:
        extension = ET.SubElement(root, "mujoco")
    settings = extension.find("compiler")
    if settings is None:
        settings = ET.SubElement(extension, "compiler")
    settings.set("fusestatic", "false")
    settings.set("discardvisual", "false")
    settings.set("strippath", "false")
    serialized = ET.tostring(root, encoding="unicode")
    try:
        with mujoco_messages(f"load_model_spec: {str(file)!r}", handled=MIMIC_HANDLED):
            spec = mujoco.MjSpec.from_string(serialized)
    except ValueError as err:
        message = _in_source_lines(str(err), serialized, root, source_lines, text)
        raise ModelError(f"load_model_spec: MuJoCo rejected the URDF {str(file)!r}: {message}") from None
    spec.modelfiledir = str(file.parent)
    _add_mimic_equalities(spec, root, file, source_lines)
    return spec


def _check_unique_names(file: Path, root: ET.Element, source_lines: dict[ET.Element, int]) -> None:
    """Raise :class:`ModelError` naming the first link or joint name the URDF gives twice
    and the lines of both (MuJoCo's URDF reader takes it and fails later with a bare
    "repeated name")."""
    for tag, users in (("link", "joints"), ("joint", "mimics")):
        seen: dict[str, ET.Element] = {}
        for element in root.findall(tag):
            name = element.get("name", "")
            if name not in seen:
                seen[name] = element
                continue
            lines = [source_lines.get(e, 0) for e in (seen[name], element)]
            where = f" (lines {lines[0]} and {lines[1]})" if all(lines) else ""
            raise ModelError(
                f"load_model_spec: the URDF {str(file)!r} has two {tag}s named {name!r}{where}; expected each "
                f"{tag} to have its own name: rename one (and the {users} that refer to it)."
            )


def _drop_fixed_mimics(file: Path, root: ET.Element, source_lines: dict[ET.Element, int]) -> None:
    """Drop the ``<mimic>`` of a fixed joint, with a note (it cannot move: a reduced model
    that froze a gripper's joints keeps their mimics, example-robot-data's Talos files,
    and MuJoCo's reader coupled a joint it does not make: "unknown element ... in
    equality constraint"); a mimic of a fixed joint is an error naming its line."""
    kinds = {joint.get("name", ""): joint.get("type", "") for joint in root.findall("joint")}
    dropped = []
    for joint in root.findall("joint"):
        mimic = joint.find("mimic")
        if mimic is None:
            continue
        line = source_lines.get(mimic, 0)
        if kinds.get(mimic.get("joint", "")) == "fixed" and joint.get("type") != "fixed":
            raise ModelError(
                f"load_model_spec: joint {joint.get('name', '')!r} in {str(file)!r}{f' (line {line})' if line else ''} "
                f"mimics joint {mimic.get('joint', '')!r}, which is fixed and does not move; expected a moving joint "
                "to follow: remove the <mimic>, or make the follower fixed too."
            )
        if joint.get("type") == "fixed":
            joint.remove(mimic)
            dropped.append(f"{joint.get('name', '')!r}{f' (line {line})' if line else ''}")
    if dropped:
        warnings.warn(
            f"{str(file)!r}: dropped the <mimic> of {len(dropped)} fixed joint(s) ({', '.join(dropped[:4])}"
            f"{' ...' if len(dropped) > 4 else ''}): a fixed joint does not move.",
            RuntimeWarning,
            stacklevel=4,
        )


def _did_you_mean(given: str, names: list[str]) -> str:
    """`` did you mean 'a', 'b'?`` for the names closest to ``given``; empty when none is close."""
    close = close_names(given, names)
    return f" did you mean {', '.join(repr(n) for n in close)}?" if close else ""


def _element_lines(file: Path, root: ET.Element) -> dict[ET.Element, int]:
    """The line in ``file`` where each element of ``root`` (as parsed) starts: MuJoCo
    reads the URDF after the library's edits (resolved meshes, dropped shapes), so its
    line numbers are mapped back through these."""
    lines: list[int] = []
    parser = expat.ParserCreate()
    parser.StartElementHandler = lambda *_: lines.append(parser.CurrentLineNumber)
    try:
        with file.open("rb") as stream:
            parser.ParseFile(stream)
    except expat.ExpatError:
        return {}
    elements = list(root.iter())
    return dict(zip(elements, lines, strict=True)) if len(elements) == len(lines) else {}


def _in_source_lines(
    message: str, serialized: str, root: ET.Element, source_lines: dict[ET.Element, int], text: str
) -> str:
    """MuJoCo's ``message`` about the ``serialized`` URDF with its ``line N`` put back into
    the user's file (the same element's line there), plus a hint for unexpanded xacro."""
    found = re.search(r"\bline (\d+)", message)
    if not found or not source_lines:
        return message
    wanted = int(found.group(1))
    # ElementTree escapes every "<" in text and attribute values: each other "<" (no
    # comments or declarations are written) starts the next element in document order.
    starts = [serialized.count("\n", 0, m.start()) + 1 for m in re.finditer(r"<(?![/!?])", serialized)]
    element = next((e for e, line in zip(root.iter(), starts, strict=False) if line == wanted), None)
    if element is None or element not in source_lines:
        return message
    line = source_lines[element]
    mapped = (message[: found.start(1)] + str(line) + message[found.end(1) :]).rstrip()
    source = text.splitlines()[line - 1] if 0 < line <= len(text.splitlines()) else ""
    if "$(" in source or "${" in source:
        mapped += (
            f"; line {line} holds an unexpanded xacro expression ({source.strip()[:120]}): expand the file first "
            "(xacro model.urdf.xacro > model.urdf) and load the result"
        )
    return mapped


#: MuJoCo's URDF reader's word on a ``<mimic>`` it left out: :func:`_add_mimic_equalities`
#: couples the joint itself, or refuses a mimic of a joint the file does not have.
MIMIC_HANDLED = ("<mimic> on joint",)


def _add_mimic_equalities(
    spec: mujoco.MjSpec, root: ET.Element, file: Path, source_lines: dict[ET.Element, int]
) -> None:
    """Couple URDF ``<mimic>`` joints with joint equalities
    (``follower = multiplier * leader + offset``) where MuJoCo's URDF parser did not
    (4.0.0's parser does; 3.3.7's drops the tag). A mimic naming a joint the file does
    not have is an error naming ``file`` and the mimic's line (``source_lines``)."""
    existing = {(eq.name1, eq.name2) for eq in spec.equalities if eq.type == mujoco.mjtEq.mjEQ_JOINT}
    names = [j.get("name", "") for j in root.findall("joint")]
    for joint in root.findall("joint"):
        mimic = joint.find("mimic")
        follower = joint.get("name", "")
        if mimic is not None and mimic.get("joint", "") not in names:
            line = source_lines.get(mimic, 0)
            raise ModelError(
                f"load_model_spec: joint {follower!r} in {str(file)!r}{f' (line {line})' if line else ''} mimics joint "
                f"{mimic.get('joint', '')!r}, which is not in the URDF;{_did_you_mean(mimic.get('joint', ''), names)} "
                f"joints: {names}."
            )
        if mimic is None or (follower, mimic.get("joint", "")) in existing:
            continue
        equality = spec.add_equality()
        equality.type = mujoco.mjtEq.mjEQ_JOINT
        equality.name1, equality.name2 = follower, mimic.get("joint", "")
        data = np.zeros(len(equality.data))
        data[0], data[1] = float(mimic.get("offset", 0.0)), float(mimic.get("multiplier", 1.0))
        equality.data = data


def _resolve_mesh(urdf: Path, filename: str, compiler: CompilerSettings) -> Path:
    if not filename:
        raise ModelError(f"load_model_spec: a <mesh> in {str(urdf)!r} has no filename attribute.")
    candidates: list[Path] = []
    if filename.startswith("package://"):
        relative = Path(filename[len("package://") :])
        # package://<pkg>/<rest>: look for <rest> and <pkg>/<rest> next to the URDF, above
        # it, and in the declared search paths.
        for base in (urdf.parent, *urdf.parent.parents, *compiler.search_paths()):
            candidates += [base / relative, base / Path(*relative.parts[1:])]
    elif filename.startswith("file://"):
        candidates.append(Path(filename[len("file://") :]))
    else:
        path = Path(filename)
        candidates.append(path if path.is_absolute() else urdf.parent / path)
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
    raise ModelError(
        f"load_model_spec: mesh {filename!r} referenced by {str(urdf)!r} was not found; looked at "
        f"{', '.join(repr(str(c)) for c in candidates[:4])}{' ...' if len(candidates) > 4 else ''} "
        "(package:// folders can be added with CompilerSettings(package_paths=...) or ROBOT_AGENTS_PACKAGE_PATH)."
    )
