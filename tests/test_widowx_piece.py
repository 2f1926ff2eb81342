"""The WidowX 250 S gripper as a piece (``ra.get_piece("widowx250s_gripper")``) checked
against numbers: the same assembly as on the built-in arm (masses, TCP offset), turned
so that its z axis points out of the flange, the 30-74 mm opening of Trossen's
specification across the action's range, and, mounted on a UR10e's flange and on the
arm file of docs/defining-a-robot.md, the composed robot's parts and keyframes, the
library's physics checks, and a cube grasped, lifted and held."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import run_checks
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.robot_source import robot_from_file
from robot_agents.robots.universal_robots.ur10e import FLANGE, UR10e, with_tool
from robot_agents.robots.widowx.widowx250s import FINGER_EFFORT, WidowX250SGripperPiece
from tests.grasp_check import assert_grasps_lifts_and_holds

#: Trossen's specification: 30 .. 74 mm between the pads (fingers 0.015 .. 0.037 m each).
OPENING = (0.030, 0.074)
#: Interbotix wx250s.urdf.xacro: gripper_link -> ee_arm_link 0.043 m, -> fingers_link
#: 0.023 m, -> ee_gripper_link 0.027575 m, all along the link's x.
TCP_OUT = 0.043 + 0.023 + 0.027575
#: The same file's masses (kg): gripper_link (servo and bracket), the horn, the bar, two fingers.
MASS = 0.072885 + 0.00434 + 0.034199 + 2 * 0.016246
#: The bodies of the gripper assembly, on the WidowX below its wrist_rotate joint.
ASSEMBLY = (
    "gripper_link",
    "ee_arm_link",
    "gripper_prop_link",
    "gripper_bar_link",
    "fingers_link",
    "left_finger_link",
    "right_finger_link",
    "ee_gripper_link",
)
PAD_HALF_THICKNESS = 0.003  # wx250s_gripper.xml: each pad's inner face on its finger's origin plane
CUBE_MASS, CUBE_HALF = 0.1, 0.02
PAD_BEYOND_TCP = 0.0024  # the pads' centre (0.03 m past fingers_link) past ee_gripper_link, m


class UR10eWidowXGripper(UR10e):
    """A UR10e with the WidowX 250 S gripper on its flange (``tool0``, z out of it)."""

    uid = ""
    attachments = (ra.Attachment(ra.get_piece("widowx250s_gripper"), at=FLANGE, prefix="wx/"),)
    parts = with_tool("wx/ee_gripper_link")
    keyframes = {
        "rest": UR10e.keyframes["rest"],
        "closed_rest": ra.Keyframe(qpos={**UR10e.keyframes["rest"].qpos, "wx/left_finger": 0.015}),
    }


def rotation(quat: np.ndarray) -> np.ndarray:
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, np.asarray(quat, dtype=np.float64))
    return out.reshape(3, 3)


def pad_gap(scene: ra.Scene, prefix: str) -> float:
    """The distance (m) between the pads' inner faces, along the fingers' sliding axis."""
    model, data = scene.model, scene.world.physics_sources([0])[0]
    left, right = (model.geom(f"{prefix}{side}_finger_pad").id for side in ("left", "right"))
    axis = data.xmat[model.body(f"{prefix}fingers_link").id].reshape(3, 3)[:, 1]
    return float((data.geom_xpos[left] - data.geom_xpos[right]) @ axis) - 2 * PAD_HALF_THICKNESS


def test_the_piece_is_the_arms_gripper_turned_z_out_of_its_mount() -> None:
    """Alone: its z axis out of the mount carries the WidowX's x (the TCP 0.093575 m
    out, on the axis), the fingers slide along the mount's y; its bodies weigh what the
    WidowX's gripper assembly weighs and sit as there, relative to gripper_link."""
    assert ra.get_piece("widowx250s_gripper") is WidowX250SGripperPiece
    with pytest.raises(ra.UnknownNameError, match=r"get_piece.*'widowx_gripper'.*Did you mean 'widowx250s_gripper'"):
        ra.get_piece("widowx_gripper")
    checked = WidowX250SGripperPiece.check()
    assert list(checked.keyframes) == ["open", "closed"]
    assert checked.part_joints == {"gripper": ("left_finger", "right_finger")}
    assert [d.joint for d in checked.drives] == ["left_finger", "right_finger"]
    scene = ra.Scene(WidowX250SGripperPiece)
    agent = scene.agents[0]
    scene.reset()
    tcp = agent.frame_pose("ee_gripper_link", relative_to="gripper_mount")[0]
    np.testing.assert_allclose(tcp[:3], [0.0, 0.0, TCP_OUT], atol=1e-12)
    turned = rotation(tcp[3:])
    np.testing.assert_allclose(turned[:, 0], [0.0, 0.0, 1.0], atol=1e-12)  # the WidowX's x: out of the mount
    np.testing.assert_allclose(turned[:, 1], [0.0, 1.0, 0.0], atol=1e-12)  # the fingers' axis
    for keyframe, gap in (("open", OPENING[1]), ("closed", OPENING[0])):
        scene.reset(keyframes=keyframe)  # (``closed`` names the left finger: the right mirrors it)
        assert pad_gap(scene, agent.prefix) == pytest.approx(gap, abs=1e-9)
        assert scene.world.datas[0].ncon == 0
    scene.reset()  # open, as the arm's default
    model = scene.model
    own = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    assert sum(model.body_mass[b] for b in own) == pytest.approx(MASS, abs=1e-9)
    assert model.body_mass[model.body(f"{agent.prefix}gripper_mount").id] == 0.0
    scene.close()

    arm = ra.Scene("widowx250s")
    arm.reset()
    widowx = arm.agents[0]
    ids = [arm.model.body(widowx.prefix + name).id for name in ASSEMBLY]
    assert sum(arm.model.body_mass[b] for b in ids) == pytest.approx(MASS, abs=1e-9)
    for name in ASSEMBLY[1:]:
        on_arm = widowx.frame_pose(name, relative_to="gripper_link")[0]
        in_piece = agent.frame_pose(name, relative_to="gripper_link")[0]
        np.testing.assert_allclose(on_arm, in_piece, atol=1e-12, err_msg=name)
    arm.close()


