"""Non-convex collision meshes split into convex pieces for contacts (a robot's
``convex_decomposition``).

MuJoCo collides every mesh geom as its convex hull, so a jaw with a notch or a U-shaped
finger collides as if the notch were filled. With ``convex_decomposition = True`` each
colliding mesh geom whose mesh is markedly non-convex (:func:`convexity_ratio` above
:data:`NONCONVEX_RATIO`) is replaced, for contacts only, by convex pieces from CoACD
(the ``robot-agents[meshes]`` extra): one new mesh asset and one new geom per piece on
the same body, at the same pose, with the original geom's contact settings, in geom
group :data:`PIECE_GROUP` (not drawn) and without mass. The original geom stays as the
drawn geom and as the carrier of the body's mass (its ``contype`` and ``conaffinity``
become 0), so the robot looks and weighs the same.

Decomposing takes seconds per mesh (about 17 s and 44 s for the Unitree Z1's two jaws on
a 2-core machine), so the pieces are kept in ``$ROBOT_AGENTS_CACHE/meshes/convex``
(beside the converted meshes), named by a hash of the mesh's vertices and faces and the
decomposition's parameters: a second load reads them back in milliseconds.
"""

from __future__ import annotations

import hashlib
import time
import warnings
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from robot_agents.errors import ModelError
from robot_agents.model.meshes import cache_dir, write_cache_file
from robot_agents.parts.declaration import Part, is_jaw_gripper

#: A mesh is markedly non-convex when its convex hull's volume exceeds its own by more
#: than this factor. Tessellated convex shapes read 1.00-1.03 (the Z1's ``link06``
#: housing 1.029); a U-shaped finger 1.5 and more; the Z1's jaws 1.82 and 2.05.
NONCONVEX_RATIO = 1.1
#: CoACD's concavity threshold (its default): lower gives more, tighter pieces.
COACD_THRESHOLD = 0.05
#: CoACD's random seed: the same mesh always gives the same pieces.
COACD_SEED = 0
#: Geom group of the convex pieces: MuJoCo draws groups 0-2 by default, so 3 is not drawn.
PIECE_GROUP = 3
INSTALL_HINT = "pip install 'robot-agents[meshes]' (coacd)"
#: What a piece copies from the geom it replaces in contacts.
_CONTACT_SETTINGS = (
    "contype",
    "conaffinity",
    "condim",
    "priority",
    "friction",
    "solmix",
    "solref",
    "solimp",
    "margin",
    "gap",
    "rgba",
)


class DecompositionUnavailable(ModelError):
    """A robot asks for convex decomposition and CoACD is not installed."""


@dataclass(frozen=True)
class Split:
    """One mesh geom replaced by convex pieces.

    Attributes:
        mesh: the mesh's name.
        pieces: how many convex pieces collide in its place.
        ratio: its convex hull's volume over its own volume (see :data:`NONCONVEX_RATIO`).
        seconds: the time the decomposition took (0 when read from the cache).
    """

    mesh: str
    pieces: int
    ratio: float
    seconds: float


def mesh_arrays(model: mujoco.MjModel, mesh: int) -> tuple[np.ndarray, np.ndarray]:
    """A compiled mesh's vertices ``(n, 3)`` (m, float64, in the frame of the geoms that
    use it: ``geom_pos`` / ``geom_quat``) and triangles ``(k, 3)`` (int32 vertex indices)."""
    start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
    vertices = np.array(model.mesh_vert[start : start + count], dtype=np.float64)
    start, count = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
    faces = np.array(model.mesh_face[start : start + count], dtype=np.int32)
    return vertices, faces


def _volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The volume (m^3) a triangle mesh encloses, from signed tetrahedra to the origin
    (exact for a closed mesh; close for one with small holes)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    return abs(float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0)


def hull_volume(model: mujoco.MjModel, mesh: int) -> float | None:
    """The volume (m^3) of the convex hull MuJoCo collides a mesh as (read from
    ``mesh_graph``); ``None`` when MuJoCo built no hull (a mesh no colliding geom uses)."""
    start = int(model.mesh_graphadr[mesh])
    if start < 0:
        return None
    graph = model.mesh_graph
    nvert, nface = int(graph[start]), int(graph[start + 1])
    # numvert, numface, vert_edgeadr[nv], vert_globalid[nv], edge_localid[nv + 3 nf], face_globalid[3 nf]
    first = start + 2 + 3 * nvert + 3 * nface
    faces = np.asarray(graph[first : first + 3 * nface]).reshape(-1, 3)
    vertices, _ = mesh_arrays(model, mesh)
    return _volume(vertices, faces)


