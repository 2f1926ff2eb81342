"""XLeRobot checked against numbers: forward kinematics of both arms, the head and the
cameras against the URDF's joint origins chained independently, limits, masses and
servo data, ManiSkill's mode table and action layouts, ``rest`` held in the single- and
dual-arm modes, and each arm's jaw grasping, lifting and holding a cube."""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.controllers.passive import PassiveConfig
from robot_agents.kinematics import IKConfig, IKSolver
from robot_agents.kinematics.rotations import quat_rotate
from tests.chain_check import assert_camera_on_frame, assert_pan_turns_the_view

UID = "xlerobot"
BASE = ("root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint")
HEAD = ("head_pan_joint", "head_tilt_joint")
KINDS = ("Rotation", "Pitch", "Elbow", "Wrist_Pitch", "Wrist_Roll")
SUFFIXES = ("", "_2")

#: A URDF joint: origin xyz (m) and rpy (rad) in the parent link, axis (zero for fixed).
UrdfJoint = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
FIXED = (0.0, 0.0, 0.0)
# Vector-Wangel/ManiSkill-XLeRobot xlerobot.urdf (commit 70751bb): base_link to each arm's
# jaws, the tip frames and the arm camera; top_base_link and the head.
ARM_MOUNT = {"": ((-0.135, -0.133, 0.760), (0.0, 0.0, 1.5708)), "_2": ((-0.135, 0.133, 0.760), (0.0, 0.0, 1.5708))}
ARM_CHAIN: list[UrdfJoint] = [
    ((0.0, -0.0452, 0.0165), (1.5708, 0.0, 0.0), (0.0, -1.0, 0.0)),  # Rotation
    ((0.0, 0.1025, 0.0306), (1.5708, 0.0, 0.0), (-1.0, 0.0, 0.0)),  # Pitch
    ((0.0, 0.11257, 0.028), (-1.5708, 0.0, 0.0), (1.0, 0.0, 0.0)),  # Elbow
    ((0.0, 0.0052, 0.1349), (-1.5708, 0.0, 0.0), (1.0, 0.0, 0.0)),  # Wrist_Pitch
    ((0.0, -0.0601, 0.0), (0.0, 1.5708, 0.0), (0.0, -1.0, 0.0)),  # Wrist_Roll -> Fixed_Jaw
]
JAW: UrdfJoint = ((-0.0202, -0.0244, 0.0), (3.1416, 0.0, 3.33), (0.0, 0.0, 1.0))
FIXED_TIP = (0.01, -0.097, 0.0)
MOVING_TIP = (-0.01, -0.073, 0.0)
ARM_CAMERA = ((0.0, -0.02, 0.05), (1.5708, 0.0, -1.5708))
HEAD_CHAIN: list[UrdfJoint] = [
    ((0.0, 0.0, 0.73), FIXED, FIXED),  # top_base_joint
    ((-0.178, 0.0, 0.0), FIXED, (0.0, 0.0, 1.0)),  # head_pan_joint
    ((0.031, 0.0, 0.43815), FIXED, (0.0, 1.0, 0.0)),  # head_tilt_joint
    ((0.055, 0.0, 0.0225), FIXED, FIXED),  # head_camera_joint
]


def rotation(axis: Sequence[float], angle: float) -> np.ndarray:
    """Rotation ``(3, 3)`` of ``angle`` (rad) about the unit ``axis`` (Rodrigues)."""
    x, y, z = axis
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF rpy: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    return rotation((0, 0, 1), yaw) @ rotation((0, 1, 0), pitch) @ rotation((1, 0, 0), roll)


def frame(xyz: Sequence[float], angles: Sequence[float] = FIXED) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rpy(*angles), xyz
    return pose


def joint(spec: UrdfJoint, q: float) -> np.ndarray:
    xyz, angles, axis = spec
    turn = np.eye(4)
    if any(axis):
        turn[:3, :3] = rotation(axis, q)
    return frame(xyz, angles) @ turn


def base_pose(x: float, y: float, yaw: float) -> np.ndarray:
    """base_link in the world: the planar joints (x, y slides, yaw hinge) from the origin."""
    return frame((x, y, 0.0), (0.0, 0.0, yaw))


