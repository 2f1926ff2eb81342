"""Unitree G1 simplified upper body (ManiSkill's ``unitree_g1_simplified_upper_body``):
masses, joint ranges and forward kinematics are the URDF's (its joint origins chained
here), actions follow ManiSkill's order and bounds, the keyframes hold, random actions in
every mode stay stable, and either hand holds a cube against gravity (numbers, not
smoke)."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.robots.unitree.g1 import (
    G1_DRIVES,
    G1_PARTS,
    GRASP_CUBE_CENTRE,
    GRASP_CUBE_EDGE,
    LEFT_CLOSED,
    MANISKILL_JOINTS,
    OPEN,
    RIGHT_ARM_JOINTS,
    STANDING_HEIGHT,
    UnitreeG1UpperBody,
    UnitreeG1UpperBodyRightArm,
)
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform

UID = "unitree_g1_simplified_upper_body"
X, Y, Z = np.eye(3)

# ---------------------------------------------------------------- the URDF's numbers
# ManiSkill 3.0.1 assets/robots/g1_humanoid/g1_simplified_upper_body.urdf, written out
# here (left side; the right side mirrors y), not read from our model.
#: Link masses (kg) of the moving links and the rigid ones.
MASSES = {
    "pelvis": 2.86,
    "torso_link": 6.33959811,
    "head_link": 1.17976522,
    "logo_link": 0.001,
    "hip_pitch_link": 1.299,
    "hip_roll_link": 1.446,
    "hip_yaw_link": 2.052,
    "knee_link": 2.252,
    "ankle_pitch_link": 0.074,
    "ankle_roll_link": 0.391,
    "shoulder_pitch_link": 0.713,
    "shoulder_roll_link": 0.642,
    "shoulder_yaw_link": 0.713,
    "elbow_pitch_link": 0.601,
    "elbow_roll_link": 0.227,
    "palm_link": 0.28126043,
    "zero_link": 0.05098927,
    "one_link": 0.04776204,
    "two_link": 0.01385835,
    "three_link": 0.04884689,
    "four_link": 0.01385835,
    "five_link": 0.04884689,
    "six_link": 0.01385835,
}
CENTRAL = ("pelvis", "torso_link", "head_link", "logo_link")
#: Joint ranges (rad), left side.
LEFT_RANGES = {
    "shoulder_pitch": (-2.9671, 2.7925),
    "shoulder_roll": (-1.5882, 2.2515),
    "shoulder_yaw": (-2.618, 2.618),
    "elbow_pitch": (-0.2268, 3.4208),
    "elbow_roll": (-2.0943, 2.0943),
    "zero": (-0.523598, 0.523598),
    "one": (-1.0, 1.2),
    "two": (0.0, 1.84),
    "three": (-1.84, 0.3),
    "four": (-1.84, 0.0),
    "five": (-1.84, 0.3),
    "six": (-1.84, 0.0),
}
#: Joints mirrored on the right (range negated and swapped): rolls, yaws and the fingers'
#: z-axis joints.
MIRRORED = ("shoulder_roll", "shoulder_yaw", "one", "two", "three", "four", "five", "six")
#: Arm: (origin in the parent, fixed roll about x (URDF rpy), axis), left side.
ARM = (
    ((-0.0025, 0.10396, 0.25928), 0.27925, Y),  # shoulder pitch, on the torso
    ((0.0, 0.052, 0.0), -0.27925, X),  # shoulder roll
    ((-0.00354, 0.0062424, -0.1032), 0.0, Z),  # shoulder yaw
    ((0.0, 0.00189, -0.0855), 0.0, Y),  # elbow pitch
    ((0.1, 0.0, 0.0), 0.0, X),  # elbow roll
)
PALM, TCP = (0.12, 0.0, 0.0), (0.07, -0.035, 0.0)
#: Fingers from the palm: (origin, axis) per joint, left side.
THUMB = (((0.05, 0.0, 0.0), Y), ((-0.02652502957, -0.0188, -0.00005), Z), ((0.0, -0.0431, 0.0), Z))
UPPER = (((0.085, 0.004, 0.02395), Z), ((0.0471, -0.0036, 0.0), Z))
LOWER = (((0.085, 0.004, -0.02395), Z), ((0.0471, -0.0036, 0.0), Z))
ARM_KINDS = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "elbow_roll")


def mirror(vector: tuple[float, float, float], side: float) -> np.ndarray:
    return np.array([vector[0], side * vector[1], vector[2]])


def chain(pose: np.ndarray, joints: tuple, q: np.ndarray, side: float) -> np.ndarray:
    """``pose`` carried through each (origin, axis) joint (y mirrored on the right)."""
    for (origin, axis), angle in zip(joints, q, strict=True):
        pose = pose @ transform(axis_rotation(axis, float(angle)), mirror(origin, side))
    return pose


def arm_chain(torso: np.ndarray, q: np.ndarray, side: float) -> np.ndarray:
    """The palm link's pose (4x4) chained from the torso link and the arm's origins."""
    pose = torso
    for (origin, roll, axis), angle in zip(ARM, q, strict=True):
        fixed = axis_rotation(X, side * roll)
        pose = pose @ transform(fixed @ axis_rotation(axis, float(angle)), mirror(origin, side))
    return pose @ transform(np.eye(3), np.array(PALM))


def body_pose(scene: ra.Scene, name: str) -> np.ndarray:
    body = scene.world.datas[0].body(scene.agents[0].prefix + name)
    return transform(body.xmat.reshape(3, 3), body.xpos.copy())


def joints(side: str, kinds: tuple[str, ...]) -> list[str]:
    return [f"{side}_{kind}_joint" for kind in kinds]


# ---------------------------------------------------------------- data
def test_masses_are_the_urdfs() -> None:
    assert_masses_are_the_urdfs(UID)


def assert_masses_are_the_urdfs(uid: str) -> None:
    """Every body of robot ``uid`` with a URDF mass (:data:`MASSES`, both sides but the
    :data:`CENTRAL` links) weighs it, and they are all the robot weighs: 32.2389 kg
    (the upper body's and the full G1's: the URDFs' links are the same)."""
    scene = ra.Scene(uid)
    model, prefix = scene.model, scene.agents[0].prefix
    total = 0.0
    for name, mass in MASSES.items():
        for side in ("",) if name in CENTRAL else ("left_", "right_"):
            assert model.body(prefix + side + name).mass[0] == pytest.approx(mass, abs=1e-9), side + name
            total += mass
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(prefix)]
    assert float(model.body_mass[robot].sum()) == pytest.approx(total, abs=1e-9)
    assert total == pytest.approx(32.2389, abs=1e-4)
    scene.close()


