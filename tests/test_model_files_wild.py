"""Model files from the wild, each case reproduced by a small file written here: what
the two-line definition derives from them, and what it says when it cannot."""

from __future__ import annotations

import contextlib
import io
import re
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.agent.declaration import build_spec
from robot_agents.checks import run_random_actions
from robot_agents.cli import main as cli_main
from robot_agents.robot_source import robot_from_file


def two_line(path: Path, **extra: object) -> type[ra.Agent]:
    field = "urdf_path" if path.suffix == ".urdf" else "mjcf_path"
    return type("Wild", (ra.Agent,), {"uid": "wild", field: path, **extra})


def scene_of(cls: type[ra.Agent], **kwargs: object) -> ra.Scene:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return ra.Scene(cls, **kwargs)  # type: ignore[arg-type]


# A three-finger hand driven by <position> actuators without kv (as robosuite's hands; three
# fingers, so that it is not a two-finger Gripper, whose one mode takes no velocities).
UNDAMPED_HAND = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="palm" pos="0 0 0.2">
      <geom type="box" size="0.04 0.04 0.01" mass="0.3"/>
      <body name="left" pos="0.02 0 -0.02">
        <joint name="left_joint" axis="0 1 0" range="0 1"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.05" size="0.008" mass="0.05"/>
      </body>
      <body name="middle" pos="0 0.02 -0.02">
        <joint name="middle_joint" axis="1 0 0" range="0 1"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.05" size="0.008" mass="0.05"/>
      </body>
      <body name="right" pos="-0.02 0 -0.02">
        <joint name="right_joint" axis="0 1 0" range="-1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.05" size="0.008" mass="0.05"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="left_drive" joint="left_joint" kp="5" ctrlrange="0 1"/>
    <position name="middle_drive" joint="middle_joint" kp="5" ctrlrange="0 1"/>
    <position name="right_drive" joint="right_joint" kp="5" ctrlrange="-1 0"/>
  </actuator>
</mujoco>
"""


def test_generated_modes_leave_out_velocity_modes_of_undamped_file_drives(tmp_path: Path) -> None:
    path = tmp_path / "hand.xml"
    path.write_text(UNDAMPED_HAND)
    cls = two_line(path)
    modes = cls.check().modes
    assert "pd_joint_vel" not in modes  # a <position> without kv cannot follow velocities
    assert {"pd_joint_pos", "pd_joint_delta_pos", "pd_joint_pos_vel", "pd_joint_delta_pos_vel"} <= set(modes)
    scene = scene_of(cls)
    agent = scene.agents[0]
    for mode in modes:  # every generated mode can be selected and stepped
        agent.set_control_mode(mode)
        scene.reset()
        for _ in range(5):
            agent.set_action(np.zeros(agent.action_space.shape))
            scene.step()
    scene.close()
    # with damping the velocity mode is generated
    damped = tmp_path / "damped.xml"
    damped.write_text(UNDAMPED_HAND.replace('kp="5"', 'kp="5" kv="0.1"'))
    assert "pd_joint_vel" in two_line(damped).check().modes


def test_cli_info_and_check_run_on_a_file_with_undamped_drives(tmp_path: Path) -> None:
    path = tmp_path / "hand.xml"
    path.write_text(UNDAMPED_HAND)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        assert cli_main(["info", str(path)], io.StringIO()) == 0
        assert cli_main(["check", str(path), "--seconds", "0.2"], io.StringIO()) in (0, 1)


# A body lying on its side in the file (dm_control's humanoid_CMU: euler="90 0 0").
ROTATED_ROOT = """<mujoco>
  <worldbody>
    <body name="root" pos="0 0 1" euler="90 0 0">
      {free}
      <geom type="capsule" fromto="0 0 0 0 0.4 0" size="0.05" mass="2"/>
      <body name="leg" pos="0 0.4 0">
        <joint name="knee" axis="1 0 0" range="-90 90"/>
        <geom type="capsule" fromto="0 0 0 0 0.3 0" size="0.04" mass="1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("free", ['<freejoint name="root"/>', ""])
def test_floating_root_keeps_the_files_orientation_and_rests_on_the_floor(tmp_path: Path, free: str) -> None:
    path = tmp_path / "rotated.xml"
    path.write_text(ROTATED_ROOT.format(free=free))
    checked = two_line(path, fix_root_link=False).check()
    base = checked.keyframes["default"].base
    assert base is not None
    half = np.sqrt(0.5)
    np.testing.assert_allclose(base[3:], [half, half, 0.0, 0.0], atol=1e-9)  # +90 degrees about x
    # The chain now points up (+y rotated to +z): the root capsule's lower cap is lowest.
    np.testing.assert_allclose(base[2], 0.05 + 0.001, atol=1e-9)
    np.testing.assert_allclose(base[:2], [0.0, 0.0])


# A leg whose actuators drive fixed tendons (dm_control's quadruped and manipulator).
TENDON_LEG = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="hip" pos="0 0 0.5">
      <geom type="box" size="0.05 0.05 0.05" mass="1"/>
      <body name="thigh" pos="0 0 -0.05">
        <joint name="hip_joint" axis="0 1 0" range="-1 1"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/>
        <body name="shin" pos="0 0 -0.2">
          <joint name="knee_joint" axis="0 1 0" range="-1 1"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.3"/>
        </body>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="lift"><joint joint="hip_joint" coef="1"/><joint joint="knee_joint" coef="-0.5"/></fixed>
    <fixed name="bend"><joint joint="knee_joint" coef="1"/></fixed>
  </tendon>
  <actuator>
    {actuators}
  </actuator>
