"""Model files from the wild, each case reproduced by a small file written here: what
the two-line definition derives from them, and what it says when it cannot."""

from __future__ import annotations

import io
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.cli import main as cli_main


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
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        assert cli_main(["check", str(path), "--seconds", "0.2"], io.StringIO()) == 0
        cls = two_line(path)
        cls.check()
        for _ in range(2):
            ra.Scene(cls).close()
        env = ra.make_env("Empty-v1", robot_uids=cls)
        env.close()
    notes = [str(w.message) for w in record if "zero-size visual" in str(w.message)]
    assert len(notes) == 2, notes  # the command line's robot once, the class once


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
