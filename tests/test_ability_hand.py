"""The PSYONIC Ability Hand (right) checked against numbers: fingertip forward kinematics
against the URDF's joint origins chained here, the masses, ranges and the distal
joints' coupling, the coupling kept while the fingers move, the keyframe held and random
actions in every mode, a cube grasped, held and lifted by the floating hand (the contact
forces carrying its weight), the sweep's grasp claim, and the hand as a piece on an arm."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions, hold_action
from robot_agents.model.compose import Attachment
from robot_agents.robots.psyonic.ability_hand import (
    ABILITY_HAND,
    CLOSED,
    COUPLING_OFFSET,
    COUPLING_RATIO,
    HAND_ON_MOUNT,
    JOINTS,
    OPEN,
    POWER_GRASP,
    TIP_LINKS,
    AbilityHandRight,
    FloatingAbilityHandRight,
    hand_pose,
)
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform

UID = "floating_ability_hand_right"
MOUNT = [f"root_{a}_axis_joint" for a in "xyz"] + [f"root_{a}_rot_joint" for a in "xyz"]

# ---------------------------------------------------------------- independent kinematics
# ManiSkill's ability_hand_right.urdf (PSYONIC's description), written out here, not read
# from our model: each joint's origin (xyz, rpy) in its parent; every joint turns about z.
X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
WRIST_TO_PALM = ((-24.0476665e-3, 3.78124745e-3, 32.32964923e-3), (3.14148426, -0.08848813, -3.14036612))
FINGER_BASES = {
    "index": ((9.49e-3, -13.04e-3, -62.95e-3), (-1.1595426535897932, 1.284473, -1.0510016535897932)),
    "middle": ((-9.653191e-3, -15.310271e-3, -67.853949e-3), (-1.2810616535897934, 1.308458, -1.2453756535897933)),
    "ring": ((-29.95426e-3, -14.212492e-3, -67.286105e-3), (-1.424994653589793, 1.321452, -1.4657306535897934)),
    "pinky": ((-49.521293e-3, -11.004583e-3, -63.029065e-3), (-1.3764826535897934, 1.32222, -1.4832096535897932)),
}
FINGER_Q2 = ((38.472723e-3, 3.257695e-3, 0.0), (0.0, 0.0, 0.084474))
FINGER_TIP = (0.035, -0.018, 0.0)
THUMB_Q1 = ((0.0, 0.0, 0.0), (math.pi, 0.0, -0.18884434641020664))
THUMB_Q2 = ((27.8283501e-3, 0.0, 14.7507e-3), (1.832595714594045, 0.0, 0.0))
THUMB_TIP = (0.065, 0.016, 0.0)


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    rotation: np.ndarray = axis_rotation(Z, yaw) @ axis_rotation(Y, pitch) @ axis_rotation(X, roll)
    return rotation


def origin(xyz: tuple[float, float, float], rpy: tuple[float, float, float]) -> np.ndarray:
    return transform(rpy_matrix(*rpy), np.array(xyz))


def tip_in_wrist(finger: str, q1: float, q2: float) -> np.ndarray:
    """The fingertip link's position in the wrist (``base``) frame (m)."""
    pose = origin(*WRIST_TO_PALM)
    first, second, tip = (
        (THUMB_Q1, THUMB_Q2, THUMB_TIP) if finger == "thumb" else (FINGER_BASES[finger], FINGER_Q2, FINGER_TIP)
    )
    pose = pose @ origin(*first) @ transform(axis_rotation(Z, q1), np.zeros(3))
    pose = pose @ origin(*second) @ transform(axis_rotation(Z, q2), np.zeros(3))
    point: np.ndarray = (pose @ np.array([*tip, 1.0]))[:3]
    return point


@pytest.mark.parametrize("pose", ["keyframe", "closed", "random"])
def test_fingertips_match_the_urdf_chain(pose: str) -> None:
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    rng = np.random.default_rng(5)
    for _ in range(1 if pose != "random" else 5):
        if pose == "keyframe":
            q = agent.keyframe_qpos("rest")
        elif pose == "closed":
            q = agent.qpos[0].copy()
            q[[agent.joint_names.index(j) for j in JOINTS]] = CLOSED
        else:  # every joint anywhere in its range, the distal joints too (kinematics only)
            low, high = np.array([scene.model.joint(f"{agent.prefix}{j}").range for j in agent.joint_names]).T
            q = rng.uniform(low, high)
        for finger, tip in zip(("thumb", "index", "middle", "ring", "pinky"), TIP_LINKS, strict=True):
            measured = agent.frame_pose(tip, q, relative_to="base")[0, :3]
            q1, q2 = (q[agent.joint_names.index(f"{finger}_q{k}")] for k in (1, 2))
            np.testing.assert_allclose(measured, tip_in_wrist(finger, q1, q2), atol=1e-6)
    scene.close()