def test_joint_ranges_and_limits_are_the_urdfs() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    limits = dict(zip(agent.joint_names, agent.qpos_limits, strict=True))
    assert len(limits) == 25
    assert tuple(limits["torso_joint"]) == pytest.approx((-2.618, 2.618))
    for kind, (low, high) in LEFT_RANGES.items():
        assert tuple(limits[f"left_{kind}_joint"]) == pytest.approx((low, high)), kind
        right = (-high, -low) if kind in MIRRORED else (low, high)
        assert tuple(limits[f"right_{kind}_joint"]) == pytest.approx(right), kind
    # the URDF's efforts; kp = effort / ManiSkill's largest delta (torso, arms) or / 0.1 rad
    # (fingers), kv = 0.1 s * kp
    drives = sorted((d.effort_limit, d.velocity_limit, d.stiffness, d.damping) for d in G1_DRIVES)
    expected = [(0.7, 23.0, 7.0, 0.7), (21.0, 53.0, 105.0, 10.5), (88.0, 32.0, 440.0, 44.0)]
    np.testing.assert_allclose(np.array(drives, dtype=np.float64), expected, rtol=1e-12)
    scene.close()


# ---------------------------------------------------------------- kinematics
def test_standing_mounts_the_pelvis_0_755_m_up() -> None:
    scene = ra.Scene(UID)
    scene.reset(keyframes="standing")
    np.testing.assert_allclose(body_pose(scene, "pelvis"), transform(np.eye(3), np.array([0, 0, STANDING_HEIGHT])))
    assert np.all(scene.agents[0].qpos[0] == 0.0)
    scene.close()


