"""The xArm7 with the Ability Hand checked against numbers: the wrist and the fingertips
against the URDF's joint origins chained here (random configurations), the arm's
masses, ranges and limits, the keyframe held and random actions in every mode, ManiSkill's
modes with the hand's target deltas, a cube held in the hand on the arm (the contact
forces carrying its weight while the arm moves) and the sweep's grasp claim."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions, hold_action
from robot_agents.robots.psyonic.ability_hand import CLOSED, JOINTS, OPEN, POWER_GRASP, TIP_LINKS
from robot_agents.robots.ufactory.xarm7 import XArm7Ability
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform
from tests.test_ability_hand import Z, origin, tip_in_wrist

UID = "xarm7_ability"
ARM = [f"joint{i}" for i in range(1, 8)]

# UFactory's xarm_description as ManiSkill's xarm7_ability_right_hand.urdf gives it, written
# out here: each arm joint's origin (xyz, rpy) in its parent, every joint about its z;
# then the hand's wrist on link7 (joint_eef).
ARM_ORIGINS = [
    ((0.0, 0.0, 0.267), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (-1.5708, 0.0, 0.0)),
    ((0.0, -0.293, 0.0), (1.5708, 0.0, 0.0)),
    ((0.0525, 0.0, 0.0), (1.5708, 0.0, 0.0)),
    ((0.0775, -0.3425, 0.0), (1.5708, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (1.5708, 0.0, 0.0)),
    ((0.076, 0.097, 0.0), (-1.5708, 0.0, 0.0)),
]
WRIST_ON_LINK7 = ((0.0, 0.0, 0.0), (0.0, 0.0, 1.57079))


def wrist_pose(q: np.ndarray) -> np.ndarray:
    """The hand's wrist ``base`` in the arm's base frame ``(4, 4)`` at arm angles ``q`` (rad)."""
    pose = np.eye(4)
    for (xyz, rpy), angle in zip(ARM_ORIGINS, q, strict=True):
        pose = pose @ origin(xyz, rpy) @ transform(axis_rotation(Z, float(angle)), np.zeros(3))
    result: np.ndarray = pose @ origin(*WRIST_ON_LINK7)
    return result


def test_the_wrist_and_fingertips_match_the_urdf_chain() -> None:
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    low, high = np.array([scene.model.joint(f"{agent.prefix}{j}").range for j in agent.joint_names]).T
    rng = np.random.default_rng(7)
    for trial in range(6):
        q = agent.keyframe_qpos("rest") if trial == 0 else rng.uniform(low, high)
        arm = q[[agent.joint_names.index(j) for j in ARM]]
        wrist = wrist_pose(arm)
        measured = agent.frame_pose("base", q, relative_to="link_base")[0]
        np.testing.assert_allclose(measured[:3], wrist[:3, 3], atol=1e-6)
        for finger, tip in zip(("thumb", "index", "middle", "ring", "pinky"), TIP_LINKS, strict=True):
            q1, q2 = (q[agent.joint_names.index(f"{finger}_q{k}")] for k in (1, 2))
            expected = wrist[:3, :3] @ tip_in_wrist(finger, q1, q2) + wrist[:3, 3]
            np.testing.assert_allclose(agent.frame_pose(tip, q, relative_to="link_base")[0, :3], expected, atol=1e-6)
    scene.close()


def test_the_chain_check_can_fail() -> None:
    """A 1 mm change of the upper arm's length moves the wrist 1 mm (arm stretched up)."""
    q = np.zeros(7)
    before = wrist_pose(q)[:3, 3]
    kept = ARM_ORIGINS[2]
    ARM_ORIGINS[2] = ((0.0, -0.294, 0.0), kept[1])
    try:
        assert np.linalg.norm(wrist_pose(q)[:3, 3] - before) == pytest.approx(0.001)
    finally:
        ARM_ORIGINS[2] = kept


#: The URDF's link masses (kg): link_base, link1..link7.
MASSES = {"link_base": 0.88556, "link1": 2.382, "link2": 1.869, "link3": 1.6383, "link4": 1.7269}
MASSES |= {"link5": 1.3203, "link6": 1.325, "link7": 0.17}
RANGES = [(-2 * np.pi, 2 * np.pi), (-2.059, 2.0944), (-2 * np.pi, 2 * np.pi), (-0.19198, 3.927)]
RANGES += [(-2 * np.pi, 2 * np.pi), (-1.69297, np.pi), (-2 * np.pi, 2 * np.pi)]


def test_masses_ranges_and_limits_match_the_sources() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    for body, mass in MASSES.items():
        assert model.body(f"{agent.prefix}{body}").mass[0] == pytest.approx(mass, abs=1e-9), body
    assert sum(MASSES.values()) == pytest.approx(11.31706)
    assert list(agent.joint_names) == ARM + list(JOINTS)
    ranges = np.array([model.joint(f"{agent.prefix}{j}").range for j in ARM])
    np.testing.assert_allclose(ranges, RANGES, atol=1e-9)
    drives = {d.joint: d for d in XArm7Ability.check().drives}
    assert [drives[j].effort_limit for j in ARM] == [50.0, 50.0, 30.0, 30.0, 30.0, 20.0, 20.0]
    assert all(drives[j].velocity_limit == 3.14 for j in ARM)
    assert drives["index_q1"].effort_limit == 6.0  # the hand's own drives come with it
    scene.close()


