"""Compiling a model file from the wild: the known compile failures and the compiler
settings that fix them (:data:`FALLBACKS`), tried one after another with a note
(:func:`compile_with_fallbacks`), and an inertia MuJoCo cannot use located in its file
(:func:`inertia_message`)."""

from __future__ import annotations

import dataclasses
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from robot_agents.errors import ModelError
from robot_agents.model.compiler import CompilerSettings
from robot_agents.model.compiling import compile_spec
from robot_agents.model.loading import looked_up, stripped_note

NOT_POSITIVE = "inertia must have positive eigenvalues"
#: How :func:`~robot_agents.model.compiling.compile_spec` introduces MuJoCo's message.
COULD_NOT = "MuJoCo could not compile the model:"
#: MuJoCo's refusal of a flat or open mesh, followed by the mesh's name.
SMALL_VOLUME = re.compile(r"mesh volume is too small: (\S+?)\s*\.\s*Try setting inertia to shell")

#: The most flat meshes the fallbacks give shell inertia, one compile each.
MAX_SHELL_MESHES = 16
#: Known compile failures of files from the wild and the compiler settings that fix them.
FALLBACKS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("balanceinertia", {"balanceinertia": True}),
    ("mjMINVAL", {"boundmass": 1e-3, "boundinertia": 1e-6}),
    # a dummy link's all-equal tiny inertia (1e-6 everywhere): bounded, it becomes valid
    (NOT_POSITIVE, {"boundmass": 1e-3, "boundinertia": 1e-6}),
)


def compile_with_fallbacks(
    name: str,
    spec: mujoco.MjSpec,
    compiler: CompilerSettings,
    rebuild: Callable[[CompilerSettings], mujoco.MjSpec],
    path: Path,
    pieces: bool = False,
) -> tuple[mujoco.MjModel, CompilerSettings]:
    """Compile; on a known failure (inertia triangle inequality, massless moving body, a
    flat mesh: :data:`SMALL_VOLUME`) rebuild with the setting that fixes it and say so in
    one warning. ``name``: the robot's; ``rebuild``: its spec built again with other
    compiler settings; ``path``: its model file (for an inertia's line, and named in
    MuJoCo's other refusals); ``pieces``: the robot has pieces mounted, whose files an
    error may be in."""
    for _ in range(len(FALLBACKS) + MAX_SHELL_MESHES + 1):
        try:
            return compile_spec(spec, name), compiler
        except ModelError as err:
            negative = negative_inertial(spec)
            if negative is not None:  # a file's fault that no setting fixes (bounded, it was simulated as another)
                element, mass = negative
                raise ModelError(inertia_message(name, path, f"Element name '{element}'", compiler, mass)) from None
            missing = missing_file_message(name, spec, path, str(err))
            if missing is not None:
                raise ModelError(missing) from None
            fix = next((changes for key, changes in FALLBACKS if key in str(err)), None)
            small = SMALL_VOLUME.search(str(err))
            if small is not None and small.group(1) not in compiler.shell_meshes:
                # MuJoCo's own advice for a flat or open mesh: its volume from its surface
                fix = {"shell_meshes": (*compiler.shell_meshes, small.group(1))}
            if fix is None or all(getattr(compiler, k) == v for k, v in fix.items()):
                if NOT_POSITIVE in str(err):
                    raise ModelError(inertia_message(name, path, str(err), compiler)) from None
                if str(path) in str(err):
                    raise
                # MuJoCo gives the element and its line; the file they are in:
                files = f"{str(path)!r}{' or of a piece mounted on it' if pieces else ''}"
                located = str(err).replace(COULD_NOT, f"{COULD_NOT[:-1]} of {files}:", 1)
                raise ModelError(located) from None
            compiler = dataclasses.replace(compiler, **fix)
            lines = str(err).split(": MuJoCo could not compile the model: ")[-1].splitlines()
            reason = "; ".join(line.strip() for line in lines[:2] if line.strip())
            warnings.warn(
                f"{name}: MuJoCo refused the model ({reason}); compiled with "
                f"{', '.join(f'{k}={v}' for k, v in fix.items())}: declare compiler = CompilerSettings(...) to make "
                "this explicit, or fix the file.",
                RuntimeWarning,
                stacklevel=4,
            )
            spec = rebuild(compiler)
    raise ModelError(f"{name}: the model does not compile.")


#: MuJoCo's refusal of an asset file it cannot open, followed by the name the file gives.
MISSING_FILE = re.compile(r"Error opening file '([^']*)'")