def test_arms_and_fingers_follow_the_urdf_joint_origins_at_random_poses() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        at = dict(zip(agent.joint_names, q, strict=True))
        pelvis = transform(np.eye(3), np.array([0.0, 0.0, STANDING_HEIGHT]))
        torso = pelvis @ transform(axis_rotation(Z, at["torso_joint"]), np.zeros(3))
        np.testing.assert_allclose(body_pose(scene, "torso_link"), torso, atol=1e-9)
        for side, s in (("left", 1.0), ("right", -1.0)):
            palm = arm_chain(torso, np.array([at[j] for j in joints(side, ARM_KINDS)]), s)
            np.testing.assert_allclose(body_pose(scene, f"{side}_palm_link"), palm, atol=1e-9)
            tcp = palm @ transform(np.eye(3), mirror(TCP, s))
            np.testing.assert_allclose(agent.frame_pose(f"{side}_tcp")[0, :3], tcp[:3, 3], atol=1e-9)
            for links, kinds in ((THUMB, ("zero", "one", "two")), (UPPER, ("three", "four")), (LOWER, ("five", "six"))):
                tip = chain(palm, links, np.array([at[j] for j in joints(side, kinds)]), s)
                np.testing.assert_allclose(body_pose(scene, f"{side}_{kinds[-1]}_link"), tip, atol=1e-9)
    scene.close()