def urdf_frames(q: dict[str, float]) -> dict[str, np.ndarray]:
    """World poses (4 x 4) of both arms' jaws, tips and cameras and of head_camera_link,
    from the URDF's numbers alone, at joint angles ``q`` (by name)."""
    base = base_pose(q["root_x_axis_joint"], q["root_y_axis_joint"], q["root_z_rotation_joint"])
    frames = {}
    for s in SUFFIXES:
        pose = base @ frame(*ARM_MOUNT[s])
        for spec, kind in zip(ARM_CHAIN, KINDS, strict=True):
            pose = pose @ joint(spec, q[kind + s])
        frames["Fixed_Jaw" + s] = pose
        frames["Fixed_Jaw_tip" + s] = pose @ frame(FIXED_TIP)
        frames["Moving_Jaw" + s] = pose @ joint(JAW, q["Jaw" + s])
        frames["Moving_Jaw_tip" + s] = frames["Moving_Jaw" + s] @ frame(MOVING_TIP)
        frames[("Right" if s == "" else "Left") + "_Arm_Camera"] = pose @ frame(*ARM_CAMERA)
    pose = base
    for spec, name in zip(HEAD_CHAIN, ("", *HEAD, ""), strict=True):
        pose = pose @ joint(spec, q.get(name, 0.0))
    frames["head_camera_link"] = pose
    return frames


def random_configurations(agent: ra.Agent, count: int, seed: int) -> np.ndarray:
    """``(count, nq)`` joint vectors uniform within the limits, the base within 2 m and a turn."""
    limits = agent.qpos_limits.copy()
    limits[[agent.joint_names.index(n) for n in BASE]] = [[-2.0, 2.0], [-2.0, 2.0], [-math.pi, math.pi]]
    return np.random.default_rng(seed).uniform(limits[:, 0], limits[:, 1], (count, agent.nq))


def test_forward_kinematics_match_the_urdf_joint_origins() -> None:
    """20 random configurations: every jaw, tip, arm camera and the head camera link
    within 1e-6 m and 1e-6 of rotation of the URDF chain."""
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    scene.reset()
    for q in random_configurations(agent, 20, seed=0):
        agent.reset(qpos=q)
        expected = urdf_frames(dict(zip(agent.joint_names, q, strict=True)))
        for name, pose in expected.items():
            got = agent.frame_pose(name)[0]
            np.testing.assert_allclose(got[:3], pose[:3, 3], atol=1e-6, err_msg=name)
            matrix = np.zeros(9)
            mujoco.mju_quat2Mat(matrix, got[3:])
            np.testing.assert_allclose(matrix.reshape(3, 3), pose[:3, :3], atol=1e-5, err_msg=name)
    scene.close()


def test_cameras_sit_on_their_links_and_the_head_pans_the_view() -> None:
    """fetch_head on head_camera_link, the arm cameras on Right_Arm_Camera /
    Left_Arm_Camera (chained from the URDF, 1e-6), each looking along its link's x with
    z up; panning the head by 0.8 rad turns the head camera's view by 0.8 rad."""
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    scene.reset()
    cameras = {"fetch_head": "head_camera_link", "fetch_right_arm_camera": "Right_Arm_Camera"}
    cameras["fetch_left_arm_camera"] = "Left_Arm_Camera"
    for q in random_configurations(agent, 5, seed=3):
        agent.reset(qpos=q)
        expected = urdf_frames(dict(zip(agent.joint_names, q, strict=True)))
        for camera, link in cameras.items():
            pose = scene.world.camera_poses(scene.model.camera(agent.prefix + camera).id)[0]
            # the arm cameras' link frames are rotated by the URDF's rpy: compare with 1e-5 of rounding
            assert_camera_on_frame(pose, expected[link])
    camera = scene.model.camera(agent.prefix + "fetch_head").id
    base = [agent.joint_names.index(n) for n in BASE]
    head = [agent.joint_names.index(n) for n in HEAD]
    assert_pan_turns_the_view(scene, camera, base, head)
    sizes = {c.uid: (c.width, c.height, round(math.radians(c.fovy), 6)) for c in type(agent).cameras}
    assert sizes == {
        "fetch_head": (256, 256, 1.6),
        "fetch_right_arm_camera": (128, 128, 1.3),
        "fetch_left_arm_camera": (128, 128, 1.3),
    }
    scene.close()


