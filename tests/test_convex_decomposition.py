"""convex_decomposition: a U-shaped collision mesh (written here as an OBJ) collides as
its hull unless split into convex pieces; split, a box rests in its notch."""

from __future__ import annotations

import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

pytest.importorskip("coacd")

import robot_agents as ra
from robot_agents.errors import ConfigError
from robot_agents.model import decompose

# A U in the x-y plane (m), counter-clockwise: 6 cm wide, 4 cm tall, a notch 2 cm wide
# and 3 cm deep; extruded 2 cm along z. Triangulated with its own corners only.
_U = [(0.0, 0.0), (0.06, 0.0), (0.06, 0.04), (0.04, 0.04), (0.04, 0.01), (0.02, 0.01), (0.02, 0.04), (0.0, 0.04)]
_U_CAP = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (0, 4, 5), (0, 5, 7), (5, 6, 7)]
_HALF_DEPTH = 0.01
_BOX_HALF = 0.008  # m: the box fits the 2 cm notch with 2 mm each side


def _prism(polygon: list[tuple[float, float]], caps: list[tuple[int, int, int]]) -> tuple[np.ndarray, np.ndarray]:
    n = len(polygon)
    bottom = [(x, y, -_HALF_DEPTH) for x, y in polygon]
    top = [(x, y, _HALF_DEPTH) for x, y in polygon]
    faces = [(c, b, a) for a, b, c in caps] + [(a + n, b + n, c + n) for a, b, c in caps]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    return np.array(bottom + top), np.array(faces)


