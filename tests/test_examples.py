"""The README's examples run as written."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np

import robot_agents as ra
from robot_agents.checks import run_checks

ROOT = Path(__file__).resolve().parents[1]


def test_define_robot_example_runs() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "define_robot.py")], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("qpos [")


def test_ee_square_example_traces_the_square() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "ee_square.py")], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 4 and all(line.endswith("IK solved every step: True") for line in lines)
    moved = [np.array(re.findall(r"[-+]\d+\.\d+", line.split("moved")[1])[:3], dtype=float) for line in lines]
    expected = [(100, 0, 0), (0, 100, 0), (-100, 0, 0), (0, -100, 0)]
    np.testing.assert_allclose(moved, expected, atol=2.0)  # mm


def test_readme_python_blocks_run() -> None:
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert len(blocks) >= 4
    namespace: dict[str, object] = {}
    exec(compile(blocks[0], "README block 1", "exec"), namespace)
    assert namespace["obs"].shape == (4, 34)  # type: ignore[attr-defined]
    two_lines: dict[str, object] = {}
    exec(compile(blocks[1], "README block 2", "exec"), two_lines)  # a class only: nothing is loaded
    assert two_lines["MyArm"].urdf_path == "path/to/my_arm.urdf"  # type: ignore[attr-defined]
    robot = next(b for b in blocks if "class TwoLinkArm" in b)
    try:
        exec(compile(robot.replace('Path("examples/', f'Path("{ROOT}/examples/'), "README robot block", "exec"), {})
        scene = ra.Scene("two_link_arm", control_modes="pd_joint_pos")
        scene.reset(keyframes="home")
        np.testing.assert_allclose(scene.agents[0].qpos[0], [0.0, 0.5])
    finally:
        ra.unregister_agent("two_link_arm")
    ee: dict[str, object] = {"ra": ra}
    exec(compile(next(b for b in blocks if "pd_ee" in b and "frame_jacobian" in b), "README EE block", "exec"), ee)
    assert ee["info"]["ik_success"].shape == (4,)  # type: ignore[index]
    assert ee["agent"].frame_jacobian("panda_hand_tcp").shape == (4, 6, 9)  # type: ignore[attr-defined]


def test_compose_arm_gripper_example_runs_the_tasks() -> None:
    """The composed arm (a six-joint URDF without actuators plus the Robotiq 2F-85) gets
    the end-effector modes and runs every task; ReachPose-v1 20/20 measured, here 3/3."""
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "compose_arm_gripper.py"), "--seeds", "3"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert lines[0].startswith("six_joint_arm_2f85: end-effector modes pd_ee_delta_pos, pd_ee_delta_pose")
    assert [line.split(":")[0] for line in lines[1:]] == ["PickCube-v1", "PushCube-v1", "ReachPose-v1"]
    assert lines[3].startswith("ReachPose-v1: 3/3"), lines


def test_docs_python_blocks_run() -> None:
    """Every Python block of ``docs/*.md`` runs as written (``ra`` and ``np`` imported,
    as the docs assume), but those that load the reader's own model file (a name like
    ``my_arm.urdf`` that is not in this repository): the docs' API calls are current."""
    ran, registered = 0, set(ra.list_agents())
    for page in sorted((ROOT / "docs").glob("*.md")):
        for k, block in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)):
            files = re.findall(r"[\"']([\w./-]+\.(?:urdf|xml))[\"']", block)
            if any(not (ROOT / name).exists() for name in files):
                continue  # the reader's own file
            namespace: dict[str, object] = {"ra": ra, "np": np}
            block = block.replace('Path("examples/', f'Path("{ROOT}/examples/')  # written for the repository's root
            try:
                exec(compile(block, f"{page.name} block {k + 1}", "exec"), namespace)
            finally:
                for uid in set(ra.list_agents()) - registered:
                    ra.unregister_agent(uid)  # a block's robot class leaves the registry as found
            ran += 1
    assert ran >= 12


def test_worked_example_passes_the_physics_checks() -> None:
    """defining-a-robot.md's worked example (examples/my_arm.urdf with the hand of
    examples/two_finger_hand.xml) is a sound robot: every check ``robot-agents check``
    runs passes, its end effector is where the page says, and the hand grips: the
    closing fingers stop on a cube between the pads and ``is_grasping`` reports it."""
    page = (ROOT / "docs" / "defining-a-robot.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", page, flags=re.S) if "class MyArm" in b)
    namespace: dict[str, object] = {}
    try:
        exec(compile(block.replace('Path("examples/', f'Path("{ROOT}/examples/'), "worked example", "exec"), namespace)
        results = run_checks(namespace["MyArm"])  # type: ignore[arg-type]
        assert [r.name for r in results if not r.passed] == [], results
        assert "11/11 modes stable" in next(r.detail for r in results if r.name.startswith("5 s of random"))
        agent = namespace["env"].unwrapped.agent  # type: ignore[attr-defined]
        np.testing.assert_allclose(agent.tcp_pose[0, :3], (0.57, 0.0, 0.22), atol=0.01)
        # a 4 cm cube turned 45 deg about z: its faces square to the pads (the hand is turned -45 deg)
        cube = ra.Prop(
            "cube", "box", (0.02,) * 3, pos=(0.572, 0.0, 0.0201), quat=(0.9238795, 0, 0, 0.3826834), mass=0.1
        )
        scene = ra.Scene("my_arm", props=[cube], control_modes="pd_ee_delta_pos")
        scene.reset(keyframes="home")
        arm = scene.agents[0]

        def move(dz: float, gripper: float, steps: int) -> None:  # dz: m per control step
            for _ in range(steps):
                arm.set_action(np.array([0.0, 0.0, dz / 0.1, gripper]))  # 0.1 m: the action's bound
                scene.step()

        # down, open, to the tool point 3.5 cm up (the pads reach 3 cm below it: they clear the floor)
        move((0.035 - arm.tcp_pose[0, 2]) / 8, 1.0, 8)
        move(0.0, 1.0, 10)
        assert abs(arm.tcp_pose[0, 2] - 0.035) < 0.003 and not arm.is_grasping("cube")[0]
        move(0.0, -1.0, 10)  # close
        assert arm.is_grasping("cube")[0]
        offset = arm.tcp_pose[0, 2] - scene.body_pose("cube")[0, 2]
        move(0.01, -1.0, 10)  # lift 10 cm
        move(0.0, -1.0, 20)  # hold 1 s
        assert arm.is_grasping("cube")[0] and scene.body_pose("cube")[0, 2] > 0.11
        assert abs(arm.tcp_pose[0, 2] - scene.body_pose("cube")[0, 2] - offset) < 0.002  # slipped < 2 mm
        move(0.0, 1.0, 10)  # open: let go
        assert not arm.is_grasping("cube")[0]
        scene.close()
    finally:
        ra.unregister_agent("my_arm")
