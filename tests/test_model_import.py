"""Model files from the wild load without hand edits: meshes MuJoCo cannot read are
converted (or a visual one dropped with a note), known compile failures are fixed with
a note, and what cannot be fixed names the element, the file, the line and the fix."""

from __future__ import annotations

import math
import re
import sys
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.robot_source import robot_from_file
from tests.conftest import INERTIAL

trimesh = pytest.importorskip("trimesh")  # the test extra installs it (robot-agents[meshes])


def urdf(links: str, joints: str) -> str:
    return f'<?xml version="1.0"?>\n<robot name="r">\n{links}\n{joints}\n</robot>\n'


def link(name: str, body: str = "", mass: float = 1.0) -> str:
    inertial = INERTIAL.format(m=mass) if mass else ""
    return f'<link name="{name}">{inertial}{body}</link>'


def joint(name: str, parent: str, child: str, kind: str = "revolute", z: float = 0.1) -> str:
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0 0 {z}"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
    )


BOX = '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>'


@pytest.fixture(autouse=True)
def mesh_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    cache = tmp_path / "cache"
    monkeypatch.setenv("ROBOT_AGENTS_CACHE", str(cache))
    return cache


def write_glb(path: Path, size: float = 0.08) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(trimesh.creation.box((size, size, size)).export(file_type="glb"))


def test_glb_meshes_are_converted_once_into_the_cache(tmp_path: Path, mesh_cache: Path) -> None:
    write_glb(tmp_path / "meshes" / "arm.glb")
    arm = '<visual><geometry><mesh filename="meshes/arm.glb"/></geometry></visual><collision><geometry><mesh filename="meshes/arm.glb"/></geometry></collision>'
    path = tmp_path / "glb_arm.urdf"
    path.write_text(urdf(link("base", BOX) + link("arm", arm), joint("j", "base", "arm")))
    scene = ra.Scene(robot_from_file(path))
    model = scene.model
    assert model.nmesh >= 1
    vertices = model.mesh_vert[: model.mesh_vertnum[0]]
    np.testing.assert_allclose(np.ptp(vertices, axis=0), [0.08, 0.08, 0.08], atol=1e-6)  # the box, converted
    converted = list(mesh_cache.glob("meshes/arm-*.obj"))
    assert len(converted) == 1
    stamp = converted[0].stat().st_mtime_ns
    ra.Scene(robot_from_file(path))  # a second load uses the cache
    assert converted[0].stat().st_mtime_ns == stamp


def test_without_a_converter_visual_meshes_drop_with_one_note(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "trimesh", None)  # as if robot-agents[meshes] were not installed
    write_glb(tmp_path / "meshes" / "shell.glb")
    shell = '<visual><geometry><mesh filename="meshes/shell.glb"/></geometry></visual>'
    path = tmp_path / "visual_only.urdf"
    path.write_text(urdf(link("base", BOX) + link("arm", BOX + shell), joint("j", "base", "arm")))
    with pytest.warns(RuntimeWarning, match=r"dropped 1 visual mesh.*pip install 'robot-agents\[meshes\]'"):
        scene = ra.Scene(robot_from_file(path))
    assert scene.model.nmesh == 0
    collision = '<collision><geometry><mesh filename="meshes/shell.glb"/></geometry></collision>'
    path.write_text(urdf(link("base", BOX) + link("arm", collision), joint("j", "base", "arm")))
    with pytest.raises(ra.ModelError, match=r"collision mesh of link 'arm'.*robot-agents\[meshes\]"):
        ra.Scene(robot_from_file(path))