def convexity_ratio(model: mujoco.MjModel, mesh: int) -> float:
    """A mesh's convex hull volume over its own volume: 1 for a convex mesh, more the
    more its hull fills (``inf`` for a mesh enclosing no volume, 1 when MuJoCo built
    no hull for it)."""
    hull = hull_volume(model, mesh)
    if hull is None:
        return 1.0
    volume = _volume(*mesh_arrays(model, mesh))
    return hull / volume if volume > 0.0 else float("inf")


def nonconvex_geoms(model: mujoco.MjModel, bodies: set[int] | None = None) -> list[tuple[int, float]]:
    """The colliding mesh geoms (``contype`` or ``conaffinity`` nonzero) whose mesh is
    markedly non-convex, with their :func:`convexity_ratio`; only on ``bodies`` when given."""
    found = []
    for geom in range(model.ngeom):
        if model.geom_type[geom] != mujoco.mjtGeom.mjGEOM_MESH:
            continue
        if not (model.geom_contype[geom] or model.geom_conaffinity[geom]):
            continue
        if bodies is not None and int(model.geom_bodyid[geom]) not in bodies:
            continue
        ratio = convexity_ratio(model, int(model.geom_dataid[geom]))
        if ratio > NONCONVEX_RATIO:
            found.append((geom, ratio))
    return found


def note_nonconvex_fingers(name: str, model: mujoco.MjModel, parts: Sequence[Part]) -> None:
    """A note (RuntimeWarning) when a gripper's finger bodies collide through markedly
    non-convex meshes (their hulls fill the space between the jaws, so it may not hold
    what it closes on), suggesting ``convex_decomposition``. Cheap: volumes only."""
    bodies = {
        mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, link)
        for part in parts
        if is_jaw_gripper(part)  # a hand's links are not jaws
        for finger in part.finger_links
        for link in finger
    }
    found = nonconvex_geoms(model, bodies - {-1}) if bodies else []
    if not found:
        return
    meshes = {
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MESH, int(model.geom_dataid[g])): ratio for g, ratio in found
    }
    described = ", ".join(f"{mesh!r} (hull/volume {ratio:.2f})" for mesh, ratio in meshes.items())
    warnings.warn(
        f"{name}: its gripper's fingers collide through non-convex meshes {described}; MuJoCo collides a mesh as its "
        "convex hull, which fills the space between the jaws, so the gripper may not hold what it closes on. Set "
        f"convex_decomposition = True to split them into convex pieces ({INSTALL_HINT}; seconds per mesh, cached).",
        RuntimeWarning,
        stacklevel=4,
    )


def _parameters() -> str:
    import coacd

    version = getattr(coacd, "__version__", "?")
    return f"coacd {version} threshold={COACD_THRESHOLD} seed={COACD_SEED}"


def convex_pieces(vertices: np.ndarray, faces: np.ndarray) -> tuple[list[tuple[np.ndarray, np.ndarray]], bool]:
    """Convex pieces covering a triangle mesh (CoACD), from the cache when it has them.

    Args:
        vertices: ``(n, 3)`` vertex positions (m).
        faces: ``(k, 3)`` triangles (vertex indices).

    Returns:
        The pieces, each ``(vertices (p, 3) float64, faces (q, 3) int32)`` in the input's
        frame, and whether they came from the cache.

    Raises:
        DecompositionUnavailable: CoACD is not installed.
    """
    try:
        import coacd
    except ImportError:
        raise DecompositionUnavailable(f"convex_decomposition needs CoACD: {INSTALL_HINT}.") from None
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int32)
    digest = hashlib.sha256()
    for chunk in (vertices.tobytes(), faces.tobytes(), _parameters().encode()):
        digest.update(chunk)
    target = cache_dir() / "convex" / f"{digest.hexdigest()[:32]}.npz"
    if target.is_file():
        try:
            with np.load(target) as stored:  # arr_0, arr_1: the first piece's vertices, faces; ...
                count = len(stored.files) // 2
                return [(stored[f"arr_{2 * k}"], stored[f"arr_{2 * k + 1}"]) for k in range(count)], True
        except (OSError, ValueError, KeyError, zipfile.BadZipFile):
            pass  # an unreadable cache entry: decompose again and replace it
    coacd.set_log_level("error")
    parts = coacd.run_coacd(coacd.Mesh(vertices, faces), threshold=COACD_THRESHOLD, seed=COACD_SEED)
    pieces = [(np.asarray(v, dtype=np.float64), np.asarray(f, dtype=np.int32)) for v, f in parts]
    # np.savez adds ".npz" to a name without it: the temporary file keeps that suffix
    write_cache_file(target, lambda partial: np.savez(partial, *(a for piece in pieces for a in piece)), ".npz")
    return pieces, False


