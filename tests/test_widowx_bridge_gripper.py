"""The Bridge setups' WidowX 250 S gripper on another arm: not a piece of its own but
``ra.get_piece("widowx250s_gripper")`` with the setups' tuned finger drive declared on
a subclass (ManiSkill's Bridge robot is its plain WidowX 250 S, same model file, with
other gains). Checked against numbers: the subclass compiles to the piece's model with
only the finger actuators' gains and force range changed, to those of the Bridge
robots' fingers; mounted on a UR10e's flange and on ``examples/my_arm.urdf`` it grasps,
lifts and holds a cube, squeezing with the tuned drive's spring (1000 N/m times the
target's depth in the cube: 7 N per finger, where the servo's drive saturates at
53.6 N)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.robots.universal_robots.ur10e import FLANGE, UR10e, with_tool
from robot_agents.robots.widowx.widowx250s import (
    BRIDGE_FINGER_DRIVES,
    FINGER_EFFORT,
    WX250S_FINGER_DRIVES,
    WidowX250SGripperPiece,
)
from tests.grasp_check import assert_grasps_lifts_and_holds
from tests.test_widowx_piece import ASSEMBLY, CUBE_HALF, CUBE_MASS, TCP_OUT, pedestal_and_cube, rotation

MY_ARM = Path(__file__).parents[1] / "examples" / "my_arm.urdf"
#: ManiSkill 3.0.1, bridge_dataset_eval/base_env.py: gripper_stiffness, _damping, _force_limit.
BRIDGE_KP, BRIDGE_KV, BRIDGE_FORCE = 1000.0, 200.0, 60.0
#: The gripper action's -1: 2 mm past the 15 mm stop per finger (WX250S_GRIPPER's squeeze).
CLOSED_TARGET = 0.015 - 0.002


class BridgeTunedWidowXGripper(WidowX250SGripperPiece):
    """The WidowX 250 S gripper piece with the Bridge setups' finger drive."""

    actuators = (BRIDGE_FINGER_DRIVES,)


class UR10eBridgeGripper(UR10e):
    """A UR10e with the Bridge-tuned gripper on its flange (``tool0``)."""

    uid = ""
    attachments = (ra.Attachment(BridgeTunedWidowXGripper, at=FLANGE, prefix="wx/"),)
    parts = with_tool("wx/ee_gripper_link")


class MyArmBridgeGripper(ra.Agent):
    """The five-joint arm file of docs/defining-a-robot.md with the Bridge-tuned gripper
    on its flange: the arm, its drives and its task space derived from the file."""

    urdf_path = MY_ARM
    attachments = (ra.Attachment(BridgeTunedWidowXGripper, at="flange", prefix="wx/"),)


def finger_actuators(model: object, prefix: str) -> list[int]:
    return [model.actuator(f"{prefix}{side}_finger").id for side in ("left", "right")]  # type: ignore[attr-defined]