def test_limits_masses_and_drives() -> None:
    """The URDF's joint ranges and link masses (79.25 kg in all); every arm joint a 12 V
    STS3215 (2.94 N*m, 4.71 rad/s); the head's URDF efforts."""
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    for s in SUFFIXES:
        names = [k + s for k in (*KINDS, "Jaw")]
        np.testing.assert_allclose(
            agent.qpos_limits[[agent.joint_names.index(n) for n in names]],
            [[-2.1, 2.1], [-0.1, 3.45], [-0.2, 3.14159], [-1.8, 1.8], [-3.14159, 3.14159], [0.0, 1.7]],
        )
    np.testing.assert_allclose(
        agent.qpos_limits[[agent.joint_names.index(n) for n in HEAD]], [[-1.57, 1.57], [-0.76, 1.45]]
    )
    model = scene.model
    links = ("Base", "Rotation_Pitch", "Upper_Arm", "Lower_Arm", "Wrist_Pitch_Roll", "Fixed_Jaw", "Moving_Jaw")
    urdf = (0.193184127927598, 0.119226314127197, 0.162409284599177, 0.147967774582291, 0.066132067097723)
    urdf += (0.0929859131176897, 0.0202443794940372)
    for s in SUFFIXES:
        masses = [model.body_mass[model.body(agent.prefix + n + s).id] for n in links]
        np.testing.assert_allclose(masses, urdf, rtol=1e-12)
    for name, mass in (("base_link", 70.1294), ("top_base_link", 4.3542), ("head_pan_link", 2.2556)):
        assert model.body_mass[model.body(agent.prefix + name).id] == pytest.approx(mass, rel=1e-12)
    assert model.body_mass[model.body(agent.prefix + "head_tilt_link").id] == pytest.approx(0.9087, rel=1e-12)
    total = sum(model.body_mass[b] for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix))
    assert total == pytest.approx(79.2522, abs=1e-4)
    drives = {d.joint: d for d in type(agent).check().drives}
    for s in SUFFIXES:
        for kind in (*KINDS, "Jaw"):
            drive = drives[kind + s]
            assert drive.effort_limit == pytest.approx(30 * 0.0980665)
            assert drive.velocity_limit == pytest.approx(45 * 2 * math.pi / 60)
    assert (drives["head_pan_joint"].effort_limit, drives["head_tilt_joint"].effort_limit) == (0.32, 0.68)
    scene.close()


#: ManiSkill 3.0.1's ``Xlerobot`` table (its dict order) and our two end-effector modes.
SINGLE = (
    "pd_joint_delta_pos",
    "pd_joint_pos",
    "pd_joint_target_delta_pos",
    "pd_joint_vel",
    "pd_joint_pos_vel",
    "pd_joint_delta_pos_vel",
    "pd_joint_delta_pos_stiff_body",
)
MODES = (*SINGLE, *(m + "_arm2" for m in SINGLE), "pd_joint_delta_pos_dual_arm", "pd_joint_pos_dual_arm")