def missing_file_message(name: str, spec: mujoco.MjSpec, path: Path, error: str) -> str | None:
    """For MuJoCo's "Error opening file" (a mesh or texture that is not there, which it
    names without the model file or where it looked): the asset, the model file and its
    line, and the path it was looked for at; ``None`` for any other error."""
    found = MISSING_FILE.search(error)
    if found is None:
        return None
    given = found.group(1)
    for kind, tag, folder in (("meshes", "mesh", spec.meshdir), ("textures", "texture", spec.texturedir)):
        # MuJoCo names the file with its folder (<compiler meshdir>) in front, and under
        # <compiler strippath="true"> without the folders written in the file's name
        asset = next((a for a in getattr(spec, kind) if a.file and Path(given) in _named(spec, a.file, folder)), None)
        if asset is None:
            continue
        looked = looked_up(spec, asset.file, Path(spec.modelfiledir or path.parent) / folder)
        line = 0
        if path.is_file():
            text = path.read_text(errors="replace")
            match = re.search(rf'<{tag}\b[^>]*\bfile\s*=\s*["\']{re.escape(asset.file)}["\']', text)
            line = text.count("\n", 0, match.start()) + 1 if match else 0
        return (
            f"{name}: the {tag} file {asset.file!r} of <{tag} name={asset.name!r}> in {str(path)!r}"
            f"{f' (line {line})' if line else ''} was not found at {str(looked)!r}{stripped_note(spec, asset.file)}; "
            "expected a file there (a path "
            f"relative to the model file's folder, under its <compiler {tag}dir> when it has one): fix the path or "
            "add the file."
        )
    return None


def _named(spec: mujoco.MjSpec, name: str, folder: str) -> tuple[Path, Path]:
    """How MuJoCo names an asset file written ``name`` when it cannot open it: with its
    folder (``meshdir`` / ``texturedir``) in front or not, its own folders dropped under
    ``<compiler strippath="true">``."""
    shown = Path(name).name if spec.strippath else name
    return Path(shown), Path(folder) / shown


def negative_inertial(spec: mujoco.MjSpec) -> tuple[str, float] | None:
    """The first body whose explicit inertial has a negative mass or a negative principal
    moment: its name and its mass (kg); ``None`` when there is none. MuJoCo refuses both
    with the messages of a massless or unbalanced body, whose fallbacks (``boundmass``,
    ``balanceinertia``) would then simulate another body: -0.5 kg as 0.001 kg."""
    for body in spec.bodies[1:]:
        if not body.explicitinertial:
            continue
        full = np.asarray(body.fullinertia, dtype=np.float64)
        if np.isnan(full[0]):
            moments = np.asarray(body.inertia, dtype=np.float64)
        else:  # ixx, iyy, izz, ixy, ixz, iyz
            moments = np.linalg.eigvalsh(
                np.array([[full[0], full[3], full[4]], [full[3], full[1], full[5]], [full[4], full[5], full[2]]])
            )
        scale = float(np.max(np.abs(moments)))
        if body.mass < 0 or float(np.min(moments)) < -1e-9 * scale:
            return body.name, float(body.mass)
    return None


def inertia_message(name: str, path: Path, error: str, compiler: CompilerSettings, mass: float | None = None) -> str:
    """Where an inertia MuJoCo cannot use sits (file, link, line) and how to fix it;
    ``mass`` (kg): the body's, when it is negative the message says so."""
    found = re.search(r"Element name '([^']*)'", error)
    element = found.group(1) if found else ""
    line = 0
    if element and path.is_file():
        tag = "link" if path.suffix.lower() == ".urdf" else "body"
        text = path.read_text(errors="replace")
        match = re.search(rf'<{tag}\b[^>]*\bname\s*=\s*["\']{re.escape(element)}["\']', text)
        line = text.count("\n", 0, match.start()) + 1 if match else 0
    where = f"{'link' if path.suffix.lower() == '.urdf' else 'body'} {element!r}" if element else "a body"
    tried = (
        " (also with boundmass / boundinertia, which do not fix it)"
        if compiler.boundinertia or compiler.boundmass
        else ""
    )
    if mass is not None and mass < 0:
        return (
            f"{name}: the mass of {where} in {str(path)!r}{f' (line {line})' if line else ''} is {mass:g} kg: MuJoCo "
            "refuses it. Expected a mass >= 0 (0 for a link that only carries a frame); edit that "
            f"{'<mass>' if path.suffix.lower() == '.urdf' else '<inertial> mass'}."
        )
    return (
        f"{name}: the inertia of {where} in {str(path)!r}{f' (line {line})' if line else ''} is not "
        f"positive-definite: MuJoCo refuses it{tried}. Expected an <inertia> whose matrix has positive eigenvalues "
        "(ixx, iyy, izz > 0, each at most the sum of the other two, small off-diagonal terms); edit that <inertia>, "
        "or remove the <inertial> of a link that only carries a frame."
    )
