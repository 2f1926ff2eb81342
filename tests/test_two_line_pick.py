"""A model file in two lines picks a cube: a written six-joint arm with a hand and two
sliding fingers (URDF, no actuators), its gripper, pads, drives, task space and table
layout all derived, solved by the scripted solver of ``examples/scripted_pick.py``."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.envs.tasks.layout import SPAWN_HALF_SIZE, UPRIGHT_AHEAD, table_top_layout
from tests.test_derived_task_space import JOINTS, arm_urdf
from tests.test_scripted_solvers import load_solver

#: The fingers: stroke (m) and effort limit (N) each, written in the file.
STROKE, FINGER_EFFORT = 0.04, 20.0


def _link(name: str, mass: float, com: str, box: str, inertia: float) -> str:
    return (
        f'<link name="{name}"><inertial><origin xyz="{com}"/><mass value="{mass}"/>'
        f'<inertia ixx="{inertia}" iyy="{inertia}" izz="{inertia}" ixy="0" ixz="0" iyz="0"/></inertial>'
        f'<collision><origin xyz="{com}"/><geometry><box size="{box}"/></geometry></collision></link>'
    )


def arm_with_gripper_urdf() -> str:
    """``arm_urdf(6)`` (upright at zero: 0.3, 0.3, 0.25 m links, then a short wrist) with
    a 0.4 kg hand on its flange and two 30 g fingers sliding apart across it (0 closed,
    ``STROKE`` open, 4 cm pads, 2 mm apart when closed)."""
    parts = _link("hand", 0.4, "0 0 0.02", "0.04 0.12 0.04", 4e-4)
    parts += (
        '<joint name="hand_mount" type="fixed"><parent link="flange_roll_link"/><child link="hand"/>'
        f'<origin xyz="0 0 {JOINTS[-1][3]}"/></joint>'
    )
    for side, sign in (("left", 1), ("right", -1)):
        parts += _link(f"{side}_finger", 0.03, "0 0 0.03", "0.02 0.01 0.04", 1e-5)
        parts += (
            f'<joint name="{side}_finger_joint" type="prismatic"><parent link="hand"/><child link="{side}_finger"/>'
            f'<origin xyz="0 {sign * 0.006} 0.04"/><axis xyz="0 {sign} 0"/>'
            f'<limit lower="0" upper="{STROKE}" effort="{FINGER_EFFORT}" velocity="0.2"/></joint>'
        )
    return arm_urdf(6).replace("</robot>", parts + "</robot>")


@pytest.fixture
def two_line_arm(tmp_path: Path) -> Iterator[type[ra.Agent]]:
    path = tmp_path / "arm_gripper.urdf"
    path.write_text(arm_with_gripper_urdf())
    cls = type("TwoLineArm", (ra.Agent,), {"uid": "two_line_gripper_arm", "urdf_path": path})
    ra.register_agent(cls, override=True)
    yield cls
    ra.unregister_agent(cls.uid)  # (the solver suites list every registered robot)


def test_an_upright_arm_gets_its_workspace_where_it_grasps_pointing_down(two_line_arm: type[ra.Agent]) -> None:
    """The arm rests upright (every joint at zero); pointing its fingers down it reaches
    at most 0.62 m ahead of its shoulder (probed with IK when the rule was written), so
    the workspace centre comes nearer than ``UPRIGHT_AHEAD`` reach (0.57 m: a third of
    the cubes lay beyond, PickCube 14/20), with every cube drawn within that reach."""
    layout = table_top_layout(two_line_arm)
    ahead = -layout.robot_pose[0]  # the shoulder's axis is the root's vertical; the centre is the origin
    assert ahead < UPRIGHT_AHEAD * layout.reach
    assert ahead + SPAWN_HALF_SIZE * layout.reach < 0.62
    assert ahead > 0.2  # not at the arm's foot


def test_the_two_line_arm_picks_the_cube(two_line_arm: type[ra.Agent]) -> None:
    solver = load_solver()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        successes, _ = solver.success_rate("PickCube-v1", two_line_arm.uid, 20)
    assert successes >= 18, successes
    env = ra.make_env("PickCube-v1", robot_uids=two_line_arm.uid).unwrapped
    try:
        agent = env.agents[0]
        assert [type(p).__name__ for p in agent.parts_by_name.values()] == ["Arm", "Gripper"]
        assert np.all(np.isfinite(agent.qpos))
    finally:
        env.close()
