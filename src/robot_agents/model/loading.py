"""Read a robot's URDF or MJCF file into a fresh :class:`mujoco.MjSpec`.

URDF files are checked before MuJoCo sees them, so that pieces MuJoCo cannot use
(COLLADA meshes, missing mesh files, floating joints below the root) fail with a
clear :class:`~robot_agents.errors.ModelError` instead of a silent drop. Fixed
links are kept as bodies (``fusestatic="false"``) so tool frames survive.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

from robot_agents.errors import ModelError

SUPPORTED_MESH_SUFFIXES = (".stl", ".obj", ".msh")
_URDF_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")


def load_model_spec(path: str | os.PathLike[str]) -> mujoco.MjSpec:
    """Parse a ``.urdf`` or ``.xml``/``.mjcf`` file into a new MjSpec.

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
        return _load_urdf(file)
    if suffix in (".xml", ".mjcf"):
        return _load_mjcf(file)
    raise ModelError(f"load_model_spec: expected a model file ending in .urdf, .xml or .mjcf, got {str(file)!r}.")


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


def _load_mjcf(file: Path) -> mujoco.MjSpec:
    _parse_xml(file, "mujoco", "an MJCF")
    try:
        return mujoco.MjSpec.from_file(str(file))
    except ValueError as err:
        raise ModelError(f"load_model_spec: MuJoCo rejected {str(file)!r}: {err}") from None


def _load_urdf(file: Path) -> mujoco.MjSpec:
    root = _parse_xml(file, "robot", "a URDF")
    links = [link.get("name", "") for link in root.findall("link")]
    if not links:
        raise ModelError(f"load_model_spec: the URDF {str(file)!r} has no <link>; expected at least one.")
    children = {child.get("link", "") for child in root.findall("joint/child")}
    roots = [name for name in links if name not in children]
    for joint in root.findall("joint"):
        name = joint.get("name", "?")
        jtype = joint.get("type", "")
        if jtype not in _URDF_JOINT_TYPES:
            raise ModelError(
                f"load_model_spec: joint {name!r} in {str(file)!r} has type {jtype!r}; expected one of {', '.join(_URDF_JOINT_TYPES)}."
            )
        parent = joint.find("parent")
        if jtype == "floating" and parent is not None and parent.get("link") not in roots:
            raise ModelError(
                f"load_model_spec: floating joint {name!r} in {str(file)!r} is below link {parent.get('link')!r}; "
                "MuJoCo supports a free joint only on the root link (set fix_root_link=False instead)."
            )
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename", "")
        resolved = _resolve_mesh(file, filename)
        mesh.set("filename", str(resolved))
    # Keep fixed links (tool frames) as bodies, keep visual geoms, use the absolute mesh paths.
    extension = root.find("mujoco")
    if extension is None:
        extension = ET.SubElement(root, "mujoco")
    compiler = extension.find("compiler")
    if compiler is None:
        compiler = ET.SubElement(extension, "compiler")
    compiler.set("fusestatic", "false")
    compiler.set("discardvisual", "false")
    compiler.set("strippath", "false")
    try:
        spec = mujoco.MjSpec.from_string(ET.tostring(root, encoding="unicode"))
    except ValueError as err:
        raise ModelError(f"load_model_spec: MuJoCo rejected the URDF {str(file)!r}: {err}") from None
    spec.modelfiledir = str(file.parent)
    _add_mimic_equalities(spec, root)
    return spec


def _add_mimic_equalities(spec: mujoco.MjSpec, root: ET.Element) -> None:
    """Couple URDF ``<mimic>`` joints with joint equalities
    (``follower = multiplier * leader + offset``) where MuJoCo's URDF parser did not
    (4.0.0's parser does; 3.3.7's drops the tag)."""
    existing = {(eq.name1, eq.name2) for eq in spec.equalities if eq.type == mujoco.mjtEq.mjEQ_JOINT}
    for joint in root.findall("joint"):
        mimic = joint.find("mimic")
        follower = joint.get("name", "")
        if mimic is None or (follower, mimic.get("joint", "")) in existing:
            continue
        equality = spec.add_equality()
        equality.type = mujoco.mjtEq.mjEQ_JOINT
        equality.name1, equality.name2 = follower, mimic.get("joint", "")
        data = np.zeros(len(equality.data))
        data[0], data[1] = float(mimic.get("offset", 0.0)), float(mimic.get("multiplier", 1.0))
        equality.data = data


def _resolve_mesh(urdf: Path, filename: str) -> Path:
    if not filename:
        raise ModelError(f"load_model_spec: a <mesh> in {str(urdf)!r} has no filename attribute.")
    suffix = Path(filename).suffix.lower()
    if suffix not in SUPPORTED_MESH_SUFFIXES:
        raise ModelError(
            f"load_model_spec: mesh {filename!r} in {str(urdf)!r} has format {suffix or '(none)'!r}; "
            f"MuJoCo reads {', '.join(SUPPORTED_MESH_SUFFIXES)} (convert it, e.g. COLLADA .dae to .obj)."
        )
    candidates: list[Path] = []
    if filename.startswith("package://"):
        relative = Path(filename[len("package://") :])
        # package://<pkg>/<rest>: look for <rest> and <pkg>/<rest> next to the URDF and above it.
        for base in (urdf.parent, *urdf.parent.parents):
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
        f"{', '.join(repr(str(c)) for c in candidates[:4])}{' ...' if len(candidates) > 4 else ''}."
    )