def test_maniskill_mode_table_and_action_layouts() -> None:
    """ManiSkill's 16 modes in its order (and pd_ee_delta_pos, pd_ee_target_delta_pos);
    single-arm modes are (arm, gripper, body, base) with the other arm passive; dual-arm
    modes have ManiSkill's two orders; bounds: 0.1 rad deltas, 1 rad/s, base 1 m/s and
    3.14 rad/s, the jaw -0.3 .. 1.7 rad."""
    cls = ra.get_agent(UID)
    assert tuple(cls.modes()) == (*MODES, "pd_ee_delta_pos", "pd_ee_target_delta_pos")
    assert cls.default_mode() == "pd_joint_delta_pos"
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    for mode in cls.modes():
        controller = agent.controller_for(mode)
        widths = {name: s.stop - s.start for name, s in controller.slices.items()}
        base = controller.parts["base"]
        np.testing.assert_allclose([base.raw_low, base.raw_high], [[-1.0, -3.14], [1.0, 3.14]])
        if mode.endswith("dual_arm"):
            order = ["base", "arm1", "arm2", "gripper1", "gripper2", "body"]
            if mode == "pd_joint_pos_dual_arm":
                order = [*order[1:], "base"]
            assert list(widths) == order
            assert controller.parts["arm2"].config.joint_names == tuple(k + "_2" for k in KINDS)
            continue
        second = mode.endswith("_arm2")
        suffix = "_2" if second else ""
        arm = 3 if "_ee_" in mode else 10 if mode.endswith("pos_vel") or mode.endswith("pos_vel_arm2") else 5
        assert widths == {"arm": arm, "gripper": 1, "body": 2, "base": 2, "idle": 0}, mode
        if "_ee_" not in mode:
            assert controller.parts["arm"].config.joint_names == tuple(k + suffix for k in KINDS), mode
        assert controller.parts["gripper"].config.joint_names == ("Jaw" + suffix,)
        jaw = controller.parts["gripper"]
        assert (jaw.raw_low[0], jaw.raw_high[0]) == pytest.approx((-0.3, 1.7))
        idle = controller.parts["idle"].config
        assert isinstance(idle, PassiveConfig)
        other = "" if second else "_2"
        assert idle.joint_names == (*(k + other for k in KINDS), "Jaw" + other)
        if "delta_pos" in mode and "_ee_" not in mode:
            arm_part = controller.parts["arm"]
            np.testing.assert_allclose([arm_part.raw_low, arm_part.raw_high][1][:5], [0.1] * 5)
        if "stiff_body" in mode:
            assert not controller.parts["body"].config.use_delta
    vel = agent.controller_for("pd_joint_vel").parts["arm"]
    np.testing.assert_allclose(vel.raw_high, [1.0] * 5)
    scene.close()


@pytest.mark.parametrize("mode", ["pd_joint_delta_pos", "pd_joint_delta_pos_arm2", "pd_joint_pos_dual_arm"])
def test_rest_is_held(mode: str) -> None:
    """``rest`` under the hold action for 3 s: every joint within 2 mrad of the keyframe
    (the passive arm in the single-arm modes too), the base within 0.1 mm."""
    scene = ra.Scene(UID, control_modes=mode)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    start = agent.qpos[0].copy()
    np.testing.assert_allclose(start[5:], [0.0, 3.14, 3.14, 0.0, 1.57, 0.0] * 2)
    action = hold_action(agent)
    for _ in range(3 * scene.control_freq):
        agent.set_action(action)
        scene.step()
    moved = np.abs(agent.qpos[0] - start)
    assert moved[:3].max() < 1e-4, moved[:3]
    assert moved[3:].max() < 2e-3, dict(zip(agent.joint_names[3:], moved[3:].round(5), strict=True))
    scene.close()


#: The jaw pointing straight down, in ``KINDS`` order: our SO-100 test's pose (0, -0.6,
#: 0.9, 1.2708, 0) in XLeRobot's joint frames (Pitch = pi/2 - shoulder_lift, Elbow =
#: elbow_flex + pi/2, Wrist_Roll = -wrist_roll).
DOWN = (0.0, math.pi / 2 + 0.6, 0.9 + math.pi / 2, 1.2708, 0.0)
#: A 3 cm, 100 g cube; the fixed pad's face 1.45 mm past the TCP along the closing axis.
CUBE_HALF, CUBE_MASS = 0.015, 0.1
FIXED_FACE = 0.0085 - 0.00705
#: How much further out than at ``DOWN`` the cube is (m).
REACH = 0.15