def test_the_chain_check_can_fail() -> None:
    """A 1 mm change in one origin of the chain written here moves the tip 1 mm."""
    before = tip_in_wrist("middle", 0.3, 1.0)
    kept = FINGER_BASES["middle"]
    xyz, rpy = kept
    FINGER_BASES["middle"] = ((xyz[0], xyz[1], xyz[2] + 0.001), rpy)
    try:
        assert np.linalg.norm(tip_in_wrist("middle", 0.3, 1.0) - before) == pytest.approx(0.001)
    finally:
        FINGER_BASES["middle"] = kept


def test_the_hand_on_the_mount_is_turned_as_maniskills_base_joint() -> None:
    """ManiSkill's base_joint turns the wrist -pi/2 about z (rpy 0 0 -1.57079): with the
    mount at 0 the fingers point up and the palm faces +x."""
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    wrist = agent.frame_pose("base", relative_to="root")[0]
    np.testing.assert_allclose(wrist[:3], 0.0, atol=1e-12)
    np.testing.assert_allclose(wrist[3:], HAND_ON_MOUNT, atol=1e-12)
    middle = agent.frame_pose("middle_tip")[0, :3]
    assert middle[2] > 0.5 + 0.17  # the stretched middle finger 17.6 cm above the wrist
    scene.close()


# ---------------------------------------------------------------- masses, ranges, coupling
#: PSYONIC's abh_right.xml (palm 0.4 kg, links as ManiSkill's URDF) and its large hand's
#: wrist (0.01591 kg), kg.
MASSES = {"base": 0.01591, "thumb_base": 0.4, "thumb_L1": 0.00268342, "thumb_L2": 0.0055}
for finger in ("index", "middle", "ring", "pinky"):
    MASSES |= {f"{finger}_L1": 0.00635888, f"{finger}_L2": 0.00645}
#: The URDF's ranges (rad): thumb rotator, flexor; each finger's q1, q2.
RANGES = [(-2.0943951, 0.0), (0.0, 2.0943951)] + [(0.0, 2.0943951), (0.0, 2.6586)] * 4


def test_masses_ranges_limits_and_coupling_match_the_sources() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    for body, mass in MASSES.items():
        assert model.body(f"{agent.prefix}{body}").mass[0] == pytest.approx(mass, abs=1e-9), body
    assert sum(MASSES.values()) == pytest.approx(0.47533, abs=1e-5)
    assert list(agent.joint_names) == MOUNT + list(JOINTS)
    ranges = np.array([model.joint(f"{agent.prefix}{j}").range for j in JOINTS])
    np.testing.assert_allclose(ranges, RANGES, atol=1e-12)
    # the distal joints follow their knuckles: q2 = 0.72349796 + 1.05851325 q1 (ManiSkill's mimic)
    for finger in ("index", "middle", "ring", "pinky"):
        eq = model.equality(f"{agent.prefix}{finger}_coupling")
        assert model.joint(eq.obj1id[0]).name == f"{agent.prefix}{finger}_q2"
        assert model.joint(eq.obj2id[0]).name == f"{agent.prefix}{finger}_q1"
        np.testing.assert_allclose(eq.data[:5], [COUPLING_OFFSET, COUPLING_RATIO, 0.0, 0.0, 0.0])
    # the six motors: the URDF's effort (N*m) and velocity (rad/s) limits
    drives = {d.joint: d for d in FloatingAbilityHandRight.check().drives}
    assert sorted(drives) == sorted([*MOUNT, "thumb_q1", "thumb_q2", "index_q1", "middle_q1", "ring_q1", "pinky_q1"])
    assert drives["thumb_q1"].effort_limit == 1.2 and drives["thumb_q1"].velocity_limit == pytest.approx(40.338888721)
    for joint in ("thumb_q2", "index_q1", "pinky_q1"):
        assert drives[joint].effort_limit == 6.0 and drives[joint].velocity_limit == pytest.approx(8.0677777442)
    scene.close()