@dataclass(frozen=True)
class Decomposition:
    """What :func:`decompose` did to a spec, to redo on a spec built the same way (the
    same robot class and compiler settings) without compiling it again.

    Attributes:
        meshes: each piece's mesh asset: ``(name, vertices (p, 3) m, faces (q, 3))``.
        geoms: each geom replaced: ``(its index in spec.geoms, its mesh's name, pos (m),
            quat (w, x, y, z), number of pieces)``.
        splits: one per mesh split, for the note.
    """

    meshes: tuple[tuple[str, np.ndarray, np.ndarray], ...]
    geoms: tuple[tuple[int, str, tuple[float, ...], tuple[float, ...], int], ...]
    splits: tuple[Split, ...]


def decompose(spec: mujoco.MjSpec, where: str, again: Decomposition | None = None) -> Decomposition:
    """Replace, for contacts, every markedly non-convex colliding mesh geom of ``spec`` by
    convex pieces (see the module's description); a note (RuntimeWarning) names the
    meshes split. ``where``: the robot, for messages. ``again``: what this returned for a
    spec built the same way, redone without compiling ``spec`` (the compile is what a
    build with decomposition costs: 0.2 s for the Unitree Z1); it must name the same
    meshes at the same geoms, else ``spec`` is decomposed from scratch.

    A spec that does not compile is left as it is (its compile reports why).

    Raises:
        DecompositionUnavailable: a mesh needs splitting and CoACD is not installed.
    """
    geoms = spec.geoms
    if again is None or not all(
        index < len(geoms) and geoms[index].meshname == mesh for index, mesh, _, _, _ in again.geoms
    ):
        again = _plan(spec)
        if again is None:
            return Decomposition((), (), ())
    else:
        again = Decomposition(again.meshes, again.geoms, tuple(replace(s, seconds=0.0) for s in again.splits))
    for name, vertices, faces in again.meshes:
        spec.add_mesh(name=name, uservert=vertices.ravel(), userface=faces.ravel())
    for index, mesh, pos, quat, count in again.geoms:
        original = geoms[index]
        body = original.parent
        for k in range(count):
            piece = body.add_geom(
                name=f"{original.name}__convex{k}" if original.name else "",
                type=mujoco.mjtGeom.mjGEOM_MESH,
                meshname=f"{mesh}__convex{k}",
                pos=pos,
                quat=quat,
            )
            for attr in _CONTACT_SETTINGS:
                setattr(piece, attr, getattr(original, attr))
            piece.group = PIECE_GROUP
            piece.density = 0.0
            piece.mass = 0.0
        original.contype = 0
        original.conaffinity = 0
    if again.splits:
        described = ", ".join(f"{s.mesh!r} into {s.pieces} (hull/volume {s.ratio:.2f})" for s in again.splits)
        computed = sum(s.seconds for s in again.splits)
        timing = f"decomposed in {computed:.1f} s, cached" if computed else "read from the cache"
        warnings.warn(
            f"{where}: convex_decomposition split {len(again.splits)} non-convex collision mesh(es) into convex pieces "
            f"for contacts: {described} (CoACD, {timing} in {cache_dir() / 'convex'}); the original meshes are drawn "
            "and carry the mass.",
            RuntimeWarning,
            stacklevel=3,
        )
    return again


def _plan(spec: mujoco.MjSpec) -> Decomposition | None:
    """The pieces of ``spec``'s non-convex colliding meshes and the geoms they replace
    (compiles ``spec``; ``None`` when it does not compile)."""
    try:
        model = spec.compile()
    except ValueError:
        return None
    index_of = {geom.id: index for index, geom in enumerate(spec.geoms)}
    meshes: list[tuple[str, np.ndarray, np.ndarray]] = []
    replaced: list[tuple[int, str, tuple[float, ...], tuple[float, ...], int]] = []
    splits: list[Split] = []
    count_of: dict[int, int] = {}  # by mesh id: one split per mesh
    for geom_id, ratio in nonconvex_geoms(model):
        mesh_id = int(model.geom_dataid[geom_id])
        mesh_name = spec.geoms[index_of[geom_id]].meshname
        if mesh_id not in count_of:
            began = time.perf_counter()
            pieces, cached = convex_pieces(*mesh_arrays(model, mesh_id))
            seconds = 0.0 if cached else time.perf_counter() - began
            count_of[mesh_id] = len(pieces)
            meshes.extend((f"{mesh_name}__convex{k}", v, f) for k, (v, f) in enumerate(pieces))
            splits.append(Split(mesh_name, len(pieces), ratio, seconds))
        replaced.append(
            (
                index_of[geom_id],
                mesh_name,
                tuple(float(v) for v in model.geom_pos[geom_id]),
                tuple(float(v) for v in model.geom_quat[geom_id]),
                count_of[mesh_id],
            )
        )
    return Decomposition(tuple(meshes), tuple(replaced), tuple(splits))