# ---------------------------------------------------------------- actions
def test_actions_follow_maniskills_joint_order_and_bounds() -> None:
    """One part, ``body``, over ManiSkill's 25 joints in its order: absolute targets within
    the joint limits; deltas of at most 0.2 rad on the torso and arms, 0.5 on the fingers."""
    scene = ra.Scene(UID, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert list(agent.controller.parts) == ["body"]
    assert agent.controller.parts["body"].config.joint_names == MANISKILL_JOINTS
    limits = agent.qpos_limits[[agent.joint_names.index(j) for j in MANISKILL_JOINTS]]
    np.testing.assert_allclose(agent.single_action_space.low, limits[:, 0].astype(np.float32))
    np.testing.assert_allclose(agent.single_action_space.high, limits[:, 1].astype(np.float32))
    scene.close()
    delta = ra.Scene(UID, control_modes="pd_joint_delta_pos")
    controller = delta.agents[0].controller.parts["body"]
    np.testing.assert_allclose(controller.to_raw(np.ones((1, 25)))[0], [0.2] * 11 + [0.5] * 14)
    delta.close()
    assert set(UnitreeG1UpperBody.modes()) >= {"pd_joint_pos", "pd_joint_delta_pos"}
    assert UnitreeG1UpperBody.default_mode() == "pd_joint_delta_pos"  # ManiSkill's first


def test_keyframes_hold_and_random_actions_stay_stable() -> None:
    held = check_holds(ra.get_agent(UID), seconds=2.0)
    assert held.passed, held.detail
    random = check_random_actions(ra.get_agent(UID), seconds=5.0)
    assert random.passed, random.detail


# ---------------------------------------------------------------- grasp
CUBE_MASS = 0.05


def hand_grasp(side: str, closed: tuple[float, ...], mass: float = CUBE_MASS) -> dict[str, float | bool]:
    """The zero pose (forearms forward, palms facing inwards); a cube placed weightless at
    the power grasp's place in front of ``side``'s palm, the hand closed to ``closed`` for
    2 s, then the cube's weight on for 2 s: how far it moved relative to the palm, whether
    ``is_grasping`` held, and the contact forces on it."""
    half = 0.5 * GRASP_CUBE_EDGE
    cube = ra.Prop("cube", "box", (half,) * 3, pos=(0.6, 0.5, half), mass=mass)
    scene = ra.Scene(UID, props=[cube], control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    s = 1.0 if side == "left" else -1.0
    palm = agent.frame_pose(f"{side}_palm_link")[0]
    rotation = quat_to_matrix(palm[3:])
    centre = palm[:3] + rotation @ mirror(GRASP_CUBE_CENTRE, s)
    model, data = scene.model, scene.world.datas[0]
    body = model.body("cube")
    joint = int(body.jntadr[0])
    qpos_adr = np.arange(7) + int(model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(model.jnt_dofadr[joint])
    scene.world.write_joint_state([0], qpos_adr, np.array([[*centre, 1.0, 0.0, 0.0, 0.0]]), dof_adr, np.zeros((1, 6)))
    target = agent.qpos[0].copy()
    for name, value in zip(joints(side, ("zero", "one", "two", "three", "four", "five", "six")), closed, strict=True):
        target[agent.joint_names.index(name)] = value
    action = np.array([target[agent.joint_names.index(j)] for j in MANISKILL_JOINTS])

    def in_palm() -> np.ndarray:
        pose = agent.frame_pose(f"{side}_palm_link")[0]
        return np.asarray(quat_to_matrix(pose[3:]).T @ (scene.body_pose("cube")[0, :3] - pose[:3]))

    weight = mass * 9.81
    data.xfrc_applied[body.id, 2] = weight  # weightless while the fingers close
    for _ in range(2 * scene.control_freq):
        agent.set_action(action)
        scene.step()
    start, moved = in_palm(), 0.0
    data.xfrc_applied[body.id, 2] = 0.0
    for _ in range(2 * scene.control_freq):
        agent.set_action(action)
        scene.step()
        moved = max(moved, float(np.linalg.norm(in_palm() - start)))
    force = np.zeros(3)
    wrench = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        bodies = (int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2]))
        if body.id in bodies:
            mujoco.mj_contactForce(model, data, i, wrench)
            on_cube = contact.frame.reshape(3, 3).T @ wrench[:3]  # on geom2, in world axes
            force += on_cube if bodies[1] == body.id else -on_cube
    result = {
        "moved": moved,
        "grasping": bool(agent.is_grasping("cube", gripper=f"{side}_hand")[0]),
        "force_z": float(force[2]),
        "force_xy": float(np.linalg.norm(force[:2])),
        "weight": weight,
    }
    scene.close()
    return result


@pytest.mark.parametrize("side", ["left", "right"])
def test_a_free_hand_closes_and_opens_again_within_its_tolerance(side: str) -> None:
    """Without an object, 2 s to ``closed`` then 2 s to ``open`` (the fingers' top speed
    is about 1.4 rad/s: 0.7 N*m against the joints' 0.5 N*m*s/rad): each time every finger
    joint ends within 0.03 rad (the hand's tolerance: the friction loss over kp leaves up
    to 0.014 rad) and ``is_gripper_closed`` / ``is_gripper_open`` say so. (With the thumb's
    tip passing inside the curled fingers the hand jammed and stayed 1 rad from open.)"""
    scene = ra.Scene(UID, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    hand = f"{side}_hand"
    names = agent.part_joints[hand]
    part = next(p for p in G1_PARTS if p.name == hand)
    opened, closed = part.positions(len(names))
    for pose, check in ((closed, agent.is_gripper_closed), (opened, agent.is_gripper_open)):
        target = agent.qpos[0].copy()
        target[[agent.joint_names.index(n) for n in names]] = pose
        action = np.array([target[agent.joint_names.index(j)] for j in MANISKILL_JOINTS])
        for _ in range(2 * scene.control_freq):
            agent.set_action(action)
            scene.step()
        error = np.abs(agent.qpos[0, [agent.joint_names.index(n) for n in names]] - pose)
        assert np.max(error) < 0.03, error
        assert check(gripper=hand)[0]
    scene.close()


@pytest.mark.parametrize("side", ["left", "right"])
def test_either_hand_holds_a_cube_against_gravity(side: str) -> None:
    """A 4 cm, 50 g cube held by the thumb and the two fingers: ``is_grasping``, it moves
    less than 1 mm relative to the palm as its weight comes on, and the contact forces on
    it sum to its weight (vertical, 1%)."""
    closed = LEFT_CLOSED if side == "left" else tuple(-q for q in LEFT_CLOSED)
    result = hand_grasp(side, closed)
    assert result["grasping"]
    assert result["moved"] < 0.001, result
    assert result["force_z"] == pytest.approx(result["weight"], rel=0.01)
    assert result["force_xy"] < 0.01 * result["weight"]


def test_the_grasp_check_can_fail() -> None:
    """The hand left open: no grasp, and the cube falls away (more than 5 cm in 2 s)."""
    result = hand_grasp("left", OPEN)
    assert not result["grasping"]
    assert result["moved"] > 0.05


def test_the_sweeps_grasp_claim_holds_the_declared_power_grasp() -> None:
    claim = grasp_claim(UnitreeG1UpperBody, UnitreeG1UpperBody.sim_freq or 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.001 and "not opposed" not in claim.detail


class _NeverCloses(UnitreeG1UpperBody):
    """The G1 whose left power grasp is its open pose: the fingers never close."""

    parts = tuple(dataclasses.replace(p, closed=OPEN) if p.name == "left_hand" else p for p in G1_PARTS)


def test_the_sweeps_grasp_claim_fails_when_the_hand_does_not_close() -> None:
    claim = grasp_claim(_NeverCloses, UnitreeG1UpperBody.sim_freq or 500, 20, Penetration())
    assert claim is not None and not claim.passed
    assert "not opposed" in claim.detail


# ---------------------------------------------------------------- variants
def test_the_head_camera_variant_is_the_base_robot_with_a_camera() -> None:
    """Same model and modes; one camera, ``head_camera`` on ``head_link``
    (tests/test_camera_sources.py checks its pose and projection against ManiSkill's)."""
    base = ra.Scene(UID)
    cam = ra.Scene(f"{UID}_with_head_camera")
    assert cam.model.nbody == base.model.nbody and cam.model.njnt == base.model.njnt
    assert set(cam.cameras.params(cam.world)) == {"head_camera"}
    assert base.cameras.params(base.world) == {}
    assert ra.get_agent(f"{UID}_with_head_camera").modes() == UnitreeG1UpperBody.modes()
    base.close()
    cam.close()


def test_the_right_arm_variant_commands_maniskills_11_joints_and_leaves_the_rest_passive() -> None:
    """ManiSkill's ``..._right_arm``: the right arm but its shoulder pitch, and the right
    hand, in its order, deltas of at most 0.2 rad on all 11; the other joints take no
    action: under random delta actions for 2 s the torso and the left arm and hand stay
    within 2 mrad of the keyframe (passive, damped, gravity compensated), the right
    shoulder pitch, which carries the moving arm, is turned by its reaction (0.060 rad,
    seed 0) but not driven, while the commanded joints move."""
    uid = "unitree_g1_simplified_upper_body_right_arm"
    scene = ra.Scene(uid, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    assert agent.controller.parts["body"].config.joint_names == RIGHT_ARM_JOINTS
    assert agent.controller.action_dim == 11
    np.testing.assert_allclose(agent.controller.parts["body"].to_raw(np.ones((1, 11)))[0], 0.2)
    rng = np.random.default_rng(0)
    start = agent.qpos[0].copy()
    commanded = [agent.joint_names.index(j) for j in RIGHT_ARM_JOINTS]
    passive = [i for i in range(len(agent.joint_names)) if i not in commanded]
    for _ in range(2 * scene.control_freq):
        agent.set_action(rng.uniform(-1.0, 1.0, 11))
        scene.step()
    moved = dict(zip(agent.joint_names, np.abs(agent.qpos[0] - start), strict=True))
    carried = "right_shoulder_pitch_joint"
    assert max(moved[agent.joint_names[i]] for i in passive if agent.joint_names[i] != carried) < 0.002, moved
    assert 0.01 < moved[carried] < 0.2
    assert max(moved[j] for j in RIGHT_ARM_JOINTS) > 0.2
    scene.close()
    assert UnitreeG1UpperBodyRightArm.default_mode() == "pd_joint_pos"  # ManiSkill's first there


def test_the_right_arm_variants_grasp_claim_is_the_right_hands() -> None:
    claim = grasp_claim(UnitreeG1UpperBodyRightArm, UnitreeG1UpperBodyRightArm.sim_freq or 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.001 and "not opposed" not in claim.detail
