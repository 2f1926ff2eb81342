"""Model files from the wild, each case reproduced by a small file written here: what
the two-line definition derives from them, and what it says when it cannot."""

from __future__ import annotations

import io
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


# A two-finger hand driven by <position> actuators without kv (robosuite's grippers).
UNDAMPED_HAND = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="palm" pos="0 0 0.2">
      <geom type="box" size="0.04 0.04 0.01" mass="0.3"/>
      <body name="left" pos="0.02 0 -0.02">
        <joint name="left_joint" axis="0 1 0" range="0 1"/>
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
