"""Shared fixtures: small user robots written on the fly (MJCF and URDF)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")

import robot_agents as ra

PENDULUM_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="base" pos="0 0 1.0">
      <geom type="box" size="0.05 0.05 0.05" mass="1"/>
      <body name="link1">
        <joint name="shoulder" axis="0 1 0" range="-2.5 2.5"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="1"/>
        <body name="link2" pos="0 0 -0.3">
          <joint name="elbow" axis="0 1 0" range="-2.5 2.5"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.25" size="0.02" mass="0.5"/>
          <body name="tip" pos="0 0 -0.25"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

INERTIAL = '<inertial><mass value="{m}"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'

TWO_LINK_URDF = f"""<?xml version="1.0"?>
<robot name="two_link">
  <link name="base_link">{INERTIAL.format(m=2.0)}
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <link name="upper">{INERTIAL.format(m=1.0)}
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry></collision>
  </link>
  <link name="lower">{INERTIAL.format(m=0.5)}
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.02" length="0.2"/></geometry></collision>
  </link>
  <link name="tool"/>
  <joint name="joint_a" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="50" velocity="2"/></joint>
  <joint name="joint_b" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="20" velocity="2"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="lower"/><child link="tool"/><origin xyz="0 0 0.2"/></joint>
</robot>
"""


@pytest.fixture
def pendulum_file(tmp_path: Path) -> Path:
    path = tmp_path / "pendulum.xml"
    path.write_text(PENDULUM_MJCF)
    return path


@pytest.fixture
def urdf_file(tmp_path: Path) -> Path:
    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF)
    return path


def make_pendulum_class(path: Path, uid: str = "test_pendulum", **extra: object) -> type[ra.Agent]:
    """A 2-joint pendulum robot defined the way a user would."""
    attrs: dict[str, object] = {
        "uid": uid,
        "mjcf_path": path,
        "actuators": (ra.PDActuator(joints=("shoulder", "elbow"), stiffness=200.0, damping=20.0, effort_limit=50.0),),
        "parts": (ra.Arm(name="arm", joints=("shoulder", "elbow"), end_effectors=(ra.EndEffector("tip"),)),),
        "keyframes": {"down": ra.Keyframe(qpos=(0.0, 0.0)), "bent": ra.Keyframe(qpos={"shoulder": 0.5, "elbow": -0.8})},
        "control_modes": ra.joint_control_modes(ra.JointGroup(joint_names=("shoulder", "elbow"))),
    }
    attrs.update(extra)
    return type("Pendulum", (ra.Agent,), attrs)


@pytest.fixture
def pendulum_cls(pendulum_file: Path) -> Iterator[type[ra.Agent]]:
    cls = make_pendulum_class(pendulum_file)
    yield cls