</mujoco>
"""
TENDON_ACTUATORS = '<motor name="lift_drive" tendon="lift" gear="5"/><motor name="bend_drive" tendon="bend" gear="5"/>'


def test_tendon_actuators_give_way_to_derived_joint_drives_with_a_note(tmp_path: Path) -> None:
    path = tmp_path / "tendon_leg.xml"
    path.write_text(TENDON_LEG.format(actuators=TENDON_ACTUATORS))
    cls = two_line(path)
    with pytest.warns(
        RuntimeWarning, match=r"2 of the model file's actuators \(lift_drive, bend_drive\) drive tendons, not joints"
    ):
        checked = cls.check()
    assert [d.joint for d in checked.drives] == ["hip_joint", "knee_joint"]
    assert checked.derived_gains is not None  # PD drives from the inertia, as for a file without actuators
    scene = scene_of(cls)
    agent = scene.agents[0]
    for mode in checked.modes:
        agent.set_control_mode(mode)
        scene.reset()
        rng = np.random.default_rng(0)
        for _ in range(20):
            agent.set_action(rng.uniform(-1, 1, agent.action_space.shape))
            scene.step()
    assert not np.any(scene.world.instability_counts())
    scene.close()


def test_a_file_mixing_tendon_and_joint_actuators(tmp_path: Path) -> None:
    path = tmp_path / "mixed_leg.xml"
    path.write_text(
        TENDON_LEG.format(actuators='<motor name="lift_drive" tendon="lift"/><position joint="knee_joint" kp="10"/>')
    )
    # Declaring nothing: all the file's actuators give way to derived joint drives, with a note.
    with pytest.warns(RuntimeWarning, match=r"\(lift_drive\) drive tendons.*replacing the other 1 file actuators"):
        checked = two_line(path).check()
    assert checked.derived_gains is not None and len(checked.drives) == 2
    # Declaring drives: the message names the one setting that removes the tendon actuator.
    declared = two_line(path, actuators=(ra.FileActuators(joints=("knee_joint",)),))
    with pytest.raises(ra.ConfigError, match=r"actuator 'lift_drive' drives a tendon.*replace_file_actuators = True"):
        declared.check()
    assert two_line(path, replace_file_actuators=True).check().derived_gains is not None


ZERO_VISUAL_URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
  </inertial><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
  </inertial><visual><geometry><sphere radius="0"/></geometry></visual>
  <collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def test_load_notes_are_given_once_per_robot(tmp_path: Path) -> None:
    path = tmp_path / "zero_visual.urdf"
    path.write_text(ZERO_VISUAL_URDF)
    err = io.StringIO()
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        with contextlib.redirect_stderr(err):  # the command line prints its notes, one line each
            assert cli_main(["check", str(path), "--seconds", "0.2"], io.StringIO()) == 0
        cls = two_line(path)
        cls.check()
        for _ in range(2):
            ra.Scene(cls).close()
        env = ra.make_env("Empty-v1", robot_uids=cls)
        env.close()
    assert [line for line in err.getvalue().splitlines() if "zero-size visual" in line] == [
        f"robot-agents: note: {str(path)!r}: dropped a zero-size visual <sphere> of link 'arm' (line 5)."
    ]  # the command line's robot once
    notes = [str(w.message) for w in record if "zero-size visual" in str(w.message)]
    assert len(notes) == 1, notes  # the class once


def inertia_urdf(inertia: str) -> str:
    """A one-joint arm whose root is a dummy link with ``inertia`` (go1's and tiago's)."""
    return f"""<?xml version="1.0"?>
<robot name="r">
  <!-- a dummy root link -->
  <link name="dummy">
    <inertial><mass value="1e-6"/><inertia {inertia}/></inertial>
  </link>
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
  </inertial><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>
  </inertial><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="dummy"/><child link="base"/></joint>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def test_a_singular_dummy_inertia_is_bounded_with_a_note(tmp_path: Path) -> None:
    path = tmp_path / "singular.urdf"
    path.write_text(inertia_urdf('ixx="1e-6" ixy="1e-6" ixz="1e-6" iyy="1e-6" iyz="1e-6" izz="1e-6"'))
    with pytest.warns(RuntimeWarning) as record:
        checked = two_line(path).check()
    notes = " ".join(str(w.message) for w in record)
    assert re.search(r"positive eigenvalues.*'dummy'.*compiled with boundmass=0.001, boundinertia=1e-06", notes)
    assert checked.compiler is not None and checked.compiler.boundinertia == 1e-6


def test_an_indefinite_inertia_names_the_file_link_line_and_fix(tmp_path: Path) -> None:
    path = tmp_path / "indefinite.urdf"
    path.write_text(inertia_urdf('ixx="2.4e-8" ixy="6.1e-8" ixz="1.2e-8" iyy="2.8e-8" iyz="7.7e-9" izz="3.8e-8"'))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the bounded retry's note
        with pytest.raises(ra.ModelError) as caught:
            two_line(path).check()
    message = str(caught.value)
    assert f"link 'dummy' in {str(path)!r} (line 4) is not positive-definite" in message
    assert "edit that <inertia>, or remove the <inertial>" in message


def test_mujocos_urdf_errors_give_the_line_in_the_users_file(tmp_path: Path) -> None:
    # Comments and the declaration above the bad element: MuJoCo reads the library's
    # re-serialised copy, whose lines differ; the message gives the user's line.
    good = ZERO_VISUAL_URDF.replace('<sphere radius="0"/>', '<sphere radius="0.01"/>')
    bad = good.replace(
        '<origin xyz="0 0 0.3"/>',
        '\n    <!-- mounted from\n         the environment -->\n    <origin xyz="$(optenv ARM_XYZ 0 0 0.3)"/>',
    )
    path = tmp_path / "xacro_left.urdf"
    path.write_text(bad)
    line = next(n for n, text in enumerate(bad.splitlines(), 1) if "$(optenv" in text)
    with pytest.raises(ra.ModelError) as caught:
        two_line(path).check()
    message = str(caught.value)
    assert f"line {line}" in message and f"line {line} holds an unexpanded xacro expression" in message
    assert "xacro model.urdf.xacro > model.urdf" in message