def test_the_distal_joints_follow_the_coupling_while_the_fingers_move() -> None:
    """Knuckles driven from 0 to 1.6 rad and back in 0.1 rad steps (20 Hz): every distal
    joint stays within 5 mrad of 0.7235 + 1.0585 q1, and reaches 2.417 rad."""
    scene = ra.Scene(UID, control_modes="pd_joint_delta_pos")
    scene.reset()
    agent = scene.agents[0]
    hand = agent.controller.slices["hand"]
    names = agent.controller.parts["hand"].config.joint_names
    knuckles = [names.index(f"{f}_q1") for f in ("index", "middle", "ring", "pinky")]
    action = np.zeros_like(hold_action(agent))
    worst, top = 0.0, 0.0
    for step in range(45):  # 16 steps up, 10 held, 16 down
        action[:] = 0.0
        if step < 16 or 26 <= step < 42:
            action[hand.start + np.array(knuckles)] = 1.0 if step < 16 else -1.0  # +-0.1 rad of target
        agent.set_action(action)
        scene.step()
        for finger in ("index", "middle", "ring", "pinky"):
            q1, q2 = (agent.qpos[0, agent.joint_names.index(f"{finger}_q{k}")] for k in (1, 2))
            worst = max(worst, abs(q2 - (COUPLING_OFFSET + COUPLING_RATIO * q1)))
            top = max(top, q2)
    assert worst < 0.005, worst
    assert top == pytest.approx(COUPLING_OFFSET + COUPLING_RATIO * 1.6, abs=0.01)
    scene.close()


# ---------------------------------------------------------------- modes, keyframes, stability
def test_modes_match_maniskills_shape_and_the_hand_takes_target_deltas() -> None:
    """ManiSkill's pd_joint_pos: the mount's six absolute targets (m, rad) then the hand's
    six motors, absolute too; in the modes where the mount's targets are not absolute the
    hand takes +-0.1 rad deltas from its targets (as ManiSkill's hands on arms), so held
    at zero it keeps its targets."""
    modes = FloatingAbilityHandRight.modes()
    assert set(modes) >= {"pd_joint_pos", "pd_joint_delta_pos", "pd_joint_target_delta_pos", "pd_ee_delta_pose"}
    absolute = {"pd_joint_pos", "pd_joint_pos_vel", "pd_ee_pose"}
    for name, mode in modes.items():
        assert isinstance(mode, dict)
        config = mode["hand"]
        assert isinstance(config, ra.PDJointPosConfig)
        if name in absolute:
            assert not config.use_delta and not config.normalize_action, name
        else:
            assert config.use_delta and config.use_target, name
        assert config.joint_names == ("thumb_q1", "thumb_q2", "index_q1", "middle_q1", "ring_q1", "pinky_q1")
    arm = modes["pd_joint_pos"]["arm"]  # type: ignore[index]
    assert isinstance(arm, ra.PDJointPosConfig) and not arm.use_delta and not arm.normalize_action
    assert FloatingAbilityHandRight.default_mode() == "pd_joint_pos"
    scene = ra.Scene(UID)
    assert scene.agents[0].action_space.shape == (1, 12)  # one env
    scene.close()


def test_keyframe_holds_and_random_actions_stay_stable() -> None:
    held = check_holds(FloatingAbilityHandRight, seconds=2.0)
    assert held.passed, held.detail
    random = check_random_actions(FloatingAbilityHandRight, seconds=5.0)
    assert random.passed, random.detail


# ---------------------------------------------------------------- grasp
CUBE_EDGE = POWER_GRASP.cube_edge
CUBE_MASS = 1000.0 * CUBE_EDGE**3  # water's density: 27 g


def wrist_to_world(point: tuple[float, float, float]) -> tuple[float, float, float]:
    """A wrist-frame point in the world with the mount at 0 (wrist y -> world x, x -> -y)."""
    return (point[1], -point[0], 0.5 + point[2])