def _write_obj(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


_MJCF = """<mujoco model="u_finger">
  <compiler meshdir="."/>
  <asset>
    <mesh name="u_mesh" file="u.obj"/>
    <mesh name="block_mesh" file="block.obj"/>
  </asset>
  <worldbody>
    <body name="base" pos="0 0 0.1">
      <!-- the U's notch opens upward: its y axis turned onto z -->
      <geom name="u" type="mesh" mesh="u_mesh" quat="0.7071068 0.7071068 0 0" density="1000"/>
      <geom name="block" type="mesh" mesh="block_mesh" pos="-0.05 0 0" density="1000"/>
      <body name="knob" pos="-0.05 0 0.03">
        <joint name="knob_joint" type="hinge" axis="0 0 1" range="-1 1"/>
        <geom type="capsule" size="0.005 0.01" density="1000"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("u_finger")
    vertices, faces = _prism(_U, _U_CAP)
    _write_obj(folder / "u.obj", vertices, faces)
    square = [(0.0, 0.0), (0.02, 0.0), (0.02, 0.02), (0.0, 0.02)]
    _write_obj(folder / "block.obj", *_prism(square, [(0, 1, 2), (0, 2, 3)]))
    (folder / "u_finger.xml").write_text(_MJCF)
    return folder


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROBOT_AGENTS_CACHE", str(root))
        yield root


def _classes(files: Path) -> tuple[type[ra.Agent], type[ra.Agent]]:
    class Plain(ra.Agent):
        uid = "u_plain"
        mjcf_path = files / "u_finger.xml"

    class Split(Plain):
        uid = "u_split"
        convex_decomposition = True

    return Plain, Split


@pytest.fixture(scope="module")
def loaded(files: Path, cache: Path) -> tuple[type[ra.Agent], type[ra.Agent], list[str]]:
    plain, split = _classes(files)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plain.check()
        split.check()
    return plain, split, [str(w.message) for w in caught]


def _geoms(model: mujoco.MjModel, body: str) -> list[int]:
    bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] == bid]


def _box_in_notch(cls: type[ra.Agent]) -> tuple[float, float, np.ndarray]:
    """The deepest penetration (m) between the box and the robot at the first step and
    after 1 s, and how far the box moved (m) over that second."""
    spec = cls.build_spec()
    box = spec.worldbody.add_body(name="box", pos=[0.03, 0.0, 0.1 + 0.01 + _BOX_HALF + 0.0005])
    box.add_freejoint()
    box.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[_BOX_HALF] * 3, density=500)
    model = spec.compile()
    model.opt.gravity[:] = (0.0, 0.0, -9.81)
    data = mujoco.MjData(model)

    def deepest() -> float:
        box_id = model.nbody - 1
        depth = 0.0
        for c in data.contact[: data.ncon]:
            if box_id in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]):
                depth = max(depth, -float(c.dist))
        return depth

    mujoco.mj_forward(model, data)
    start = data.xpos[model.nbody - 1].copy()
    first = deepest()
    for _ in range(int(1.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return first, deepest(), data.xpos[model.nbody - 1] - start


def test_the_flag_is_validated(files: Path) -> None:
    class Wrong(ra.Agent):
        uid = "u_wrong"
        mjcf_path = files / "u_finger.xml"
        convex_decomposition = 1  # type: ignore[assignment]

    with pytest.raises(ConfigError, match="convex_decomposition"):
        Wrong.validate_definition()


def test_the_u_is_non_convex_and_the_block_is_not(loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]]) -> None:
    model = loaded[0].build_spec().compile()
    ratios = {
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MESH, m): decompose.convexity_ratio(model, m)
        for m in range(model.nmesh)
    }
    # the U: 18 cm^2 of cross-section; its hull, the 6 x 4 cm rectangle: 24 cm^2
    assert ratios["u_mesh"] == pytest.approx(24 / 18, rel=1e-4)
    assert ratios["block_mesh"] == pytest.approx(1.0, rel=1e-6)


def test_without_the_flag_the_hull_fills_the_notch(loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]]) -> None:
    plain = loaded[0]
    model = plain.build_spec().compile()
    assert len([g for g in _geoms(model, "base") if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH]) == 2
    first, _, moved = _box_in_notch(plain)
    assert first > 0.015  # the box sits 2.2 cm deep inside the hull
    assert np.linalg.norm(moved) > 0.01  # and is thrown out of the notch


def test_split_the_box_rests_in_the_notch(loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]]) -> None:
    first, last, moved = _box_in_notch(loaded[1])
    assert first == 0.0
    assert last < 1e-3
    assert np.linalg.norm(moved) < 2e-3


def test_pieces_are_convex_massless_and_hidden(loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]]) -> None:
    plain, split, notes = loaded
    before, after = plain.build_spec().compile(), split.build_spec().compile()
    assert np.array_equal(before.body_mass, after.body_mass)
    assert np.array_equal(before.body_inertia, after.body_inertia)
    assert np.array_equal(before.body_ipos, after.body_ipos)
    assert np.array_equal(before.body_iquat, after.body_iquat)
    u = mujoco.mj_name2id(after, mujoco.mjtObj.mjOBJ_GEOM, "u")
    assert (after.geom_contype[u], after.geom_conaffinity[u]) == (0, 0)  # drawn only
    assert after.geom_group[u] == before.geom_group[u]
    assert after.geom_dataid[u] == mujoco.mj_name2id(after, mujoco.mjtObj.mjOBJ_MESH, "u_mesh")
    pieces = [
        g
        for g in range(after.ngeom)
        if (mujoco.mj_id2name(after, mujoco.mjtObj.mjOBJ_GEOM, g) or "").startswith("u__convex")
    ]
    assert len(pieces) >= 3
    for g in pieces:
        assert after.geom_group[g] == decompose.PIECE_GROUP
        assert (after.geom_contype[g], after.geom_conaffinity[g]) == (1, 1)
        assert np.array_equal(after.geom_friction[g], before.geom_friction[u])
        assert decompose.convexity_ratio(after, int(after.geom_dataid[g])) < 1.01
    block = mujoco.mj_name2id(after, mujoco.mjtObj.mjOBJ_GEOM, "block")
    assert after.geom_contype[block] == 1  # convex: left alone
    assert after.ngeom == before.ngeom + len(pieces)
    assert [n for n in notes if "convex_decomposition split 1" in n and "'u_mesh' into" in n]


def test_a_second_load_reads_the_cache_and_is_deterministic(
    loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]],
    cache: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    model = loaded[0].build_spec().compile()
    mesh = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_MESH, "u_mesh")
    arrays = decompose.mesh_arrays(model, mesh)
    stored, cached = decompose.convex_pieces(*arrays)
    assert cached
    assert len(list((cache / "meshes" / "convex").glob("*.npz"))) == 1
    monkeypatch.setenv("ROBOT_AGENTS_CACHE", str(tmp_path))  # an empty cache: decompose again
    fresh, cached = decompose.convex_pieces(*arrays)
    assert not cached
    assert len(fresh) == len(stored)
    for (v1, f1), (v2, f2) in zip(fresh, stored, strict=True):
        assert np.array_equal(v1, v2) and np.array_equal(f1, f2)


def test_a_missing_coacd_names_the_extra(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "coacd", None)
    monkeypatch.setenv("ROBOT_AGENTS_CACHE", str(tmp_path))
    vertices, faces = _prism(_U, _U_CAP)
    with pytest.raises(decompose.DecompositionUnavailable, match=r"robot-agents\[meshes\]"):
        decompose.convex_pieces(vertices, faces)


def test_non_convex_fingers_are_noted(loaded: tuple[type[ra.Agent], type[ra.Agent], list[str]]) -> None:
    plain, split, _ = loaded
    jaws = (ra.Gripper(name="gripper", joints=("knob_joint",), open=1.0, closed=-1.0, fingers=("base", "knob")),)
    with pytest.warns(RuntimeWarning, match=r"non-convex meshes 'u_mesh' \(hull/volume 1.33\).*convex_decomposition"):
        decompose.note_nonconvex_fingers("Plain", plain.build_spec().compile(), jaws)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        decompose.note_nonconvex_fingers("Split", split.build_spec().compile(), jaws)  # split: nothing to note
        knob = (ra.Gripper(name="gripper", joints=("knob_joint",), open=1.0, closed=-1.0, fingers=("knob", "knob")),)
        decompose.note_nonconvex_fingers("Plain", plain.build_spec().compile(), knob)  # a capsule finger


def test_later_builds_redo_the_decomposition_without_compiling(
    files: Path, cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _, split = _classes(files)  # a fresh class: its first build plans, the later ones redo the plan
    planned: list[int] = []
    plan = decompose._plan
    monkeypatch.setattr(decompose, "_plan", lambda spec: planned.append(1) or plan(spec))
    with pytest.warns(RuntimeWarning, match=r"'u_mesh' into 3 .* read from the cache"):
        models = [split.build_spec().compile() for _ in range(3)]
    assert planned == [1]  # check()'s build; build_spec's reuse it
    for later in models[1:]:
        for field in ("geom_type", "geom_dataid", "geom_pos", "geom_quat", "geom_contype", "geom_group", "mesh_vert"):
            assert np.array_equal(getattr(later, field), getattr(models[0], field)), field
    assert models[0].ngeom > loaded_geoms(files)


def loaded_geoms(files: Path) -> int:
    """Geoms of the robot without the decomposition."""
    return _classes(files)[0].build_spec().compile().ngeom