def grasp_poses(scene: ra.Scene, suffix: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arm's joints with the jaw down around a cube (its centre returned too) and
    10 cm higher."""
    agent = scene.agents[0]
    arm = np.array([agent.joint_names.index(k + suffix) for k in KINDS])
    solver = IKSolver(
        agent.kinematics,
        agent.frames.end_effector("tcp" + suffix, "test"),
        agent.qpos_adr[arm],
        agent.dof_adr[arm],
        agent.qpos_limits[arm],
        IKConfig(max_iterations=300),
    )
    q = agent.qpos[0].copy()
    q[arm] = DOWN
    tool = agent.frame_pose("tcp" + suffix, q)[0]
    closing = quat_rotate(tool[3:], np.array([1.0, 0.0, 0.0]))
    # beyond the cart's front (x = 0.16 m): REACH further out
    outward = np.array([REACH, 0.0, 0.0])
    cube = tool[:3] + outward + (FIXED_FACE - CUBE_HALF - 0.001) * closing
    target = tool.copy()
    target[:3] += outward
    context = scene.world.qpos.copy()
    grasp = solver.solve(context, target[None], np.array(DOWN)[None])
    lifted = target + np.array([0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0])
    lift = solver.solve(context, lifted[None], grasp.qpos, position_only=True)
    assert grasp.success.all() and lift.success.all()
    return grasp.qpos[0], lift.qpos[0], cube


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_each_jaw_grasps_lifts_and_holds_a_cube(suffix: str) -> None:
    """Each arm's jaw (pd_joint_pos, pd_joint_pos_arm2) closes on a 3 cm, 100 g cube on a
    pedestal, lifts it 10 cm and holds it 2 s: ``is_grasping`` throughout, both fingers
    squeeze (> 2 N) and carry its weight (within 0.02 N), false again once opened."""
    probe = ra.Scene(UID)
    probe.reset(keyframes="rest")
    grasp, lift, cube = grasp_poses(probe, suffix)
    probe.close()
    top = float(cube[2] - CUBE_HALF)
    props = [
        ra.Prop("pedestal", "box", (0.01, 0.01, top / 2), pos=(float(cube[0]), float(cube[1]), top / 2), mass=None),
        ra.Prop(
            "cube", "box", (CUBE_HALF,) * 3, pos=(float(cube[0]), float(cube[1]), float(cube[2]) + 1e-4), mass=CUBE_MASS
        ),
    ]
    mode = "pd_joint_pos" + ("_arm2" if suffix else "")
    scene = ra.Scene(UID, props=props, control_modes=mode)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    arm = [agent.joint_names.index(k + suffix) for k in KINDS]
    q = agent.qpos[0].copy()
    q[arm] = grasp
    q[agent.joint_names.index("Jaw" + suffix)] = 1.7
    agent.reset(qpos=q)
    head = agent.qpos[0, 3:5].copy()

    def run(target: np.ndarray, jaw: float, steps: int) -> None:
        for _ in range(steps):
            agent.set_action(np.concatenate([target, [jaw], [0.0, 0.0], [0.0, 0.0]]))
            scene.step()

    run(grasp, 1.0, 10)
    assert not agent.is_grasping("cube", gripper="gripper" + suffix)[0]
    run(grasp, -1.0, 20)
    assert agent.is_grasping("cube", gripper="gripper" + suffix)[0]
    start = scene.body_pose("cube")[0, 2]
    for i in range(20):
        run(grasp + (i + 1) / 20 * (lift - grasp), -1.0, 1)
    held = []
    for _ in range(2 * scene.control_freq):
        run(lift, -1.0, 1)
        held.append(bool(agent.is_grasping("cube", gripper="gripper" + suffix)[0]))
    assert all(held)
    assert scene.body_pose("cube")[0, 2] - start > 0.085

    def body(name: str) -> int:
        return int(mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_BODY, name))

    gripper = agent.parts_by_name["gripper" + suffix]
    assert isinstance(gripper, ra.Gripper)
    fingers = [[body(agent.prefix + link) for link in finger] for finger in gripper.finger_links]
    forces = scene.world.contact_forces(fingers, body("cube"))[0]
    np.testing.assert_allclose(forces.sum(axis=0), [0.0, 0.0, CUBE_MASS * 9.81], atol=0.02)
    assert np.all(np.linalg.norm(forces, axis=1) > 2.0)
    np.testing.assert_allclose(agent.qpos[0, 3:5], head, atol=2e-3)  # the head held by zero deltas
    run(lift, 1.0, 10)
    assert not agent.is_grasping("cube", gripper="gripper" + suffix)[0]
    scene.close()


def test_scene_takes_the_smallest_solver_tolerance() -> None:
    """The XLeRobot declares a solver tolerance (its jaw's grasp at 160 Hz needs it: see
    ``Xlerobot.sim_freq``); a scene takes the smallest declared, MuJoCo's 1e-8 without
    one, and a bad declaration says what it expected."""
    Xlerobot = ra.get_agent(UID)
    assert Xlerobot.solver_tolerance == 1e-11 and Xlerobot.sim_freq == 160
    assert ra.Scene(UID).model.opt.tolerance == 1e-11
    assert ra.Scene("so100").model.opt.tolerance == 1e-8
    assert ra.Scene(["so100", UID]).model.opt.tolerance == 1e-11
    looser = type("LooserXlerobot", (Xlerobot,), {"uid": "", "solver_tolerance": 1e-9})
    assert ra.Scene([looser, UID]).model.opt.tolerance == 1e-11
    for bad in (0.0, 1.0, -1e-9, True, "1e-9", float("nan")):
        with pytest.raises(ra.ConfigError, match="solver_tolerance: expected a number in"):
            type("BadXlerobot", (Xlerobot,), {"uid": "", "solver_tolerance": bad}).validate_definition()


def test_table_top_cubes_lie_beyond_the_arms_reach() -> None:
    """Why the robot declares PickCube-v1, PushCube-v1 and MobilePickCube-v1 out of reach
    (``task_limits``): the table-top layout's near edge clears the cart's turning circle
    (0.30 m) 0.31 m ahead of base_link and its cubes lie about 0.40 m ahead, at 0.80 m;
    there, each arm's tool reaches 0.175 m ahead pointing down (IK succeeds at 0.17 m and
    fails at 0.18 m and at the table's edge) and 0.34 m in any orientation."""
    from robot_agents.envs.tasks.layout import table_top_layout

    cls = ra.get_agent(UID)
    layout = table_top_layout(cls)
    near_edge = layout.table_center[0] - layout.table_half_size[0] - layout.robot_pose[0]
    assert layout.turning_radius == pytest.approx(0.3016, abs=1e-3)
    assert near_edge == pytest.approx(0.312, abs=0.002)
    assert -layout.robot_pose[0] == pytest.approx(0.396, abs=0.002)  # the workspace centre, ahead of base_link
    height = layout.table_height + layout.cube_half_size
    assert height == pytest.approx(0.80, abs=0.001)
    assert set(cls.task_limits) == {"PickCube-v1", "PushCube-v1", "MobilePickCube-v1"}
    scene = ra.Scene(UID)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    context = scene.world.qpos.copy()
    for suffix in SUFFIXES:
        arm = np.array([agent.joint_names.index(k + suffix) for k in KINDS])
        solver = IKSolver(
            agent.kinematics,
            agent.frames.end_effector("tcp" + suffix, "test"),
            agent.qpos_adr[arm],
            agent.dof_adr[arm],
            agent.qpos_limits[arm],
            IKConfig(max_iterations=300),
        )
        q = agent.qpos[0].copy()
        q[arm] = DOWN
        down = agent.frame_pose("tcp" + suffix, q)[0]

        def reaches(solver: IKSolver, down: np.ndarray, x: float, position_only: bool = False) -> bool:
            """Whether the tool gets to ``x`` ahead of base_link at the cubes' height,
            pointing down as at ``DOWN`` (or in any orientation)."""
            target = down.copy()
            target[[0, 2]] = x, height
            result = solver.solve(context, target[None], np.array(DOWN)[None], position_only=position_only, restarts=20)
            return bool(result.success[0])

        assert reaches(solver, down, 0.17) and not reaches(solver, down, 0.18)
        assert not reaches(solver, down, near_edge)
        assert reaches(solver, down, 0.34, position_only=True) and not reaches(solver, down, 0.35, position_only=True)
    scene.close()