def test_modes_include_maniskills_and_the_hand_takes_target_deltas() -> None:
    """The hand takes +-0.1 rad deltas from its targets (ManiSkill's hand_target_delta_pos)
    in every mode but those where the arm's targets are absolute; there its targets are
    absolute too (the library's rule for a hand on an arm; ManiSkill keeps deltas)."""
    modes = XArm7Ability.modes()
    assert {"pd_joint_delta_pos", "pd_joint_pos", "pd_ee_delta_pose", "pd_ee_target_delta_pose"} <= set(modes)
    assert XArm7Ability.default_mode() == "pd_joint_delta_pos"
    absolute = {"pd_joint_pos", "pd_joint_pos_vel", "pd_ee_pose"}
    for name, mode in modes.items():
        assert isinstance(mode, dict)
        hand = mode["hand"]
        assert isinstance(hand, ra.PDJointPosConfig)
        if name in absolute:
            assert not hand.use_delta and not hand.normalize_action, name
        else:
            assert hand.use_delta and hand.use_target, name
            assert hand.lower == -0.1 and hand.upper == 0.1


def test_keyframe_holds_and_random_actions_stay_stable() -> None:
    held = check_holds(XArm7Ability, seconds=2.0)
    assert held.passed, held.detail
    random = check_random_actions(XArm7Ability, seconds=3.0)
    assert random.passed, random.detail


CUBE_EDGE = POWER_GRASP.cube_edge
CUBE_MASS = 1000.0 * CUBE_EDGE**3


def test_the_hand_on_the_arm_holds_a_cube_while_the_arm_moves() -> None:
    """At the rest pose (the hand pointing down), the 3 cm, 27 g cube at the power grasp's
    place, weightless while the hand closes (2 s); then with its weight, held 1 s and
    lifted 5 cm by the arm (``pd_ee_delta_pose``, 1 s) and held 1 s: the cube stays within 2 mm of where it was in the
    wrist's frame, the hand's contact forces carry its weight (2 %); opened, it drops.
    ``is_grasping`` (two fingers pressing within 85 deg of opposite) holds with the
    weight on before the lift."""
    scene = ra.Scene(
        UID,
        control_modes="pd_ee_delta_pose",
        props=[ra.Prop("cube", "box", (0.5 * CUBE_EDGE,) * 3, pos=(0.0, 0.9, 0.1), mass=CUBE_MASS)],
    )
    scene.reset()
    agent = scene.agents[0]
    q = agent.qpos[0].copy()
    q[[agent.joint_names.index(j) for j in JOINTS]] = OPEN
    agent.reset(qpos=q)
    model, data = scene.model, scene.world.datas[0]
    body = model.body("cube").id
    wrist = agent.frame_pose("base")[0]
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, wrist[3:])
    centre = wrist[:3] + rotation.reshape(3, 3) @ np.array(POWER_GRASP.cube_centre)
    joint = int(model.body("cube").jntadr[0])
    scene.world.write_joint_state(
        [0],
        np.arange(7) + int(model.jnt_qposadr[joint]),
        np.array([[*centre, *wrist[3:]]]),
        np.arange(6) + int(model.jnt_dofadr[joint]),
        np.zeros((1, 6)),
    )
    weight = CUBE_MASS * 9.81
    hand = agent.controller.parts["hand"]
    names = hand.config.joint_names
    arm = np.zeros(6)  # the end effector's (dx, dy, dz, drx, dry, drz), normalized

    def act(pose: tuple[float, ...], steps: int, cancel: bool = False) -> None:
        goal = np.array([pose[JOINTS.index(j)] for j in names])
        for _ in range(steps):
            data.xfrc_applied[body, 2] = weight if cancel else 0.0
            action = hold_action(agent)
            action[:6] = arm
            action[agent.controller.slices["hand"]] = hand.from_raw(goal - hand.target_qpos[0])
            agent.set_action(action)
            scene.step()

    def in_hand() -> np.ndarray:
        """The cube's centre in the wrist frame (m)."""
        pose = agent.frame_pose("base")[0]
        turn = np.zeros(9)
        mujoco.mju_quat2Mat(turn, pose[3:])
        return np.asarray(turn.reshape(3, 3).T @ (scene.body_pose("cube")[0, :3] - pose[:3]))

    act(CLOSED, 40, cancel=True)
    assert agent.is_grasping("cube")[0]
    act(CLOSED, 20)
    start = in_hand()
    assert agent.is_grasping("cube")[0]
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    assert scene.world.contact_forces([robot], body)[0, 0, 2] == pytest.approx(weight, rel=0.02)
    height = agent.frame_pose("base")[0, 2]
    arm[2] = 0.025  # 2.5 mm a step of the 0.1 m bound, 20 steps
    act(CLOSED, 20)
    arm[2] = 0.0
    act(CLOSED, 20)
    assert agent.frame_pose("base")[0, 2] == pytest.approx(height + 0.05, abs=0.005)
    # (the palm carries part of the load here: after the lift the thumb's and the index's
    # forces are 94 deg apart, just short of is_grasping's 95, though the cube moved 0.5 mm)
    assert np.linalg.norm(in_hand() - start) < 0.002, in_hand() - start
    assert scene.world.contact_forces([robot], body)[0, 0, 2] == pytest.approx(weight, rel=0.02)
    act(OPEN, 20)
    assert not agent.is_grasping("cube")[0]
    assert np.linalg.norm(in_hand() - start) > 0.02
    scene.close()


def test_the_sweeps_grasp_claim_holds_the_hands_power_grasp_on_the_arm() -> None:
    """The hand's declared power grasp, on the arm at its rest pose (the hand pointing
    down), held against a 1 g pull away from the palm (slip within 2 mm). The palm takes
    part of the load, so the fingers' forces end just short of is_grasping's opposition
    (the claim's detail says so; it counts the slip)."""
    claim = grasp_claim(XArm7Ability, XArm7Ability.sim_freq, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.002 and "cube lost" not in claim.detail