def test_it_is_the_piece_with_the_bridge_robots_finger_drive() -> None:
    """Compiled alone, the subclass differs from the piece only in the finger actuators'
    gains and force range, which are the Bridge robots' (ManiSkill's kp 1000 N/m, kd
    200 N*s/m, 60 N), and in the fingers' own damping (the servo's back-EMF, which the
    piece's drive declares as ``joint_damping`` and the Bridge drive does not); its bodies sit and weigh as the Bridge robot's gripper assembly
    does; the rated speed and the rotor's inertia are the servo's in both."""
    assert BRIDGE_FINGER_DRIVES.velocity_limit == WX250S_FINGER_DRIVES.velocity_limit
    assert BRIDGE_FINGER_DRIVES.armature == WX250S_FINGER_DRIVES.armature
    plain, tuned = ra.Scene(WidowX250SGripperPiece), ra.Scene(BridgeTunedWidowXGripper)
    plain.reset()
    tuned.reset()
    differ = {"actuator_gainprm", "actuator_biasprm", "actuator_forcerange", "dof_damping"}
    compared = 0
    for name in dir(plain.model):
        a, b = getattr(plain.model, name, None), getattr(tuned.model, name, None)
        if name.startswith(("_", "name_", "names")) or not isinstance(a, np.ndarray) or a.dtype == object:
            continue  # (names and their addresses: the robots' ids differ in length)
        compared += 1
        assert np.array_equal(a, b) != (name in differ), name
    assert compared > 100

    bridge = ra.Scene("widowx250s_bridgedataset_flat_table")
    bridge.reset()
    agent = bridge.agents[0]
    ours = finger_actuators(tuned.model, tuned.agents[0].prefix)
    theirs = finger_actuators(bridge.model, agent.prefix)
    for field in differ - {"dof_damping"}:
        np.testing.assert_array_equal(getattr(tuned.model, field)[ours], getattr(bridge.model, field)[theirs])
    fingers = [
        model.joint(f"{prefix}{side}_finger").dofadr[0]
        for side in ("left", "right")
        for model, prefix in ((tuned.model, tuned.agents[0].prefix), (bridge.model, agent.prefix))
    ]
    np.testing.assert_array_equal(tuned.model.dof_damping[fingers[0::2]], bridge.model.dof_damping[fingers[1::2]])
    np.testing.assert_allclose(tuned.model.actuator_gainprm[ours, 0], BRIDGE_KP)
    np.testing.assert_allclose(tuned.model.actuator_biasprm[ours, 1:3], [[-BRIDGE_KP, -BRIDGE_KV]] * 2)
    np.testing.assert_allclose(tuned.model.actuator_forcerange[ours], [[-BRIDGE_FORCE, BRIDGE_FORCE]] * 2)
    piece = tuned.agents[0]
    for body in ASSEMBLY[1:]:
        on_bridge = agent.frame_pose(body, relative_to="gripper_link")[0]
        np.testing.assert_allclose(piece.frame_pose(body, relative_to="gripper_link")[0], on_bridge, atol=1e-12)
        ids = tuned.model.body(piece.prefix + body).id, bridge.model.body(agent.prefix + body).id
        assert tuned.model.body_mass[ids[0]] == bridge.model.body_mass[ids[1]], body
    for scene in (plain, tuned, bridge):
        scene.close()


def grasp_scene(cls: type[ra.Agent], tool: tuple[float, float, float]) -> ra.Scene:
    """``cls`` in ``pd_joint_pos`` with a 4 cm, 100 g cube on a pedestal where the pads
    close on it with the TCP at ``tool`` (m)."""
    return ra.Scene(cls, props=pedestal_and_cube(tool), control_modes="pd_joint_pos")


def squeezes_with_the_tuned_spring(scene: ra.Scene) -> Callable[[], None]:
    """The check once closed: each finger presses the cube with kp times its distance
    from the target 2 mm past the stop (about 7 mm inside the 4 cm cube: 7 N), far below
    both the drive's 60 N and the servo's 53.6 N that the plain piece presses with."""
    agent = scene.agents[0]
    fingers = [[scene.model.body(f"{agent.prefix}wx/{side}_finger_link").id] for side in ("left", "right")]
    joints = [agent.joint_names.index(f"wx/{side}_finger") for side in ("left", "right")]

    def check() -> None:
        left, right = scene.world.contact_forces(fingers, scene.model.body("cube").id)[0]
        opening = rotation(agent.tcp_pose[0, 3:])[:, 1]  # the left finger opens along the TCP's +y
        left_q, right_q = agent.qpos[0, joints]
        assert left_q == pytest.approx(CUBE_HALF, abs=1e-3) and right_q == pytest.approx(-CUBE_HALF, abs=1e-3)
        assert left @ opening == pytest.approx(-BRIDGE_KP * (left_q - CLOSED_TARGET), rel=0.005)
        assert right @ opening == pytest.approx(BRIDGE_KP * (-right_q - CLOSED_TARGET), rel=0.005)
        assert abs(left @ opening) < 0.15 * FINGER_EFFORT

    return check