def test_massless_links_and_unbalanced_inertia_are_fixed_with_a_note(tmp_path: Path) -> None:
    # A mobile base's virtual x / y joints on massless dummy links, and an arm link whose
    # inertia violates the triangle inequality (izz > ixx + iyy).
    bad_inertia = (
        '<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    links = link("world_anchor", BOX, mass=2.0) + link("dummy_x", mass=0.0) + link("base", BOX, mass=5.0)
    links += f'<link name="arm">{bad_inertia}{BOX}</link>'
    joints = joint("x", "world_anchor", "dummy_x", "prismatic", 0.0) + joint("y", "dummy_x", "base", "prismatic", 0.0)
    joints += joint("j", "base", "arm")
    path = tmp_path / "wild.urdf"
    path.write_text(urdf(links, joints))
    cls = robot_from_file(path)
    with pytest.warns(RuntimeWarning) as record:
        checked = cls.check()
    notes = " ".join(str(w.message) for w in record)
    assert "balanceinertia=True" in notes and "boundmass=0.001" in notes
    assert checked.compiler is not None and checked.compiler.balanceinertia and checked.compiler.boundmass == 1e-3
    scene = ra.Scene(cls)
    assert scene.agents[0].joint_names == ("x", "y", "j")
    # Declared, the same settings compile silently.
    settings = ra.CompilerSettings(balanceinertia=True, boundmass=1e-3, boundinertia=1e-6)
    explicit = type("Explicit", (cls,), {"compiler": settings})
    # Its overlapping boxes touch at the default pose: those pairs stop colliding, with a note.
    with pytest.warns(RuntimeWarning, match=r"2 body pair\(s\) touch at the default keyframe"):
        pairs = explicit.check().derived_exclusions
    assert pairs == (("base", "world_anchor"), ("arm", "world_anchor"))


def test_broken_links_name_the_element_file_line_and_fix(tmp_path: Path) -> None:
    body = '<collision><geometry><box size="0 0.1 0.1"/></geometry></collision>'
    path = tmp_path / "broken.urdf"
    path.write_text(urdf(link("base", BOX) + f'<link name="arm">{body}</link>', joint("j", "base", "arm")))
    with pytest.raises(ra.ModelError) as err:
        ra.Scene(robot_from_file(path))
    assert "link 'arm'" in str(err.value) and "broken.urdf" in str(err.value) and "(line 3)" in str(err.value)
    assert "zero-size collision <box>" in str(err.value)


def test_two_inertials_of_a_link_are_merged(tmp_path: Path) -> None:
    """A link with two ``<inertial>`` elements (the mani-skill wheel's TriFinger Pro
    fingertips) gets one: the total mass at the combined centre of mass, each inertia
    turned into the link's axes and moved there, with a note naming the link and line."""
    first = (
        '<inertial><origin xyz="0 0 0.1" rpy="0 0 0"/><mass value="1"/>'
        '<inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    second = (  # a rod along x turned 90 deg about z: along y in the link
        '<inertial><origin xyz="0.3 0 0.1" rpy="0 0 1.5707963267948966"/><mass value="3"/>'
        '<inertia ixx="0.001" iyy="0.04" izz="0.04" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    path = tmp_path / "two_inertials.urdf"
    path.write_text(
        urdf(link("base", BOX) + f'<link name="arm">{first}{second}{BOX}</link>', joint("j", "base", "arm"))
    )
    with pytest.warns(RuntimeWarning, match=r"link 'arm' \(line 3\) has 2 <inertial> elements; a link has one: merged"):
        model = ra.Scene(robot_from_file(path)).model
    arm = model.body("two_inertials-0/arm").id
    assert model.body_mass[arm] == pytest.approx(4.0)
    # the link's frame is at its joint, 0.1 m above the base: the centre 3/4 of the way to the rod
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    centre = data.xipos[arm] - data.xpos[arm]
    np.testing.assert_allclose(centre, [0.225, 0.0, 0.1], atol=1e-9)
    # about the combined centre: the rod's 0.001 / 0.04 / 0.04 with x and y swapped, plus m d^2
    expected = np.diag([0.01 + 0.04, 0.02 + 0.001, 0.03 + 0.04]) + np.diag([0.0, 1.0, 1.0]) * (
        1.0 * 0.225**2 + 3.0 * 0.075**2
    )
    np.testing.assert_allclose(np.sort(model.body_inertia[arm]), np.sort(np.diag(expected)), rtol=1e-6)


def test_zero_size_visual_is_dropped_and_missing_links_are_named(tmp_path: Path) -> None:
    zero = '<visual><geometry><sphere radius="0"/></geometry></visual>'
    path = tmp_path / "zero.urdf"
    path.write_text(urdf(link("base", BOX) + link("arm", BOX + zero), joint("j", "base", "arm")))
    with pytest.warns(RuntimeWarning, match=r"dropped a zero-size visual <sphere> of link 'arm' \(line 3\)"):
        ra.Scene(robot_from_file(path))
    path.write_text(urdf(link("base", BOX) + link("arm", BOX), joint("j", "base", "forearm")))
    with pytest.raises(ra.ModelError, match=r"joint 'j'.*names child link 'forearm'.*links: \['base', 'arm'\]"):
        ra.Scene(robot_from_file(path))


DEGREES_MJCF = """<mujoco><worldbody><body name="base"><geom type="box" size=".1 .1 .1"/>
<body name="arm" pos="0 0 .2"><joint name="j" axis="0 1 0" range="-90 45"/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".02"/>
</body></body></worldbody></mujoco>"""


def test_angle_units_of_mjcf_files(tmp_path: Path) -> None:
    path = tmp_path / "degrees.xml"
    path.write_text(DEGREES_MJCF)  # MJCF without <compiler angle=...>: degrees
    agent = ra.Scene(robot_from_file(path)).agents[0]
    np.testing.assert_allclose(agent.qpos_limits, [[-np.pi / 2, np.pi / 4]])  # always radians in the library
    radians = type("Radians", (robot_from_file(path),), {"compiler": ra.CompilerSettings(angle="radian")})
    np.testing.assert_allclose(ra.Scene(radians).agents[0].qpos_limits, [[-90.0, 45.0]])
    with pytest.raises(ra.ConfigError, match="angle"):
        ra.CompilerSettings(angle="gradian")


def test_package_uris_resolve_in_declared_search_paths(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    elsewhere = tmp_path / "installed" / "my_robot" / "meshes"
    elsewhere.mkdir(parents=True)
    (elsewhere / "arm.obj").write_text("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    mesh = '<collision><geometry><mesh filename="package://my_robot/meshes/arm.obj"/></geometry></collision>'
    path = tmp_path / "robot" / "pkg.urdf"
    path.parent.mkdir()
    path.write_text(urdf(link("base", BOX) + link("arm", mesh), joint("j", "base", "arm")))
    with pytest.raises(ra.ModelError, match="package_paths"):
        ra.Scene(robot_from_file(path))
    declared = type(
        "Declared", (robot_from_file(path),), {"compiler": ra.CompilerSettings(package_paths=(tmp_path / "installed",))}
    )
    assert ra.Scene(declared).model.nmesh == 1
    monkeypatch.setenv("ROBOT_AGENTS_PACKAGE_PATH", str(tmp_path / "installed"))
    assert ra.Scene(robot_from_file(path)).model.nmesh == 1
    assert mujoco.mj_name2id(ra.Scene(robot_from_file(path)).model, mujoco.mjtObj.mjOBJ_JOINT, "pkg-0/j") >= 0


def test_processes_converting_the_same_mesh_at_once_all_succeed(tmp_path: Path, mesh_cache: Path) -> None:
    """Two ``robot-agents check`` runs of one model file convert its meshes at the same
    time: each writes a temporary file of its own before the rename (one shared ``.tmp``
    name made the later rename fail with FileNotFoundError)."""
    import os
    import subprocess
    import sys

    mesh = tmp_path / "ball.glb"
    mesh.write_bytes(trimesh.creation.icosphere(subdivisions=5).export(file_type="glb"))  # 20480 faces
    code = f"from pathlib import Path; from robot_agents.model.meshes import readable_mesh; print(readable_mesh(Path({str(mesh)!r})))"
    env = {**os.environ, "ROBOT_AGENTS_CACHE": str(mesh_cache)}
    runs = [
        subprocess.Popen(
            [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        for _ in range(6)
    ]
    results = [(run.wait(timeout=120), run.stdout.read(), run.stderr.read()) for run in runs]  # type: ignore[union-attr]
    assert all(code == 0 for code, _, _ in results), [err[-500:] for _, _, err in results]
    targets = {out.strip() for _, out, _ in results}
    assert len(targets) == 1 and Path(targets.pop()).stat().st_size > 0
    assert not list((mesh_cache / "meshes").glob("*.tmp"))  # no temporary file left behind


def test_stl_files_mujoco_refuses_are_converted(tmp_path: Path, mesh_cache: Path) -> None:
    """MuJoCo's STL reader refuses ASCII files and binary ones of more than 200,000
    faces (the mani-skill wheel's RealSense D415 has 425,160): both are converted to
    ``.obj`` like the formats it cannot read; a binary STL it reads is left as it is."""
    from robot_agents.model.meshes import MUJOCO_STL_MAX_FACES, mujoco_reads

    box = trimesh.creation.box((0.08, 0.08, 0.08))
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "ascii.stl").write_text(trimesh.exchange.stl.export_stl_ascii(box))
    (tmp_path / "meshes" / "binary.stl").write_bytes(trimesh.exchange.stl.export_stl(box))
    for name, converted in (("ascii", True), ("binary", False)):
        arm = (
            f'<visual><geometry><mesh filename="meshes/{name}.stl"/></geometry></visual>'
            f'<collision><geometry><mesh filename="meshes/{name}.stl"/></geometry></collision>'
        )
        path = tmp_path / f"{name}_arm.urdf"
        path.write_text(urdf(link("base", BOX) + link("arm", arm), joint("j", "base", "arm")))
        model = ra.Scene(robot_from_file(path)).model
        vertices = model.mesh_vert[: model.mesh_vertnum[0]]
        assert np.ptp(vertices, axis=0) == pytest.approx([0.08] * 3, abs=1e-6)
        assert len(list(mesh_cache.rglob("ascii-*.obj"))) == 1  # converted once
        assert not list(mesh_cache.rglob("binary-*.obj"))  # read by MuJoCo as it is
        assert mujoco_reads(tmp_path / "meshes" / f"{name}.stl") is not converted
    # the face count in a binary header, the file as long as it says: over the limit, converted
    for faces, read in ((MUJOCO_STL_MAX_FACES, True), (MUJOCO_STL_MAX_FACES + 1, False)):
        big = tmp_path / f"big_{faces}.stl"
        with big.open("wb") as stream:
            stream.write(bytes(80) + faces.to_bytes(4, "little"))
            stream.truncate(84 + 50 * faces)
        assert mujoco_reads(big) is read


def test_a_flat_mesh_gets_its_volume_from_its_surface(tmp_path: Path) -> None:
    """MuJoCo refuses a flat or open mesh ("mesh volume is too small ... Try setting
    inertia to shell"; example-robot-data's ``alex_nub_hands.urdf``): the named mesh is
    compiled with shell inertia, with a note naming the setting to declare."""
    (tmp_path / "meshes").mkdir()
    flat = trimesh.Trimesh(
        vertices=[[0, 0, 0], [0.05, 0, 0], [0.05, 0.05, 0], [0, 0.05, 0]], faces=[[0, 1, 2], [0, 2, 3]]
    )
    (tmp_path / "meshes" / "plate.stl").write_bytes(trimesh.exchange.stl.export_stl(flat))
    plate = '<visual><geometry><mesh filename="meshes/plate.stl"/></geometry></visual>'
    path = tmp_path / "plate_arm.urdf"
    path.write_text(urdf(link("base", BOX) + link("arm", BOX + plate), joint("j", "base", "arm")))
    cls = robot_from_file(path)
    with pytest.warns(
        RuntimeWarning, match=r"mesh volume is too small: plate.*compiled with shell_meshes=\('plate',\)"
    ):
        model = ra.Scene(cls).model
    assert model.nmesh == 1 and cls.check().compiler.shell_meshes == ("plate",)
    declared = type("Plate", (robot_from_file(path),), {"compiler": ra.CompilerSettings(shell_meshes=("plate",))})
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # declared: no note
        ra.Scene(declared)
    with pytest.raises(ra.ConfigError, match=r"shell_meshes: no mesh 'plat' in the model; meshes: \['plate'\]"):
        ra.Scene(type("Typo", (robot_from_file(path),), {"compiler": ra.CompilerSettings(shell_meshes=("plat",))}))
    with pytest.raises(ra.ConfigError, match=r"shell_meshes: expected a tuple of mesh names, got 'plate'"):
        ra.CompilerSettings(shell_meshes="plate")  # type: ignore[arg-type]


def test_a_name_given_twice_is_named_with_both_lines(tmp_path: Path) -> None:
    # MuJoCo's URDF reader takes two joints of one name and failed later with a bare
    # ValueError ("repeated name 'j' in joint") from the library's own spec walk
    path = tmp_path / "twice.urdf"
    links = link("base", BOX) + link("arm", BOX) + link("hand", BOX)
    path.write_text(urdf(links, joint("j", "base", "arm") + "\n" + joint("j", "arm", "hand")))
    with pytest.raises(ra.ModelError, match=r"twice\.urdf' has two joints named 'j' \(lines 4 and 5\)"):
        robot_from_file(path).check()
    path.write_text(urdf(links.replace('"hand"', '"arm"'), joint("j", "base", "arm")))
    with pytest.raises(
        ra.ModelError, match=r"has two links named 'arm' \(lines 3 and 3\).*rename one \(and the joints"
    ):
        robot_from_file(path).check()


def test_a_files_settotalmass_holds_in_a_scene() -> None:
    # gymnasium's half_cheetah.xml scales its masses to 14 kg (<compiler settotalmass>);
    # MuJoCo applies it to the model compiled, and the robot attached into a scene lost
    # it: 21.18 kg there
    import gymnasium

    path = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "half_cheetah.xml"
    file = mujoco.MjModel.from_xml_path(str(path))
    assert file.body_mass.sum() == pytest.approx(14.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # its motors: derived drives, a note
        model = ra.Scene(robot_from_file(path)).model
    assert model.body_mass.sum() == pytest.approx(14.0)
    for body in range(1, file.nbody):
        scene_body = model.body(f"half_cheetah-0/{file.body(body).name}").id
        assert model.body_mass[scene_body] == pytest.approx(file.body_mass[body])
        np.testing.assert_allclose(model.body_inertia[scene_body], file.body_inertia[body], rtol=1e-9)
        np.testing.assert_allclose(model.body_ipos[scene_body], file.body_ipos[body], atol=1e-12)


def test_a_negative_mass_or_moment_is_an_error_not_a_fallback(tmp_path: Path) -> None:
    # MuJoCo refuses a negative mass as a massless body and a negative diaginertia
    # moment as an unbalanced one: the fallbacks simulated -0.5 kg as 0.001 kg
    # (boundmass) and the moments as balanced ones, with a note about mjMINVAL
    path = tmp_path / "negative.urdf"
    path.write_text(urdf(link("base", BOX) + link("arm", BOX, mass=-0.5), joint("j", "base", "arm")))
    with pytest.raises(ra.ModelError, match=r"mass of link 'arm' in .*negative\.urdf' \(line 3\) is -0\.5 kg.*<mass>"):
        robot_from_file(path).check()
    mjcf = tmp_path / "negative.xml"
    body = '<body name="arm" pos="0 0 .2"><joint name="j" axis="0 1 0" range="-1 1"/><geom size=".05"/>'
    for inertial, expected in (
        (
            'mass="-0.5" diaginertia="0.01 0.01 0.01"',
            r"mass of body 'arm' in .*\(line 2\) is -0\.5 kg.*<inertial> mass",
        ),
        (
            'mass="0.5" diaginertia="0.006 -0.006 0.01"',
            r"inertia of body 'arm' in .*\(line 2\) is not positive-definite",
        ),
    ):
        mjcf.write_text(
            f'<mujoco><worldbody><body name="base"><geom size=".1"/>\n{body}<inertial pos="0 0 0" {inertial}/>'
            "</body></body></worldbody></mujoco>"
        )
        with pytest.raises(ra.ModelError, match=expected):
            robot_from_file(mjcf).check()


def test_a_missing_mjcf_mesh_names_the_model_file_and_where_it_was_looked_for(tmp_path: Path) -> None:
    # MuJoCo said only "Error opening file 'arm.obj'": not which model file, nor where
    path = tmp_path / "missing_mesh.xml"
    path.write_text(
        '<mujoco>\n<compiler meshdir="meshes"/>\n<asset><mesh name="arm_mesh" file="arm.obj"/></asset>\n'
        '<worldbody><body name="base"><geom size=".1"/><body name="arm"><joint name="j" axis="0 1 0" range="-1 1"/>'
        '<geom type="mesh" mesh="arm_mesh"/></body></body></worldbody></mujoco>'
    )
    expected = str(tmp_path / "meshes" / "arm.obj")
    with pytest.raises(
        ra.ModelError,
        match=rf"the mesh file 'arm.obj' of <mesh name='arm_mesh'> in .*missing_mesh\.xml' \(line 3\) was not found "
        rf"at {re.escape(repr(expected))}",
    ):
        robot_from_file(path).check()


_CUBE = [(x, y, z) for x in (-0.05, 0.05) for y in (-0.05, 0.05) for z in (-0.05, 0.05)]
_CUBE_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def _stripped_arm(tmp_path: Path, files: tuple[str, str]) -> Path:
    """An arm whose two meshes are written with folders (``files``) that
    ``<compiler strippath="true">`` drops: MuJoCo looks for them in ``meshes/``."""
    path = tmp_path / "stripped.xml"
    path.write_text(
        '<mujoco>\n<compiler meshdir="meshes" strippath="true"/>\n<asset>'
        f'<mesh name="a" file="{files[0]}"/><mesh name="b" file="{files[1]}"/></asset>\n'
        '<worldbody><body name="base"><geom type="mesh" mesh="a"/><body name="arm" pos="0 0 0.2">'
        '<joint name="j" axis="0 1 0" range="-1 1"/><geom type="mesh" mesh="b"/></body></body></worldbody></mujoco>'
    )
    return path


def test_a_missing_mesh_under_strippath_names_where_mujoco_looked(tmp_path: Path) -> None:
    # MuJoCo looked for meshes/arm.stl and the message (its own) named "meshes/arm.stl"
    # alone; a mesh to convert was looked for at meshes/some/dir/arm.ply, where MuJoCo
    # does not look, and refused though it was there
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "base.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in _CUBE)
        + "".join(f"f {' '.join(str(i + 1) for i in f)}\n" for f in _CUBE_FACES)
    )
    path = _stripped_arm(tmp_path, ("other/base.obj", "/some/dir/arm.stl"))
    expected = str(tmp_path / "meshes" / "arm.stl")
    with pytest.raises(
        ra.ModelError,
        match=rf"the mesh file '/some/dir/arm.stl' of <mesh name='b'> in .*stripped\.xml' \(line 3\) was not found "
        rf"at {re.escape(repr(expected))} \(the file's <compiler strippath=\"true\"> drops the folders",
    ):
        robot_from_file(path).check()
    path = _stripped_arm(tmp_path, ("other/base.obj", "some/dir/arm.ply"))
    expected = str(tmp_path / "meshes" / "arm.ply")
    with pytest.raises(
        ra.ModelError, match=rf"mesh 'some/dir/arm.ply' of .* was not found at {re.escape(repr(expected))}"
    ):
        robot_from_file(path).check()
    pytest.importorskip("trimesh")
    (tmp_path / "meshes" / "arm.ply").write_text(
        f"ply\nformat ascii 1.0\nelement vertex {len(_CUBE)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(_CUBE_FACES)}\nproperty list uchar int vertex_indices\nend_header\n"
        + "".join(f"{x} {y} {z}\n" for x, y, z in _CUBE)
        + "".join(f"4 {' '.join(map(str, f))}\n" for f in _CUBE_FACES)
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        model = robot_from_file(path).check().index.model
    assert model.nmesh == 2  # the converted mesh and the stripped .obj beside it both read


@pytest.mark.parametrize("suffix", [".mjcf", ".XML"])
def test_mjcf_files_ending_otherwise_than_xml_load_with_their_includes_and_meshes(tmp_path: Path, suffix: str) -> None:
    # MuJoCo 4 reads a file by its name's ending: "could not find decoder" for the
    # documented ".mjcf" (and ".XML") before
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "cube.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x in (-0.05, 0.05) for y in (-0.05, 0.05) for z in (-0.05, 0.05))
        + "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n"
    )
    (tmp_path / "defaults.xml").write_text('<mujoco><default><joint damping="0.7"/></default></mujoco>')
    path = tmp_path / f"ärm with space{suffix}"
    path.write_text(
        '<mujoco><include file="defaults.xml"/><compiler meshdir="meshes"/><asset><mesh name="cube" file="cube.obj"/>'
        '</asset><worldbody><body name="base"><geom type="mesh" mesh="cube" mass="2"/><body name="arm" pos="0 0 .2">'
        '<joint name="j" axis="0 1 0" range="-1 1"/><geom size=".05" mass="0.5"/></body></body></worldbody></mujoco>'
    )
    model = robot_from_file(path).check().index.model
    assert model.body_mass.sum() == pytest.approx(2.5)
    assert model.dof_damping[model.joint("j").dofadr[0]] == pytest.approx(0.7)
    assert model.mesh_vertnum[model.mesh("cube").id] == 8


def test_a_misspelled_link_or_mimic_joint_gets_the_close_names(tmp_path: Path) -> None:
    path = tmp_path / "typo.urdf"
    path.write_text(urdf(link("base", BOX) + link("forearm", BOX), joint("j", "base", "fore_arm")))
    with pytest.raises(
        ra.ModelError, match=r"names child link 'fore_arm', which is not in the file; did you mean 'forearm'\?"
    ):
        robot_from_file(path).check()
    follower = joint("k", "forearm", "hand").replace("</joint>", '<mimic joint="J" multiplier="2"/></joint>')
    path.write_text(
        urdf(
            link("base", BOX) + link("forearm", BOX) + link("hand", BOX),
            joint("j", "base", "forearm") + "\n" + follower,
        )
    )
    with (
        warnings.catch_warnings(record=True) as caught,
        pytest.raises(
            ra.ModelError,
            match=r"joint 'k' in .*typo\.urdf' \(line 5\) mimics joint 'J', which is not in the URDF; did you mean 'j'\?",
        ),
    ):
        warnings.simplefilter("always")
        robot_from_file(path).check()
    # MuJoCo's own word on the mimic ("ignored; mimic requires revolute...", of a revolute
    # joint) is not passed on: the library's error says what is wrong
    assert not [w for w in caught if "<mimic>" in str(w.message)]


def test_a_link_without_inertial_is_massless_as_urdf_has_it(tmp_path: Path) -> None:
    # URDF leaves such a link massless; MuJoCo's reader gave it its collision box's mass
    # at water's density (1 kg for a 10 cm box; example-robot-data's ANYmal C, whose base
    # link carries its mass in a welded base_inertia link, weighed 81.5 kg, not 52.1)
    path = tmp_path / "unweighed.urdf"
    links = link("base", BOX, mass=2.0) + link("arm", BOX, mass=0.0) + link("tool", BOX, mass=0.0)
    path.write_text(urdf(links, joint("j", "base", "arm") + joint("fixed", "arm", "tool", "fixed")))
    with pytest.warns(RuntimeWarning) as record:
        model = robot_from_file(path).check().index.model
    notes = " ".join(str(w.message) for w in record)
    assert "link(s) 'arm' (line 3), 'tool' (line 3) have collision shapes and no <inertial>: massless" in notes
    assert "boundmass=0.001" in notes  # a moving massless link: bounded, as before
    # 2 kg stated; the two massless links bounded to 1 g each (boundmass bounds every body)
    assert model.body_mass.sum() == pytest.approx(2.002)
    # a file stating no mass at all (a kinematic one) keeps MuJoCo's rule, noted
    path.write_text(urdf(link("base", BOX, mass=0.0) + link("arm", BOX, mass=0.0), joint("j", "base", "arm")))
    with pytest.warns(RuntimeWarning, match=r"states no <inertial>: link\(s\) 'base' \(line 3\), 'arm' \(line 3\) get"):
        model = robot_from_file(path).check().index.model
    assert model.body_mass[model.body("arm").id] == pytest.approx(1000.0 * 0.1**3)


def test_a_fixed_joints_mimic_is_dropped_and_a_mimic_of_a_fixed_joint_is_an_error(tmp_path: Path) -> None:
    # example-robot-data's reduced Talos files freeze the gripper's joints and keep their
    # mimics: MuJoCo refused them ("unknown element 'gripper_left_inner_double_joint' in
    # equality constraint", Element name '')
    path = tmp_path / "frozen.urdf"
    links = link("base", BOX) + link("arm", BOX) + link("pad", BOX)
    frozen = joint("frozen", "arm", "pad", "fixed").replace("</joint>", '<mimic joint="j" multiplier="-1"/></joint>')
    path.write_text(urdf(links, joint("j", "base", "arm") + "\n" + frozen))
    with pytest.warns(RuntimeWarning, match=r"dropped the <mimic> of 1 fixed joint\(s\) \('frozen' \(line 5\)\)"):
        checked = robot_from_file(path).check()
    assert checked.index.joint_names == ("j",) and checked.index.model.neq == 0
    follower = joint("k", "arm", "pad").replace("</joint>", '<mimic joint="fixed"/></joint>')
    path.write_text(urdf(links, joint("fixed", "base", "arm", "fixed") + "\n" + follower))
    with pytest.raises(
        ra.ModelError, match=r"joint 'k' in .*frozen\.urdf' \(line 5\) mimics joint 'fixed', which is fixed"
    ):
        robot_from_file(path).check()


#: A 10 cm cube drawn in millimetres (a node scaled 0.001) whose material's texture
#: sampler names a surface the file lacks (example-robot-data's ANYmal B feet).
BROKEN_MATERIAL_DAE = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_effects>
    <effect id="paint-effect"><profile_COMMON>
      <newparam sid="tex-sampler"><sampler2D><source>missing-surface</source></sampler2D></newparam>
      <technique sid="common"><phong><diffuse><texture texture="tex-sampler" texcoord="UVMap"/></diffuse></phong></technique>
    </profile_COMMON></effect>
  </library_effects>
  <library_materials><material id="paint-material" name="paint"><instance_effect url="#paint-effect"/></material></library_materials>
  <library_geometries>
    <geometry id="box-mesh" name="box"><mesh>
      <source id="box-positions"><float_array id="box-positions-array" count="24">-50 -50 -50 50 -50 -50 50 50 -50 -50 50 -50 -50 -50 50 50 -50 50 50 50 50 -50 50 50</float_array>
        <technique_common><accessor source="#box-positions-array" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
      <vertices id="box-vertices"><input semantic="POSITION" source="#box-positions"/></vertices>
      <triangles material="paint-material" count="12"><input semantic="VERTEX" source="#box-vertices" offset="0"/>
        <p>0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="Scene" name="Scene">
    <node id="box" name="box" type="NODE"><matrix sid="transform">0.001 0 0 0 0 0.001 0 0 0 0 0.001 0 0 0 0 1</matrix>
      <instance_geometry url="#box-mesh" name="box"><bind_material><technique_common>
        <instance_material symbol="paint-material" target="#paint-material"/></technique_common></bind_material></instance_geometry>
    </node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
"""


def test_a_collada_mesh_with_a_broken_material_converts(tmp_path: Path) -> None:
    # pycollada drops a shape whose material refers to a missing texture surface: the
    # ANYmal B's collision feet read as no triangles ("has no triangles to convert")
    pytest.importorskip("collada")
    (tmp_path / "foot.dae").write_text(BROKEN_MATERIAL_DAE)
    foot = '<collision><geometry><mesh filename="foot.dae"/></geometry></collision>'
    path = tmp_path / "footed.urdf"
    path.write_text(urdf(link("base", BOX) + link("foot", foot), joint("j", "base", "foot")))
    model = robot_from_file(path).check().index.model
    geom = next(g for g in range(model.ngeom) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH)
    mesh = model.geom_dataid[geom]
    vertices = model.mesh_vert[model.mesh_vertadr[mesh] : model.mesh_vertadr[mesh] + model.mesh_vertnum[mesh]]
    np.testing.assert_allclose(vertices.max(axis=0) - vertices.min(axis=0), [0.1, 0.1, 0.1], rtol=1e-6)


def test_a_mesh_scaled_to_zero_is_a_zero_size_shape(tmp_path: Path) -> None:
    # a collision mesh scaled "0.5 0 2" compiled as a flat plate through the flat-mesh
    # fallback (shell inertia); the zero-size rule of boxes, spheres and cylinders holds
    (tmp_path / "cube.obj").write_text(
        "".join(f"v {x} {y} {z}\n" for x in (-0.05, 0.05) for y in (-0.05, 0.05) for z in (-0.05, 0.05))
        + "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n"
    )
    flat = '<geometry><mesh filename="cube.obj" scale="0.5 0 2"/></geometry>'
    path = tmp_path / "flat.urdf"
    path.write_text(
        urdf(link("base", BOX) + link("arm", f"{BOX}<collision>{flat}</collision>"), joint("j", "base", "arm"))
    )
    with pytest.raises(ra.ModelError, match=r"link 'arm' in .*flat\.urdf' \(line 3\) has a zero-size collision <mesh>"):
        robot_from_file(path).check()
    path.write_text(urdf(link("base", BOX) + link("arm", f"{BOX}<visual>{flat}</visual>"), joint("j", "base", "arm")))
    with pytest.warns(RuntimeWarning, match=r"dropped a zero-size visual <mesh> of link 'arm' \(line 3\)"):
        robot_from_file(path).check()
    mirrored = '<collision><geometry><mesh filename="cube.obj" scale="1 -1 1"/></geometry></collision>'
    path.write_text(urdf(link("base", BOX) + link("arm", mirrored), joint("j", "base", "arm")))  # no fault
    assert robot_from_file(path).check().index.model.nmesh == 1


def test_a_nan_or_inf_in_a_file_names_the_element_and_line(tmp_path: Path) -> None:
    # MuJoCo reads "nan" and "inf" as numbers: a NaN joint origin failed as "EndEffector
    # 'ee'.pos: expected 3 finite numbers", an infinite mass compiled (and blew up)
    # MuJoCo's own word on the file comes as a note naming it (robot_agents.notes)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = tmp_path / "nan.urdf"
        for arm, expected in (
            (
                link("arm", BOX, mass=float("inf")),
                r"link 'arm' in .*nan\.urdf' \(line 3\) has mass \[inf\]; expected finite",
            ),
            (link("arm", BOX).replace('value="1.0"', 'value="nan"'), r"link 'arm' .* has mass \[nan\]"),
        ):
            path.write_text(urdf(link("base", BOX) + arm, joint("j", "base", "arm")))
            with pytest.raises(ra.ModelError, match=expected):
                robot_from_file(path).check()
        path.write_text(
            urdf(
                link("base", BOX) + link("arm", BOX),
                joint("j", "base", "arm").replace('xyz="0 0 0.1"', 'xyz="0 0 0.1" rpy="0 nan 0"'),
            )
        )
        with pytest.raises(
            ra.ModelError, match=r"link 'arm' .* has quat \(its parent joint's <origin>\) \[nan, nan, nan, nan\]"
        ):
            robot_from_file(path).check()
        mjcf = tmp_path / "nan.xml"
        mjcf.write_text(DEGREES_MJCF.replace('<body name="arm" pos="0 0 .2">', '<body name="arm" pos="0 0 nan">'))
        with pytest.raises(ra.ModelError, match=r"body 'arm' in .*nan\.xml' \(line 2\) has pos \[0\.0, 0\.0, nan\]"):
            robot_from_file(mjcf).check()
    notes = [str(w.message) for w in caught]
    for name in ("nan.urdf", "nan.xml"):
        assert any(f"{name}': MuJoCo: XML contains a 'NaN'" in note for note in notes)


def test_a_zero_joint_axis_names_the_joint_and_line(tmp_path: Path) -> None:
    # MuJoCo said "axis too small in joint", naming neither the joint nor the file
    path = tmp_path / "axis.urdf"
    path.write_text(
        urdf(
            link("base", BOX) + link("arm", BOX),
            joint("j", "base", "arm").replace('<axis xyz="0 1 0"/>', '<axis xyz="0 0 0"/>'),
        )
    )
    with pytest.raises(ra.ModelError, match=r"joint 'j' in .*axis\.urdf' \(line 4\) has axis \[0\.0, 0\.0, 0\.0\]"):
        robot_from_file(path).check()


def test_an_mjcf_joint_range_given_upside_down_is_an_error(tmp_path: Path) -> None:
    # MuJoCo's autolimits read range="1 0" as no limit at all, without a word
    path = tmp_path / "swapped.xml"
    body = '<body name="arm"><joint name="elbow" range="{}"/><geom size="0.05" mass="1"/></body>'
    path.write_text(f"<mujoco>\n<worldbody>\n{body.format('1 0')}\n</worldbody>\n</mujoco>")
    with pytest.raises(ra.ModelError, match=r"joint 'elbow' in .*swapped\.xml' \(line 3\) has range \[1\.0, 0\.0\]"):
        robot_from_file(path).check()
    path.write_text(f"<mujoco>\n<worldbody>\n{body.format('0 1')}\n</worldbody>\n</mujoco>")
    assert robot_from_file(path).check().index.joints[0].range == pytest.approx((0.0, math.radians(1.0)))  # degrees


def test_a_file_without_a_body_says_so(tmp_path: Path) -> None:
    # it said "expected exactly one top-level body, got 0: []"
    path = tmp_path / "assets.xml"
    path.write_text('<mujoco><default><joint damping="1"/></default><worldbody/></mujoco>')
    with pytest.raises(ra.ModelError, match=r"assets\.xml\): expected the robot model to have a body, got none"):
        robot_from_file(path).check()


def test_lines_are_found_with_single_quoted_attributes(tmp_path: Path) -> None:
    # the line look-ups matched name="..." only: a file quoting with ' read "(line 0)"
    path = tmp_path / "quoted.urdf"
    text = urdf(link("base", BOX) + link("arm", BOX), joint("j", "base", "forearm"))
    path.write_text(text.replace('"', "'"))
    with pytest.raises(ra.ModelError, match=r"joint 'j' in .*quoted\.urdf' \(line 4\) names child link 'forearm'"):
        robot_from_file(path).check()
    path.write_text(urdf(link("base", BOX) + link("arm", BOX, mass=-1.0), joint("j", "base", "arm")).replace('"', "'"))
    with pytest.raises(ra.ModelError, match=r"mass of link 'arm' in .*quoted\.urdf' \(line 3\) is -1 kg"):
        robot_from_file(path).check()