def test_the_floating_hand_grasps_holds_and_lifts_a_cube() -> None:
    """The 3 cm, 27 g cube at the power grasp's place, weightless while the hand closes
    (2 s); then its weight: held 1 s, lifted 5 cm by the mount over 1 s, held 1 s. The
    thumb and the fingers press from opposite sides, the hand's contact forces carry the
    cube's weight (within 2 %), it stays within 2 mm of where it was in the hand; opened,
    it drops."""
    cube = ra.Prop("cube", "box", (0.5 * CUBE_EDGE,) * 3, pos=wrist_to_world(POWER_GRASP.cube_centre), mass=CUBE_MASS)
    scene = ra.Scene(UID, props=[cube], control_modes="pd_joint_pos", floor=False)
    scene.reset()
    agent = scene.agents[0]
    q = agent.qpos[0].copy()
    q[[agent.joint_names.index(j) for j in JOINTS]] = OPEN
    agent.reset(qpos=q)
    model, data = scene.model, scene.world.datas[0]
    body = model.body("cube").id
    weight = CUBE_MASS * 9.81
    hand = agent.controller.parts["hand"]
    names = hand.config.joint_names
    mount = np.zeros(6)

    def act(pose: tuple[float, ...], steps: int, cancel: bool = False) -> None:
        goal = np.array([pose[JOINTS.index(j)] for j in names])
        for _ in range(steps):
            data.xfrc_applied[body, 2] = weight if cancel else 0.0
            action = hold_action(agent)
            action[:6] = mount
            # at most 0.1 rad a step, as the hand's delta modes close it: a closing hand's
            # absolute targets set at once slam the weightless cube out of its place
            step_to = np.clip(goal - hand.target_qpos[0], -0.1, 0.1)
            raw = step_to if hand.config.use_delta else hand.target_qpos[0] + step_to
            action[agent.controller.slices["hand"]] = hand.from_raw(raw)
            agent.set_action(action)
            scene.step()

    def in_hand() -> np.ndarray:
        wrist = agent.frame_pose("base")[0, :3]
        return np.asarray(scene.body_pose("cube")[0, :3] - wrist)

    act(OPEN, 2, cancel=True)
    assert not agent.is_grasping("cube")[0]
    act(CLOSED, 40, cancel=True)
    assert agent.is_grasping("cube")[0]
    start = in_hand()
    act(CLOSED, 20)
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    carried = scene.world.contact_forces([robot], body)[0, 0]
    assert carried[2] == pytest.approx(weight, rel=0.02), carried
    for step in range(20):  # the mount's z slide up 5 cm
        mount[2] = 0.05 * (step + 1) / 20
        act(CLOSED, 1)
    act(CLOSED, 20)
    assert agent.frame_pose("base")[0, 2] == pytest.approx(0.55, abs=0.002)
    assert agent.is_grasping("cube")[0]
    assert np.linalg.norm(in_hand() - start) < 0.002, in_hand() - start
    carried = scene.world.contact_forces([robot], body)[0, 0]
    assert carried[2] == pytest.approx(weight, rel=0.02), carried
    act(OPEN, 20)
    assert not agent.is_grasping("cube")[0]
    assert np.linalg.norm(in_hand() - start) > 0.02
    scene.close()


def test_the_sweeps_grasp_claim_holds_the_declared_power_grasp() -> None:
    claim = grasp_claim(FloatingAbilityHandRight, FloatingAbilityHandRight.sim_freq, 20, Penetration())
    # The claim sets the hand's absolute targets to ``closed`` at once (pd_joint_pos, the
    # default): the slammed fingers hold the cube within the bound, though not squarely
    # opposed (the detail says so); the ramped close of the grasp test above is opposed.
    assert claim is not None and claim.passed, claim


class _NeverClosesPiece(AbilityHandRight):
    parts = (dataclasses.replace(ABILITY_HAND, closed=OPEN),)


class _NeverCloses(FloatingAbilityHandRight):
    """The floating hand whose power grasp is its open pose: the fingers never close."""

    uid = ""
    attachments = (Attachment(_NeverClosesPiece, at="root", quat=HAND_ON_MOUNT),)


def test_the_sweeps_grasp_claim_fails_when_the_hand_does_not_close() -> None:
    claim = grasp_claim(_NeverCloses, FloatingAbilityHandRight.sim_freq, 20, Penetration())
    assert claim is not None and not claim.passed
    assert claim.value > 0.01 and "not opposed" in claim.detail


# ---------------------------------------------------------------- the piece
def test_the_piece_on_an_arm_keeps_its_coupling_and_power_grasp_under_its_prefix() -> None:
    from robot_agents.robots.ufactory.xarm6 import XArm6NoGripper

    class ArmWithHand(XArm6NoGripper):
        uid = "arm_with_ability_test"
        attachments = (ra.Attachment(AbilityHandRight, at="link_eef", prefix="hand/"),)

    hand = next(p for p in ArmWithHand.check().parts if isinstance(p, ra.Hand))
    assert hand.power_grasp is not None and hand.power_grasp.link == "hand/base"
    scene = ra.Scene(ArmWithHand)
    scene.reset()
    agent = scene.agents[0]
    assert scene.model.equality(f"{agent.prefix}hand/index_coupling").data[1] == pytest.approx(COUPLING_RATIO)
    config = agent.controller.parts["hand_hand"].config
    assert config.use_delta and config.use_target  # a hand riding on an arm
    np.testing.assert_allclose(
        agent.qpos[0, [agent.joint_names.index(f"hand/{j}") for j in JOINTS]], hand_pose(0.0, 0.0, 0.0), atol=1e-12
    )
    scene.close()