def test_make_env_takes_a_model_file_path_and_module_class(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "hand.xml"
    path.write_text(UNDAMPED_HAND)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        env = ra.make_env("Empty-v1", robot_uids=str(path))
    assert env.unwrapped.agent.uid == "hand"  # type: ignore[attr-defined]
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))
    env.close()
    # module:Class, as the command line takes it
    (tmp_path / "wild_robots.py").write_text(
        f"import robot_agents as ra\n\nclass MyHand(ra.Agent):\n    uid = 'my_hand'\n    mjcf_path = {str(path)!r}\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        env = ra.make_env("Empty-v1", robot_uids="wild_robots:MyHand")
    assert type(env.unwrapped.agent).__name__ == "MyHand"  # type: ignore[attr-defined]
    env.close()
    with pytest.raises(ra.ModelError, match="does not exist"):
        ra.make_env("Empty-v1", robot_uids=str(tmp_path / "missing.urdf"))
    with pytest.raises(ra.UnknownNameError, match="unknown robot uid 'pandaa'"):
        ra.make_env("Empty-v1", robot_uids="pandaa")


# A robot (an arm on a hinge, actuated) beside a world that is dropped: a target body with
# a joint, a mocap marker, and a world geom; ``{world}`` and ``{sections}`` add the
# elements that refer to them (the dm_control suite's dog.xml and swimmer.xml).
WORLD_WITH_REFERENCES = """<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <geom name="goal" type="sphere" pos="1 1 0.05" size="0.05" contype="0" conaffinity="0"/>
    {world}
    <body name="arm" pos="0 0 0.2">
      <joint name="hinge" axis="0 1 0" range="-1 1"/>
      <geom name="arm_geom" type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
      <site name="arm_site" pos="0.3 0 0"/>
    </body>
    <body name="ball" pos="2 0 0.1">
      <joint name="ball_x" type="slide" axis="1 0 0"/>
      <geom name="ball_geom" size="0.1" mass="0.2"/>
      <site name="ball_site"/>
      <body name="ball_child" pos="0 0 0.2"><geom name="child_geom" size="0.05" mass="0.1"/></body>
    </body>
    <body name="marker" mocap="true" pos="0 1 1"><geom size="0.02" contype="0" conaffinity="0"/></body>
  </worldbody>
  <actuator><position name="arm_motor" joint="hinge" kp="10" kv="1" ctrlrange="-1 1"/></actuator>
  {sections}
</mujoco>"""

# (test id, the world's extra elements, other sections, what the note names)
REFERENCE_CASES = [
    (
        "sensor-object",
        "",
        '<sensor><framepos name="s" objtype="body" objname="ball"/></sensor>',
        "sensor 's' (on body 'ball')",
    ),
    (
        "sensor-reference",
        "",
        '<sensor><framepos name="s" objtype="site" objname="arm_site" reftype="xbody" refname="ball_child"/></sensor>',
        "sensor 's' (on body 'ball_child')",
    ),
    (
        "sensor-world-geom",
        "",
        '<sensor><framepos name="s" objtype="geom" objname="goal"/></sensor>',
        "sensor 's' (on geom 'goal')",
    ),
    ("sensor-site", "", '<sensor><touch name="s" site="ball_site"/></sensor>', "sensor 's' (on site 'ball_site')"),
    ("sensor-joint", "", '<sensor><jointpos name="s" joint="ball_x"/></sensor>', "sensor 's' (on joint 'ball_x')"),
    (
        "equality-weld",
        "",
        '<equality><weld name="e" body1="marker" body2="arm"/></equality>',
        "equality 'e' (on body 'marker')",
    ),
    (
        "equality-connect",
        "",
        '<equality><connect name="e" body1="arm" body2="ball" anchor="0.3 0 0"/></equality>',
        "equality 'e' (on body 'ball')",
    ),
    (
        "equality-joint",
        "",
        '<equality><joint name="e" joint1="hinge" joint2="ball_x"/></equality>',
        "equality 'e' (on joint 'ball_x')",
    ),
    (
        "tendon-site-and-its-equality-actuator-sensor",
        "",
        '<tendon><spatial name="t"><site site="arm_site"/><site site="ball_site"/></spatial></tendon>'
        '<equality><tendon name="e" tendon1="t"/></equality>'
        '<actuator><motor name="m" tendon="t"/></actuator><sensor><actuatorfrc name="s" actuator="m"/></sensor>',
        "tendon 't' (on site 'ball_site'), actuator 'm' (on tendon 't'), sensor 's' (on actuator 'm'), equality 'e' (on tendon 't')",
    ),
    (
        "tendon-joint",
        "",
        '<tendon><fixed name="t"><joint joint="hinge" coef="1"/><joint joint="ball_x" coef="1"/></fixed></tendon>',
        "tendon 't' (on joint 'ball_x')",
    ),
    (
        "tendon-wrap-geom",
        "",
        '<tendon><spatial name="t"><site site="arm_site"/><geom geom="goal"/><site site="arm_site"/></spatial></tendon>',
        "tendon 't' (on geom 'goal')",
    ),
    (
        "actuator-site",
        "",
        '<actuator><motor name="m" site="ball_site" gear="1 0 0 0 0 0"/></actuator>',
        "actuator 'm' (on site 'ball_site')",
    ),
    (
        "actuator-body",
        "",
        '<actuator><adhesion name="m" body="ball_child" ctrlrange="0 1"/></actuator>',
        "actuator 'm' (on body 'ball_child')",
    ),
    (
        "contact-pair",
        "",
        '<contact><pair name="p" geom1="arm_geom" geom2="ball_geom"/></contact>',
        "contact pair 'p' (on geom 'ball_geom')",
    ),
    (
        "contact-exclude",
        "",
        '<contact><exclude name="x" body1="arm" body2="ball"/></contact>',
        "contact exclude 'x' (on body 'ball')",
    ),
    (
        "tuple",
        "",
        '<custom><tuple name="tu"><element objtype="body" objname="ball" prm="1"/></tuple></custom>',
        "tuple 'tu' (lists body 'ball')",
    ),
    (
        "skin",
        "",
        '<deformable><skin name="sk" vertex="0 0 0 0.1 0 0 0 0.1 0" face="0 1 2">'
        '<bone body="ball" bindpos="0 0 0" bindquat="1 0 0 0" vertid="0 1 2" vertweight="1 1 1"/></skin></deformable>',
        "skin 'sk' (on body 'ball')",
    ),
    (
        "flex",
        "",
        '<deformable><flex name="f" dim="1" body="ball ball_child" vertex="0 0 0 0 0 0" element="0 1"/></deformable>',
        "flex 'f' (on body 'ball')",
    ),
]


@pytest.mark.parametrize(
    ("world", "sections", "named"), [c[1:] for c in REFERENCE_CASES], ids=[c[0] for c in REFERENCE_CASES]
)
def test_elements_referring_to_the_dropped_world_are_dropped_with_it(
    tmp_path: Path, world: str, sections: str, named: str
) -> None:
    path = tmp_path / "world.xml"
    path.write_text(WORLD_WITH_REFERENCES.format(world=world, sections=sections))
    with pytest.warns(
        RuntimeWarning, match=r"kept top-level body 'arm' as the robot and dropped \['ball', 'marker'\]"
    ) as notes:
        checked = two_line(path).check()
    message = " ".join(str(n.message) for n in notes)
    assert f"also dropped what refers to them: {named}" in message if named else "also dropped" not in message
    assert checked.part_joints == {"arm": ("hinge",)}
    scene = scene_of(two_line(path))
    scene.reset()
    scene.step()
    assert scene.agents[0].joint_names == ("hinge",)


def test_a_sensor_on_a_dropped_world_geom_goes_with_it(tmp_path: Path) -> None:
    # swimmer.xml: one top-level body, a framepos sensor on the world geom "target".
    path = tmp_path / "swimmer.xml"
    path.write_text(
        """<mujoco><worldbody><geom name="target" type="sphere" pos="1 1 0.05" size="0.1"/>
        <body name="head"><joint name="yaw" axis="0 0 1"/><geom name="nose" size="0.05" mass="0.1"/></body>
        </worldbody><sensor><framepos name="target_pos" objtype="geom" objname="target"/>
        <framepos name="nose_pos" objtype="geom" objname="nose"/></sensor></mujoco>"""
    )
    with pytest.warns(
        RuntimeWarning, match=r"dropped the file's world geoms .*sensor 'target_pos' \(on geom 'target'\)"
    ):
        two_line(path).check()
    scene = scene_of(two_line(path))
    assert [scene.model.sensor(i).name for i in range(scene.model.nsensor)][-1].endswith("nose_pos")


def test_a_camera_or_light_targeting_a_dropped_body_stays_fixed_looking_where_it_was(tmp_path: Path) -> None:
    # dog.xml: a world camera with mode="targetbodycom" on the ball, which is dropped.
    world = (
        '<camera name="watch" mode="targetbody" target="ball" pos="1 1 1"/>'
        '<light name="spot" mode="targetbody" target="ball" pos="2 0 3"/>'
        '<camera name="other" mode="targetbodycom" target="arm" pos="0 -1 1"/>'
    )
    path = tmp_path / "cameras.xml"
    path.write_text(WORLD_WITH_REFERENCES.format(world=world, sections=""))
    with pytest.warns(RuntimeWarning, match=r"fixed camera 'watch' \(targeted body 'ball'\), light 'spot'") as notes:
        ra.Scene(two_line(path)).step()
    assert "also dropped" not in " ".join(str(n.message) for n in notes)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        model = build_spec(two_line(path)).compile()  # the robot's own model (a scene keeps its root body's tree)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    names = [model.camera(i).name for i in range(model.ncam)]
    watch = next(i for i, n in enumerate(names) if n.endswith("watch"))
    other = next(i for i, n in enumerate(names) if n.endswith("other"))
    assert model.cam_mode[watch] == mujoco.mjtCamLight.mjCAMLIGHT_FIXED
    assert model.cam_mode[other] == mujoco.mjtCamLight.mjCAMLIGHT_TARGETBODYCOM  # its target is the robot
    # It looks (along its -z axis) at where the ball was: (2, 0, 0.1) from (1, 1, 1).
    look = -data.cam_xmat[watch].reshape(3, 3)[:, 2]
    toward = np.array([2.0, 0.0, 0.1]) - np.array([1.0, 1.0, 1.0])
    np.testing.assert_allclose(look, toward / np.linalg.norm(toward), atol=1e-6)
    light = next(i for i in range(model.nlight) if model.light(i).name.endswith("spot"))
    toward = np.array([2.0, 0.0, 0.1]) - np.array([2.0, 0.0, 3.0])
    np.testing.assert_allclose(data.light_xdir[light], toward / np.linalg.norm(toward), atol=1e-6)


def test_keyframes_fit_the_model_without_the_dropped_world(tmp_path: Path) -> None:
    # The key holds the ball's slide, the marker's mocap pose, and the ctrl of a motor on
    # the ball (dropped): the robot keeps its own values.
    sections = (
        '<actuator><position name="ball_motor" joint="ball_x" kp="10" kv="1"/></actuator>'
        '<keyframe><key name="ready" qpos="0.01 0.3" ctrl="0.2 0.7" mpos="0 1 1" mquat="1 0 0 0"/></keyframe>'
    )
    path = tmp_path / "keys.xml"
    path.write_text(WORLD_WITH_REFERENCES.format(world="", sections=sections))
    with pytest.warns(RuntimeWarning, match=r"actuator 'ball_motor' \(on joint 'ball_x'\)"):
        checked = two_line(path, root_body="arm").check()
    np.testing.assert_allclose(checked.keyframes["default"].qpos, [0.01])


def test_a_dropped_motor_leaves_a_keyframe_ctrl_that_fits(tmp_path: Path) -> None:
    # No body is dropped (MuJoCo does not re-map the key): the motor on a tendon that
    # wraps the world geom goes, and the key's ctrl loses its entry.
    path = tmp_path / "tendon_ctrl.xml"
    path.write_text(
        """<mujoco><worldbody><geom name="post" type="cylinder" size="0.05 0.3" pos="0 0.2 0"/>
        <body name="arm"><joint name="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/><site name="tip" pos="0.3 0 0"/>
        <site name="base" pos="0.05 0 0"/></body></worldbody>
        <tendon><spatial name="cable"><site site="base"/><geom geom="post"/><site site="tip"/></spatial></tendon>
        <actuator><position name="hinge_motor" joint="hinge" kp="10" kv="1"/><motor name="cable_motor" tendon="cable"/></actuator>
        <keyframe><key qpos="0.4" ctrl="0.1 0.9"/></keyframe></mujoco>"""
    )
    with pytest.warns(RuntimeWarning, match=r"tendon 'cable' \(on geom 'post'\), actuator 'cable_motor'"):
        checked = two_line(path).check()
    np.testing.assert_allclose(checked.keyframes["default"].qpos, [0.4])


_KEYED_ARM = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 0.5">
      {free}
      <geom type="box" size="0.1 0.1 0.05" mass="2"/>
      <body name="link1" pos="0 0 0.05">
        <joint name="j1" axis="0 1 0" range="-1 1"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.02" mass="0.5"/>
        <body name="link2" pos="0 0 0.3">
          <joint name="j2" axis="0 1 0" range="-1 1"/>
          <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.02" mass="0.5"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe><key name="home" qpos="{qpos}" qvel="{qvel}"/></keyframe>
</mujoco>
"""


@pytest.mark.parametrize("file_has_free_joint", [False, True], ids=["no-free-joint", "free-joint"])
@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_the_files_keyframe_survives_adding_or_removing_the_root_free_joint(
    tmp_path: Path, file_has_free_joint: bool, floating: bool
) -> None:
    """A root free joint added (floating) or removed (fixed) shifts the file's keyframe
    onto the same joints: MuJoCo would read its values from the start of the new
    vectors (the added free joint's place), or refuse a key of the old size."""
    free = "<freejoint/>" if file_has_free_joint else ""
    base = "0 0 0.5 1 0 0 0 " if file_has_free_joint else ""
    speeds = "0 0 0 0 0 0 " if file_has_free_joint else ""
    path = tmp_path / "keyed.xml"
    path.write_text(_KEYED_ARM.format(free=free, qpos=base + "0.3 -0.5", qvel=speeds + "0 0"))
    cls = robot_from_file(path, floating=floating)
    if file_has_free_joint and not floating:  # the file's free joint fixed by the default: a note says so
        with pytest.warns(RuntimeWarning, match="free joint; the robot is fixed to the world"):
            checked = cls.check()
    else:
        checked = cls.check()
    np.testing.assert_array_equal(checked.keyframes["default"].qpos, [0.3, -0.5])


# A two-link arm driven by MuJoCo's default actuators: {first} on the shoulder, {second} on
# the elbow (robosuite's mobile bases use <velocity>, dm_control's soccer walkers mix
# motors with velocity servos; a <motor> written bare takes any effort).
ACTUATED_ARM = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="upper" pos="0 0 0.1">
      <joint name="shoulder" axis="0 0 1" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
      <body name="lower" pos="0.3 0 0">
        <joint name="elbow" axis="0 0 1" range="-2 2" damping="0.5"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.025" mass="0.5"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    {first}
    {second}
  </actuator>
</mujoco>
"""


def actuated_arm(tmp_path: Path, first: str, second: str, **extra: object) -> type[ra.Agent]:
    path = tmp_path / "actuated.xml"
    path.write_text(ACTUATED_ARM.format(first=first, second=second))
    return two_line(path, **extra)


#: The file's motors alone (a fixed arm the file drives with motors on every joint gets
#: PD drives within them otherwise: see the test at the end).
MOTORS_ALONE = {"actuators": (ra.FileActuators(),)}


def test_bare_motors_take_efforts_in_newtons_and_metres_and_the_check_runs(tmp_path: Path) -> None:
    from robot_agents.checks import check_random_actions

    cls = actuated_arm(tmp_path, '<motor joint="shoulder"/>', '<motor joint="elbow" ctrlrange="-2 2"/>', **MOTORS_ALONE)
    checked = cls.check()
    assert list(checked.modes) == ["joint_effort"]
    # the shoulder's effort has no bound: the actions are efforts (N*m), not normalized
    assert [d.effort_limit for d in checked.drives] == [np.inf, 2.0]
    scene = scene_of(cls)
    space = scene.agents[0].action_space
    assert np.isinf(space.high[0, 0]) and space.high[0, 1] == 2.0
    scene.reset()
    scene.agents[0].set_action(np.array([[0.3, -0.5]]))
    scene.step()
    np.testing.assert_allclose(scene.world.datas[0].actuator_force, [0.3, -0.5])
    scene.close()
    assert check_random_actions(cls, seconds=0.5).passed  # unbounded entries drawn as Gymnasium draws them
    # all bounded: normalized as before
    bounded = actuated_arm(
        tmp_path,
        '<motor joint="shoulder" ctrlrange="-1 1"/>',
        '<motor joint="elbow" ctrlrange="-2 2"/>',
        **MOTORS_ALONE,
    )
    scene = scene_of(bounded)
    np.testing.assert_array_equal(scene.agents[0].action_space.high, [[1.0, 1.0]])
    scene.close()


def test_random_actions_draw_unbounded_entries_like_gymnasium() -> None:
    from robot_agents.checks import random_action

    rng = np.random.default_rng(0)
    low, high = np.array([-1.0, -np.inf, 0.5, -np.inf]), np.array([1.0, np.inf, np.inf, -2.0])
    drawn = np.array([random_action(low, high, rng) for _ in range(2000)])
    assert np.isfinite(drawn).all()
    assert (drawn[:, 0] >= -1).all() and (drawn[:, 0] <= 1).all()
    assert abs(drawn[:, 1].std() - 1.0) < 0.1  # standard normal
    assert (drawn[:, 2] >= 0.5).all() and (drawn[:, 3] <= -2.0).all()  # a bound plus or minus an exponential
    # within finite bounds: exactly rng.uniform, the draws of every existing check
    np.testing.assert_array_equal(
        random_action(low[:1], high[:1], np.random.default_rng(3)), np.random.default_rng(3).uniform(low[:1], high[:1])
    )


def test_velocity_servos_get_the_velocity_mode_and_follow_it(tmp_path: Path) -> None:
    cls = actuated_arm(
        tmp_path,
        '<velocity joint="shoulder" kv="20" gear="2" ctrlrange="-3 3"/>',
        '<velocity joint="elbow" kv="5" ctrlrange="-1 1"/>',
    )
    checked = cls.check()
    assert list(checked.modes) == ["pd_joint_vel"] and checked.default_mode == "pd_joint_vel"
    # a velocity servo's control is its transmission's speed: the joint's times the gear
    assert [d.velocity_limit for d in checked.drives] == [1.5, 1.0]
    scene = scene_of(cls)
    scene.reset()
    agent = scene.agents[0]
    np.testing.assert_array_equal(agent.action_space.high, [[1.0, 1.0]])
    for _ in range(20):  # one second at +0.5 of the bounds
        agent.set_action(np.array([[0.5, -0.5]]))
        scene.step()
    # the servos meet their targets against the file's joint damping (0.5), which the
    # drives feed forward (a servo alone settles at kv / (kv + b): 80 / 80.5 and 5 / 5.5
    # of it), the shoulder's speed through its gear of 2 (the elbow turns on the
    # turning shoulder: within 0.5 %)
    np.testing.assert_allclose(scene.world.datas[0].qvel, [0.75, -0.5], rtol=5e-3)
    scene.close()


def test_a_velocity_servo_beside_a_position_servo_without_damping_is_refused_with_the_joints(tmp_path: Path) -> None:
    cls = actuated_arm(
        tmp_path, '<velocity joint="shoulder" kv="20"/>', '<position joint="elbow" kp="20" ctrlrange="-2 2"/>'
    )
    with pytest.raises(ra.ConfigError, match=r"\['shoulder'\] have velocity servos .* \['elbow'\] position servos"):
        cls.check()


def test_a_part_beside_the_main_one_with_velocity_servos_takes_velocities() -> None:
    from robot_agents.controllers.joint import PDJointVelConfig
    from robot_agents.controllers.rules import modes_from_parts

    parts = (ra.Arm(name="arm", joints=("a1", "a2")), ra.Body(name="base", joints=("x", "y")))
    modes = modes_from_parts(
        parts,
        {"arm": ("a1", "a2"), "base": ("x", "y")},
        {"a1": 2.0, "a2": 2.0, "x": 0.5, "y": np.inf},
        velocity_only=("x", "y"),
    )
    base = modes["pd_joint_delta_pos"]["base"]  # type: ignore[index]
    assert isinstance(base, PDJointVelConfig)
    assert base.lower == (-0.5, -1.0) and base.upper == (0.5, 1.0)  # unknown speeds: 1 m/s


def test_general_actuators_without_bias_are_motors_and_autolimits_bound_them(tmp_path: Path) -> None:
    # dm_control's soccer walker's <general biastype="affine" biasprm="0">, and ranges
    # written without ctrllimited / forcelimited under autolimits (MuJoCo Menagerie)
    cls = actuated_arm(
        tmp_path,
        '<general joint="shoulder" gear="30" ctrlrange="-1 1" biastype="affine" biasprm="0"/>',
        '<motor joint="elbow" ctrlrange="-5 5" forcerange="-2 2"/>',
        **MOTORS_ALONE,
    )
    checked = cls.check()
    assert list(checked.modes) == ["joint_effort"]
    assert [d.effort_limit for d in checked.drives] == [30.0, 2.0]
    explicit = actuated_arm(
        tmp_path, '<motor joint="shoulder" ctrllimited="false" ctrlrange="-1 1"/>', "", **MOTORS_ALONE
    )
    assert explicit.check().drives[0].effort_limit == np.inf


def test_a_massless_jointed_frame_is_judged_with_the_bodies_welded_to_it(tmp_path: Path) -> None:
    from robot_agents.checks import check_inertia

    frame = """<mujoco>
  <worldbody>
    <body name="base" pos="0 0 0.2">
      <joint name="slide" type="slide" axis="1 0 0"/>
      <inertial pos="0 0 0" mass="{frame_mass}" diaginertia="{frame_mass} {frame_mass} {frame_mass}"/>
      <body name="chassis">
        <geom type="box" size="0.2 0.1 0.05" mass="{chassis_mass}"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
    path = tmp_path / "frame.xml"
    path.write_text(frame.format(frame_mass=0, chassis_mass=20))  # robosuite's mobile bases
    result = check_inertia(two_line(path))
    assert result.passed, result.detail
    path.write_text(frame.format(frame_mass=1e-6, chassis_mass=0))  # a placeholder link a gripper would carry
    result = check_inertia(two_line(path, compiler=ra.CompilerSettings(boundmass=1e-6, boundinertia=1e-6)))
    assert not result.passed and "base mass 2e-06 kg" in result.detail  # with the chassis bounded to 1e-6


def test_a_fixed_arm_driven_by_motors_gets_pd_drives_within_them_and_keeps_joint_effort(tmp_path: Path) -> None:
    # robosuite's arms, gymnasium's reacher and pusher: torque motors on every joint
    cls = actuated_arm(
        tmp_path, '<motor joint="shoulder" gear="10" ctrlrange="-1 1"/>', '<motor joint="elbow" ctrlrange="-4 4"/>'
    )
    with warnings.catch_warnings(record=True) as notes:
        warnings.simplefilter("always")
        checked = cls.check()
    assert any("torque motors" in str(n.message) and "FileActuators" in str(n.message) for n in notes)
    assert {"pd_joint_pos", "pd_joint_delta_pos", "pd_joint_vel", "joint_effort"} <= set(checked.modes)
    assert checked.default_mode == "pd_joint_delta_pos"
    assert all(d.replaces_motor and d.stiffness > 0 and d.damping > 0 for d in checked.drives)
    assert [d.effort_limit for d in checked.drives] == [10.0, 4.0]  # the motors' gear * control range
    scene = scene_of(cls)
    agent, data = scene.agents[0], scene.world.datas[0]
    scene.reset()
    for _ in range(20):  # a joint step within the motors' torques
        agent.set_action(np.array([[0.1, -0.1]]))
        scene.step()
    assert np.abs(data.actuator_force).max() <= 10.0 + 1e-9 and np.abs(data.actuator_force[1]) <= 4.0 + 1e-9
    # joint_effort: the motors' torques, the drives' stiffness and damping relaxed
    agent.set_control_mode("joint_effort")
    np.testing.assert_array_equal(agent.action_space.high, [[1.0, 1.0]])
    agent.set_action(np.array([[0.5, -0.25]]))
    scene.step()
    np.testing.assert_allclose(data.actuator_force, [5.0, -1.0], rtol=1e-12)
    scene.close()
    # the motors alone, as the file has them
    kept = two_line(tmp_path / "actuated.xml", actuators=(ra.FileActuators(),))
    assert list(kept.check().modes) == ["joint_effort"]
    # and for a robot declaring its own modes, written for the motors: pure torques
    from robot_agents.controllers.joint import JointEffortConfig

    torques = two_line(
        tmp_path / "actuated.xml", control_modes={"torque": JointEffortConfig(joint_names=("shoulder", "elbow"))}
    )
    assert not any(d.replaces_motor for d in torques.check().drives)
    scene = scene_of(torques)
    scene.reset()
    scene.agents[0].set_action(np.array([[0.5, -0.25]]))
    scene.step()
    # the joint torques: the shoulder's motor force 0.5 through its gear of 10
    np.testing.assert_allclose(scene.world.datas[0].qfrc_actuator, [5.0, -1.0], rtol=1e-12)
    scene.close()
    # a joint without a motor (an underactuated robot: gymnasium's hopper on its root's
    # slides and hinge, a cart-pole's pole): efforts only, as the file has them
    passive = actuated_arm(tmp_path, '<motor joint="shoulder" ctrlrange="-1 1"/>', "")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        assert list(passive.check().modes) == ["joint_effort"]


def test_a_motor_driven_arm_file_with_a_built_in_gripper_mounted(tmp_path: Path) -> None:
    # robosuite's arms take their gripper at a `right_hand` body: `robot-agents demo
    # robots/ur5e/robot.xml --gripper robotiq_2f85 --at right_hand`
    path = tmp_path / "actuated.xml"
    path.write_text(
        ACTUATED_ARM.format(
            first='<motor joint="shoulder" ctrlrange="-20 20"/>', second='<motor joint="elbow" ctrlrange="-10 10"/>'
        )
    )
    cls = robot_from_file(path, gripper="franka_hand", at="lower")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        checked = cls.check()
    arm = {d.joint: d for d in checked.drives if d.replaces_motor}
    assert sorted(arm) == ["elbow", "shoulder"] and [arm["shoulder"].effort_limit, arm["elbow"].effort_limit] == [
        20,
        10,
    ]
    hand = [d for d in checked.drives if not d.replaces_motor]
    assert hand and all(d.joint.startswith("franka_hand/") for d in hand)  # the piece's own drives
    assert {"pd_joint_delta_pos", "joint_effort"} <= set(checked.modes)
    scene = scene_of(cls)
    agent = scene.agents[0]
    scene.reset()
    for _ in range(10):
        agent.set_action(np.zeros(agent.action_space.shape))
        scene.step()
    assert not scene.world.unstable_steps.any()
    scene.close()


# Two arms as top-level bodies and one keyframe over the whole file (gym_aloha's ALOHA:
# bimanual_viperx_transfer_cube.xml), one arm kept with root_body.
TWO_ARMS = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="left" pos="0 0.3 0.1">
      <joint name="left_joint" axis="0 1 0" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
    </body>
    <body name="right" pos="0 -0.3 0.1">
      <joint name="right_joint" axis="0 1 0" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="left_joint" kp="50" kv="5" ctrlrange="-1 1"/>
    <position joint="right_joint" kp="50" kv="5" ctrlrange="-1 1"/>
  </actuator>
  <keyframe>
    <key qpos="0.4 -0.2"/>
  </keyframe>
</mujoco>
"""


def test_one_arm_of_a_file_with_a_keyframe_makes_a_scene_without_mujoco_warnings(tmp_path: Path) -> None:
    path = tmp_path / "two_arms.xml"
    path.write_text(TWO_ARMS)
    cls = two_line(path, root_body="left")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        keyframe = cls.check().keyframes["default"].qpos
    np.testing.assert_array_equal(keyframe, [0.4])  # the file's keyframe, cut to the kept arm
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # MuJoCo's "Child model has pending keyframes" before
        scene = ra.Scene(cls)
        scene.reset()
    np.testing.assert_array_equal(scene.agents[0].qpos, [[0.4]])
    assert scene.model.nkey == 0  # the scene sets its states itself
    scene.close()


def test_the_command_line_picks_a_files_robot_with_root_body(tmp_path: Path) -> None:
    path = tmp_path / "two_arms.xml"
    path.write_text(TWO_ARMS)
    out = io.StringIO()
    with pytest.raises(ra.ModelError, match=r"none stands out as the robot.*robot-agents: --root-body left"):
        robot_from_file(path).check()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        assert cli_main(["info", str(path), "--root-body", "right"], out) == 0
    assert "right_joint" in out.getvalue() and "left_joint" not in out.getvalue()
    with pytest.raises(ra.ConfigError, match=r"root_body='left' picks a model file's robot, and 'panda'"):
        from robot_agents.robot_source import resolve_robot

        resolve_robot("panda", root_body="left")


def test_a_massless_frames_inertia_is_its_welded_bodies_combined(tmp_path: Path) -> None:
    from robot_agents.checks import _combined_inertia, check_inertia

    frame = """<mujoco>
  <worldbody>
    <body name="base" pos="0 0 0.5">
      <joint name="slide" type="slide" axis="1 0 0"/>
      {inertial}
      <body name="a" pos="0.5 0 0"><inertial pos="0 0 0" mass="1" diaginertia="{moment} {moment} {moment}"/></body>
      <body name="b" pos="-0.5 0 0" euler="0 0 30">
        <inertial pos="0 0 0" mass="1" diaginertia="{moment} {moment} {moment}"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
    path = tmp_path / "frame.xml"
    path.write_text(frame.format(inertial="", moment=0.01))
    cls = two_line(path)
    model = cls.check().index.model
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    bodies = np.array([model.body(n).id for n in ("a", "b")])
    # two 1 kg masses 1 m apart: 2 * 1 kg * (0.5 m)^2 about the two axes across the pair
    np.testing.assert_allclose(_combined_inertia(model, data, bodies), [0.02, 0.52, 0.52], atol=1e-12)
    assert model.body_mass[model.body("base").id] == 0  # MuJoCo takes the frame massless
    assert check_inertia(cls).passed
    # a frame with its own mass is judged on its own inertia (a welded point mass, Fetch's
    # estop link in gymnasium-robotics, is part of it)
    path.write_text(frame.format(inertial='<inertial pos="0 0 0" mass="2" diaginertia="0.1 0.1 0.1"/>', moment=0))
    assert check_inertia(two_line(path)).passed


def test_unnamed_bodies_and_joints_get_names_and_the_robot_works(tmp_path: Path) -> None:
    # hand-written MJCF names little (gymnasium-robotics' Franka kitchen: an unnamed root
    # body; no scene could be built, "no root body with prefix"; an unnamed last body
    # made "EndEffector: expected link to be a body or site name, got ''")
    from robot_agents.model.loading import load_model_spec

    path = tmp_path / "unnamed.xml"
    path.write_text(
        """<mujoco><worldbody>
  <body pos="0 0 0.1"><joint axis="0 1 0" range="-1 1"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/>
    <body name="body1" pos="0.3 0 0"><joint name="elbow" axis="0 1 0" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="0.5"/>
      <body pos="0.3 0 0"><joint axis="0 1 0" range="-1 1"/>
        <geom type="sphere" size="0.03" mass="0.2"/></body>
    </body>
  </body>
</worldbody></mujoco>"""
    )
    spec = load_model_spec(path)
    # body<k> / joint<k> by place; a name the file already uses gets "_" appended
    assert [b.name for b in spec.bodies[1:]] == ["body1_", "body1", "body3"]
    assert [j.name for j in spec.joints] == ["joint0", "elbow", "joint2"]
    cls = two_line(path)
    checked = cls.check()
    assert checked.part_joints["arm"] == ("joint0", "elbow", "joint2")
    scene = scene_of(cls)
    scene.reset()
    scene.step()
    assert scene.agents[0].index.root_body_id == scene.model.body("wild-0/body1_").id
    scene.close()


# An arm moved by a mocap weld on its hand, only its fingers actuated (gymnasium-robotics'
# Fetch, Meta-World's Sawyer), on a base slide the file locks with damping.
MOCAP_ARM = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 0.1">
      <joint name="base_slide" type="slide" axis="1 0 0" damping="1e6"/>
      <geom type="box" size="0.1 0.1 0.05" mass="5"/>
      <body name="upper" pos="0 0 0.05">
        <joint name="shoulder" axis="0 0 1" range="-2 2"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.03" mass="1"/>
        <body name="fore" pos="0 0 0.3">
          <joint name="elbow" axis="0 1 0" range="-2 2"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.025" mass="0.5"/>
          <body name="hand" pos="0.3 0 0">
            <joint name="wrist" axis="0 1 0" range="-2 2"/>
            <geom type="box" size="0.02 0.04 0.02" mass="0.2"/>
            <body name="left" pos="0.03 0.02 0">
              <joint name="left_finger" type="slide" axis="0 1 0" range="0 0.03"/>
              <geom type="box" size="0.01 0.005 0.02" mass="0.02"/>
            </body>
            <body name="right" pos="0.03 -0.02 0">
              <joint name="right_finger" type="slide" axis="0 -1 0" range="0 0.03"/>
              <geom type="box" size="0.01 0.005 0.02" mass="0.02"/>
            </body>
          </body>
        </body>
      </body>
    </body>
    <body name="mocap" mocap="true" pos="0.3 0 0.45"><geom type="sphere" size="0.01" contype="0" conaffinity="0"/></body>
  </worldbody>
  <equality><weld body1="mocap" body2="hand"/></equality>
  <actuator>
    <position joint="left_finger" kp="200" kv="5" ctrlrange="0 0.03"/>
    <position joint="right_finger" kp="200" kv="5" ctrlrange="0 0.03"/>
  </actuator>
</mujoco>
"""


def test_joints_a_dropped_mocap_weld_moved_get_derived_drives(tmp_path: Path) -> None:
    path = tmp_path / "mocap_arm.xml"
    path.write_text(MOCAP_ARM)
    cls = two_line(path)
    with warnings.catch_warnings(record=True) as notes:
        warnings.simplefilter("always")
        checked = cls.check()
    assert any("through a weld to a mocap body" in str(n.message) for n in notes)
    derived = [d.joint for d in checked.drives if d.source.startswith("derived gains")]
    assert derived == ["shoulder", "elbow", "wrist"]  # not the locked base slide
    assert [d.joint for d in checked.drives if d.source.startswith("the model file")] == ["left_finger", "right_finger"]
    assert "base_slide" not in {d.joint for d in checked.drives}
    from robot_agents.checks import check_holds

    assert check_holds(cls, seconds=1.0).passed
    # without the weld the file leaves those joints passive, as before
    unwelded = tmp_path / "unwelded.xml"
    unwelded.write_text(MOCAP_ARM.replace('<equality><weld body1="mocap" body2="hand"/></equality>', ""))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        drives = two_line(unwelded).check().drives
    assert [d.joint for d in drives] == ["left_finger", "right_finger"]


def _chain(kinds: str) -> str:
    """A serial chain of the given joint kinds ("s" slide, "h" hinge), its links 0.2 m long."""
    body, close = "", ""
    for k, kind in enumerate(kinds):
        axis, kind_name = ("0 0 1", "slide") if kind == "s" else ("0 1 0" if k % 2 else "0 0 1", "hinge")
        body += (
            f'<body name="link{k}" pos="0 0 {0.1 if k == 0 else 0.2}"><joint name="j{k}" type="{kind_name}" '
            f'axis="{axis}" range="-1 1"/><geom type="capsule" fromto="0 0 0 0 0 0.2" size="0.03" mass="1"/>'
        )
        close += "</body>"
    return f"<mujoco><compiler angle='radian'/><worldbody>{body}{close}</worldbody></mujoco>"


@pytest.mark.parametrize(
    ("kinds", "parts"),
    [
        ("shhh", {"arm": ("j1", "j2", "j3"), "torso": ("j0",)}),  # a lift under an arm: gymnasium-robotics' Fetch
        ("ssshhh", {"arm": ("j0", "j1", "j2", "j3", "j4", "j5")}),  # a floating gripper's mount stays one arm
        ("shh", {"arm": ("j0", "j1", "j2")}),  # too short an arm above the slide
        ("hhhs", {"arm": ("j0", "j1", "j2", "j3")}),
    ],
)
def test_a_lift_under_an_arm_is_a_torso(tmp_path: Path, kinds: str, parts: dict[str, tuple[str, ...]]) -> None:
    path = tmp_path / "chain.xml"
    path.write_text(_chain(kinds))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        checked = two_line(path).check()
    assert {p.name: tuple(checked.part_joints[p.name]) for p in checked.parts} == parts
    if "torso" in parts:  # the arm leads the action; the torso takes delta positions after it
        assert "pd_ee_delta_pos" in checked.modes  # three hinges: position-only end-effector modes


def test_info_lists_a_ball_joint_by_its_largest_turn(tmp_path: Path) -> None:
    # MuJoCo Menagerie's Cassie: ball joints in its leg linkage (info raised "zip() argument
    # 2 is longer than argument 1": four qpos entries for one joint name)
    path = tmp_path / "ball.xml"
    path.write_text(
        """<mujoco><compiler angle="radian"/><worldbody>
  <body name="upper" pos="0 0 0.5"><joint name="hinge" axis="0 1 0" range="-1 1"/>
    <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="1"/>
    <body name="lower" pos="0 0 -0.2"><joint name="rod" type="ball" range="0 0.5"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/></body>
  </body>
</worldbody></mujoco>"""
    )
    out = io.StringIO()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        assert cli_main(["info", str(path)], out) == 0
    lines = out.getvalue().splitlines()
    assert any(re.match(r"rod \(ball\)\s+-\s+0\.5000 rad turn", line) for line in lines)
    assert any(re.match(r"hinge\s+-1\.0000\s+1\.0000", line) for line in lines)


@pytest.mark.parametrize("axis", ["x", "-y", "-z"])
def test_a_gripper_mounted_along_another_axis_of_the_frame_points_along_it(tmp_path: Path, axis: str) -> None:
    # robosuite's Spot arm's `right_hand` has the tool along x (a ROS-Industrial `flange`
    # too): `--at-axis x` points the piece's z along it, its tcp that far out along x
    from robot_agents.robot_source import OUT_AXES, resolve_robot
    from tests.test_derived_task_space import arm_urdf

    path = tmp_path / "arm.urdf"
    path.write_text(arm_urdf(6))

    def tcp_in_flange(at_axis: str) -> np.ndarray:
        scene = scene_of(robot_from_file(path, gripper="robotiq_2f85", at="flange_roll_link", at_axis=at_axis))
        scene.reset()
        model, data = scene.world.model, scene.world.datas[0]
        mujoco.mj_kinematics(model, data)
        names = [model.body(i).name for i in range(model.nbody)]  # (the scene prefixes them)
        flange = next(i for i, name in enumerate(names) if name.endswith("/flange_roll_link"))
        tcp = next(i for i, name in enumerate(names) if name.endswith("/robotiq_2f85/robotiq_tcp"))
        offset = data.xmat[flange].reshape(3, 3).T @ (data.xpos[tcp] - data.xpos[flange])
        scene.close()
        return offset

    along_z = tcp_in_flange("z")
    assert along_z[2] > 0.15 and np.allclose(along_z[:2], 0.0, atol=1e-9)  # 0.1553 m out of the flange
    direction = np.zeros(3)
    mujoco.mju_rotVecQuat(direction, np.array([0.0, 0.0, 1.0]), np.array(OUT_AXES[axis]))
    np.testing.assert_allclose(tcp_in_flange(axis), along_z[2] * direction, atol=1e-9)
    # refused where it cannot apply, with what there is
    with pytest.raises(ra.UnknownNameError, match=r"Did you mean 'x', '-x'"):
        robot_from_file(path, gripper="robotiq_2f85", at="flange_roll_link", at_axis="+x")
    with pytest.raises(ra.ConfigError, match="no gripper is mounted"):
        robot_from_file(path, at_axis=axis)
    with pytest.raises(ra.ConfigError, match="declare its attachments instead"):
        resolve_robot("panda", at_axis=axis)


def test_a_fixed_arm_mixing_position_servos_and_motors_gets_joint_modes(tmp_path: Path) -> None:
    # an arm's <position> servos and a <motor> wrist: the whole robot got joint_effort alone
    cls = actuated_arm(
        tmp_path,
        '<position joint="shoulder" kp="40" kv="4" ctrlrange="-3 3" forcerange="-20 20"/>',
        '<motor joint="elbow" ctrlrange="-4 4"/>',
    )
    with pytest.warns(RuntimeWarning, match=r"1 joint\(s\) with torque motors.*position servos on \['shoulder'\] stay"):
        checked = cls.check()
    shoulder, elbow = checked.drives
    assert not shoulder.replaces_motor and shoulder.source == "the model file"  # the file's servo, as it is
    assert elbow.replaces_motor and elbow.stiffness > 0 and elbow.damping > 0 and elbow.effort_limit == 4.0
    assert {"pd_joint_pos", "pd_joint_delta_pos", "pd_joint_vel", "joint_effort"} <= set(checked.modes)
    assert checked.default_mode == "pd_joint_delta_pos"
    scene = scene_of(cls)
    agent, data = scene.agents[0], scene.world.datas[0]
    scene.reset()
    agent.set_control_mode("pd_joint_pos")
    for _ in range(3 * scene.control_freq):  # both joints reach position targets
        agent.set_action(np.array([[0.4, -0.3]]))
        scene.step()
    np.testing.assert_allclose(agent.qpos[0], [0.4, -0.3], atol=0.02)
    assert abs(data.actuator_force[1]) <= 4.0 + 1e-9
    # joint_effort: the servo's stiffness and damping relaxed too, efforts within each limit
    agent.set_control_mode("joint_effort")
    agent.set_action(np.array([[0.5, -0.25]]))
    scene.step()
    np.testing.assert_allclose(data.qfrc_actuator, [10.0, -1.0], rtol=1e-9)
    agent.set_control_mode("pd_joint_delta_pos")
    run_random_actions(scene, 1.0, 0)
    assert not np.any(scene.world.instability_counts())
    scene.close()
    # velocity servos with motors: no joint mode drives a velocity servo and a position drive together
    velocity = actuated_arm(tmp_path, '<velocity joint="shoulder" kv="4"/>', '<motor joint="elbow" ctrlrange="-4 4"/>')
    with pytest.warns(RuntimeWarning, match=r"\['elbow'\] with torque motors and \['shoulder'\] with velocity servos"):
        assert list(velocity.check().modes) == ["joint_effort"]


def _steps_to_close(uid: str) -> int:
    """Control steps the gripper of robot ``uid`` takes in ``PickCube-v1`` (20 Hz) from
    open to an opening under 0.05 (empty, arm held), after opening it, in its default mode; 100 where it
    does not close by then."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        env = ra.make_env("PickCube-v1", robot_uids=uid).unwrapped
    try:
        env.reset(seed=0)
        controller = env.agent.controller
        gripper = next(name for name in controller.parts if "gripper" in name)
        action = np.zeros((1, controller.action_dim))
        action[:, controller.slices[gripper]] = 1.0
        for _ in range(200):  # open (its servo's range ends where its travel does: slowly)
            env.step(action)
            if env.agent.gripper_opening()[0] > 0.8:
                break
        assert env.agent.gripper_opening()[0] > 0.8
        action[:, controller.slices[gripper]] = -1.0
        for step in range(1, 101):
            env.step(action)
            if env.agent.gripper_opening()[0] < 0.05:
                return step
        return 100
    finally:
        env.close()


def test_a_files_finger_servos_commanded_past_their_travel_close_as_the_file_commands(tmp_path: Path) -> None:
    # Meta-World's Sawyer: fingers of heavy armature and damping, position servos whose
    # control range (+-1 m) reaches far past their travel (0-3 cm, closed at 0): the close commands
    # the end of that range, as the file's users do, and the fingers close quickly.
    heavy = MOCAP_ARM.replace('range="0 0.03"/>', 'range="0 0.03" armature="100" damping="1000"/>')
    as_written = heavy.replace('kp="200" kv="5" ctrlrange="0 0.03"', 'kp="400" ctrlrange="0 0.03"')
    past = heavy.replace('kp="200" kv="5" ctrlrange="0 0.03"', 'kp="400" ctrlrange="-1 1"')
    steps = {}
    for name, text in (("within", as_written), ("past", past)):
        path = tmp_path / f"{name}.xml"
        path.write_text(text)
        cls = two_line(path, uid=f"wild_{name}")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            gripper = next(p for p in cls.check().parts if isinstance(p, ra.Gripper))
            ra.register_agent(cls)
        try:
            steps[name] = _steps_to_close(cls.uid)
        finally:
            ra.unregister_agent(cls.uid)  # the registry as found: other tests list every robot
        # the derived squeeze, a tenth of the stroke, where the range ends at the travel
        assert gripper.squeeze == pytest.approx(1.0 if name == "past" else 0.003)  # closed: 0 m
    assert steps["past"] <= 6 and steps["within"] >= 40, steps  # measured: 4 and over 100