def grasp_lift_hold(cls: type[ra.Agent], tool: tuple[float, float, float], quat: np.ndarray, seed: np.ndarray) -> None:
    """Solve the arm's joints (from ``seed``) for the TCP at ``tool`` turned by ``quat``
    (``w, x, y, z``, pointing down) and 10 cm above, then the grasp check."""
    scene = grasp_scene(cls, tool)
    agent = scene.agents[0]
    scene.reset()
    arm = np.arange(len(agent.joint_names) - 2)
    frame = resolve_frame(scene.model, "wx/ee_gripper_link", agent.prefix)
    ik = IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], agent.qpos_limits[arm])

    def arm_at(z: float, start: np.ndarray) -> np.ndarray:
        target = np.r_[tool[0], tool[1], z, quat][None]
        result = ik.solve(scene.world.qpos, target, start[None], max_iterations=200, restarts=10)
        assert result.success[0], (result.position_error, result.rotation_error)
        return result.qpos[0]

    grasp = arm_at(tool[2], seed)
    lift = arm_at(tool[2] + 0.1, grasp)
    qpos = agent.qpos[0].copy()
    qpos[arm] = grasp
    agent.reset(qpos=qpos)  # the open fingers around the cube

    def act(target: np.ndarray, gripper: float) -> None:
        agent.set_action(np.r_[target, gripper])
        scene.step()

    fingers = [[f"{agent.prefix}wx/{side}_finger_link"] for side in ("left", "right")]
    check = squeezes_with_the_tuned_spring(scene)
    assert_grasps_lifts_and_holds(scene, act, grasp, lift, fingers, CUBE_MASS, 0.5 * BRIDGE_KP * 0.007, check)
    scene.close()


def test_on_a_ur10e_flange_it_grasps_lifts_and_holds_a_cube() -> None:
    """On tool0: the TCP 0.093575 m out of the flange; the cube below the rest pose's
    tool, grasped, lifted 10 cm, held 2 s, dropped (tests/grasp_check.py)."""
    scene = ra.Scene(UR10eBridgeGripper, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    data = scene.world.physics_sources([0])[0]
    flange = scene.model.body(agent.prefix + FLANGE).id
    out = data.xmat[flange].reshape(3, 3)[:, 2]
    np.testing.assert_allclose(agent.tcp_pose[0, :3], data.xpos[flange] + TCP_OUT * out, atol=1e-9)
    rest, seed = agent.tcp_pose[0].copy(), agent.qpos[0, :6].copy()
    scene.close()
    grasp_lift_hold(UR10eBridgeGripper, (float(rest[0]), float(rest[1]), 0.06), rest[3:], seed)


def test_on_the_arm_file_it_grasps_lifts_and_holds_a_cube() -> None:
    """On examples/my_arm.urdf's flange: the arm inferred from the file ends at the
    piece's TCP, with the tuned drive on the fingers and derived drives on the arm; a
    cube 0.45 m in front of the base, grasped from above, lifted, held, dropped."""
    checked = MyArmBridgeGripper.check()
    arm = next(p for p in checked.parts if isinstance(p, ra.Arm))
    assert [ee.link for ee in arm.end_effectors] == ["wx/ee_gripper_link"]
    assert checked.part_joints["wx_gripper"] == ("wx/left_finger", "wx/right_finger")
    drives = {d.joint: d for d in checked.drives}
    for joint in checked.part_joints["wx_gripper"]:
        assert (drives[joint].stiffness, drives[joint].damping) == (BRIDGE_KP, BRIDGE_KV)
        assert drives[joint].effort_limit == BRIDGE_FORCE
    assert all(drives[j].source.startswith("derived") for j in checked.part_joints[arm.name])
    # the TCP's x (out of the gripper) turned down about y, the fingers along y; reached
    # with the shoulder lift and elbow forward and the wrist pitched down
    down = np.array([np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])
    grasp_lift_hold(MyArmBridgeGripper, (0.45, 0.0, 0.06), down, np.array([0.0, 1.0, 1.2, 0.9, 0.0]))