def test_on_a_ur10e_flange_the_action_spans_the_30_to_74_mm_opening() -> None:
    """Mounted on tool0: the composed robot's parts and keyframes (the piece's default
    opens it, ``closed`` closes it), the TCP 0.093575 m out of the flange, and the
    gripper's one action taking the pads from 74 mm apart (+1) down to the 30 mm stop
    (-1 asks 2 mm past it per finger: the squeeze), linearly in between."""
    scene = ra.Scene(UR10eWidowXGripper, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert agent.joint_names[6:] == ("wx/left_finger", "wx/right_finger")
    assert set(agent.part_joints) == {"arm", "wx_gripper"}
    assert agent.controller.slices == {"arm": slice(0, 6), "wx_gripper": slice(6, 7)}
    data = scene.world.physics_sources([0])[0]
    flange = scene.model.body(agent.prefix + FLANGE).id
    for keyframe, gap in (("rest", OPENING[1]), ("closed_rest", OPENING[0])):
        scene.reset(keyframes=keyframe)
        assert pad_gap(scene, agent.prefix + "wx/") == pytest.approx(gap, abs=1e-9)
        assert scene.world.datas[0].ncon == 0
        out = data.xmat[flange].reshape(3, 3)[:, 2]
        np.testing.assert_allclose(agent.tcp_pose[0, :3], data.xpos[flange] + TCP_OUT * out, atol=1e-9)
    scene.reset(keyframes="rest")
    arm = agent.qpos[0, :6].copy()
    for action in (1.0, 0.5, 0.0, -0.5, -1.0, 1.0):
        for _ in range(10):
            agent.set_action(np.r_[arm, action])
            scene.step()
        # the action maps [-1, 1] onto 0.013 .. 0.037 m per finger; the stop holds at 0.015
        target = max(0.015, 0.013 + (action + 1.0) / 2.0 * 0.024)
        assert pad_gap(scene, agent.prefix + "wx/") == pytest.approx(2 * target, abs=5e-4), action
    scene.close()


def pedestal_and_cube(tool: tuple[float, float, float]) -> list[ra.Prop]:
    """A 4 cm, 100 g cube on a 24 mm square pedestal, placed where the pads close on its
    centre with the TCP at ``tool`` (m, pointing down)."""
    cube_z = tool[2] - PAD_BEYOND_TCP
    return [
        ra.Prop(
            name="pedestal",
            shape="box",
            size=(0.012, 0.012, (cube_z - CUBE_HALF) / 2),
            pos=(tool[0], tool[1], (cube_z - CUBE_HALF) / 2),
            mass=None,
        ),
        ra.Prop(name="cube", shape="box", size=(CUBE_HALF,) * 3, pos=(tool[0], tool[1], cube_z + 1e-4), mass=CUBE_MASS),
    ]


def solver(scene: ra.Scene) -> IKSolver:
    agent = scene.agents[0]
    arm = np.arange(6)
    frame = resolve_frame(scene.model, "wx/ee_gripper_link", agent.prefix)
    return IKSolver(agent.kinematics, frame, agent.qpos_adr[arm], agent.dof_adr[arm], agent.qpos_limits[arm])


def test_on_a_ur10e_flange_it_grasps_lifts_and_holds_a_cube() -> None:
    """A 4 cm, 100 g cube on a pedestal under the TCP at the rest keyframe's tool
    orientation (pointing down): squeezed with the gripper servo's force through its
    horn (1.5 N*m / (2 * 0.014 m) = 53.6 N per finger), lifted 10 cm over 1 s and held
    2 s with the pads carrying its weight (tests/grasp_check.py), let go once open."""
    scene = ra.Scene(UR10eWidowXGripper, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    rest = agent.tcp_pose[0].copy()
    tool = (rest[0], rest[1], 0.06)
    scene.close()
    props = pedestal_and_cube(tool)
    scene = ra.Scene(UR10eWidowXGripper, props=props, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    scene.reset(keyframes="rest")
    ik = solver(scene)

    def arm_at(z: float, seed: np.ndarray) -> np.ndarray:
        target = np.r_[tool[0], tool[1], z, rest[3:]][None]
        result = ik.solve(scene.world.qpos, target, seed[None], max_iterations=200, restarts=10)
        assert result.success[0], (result.position_error, result.rotation_error)
        return result.qpos[0]

    grasp = arm_at(tool[2], agent.qpos[0, :6])
    lift = arm_at(tool[2] + 0.1, grasp)
    qpos = agent.qpos[0].copy()
    qpos[:6] = grasp
    agent.reset(qpos=qpos)  # the open fingers around the cube

    def act(arm: np.ndarray, gripper: float) -> None:
        agent.set_action(np.r_[arm, gripper])
        scene.step()

    fingers = [[f"{agent.prefix}wx/{side}_finger_link"] for side in ("left", "right")]
    ids = [[scene.model.body(name).id for name in finger] for finger in fingers]

    def squeezes_with_the_servos_force() -> None:
        # the target 2 mm past the stop is 7 mm inside the cube: the drive saturates
        left, right = scene.world.contact_forces(ids, scene.model.body("cube").id)[0]
        opening = rotation(agent.tcp_pose[0, 3:])[:, 1]  # the left finger opens along the TCP's +y
        assert left @ opening == pytest.approx(-FINGER_EFFORT, rel=0.01)  # (the force on the cube)
        assert right @ opening == pytest.approx(FINGER_EFFORT, rel=0.01)

    assert_grasps_lifts_and_holds(
        scene, act, grasp, lift, fingers, CUBE_MASS, 0.9 * FINGER_EFFORT, squeezes_with_the_servos_force
    )
    scene.close()


def test_on_an_arm_file_it_is_the_three_line_robot() -> None:
    """``robot_from_file("examples/my_arm.urdf", gripper="widowx250s_gripper",
    at="flange")`` (the command line's ``--gripper widowx250s_gripper --at flange``):
    the arm inferred from the file ends at the piece's TCP, the piece's gripper beside
    it, its default keyframe open, and the library's physics checks pass."""
    cls = robot_from_file("examples/my_arm.urdf", gripper="widowx250s_gripper", at="flange")
    checked = cls.check()
    assert checked.part_joints["widowx250s_gripper_gripper"] == (
        "widowx250s_gripper/left_finger",
        "widowx250s_gripper/right_finger",
    )
    arm = next(p for p in checked.parts if isinstance(p, ra.Arm))
    assert [ee.link for ee in arm.end_effectors] == ["widowx250s_gripper/ee_gripper_link"]
    np.testing.assert_allclose(checked.keyframes["default"].qpos[-2:], [0.037, -0.037])
    results = run_checks(cls, random_seconds=2.0)
    assert all(r.passed for r in results), [r.line() for r in results if not r.passed]
    # the file's flange points up with every joint at zero: the TCP is 0.093575 m above it
    scene = ra.Scene(cls)
    scene.reset()
    agent = scene.agents[0]
    tcp = agent.frame_pose("widowx250s_gripper/ee_gripper_link", relative_to="flange")[0]
    np.testing.assert_allclose(tcp[:3], [0.0, 0.0, TCP_OUT], atol=1e-9)
    assert math.isclose(float(rotation(tcp[3:])[2, 0]), 1.0, abs_tol=1e-9)
    scene.close()
