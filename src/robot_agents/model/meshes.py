"""Meshes MuJoCo cannot read (``.glb``, ``.gltf``, ``.dae``, ``.ply``, and STL files its
reader refuses: ASCII ones, and binary ones of more than 200,000 faces, as the
RealSense D415 of the mani-skill wheel's ``panda_v3.urdf``, 425,160) converted once
into ``.obj`` files in a cache, with trimesh (the ``robot-agents[meshes]`` extra:
trimesh for the formats, pycollada for COLLADA; an extra because most robots ship
meshes MuJoCo reads, and pycollada pulls in more).

The cache is ``$ROBOT_AGENTS_CACHE/meshes`` (default ``~/.cache/robot_agents/meshes``);
a converted file is named by a hash of the source's path, size and modification time,
so an edited mesh is converted again.
"""

from __future__ import annotations

import hashlib
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from robot_agents.errors import ModelError

#: Formats MuJoCo reads itself.
SUPPORTED_MESH_SUFFIXES = (".stl", ".obj", ".msh")
#: Formats converted through trimesh.
CONVERTIBLE_MESH_SUFFIXES = (".glb", ".gltf", ".dae", ".ply")
INSTALL_HINT = "pip install 'robot-agents[meshes]' (trimesh; pycollada for .dae)"
#: The most faces MuJoCo's STL reader takes (its decoder refuses a larger file, and any
#: ASCII STL); MuJoCo reads an ``.obj`` of that size.
MUJOCO_STL_MAX_FACES = 200_000
#: Bytes of a binary STL's header (80) and face count (4), and of each face.
_STL_HEADER, _STL_FACE = 84, 50


class MeshConversionUnavailable(ModelError):
    """A mesh needs converting and the converter (or one of its readers) is missing."""


def cache_dir() -> Path:
    """Where converted meshes are kept."""
    root = os.environ.get("ROBOT_AGENTS_CACHE")
    return (Path(root) if root else Path.home() / ".cache" / "robot_agents") / "meshes"


def mujoco_reads(path: Path) -> bool:
    """Whether MuJoCo reads the mesh file ``path`` itself: an ``.obj`` or ``.msh``, or a
    binary STL of 1 to :data:`MUJOCO_STL_MAX_FACES` faces (its header's count, the file
    at least that long); not an ASCII STL or a larger one. A file that cannot be read
    counts as read (MuJoCo then says what is wrong with it)."""
    suffix = path.suffix.lower()
    if suffix != ".stl":
        return suffix in SUPPORTED_MESH_SUFFIXES
    try:
        with path.open("rb") as stream:
            header = stream.read(_STL_HEADER)
        size = path.stat().st_size
    except OSError:
        return True
    if len(header) < _STL_HEADER:
        return True
    faces = int.from_bytes(header[80:84], "little")
    return 1 <= faces <= MUJOCO_STL_MAX_FACES and size >= _STL_HEADER + _STL_FACE * faces


def readable_mesh(path: Path) -> Path:
    """``path`` itself when MuJoCo reads it (:func:`mujoco_reads`), else its converted
    ``.obj`` in the cache.

    Raises:
        MeshConversionUnavailable: trimesh (or pycollada for ``.dae``) is not installed.
        ModelError: an unknown format, or a file the converter cannot read.
    """
    suffix = path.suffix.lower()
    if mujoco_reads(path):
        return path
    if suffix not in CONVERTIBLE_MESH_SUFFIXES and suffix != ".stl":
        raise ModelError(
            f"mesh {str(path)!r} has format {suffix or '(none)'!r}; MuJoCo reads {', '.join(SUPPORTED_MESH_SUFFIXES)} "
            f"and the library converts {', '.join(CONVERTIBLE_MESH_SUFFIXES)}."
        )
    stat = path.stat()
    key = hashlib.sha256(f"{path.resolve()}|{stat.st_size}|{stat.st_mtime_ns}".encode()).hexdigest()[:24]
    target = cache_dir() / f"{path.stem}-{key}.obj"
    if target.is_file():
        return target
    try:
        import trimesh
    except ImportError:
        raise MeshConversionUnavailable(f"mesh {str(path)!r} ({suffix}) needs converting: {INSTALL_HINT}.") from None
    try:
        mesh = trimesh.load(str(path), force="mesh")
    except ImportError as err:
        raise MeshConversionUnavailable(
            f"mesh {str(path)!r} ({suffix}) needs converting: {err}; {INSTALL_HINT}."
        ) from None
    except Exception as err:  # trimesh raises many kinds for unreadable files
        raise ModelError(f"mesh {str(path)!r} could not be read for conversion: {err}") from None
    if len(getattr(mesh, "faces", ())) == 0 and suffix == ".dae":
        mesh = _collada_without_materials(path, mesh)
    if len(getattr(mesh, "faces", ())) == 0:
        raise ModelError(f"mesh {str(path)!r} has no triangles to convert.")
    write_cache_file(target, lambda partial: mesh.export(str(partial), file_type="obj"))
    return target


def _collada_without_materials(path: Path, mesh: Any) -> Any:
    """``path``'s COLLADA shapes read again without their material bindings: pycollada
    drops a shape whose material refers to a missing texture surface (example-robot-data's
    ANYmal B feet, ``anymal_foot.dae``: 4604 triangles read as none), and a converted
    mesh keeps no materials. ``mesh``: the first reading, returned when this fails too."""
    import io

    import trimesh

    text = path.read_text(encoding="utf-8", errors="replace")
    stripped = re.sub(r"<bind_material\b.*?</bind_material>", "", text, flags=re.S)
    try:
        return trimesh.load(io.BytesIO(stripped.encode("utf-8")), file_type="dae", force="mesh")
    except Exception:  # trimesh raises many kinds for unreadable files
        return mesh


def write_cache_file(target: Path, write: Callable[[Path], object], suffix: str = ".tmp") -> None:
    """Put a cache entry at ``target``: ``write`` fills a temporary file of this call's own
    (named ``...suffix``) beside it, which is then renamed into place, so two processes (or
    threads) making the same entry each write theirs and the last rename wins with
    identical content; a reader never sees a half-written file."""
    target.parent.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(prefix=f"{target.stem}.", suffix=suffix, dir=target.parent)
    os.close(handle)
    partial = Path(name)
    try:
        write(partial)
        partial.replace(target)
    finally:
        partial.unlink(missing_ok=True)
