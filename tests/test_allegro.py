"""The Allegro Hand (right) checked against numbers: fingertip forward kinematics against
the URDF's joint origins chained here, Wonik's link masses and the joint ranges, both
keyframes held, random actions in every mode, and a power grasp of a cube lying in the
upturned palm that holds against a pull away from the palm. The physics claims run on
the left hand (its right hand mirrored) and the touch variant too
(tests/test_allegro_left.py and tests/test_allegro_touch.py check their own numbers)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions, hold_action
from robot_agents.errors import UnknownNameError
from robot_agents.robots.wonik.allegro import (
    ALLEGRO_HAND,
    OPEN,
    PALM_FACE,
    PALM_UP_MOUNT,
    POWER_GRASP,
    TIP_LINKS,
    AllegroHandRight,
)
from robot_agents.robots.wonik.allegro_left import AllegroHandLeft
from robot_agents.robots.wonik.allegro_touch import AllegroHandRightTouch
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform
from tests.random_actions import after_random_actions

UID = "allegro_hand_right"
#: The hands whose physics claims are checked here: the right hand, the left (the right
#: mirrored) and the right with touch sensors.
HANDS: tuple[type[ra.Agent], ...] = (AllegroHandRight, AllegroHandLeft, AllegroHandRightTouch)
HAND_UIDS = [hand.uid for hand in HANDS]

# ---------------------------------------------------------------- independent kinematics
# The Allegro Hand URDF (Wonik's allegro_hand_description_right; ManiSkill's and
# Menagerie's models carry the same numbers): per finger, the first joint's origin
# (position, rpy) in base_link, then the following joints' offsets along the parent's z,
# the axes, and the tip's offset. Written out here from the URDF, not read from our model.
Y, Z, MINUS_X = (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0)
FINGER_ORIGINS = {
    "index": ((0.0, 0.0435, -0.001542), (-0.08726646255, 0.0, 0.0)),
    "middle": ((0.0, 0.0, 0.0007), (0.0, 0.0, 0.0)),
    "ring": ((0.0, -0.0435, -0.001542), (0.08726646255, 0.0, 0.0)),
    "thumb": ((-0.0182, 0.019333, -0.045987), (0.0, -1.65806278845, -1.5707963259)),
}
FINGER_LINKS = [((0.0, 0.0, 0.0164), Y), ((0.0, 0.0, 0.054), Y), ((0.0, 0.0, 0.0384), Y)]
THUMB_LINKS = [((-0.027, 0.005, 0.0399), Z), ((0.0, 0.0, 0.0177), Y), ((0.0, 0.0, 0.0514), Y)]
TIP_OFFSET = {"index": 0.0267, "middle": 0.0267, "ring": 0.0267, "thumb": 0.0423}
FIRST_AXIS = {"index": Z, "middle": Z, "ring": Z, "thumb": MINUS_X}
#: Joint indices (ManiSkill's order) and tip links per finger.
FINGER_JOINTS = {"index": range(0, 4), "middle": range(4, 8), "ring": range(8, 12), "thumb": range(12, 16)}
FINGER_TIPS = {"index": "link_3.0_tip", "middle": "link_7.0_tip", "ring": "link_11.0_tip", "thumb": "link_15.0_tip"}


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    rotation: np.ndarray = axis_rotation(Z, yaw) @ axis_rotation(Y, pitch) @ axis_rotation((1.0, 0.0, 0.0), roll)
    return rotation


def tip_in_base(finger: str, q: np.ndarray) -> np.ndarray:
    """The fingertip's position in base_link (m) at the finger's 4 joint angles."""
    origin, rpy = FINGER_ORIGINS[finger]
    pose = transform(rpy_matrix(*rpy), np.array(origin))
    pose = pose @ transform(axis_rotation(FIRST_AXIS[finger], float(q[0])), np.zeros(3))
    links = THUMB_LINKS if finger == "thumb" else FINGER_LINKS
    for (offset, axis), angle in zip(links, q[1:], strict=True):
        pose = pose @ transform(axis_rotation(axis, float(angle)), np.array(offset))
    tip: np.ndarray = (pose @ np.array([0.0, 0.0, TIP_OFFSET[finger], 1.0]))[:3]
    return tip


@pytest.mark.parametrize("pose", ["keyframe", "closed", "random"])
def test_fingertips_match_the_urdf_chain(pose: str) -> None:
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    if pose == "keyframe":
        q = agent.keyframe_qpos("palm_side")
    elif pose == "closed":
        q = np.asarray(agent.gripper().closed, dtype=np.float64)
    else:
        low, high = scene.model.jnt_range.T  # the robot's 16 joints, nothing else in the scene
        q = np.random.default_rng(3).uniform(low, high)
    for finger, joints in FINGER_JOINTS.items():
        measured = agent.frame_pose(FINGER_TIPS[finger], q, relative_to="root")[0, :3]
        np.testing.assert_allclose(measured, tip_in_base(finger, q[list(joints)]), atol=1e-3)
    # and the keyframe's tips are where the stretched fingers end (m): 0.1334 / 0.1362 up
    if pose == "keyframe":
        middle = agent.frame_pose("link_7.0_tip", q, relative_to="root")[0, :3]
        assert middle[2] == pytest.approx(0.0007 + 0.0164 + 0.054 + 0.0384 + 0.0267, abs=1e-9)
    scene.close()


def test_the_chain_check_can_fail() -> None:
    """A 1 mm change in one origin of the chain written here moves the tip 1 mm."""
    q = np.zeros(4)
    moved = dict(FINGER_ORIGINS)
    base = tip_in_base("middle", q)
    FINGER_ORIGINS["middle"] = ((0.0, 0.0, 0.0017), (0.0, 0.0, 0.0))
    try:
        assert np.linalg.norm(tip_in_base("middle", q) - base) == pytest.approx(0.001)
    finally:
        FINGER_ORIGINS.update(moved)


# ---------------------------------------------------------------- masses and ranges
#: Wonik's V4 description (allegro_hand_ros2, allegro_hand_description_right.xacro), kg.
MASSES = {"base_link": 0.4154, "link_12.0": 0.0176, "link_13.0": 0.0119, "link_14.0": 0.038, "link_15.0": 0.0388}
MASSES |= {"link_15.0_tip": 0.0168}
for first in (0, 4, 8):
    MASSES |= {f"link_{first}.0": 0.0119, f"link_{first + 1}.0": 0.065, f"link_{first + 2}.0": 0.0355}
    MASSES |= {f"link_{first + 3}.0": 0.0096, f"link_{first + 3}.0_tip": 0.0168}
#: The URDF's joint ranges (rad): base, proximal, medial, distal; thumb.
FINGER_RANGES = [(-0.47, 0.47), (-0.196, 1.61), (-0.174, 1.709), (-0.227, 1.618)]
THUMB_RANGES = [(0.263, 1.396), (-0.105, 1.163), (-0.189, 1.644), (-0.162, 1.719)]


def test_masses_and_ranges_match_the_sources() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    for body, mass in MASSES.items():
        assert model.body(f"{agent.prefix}{body}").mass[0] == pytest.approx(mass, abs=1e-9), body
    assert sum(MASSES.values()) == pytest.approx(0.9549)
    assert list(agent.joint_names) == [f"joint_{i}.0" for i in range(16)]
    ranges = np.array([model.joint(f"{agent.prefix}{name}").range for name in agent.joint_names])
    np.testing.assert_allclose(ranges, FINGER_RANGES * 3 + THUMB_RANGES, atol=1e-12)
    scene.close()


@pytest.mark.parametrize("uid", HAND_UIDS)
def test_keyframes_hold_and_random_actions_stay_stable(uid: str) -> None:
    held = check_holds(ra.get_agent(uid), seconds=2.0)  # on the palm_side mount
    assert held.passed, held.detail
    # palm_up on its own mount: 2 s of its hold action, every joint within 0.01 rad
    scene = ra.Scene(uid, robot_poses=[PALM_UP_MOUNT])
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    action = hold_action(agent)
    drift = 0.0
    for _ in range(2 * scene.control_freq):
        agent.set_action(action)
        scene.step()
        drift = max(drift, float(np.max(np.abs(agent.qpos[0] - agent.keyframe_qpos("palm_up")))))
    assert drift < 0.01
    scene.close()
    random = check_random_actions(ra.get_agent(uid), seconds=10.0)
    assert random.passed, random.detail


# ---------------------------------------------------------------- grasp
#: A 5.5 cm, 100 g cube lying in the upturned palm (palm face 0.0111 m along base_link x),
#: its centre 15 mm from the finger bases towards the wrist (clear of the thumb's base):
#: the hand's declared power grasp.
CUBE_HALF = 0.5 * POWER_GRASP.cube_edge
CUBE_MASS = 0.1
CUBE_IN_BASE = POWER_GRASP.cube_centre


def in_world(point: tuple[float, float, float]) -> tuple[float, float, float]:
    """A base_link point in the world with the palm up (base x up, base z along -x)."""
    return (PALM_UP_MOUNT[0] - point[2], PALM_UP_MOUNT[1] + point[1], PALM_UP_MOUNT[2] + point[0])


@pytest.mark.parametrize("uid", HAND_UIDS)
def test_power_grasp_holds_a_cube_against_a_pull_away_from_the_palm(uid: str) -> None:
    cube = ra.Prop("cube", "box", (CUBE_HALF,) * 3, pos=(0.3, 0.0, CUBE_HALF), mass=CUBE_MASS)
    scene = ra.Scene(uid, props=[cube], robot_poses=[PALM_UP_MOUNT], control_modes="pd_joint_pos")
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    hand = agent.gripper()
    opened = np.asarray(hand.open, dtype=np.float64)
    closed = np.asarray(hand.closed, dtype=np.float64)

    def act(action: np.ndarray, steps: int) -> None:
        for _ in range(steps):
            agent.set_action(action)
            scene.step()

    act(opened, 20)  # the thumb stands up opposite the fingers
    assert agent.is_gripper_open()[0]
    model = scene.model
    joint = int(model.body("cube").jntadr[0])
    qpos_adr = np.arange(7) + int(model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(model.jnt_dofadr[joint])
    pose = np.array([[*in_world(CUBE_IN_BASE), 1.0, 0.0, 0.0, 0.0]])
    scene.world.write_joint_state([0], qpos_adr, pose, dof_adr, np.zeros((1, 6)))
    act(opened, 10)  # it settles onto the palm
    resting = scene.body_pose("cube")[0, :3]
    assert resting[2] == pytest.approx(PALM_UP_MOUNT[2] + PALM_FACE + CUBE_HALF, abs=5e-4)  # flat on the palm
    assert not agent.is_grasping("cube")[0]

    act(closed, 40)  # 2 s
    assert agent.is_grasping("cube")[0]
    palm = agent.frame_pose("base_link")[0]
    start = scene.body_pose("cube")[0, :3] - palm[:3]

    # its weight cancelled and as much again pulling it away from the palm (+z): 1 g net,
    # as if the hand were turned over
    data = scene.world.datas[0]
    weight = CUBE_MASS * 9.81
    data.xfrc_applied[model.body("cube").id, :3] = (0.0, 0.0, 2.0 * weight)
    moved = 0.0
    for _ in range(40):  # 2 s
        act(closed, 1)
        moved = max(moved, float(np.linalg.norm(scene.body_pose("cube")[0, :3] - palm[:3] - start)))
    assert agent.is_grasping("cube")[0]
    assert moved < 0.002, f"the cube moved {moved * 1000:.2f} mm relative to the palm"
    data.xfrc_applied[model.body("cube").id, :3] = 0.0

    act(opened, 20)
    assert not agent.is_grasping("cube")[0]
    scene.close()


def test_the_grasp_check_can_fail() -> None:
    """The fingers open, the cube only rests in the palm: no grasp, and pulled (1 g net)
    it leaves the palm (more than 2 cm in 1 s)."""
    cube = ra.Prop("cube", "box", (CUBE_HALF,) * 3, pos=in_world(CUBE_IN_BASE), mass=CUBE_MASS)
    scene = ra.Scene(UID, props=[cube], robot_poses=[PALM_UP_MOUNT], control_modes="pd_joint_pos")
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    keyframe = agent.keyframe_qpos("palm_up")
    for _ in range(10):
        agent.set_action(keyframe)
        scene.step()
    assert not agent.is_grasping("cube")[0]
    start = scene.body_pose("cube")[0, :3]
    scene.world.datas[0].xfrc_applied[scene.model.body("cube").id, :3] = (0.0, 0.0, 2.0 * CUBE_MASS * 9.81)
    for _ in range(20):
        agent.set_action(keyframe)
        scene.step()
    assert np.linalg.norm(scene.body_pose("cube")[0, :3] - start) > 0.02
    scene.close()


def test_the_hand_reports_its_opening() -> None:
    """``gripper_opening`` reads the first joint that moves between open and closed (the
    index's proximal: the spread joint before it stays at 0 in both)."""
    scene = ra.Scene(UID, robot_poses=[PALM_UP_MOUNT])
    scene.reset()
    agent = scene.agents[0]
    q = np.asarray(agent.gripper().closed, dtype=np.float64).copy()
    agent.reset(qpos=q)
    assert agent.gripper_opening()[0] == pytest.approx(0.0)
    assert agent.is_gripper_closed()[0]
    q[1] = 0.5 * 1.61
    agent.reset(qpos=q)
    assert agent.gripper_opening()[0] == pytest.approx(0.5)
    assert math.isfinite(float(agent.gripper_opening()[0]))
    scene.close()


def test_tip_links_are_maniskills() -> None:
    assert TIP_LINKS == ("link_15.0_tip", "link_3.0_tip", "link_7.0_tip", "link_11.0_tip")


# ---------------------------------------------------------------- the sweep's grasp claim
@pytest.mark.parametrize("hand", HANDS, ids=HAND_UIDS)
def test_the_sweeps_grasp_claim_holds_the_declared_power_grasp(hand: type[ra.Agent]) -> None:
    """The time-step sweep's grasp claim for a hand: the declared 5.5 cm cube (water's
    density, 166 g) held against a 1 g pull away from the palm, at the default step."""
    claim = grasp_claim(hand, hand.sim_freq, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.001 and "not opposed" not in claim.detail


class _NeverCloses(AllegroHandRight):
    """The Allegro whose power grasp is its open pose: the fingers never close."""

    parts = (dataclasses.replace(ALLEGRO_HAND, closed=OPEN),)


def test_the_sweeps_grasp_claim_fails_when_the_hand_does_not_close() -> None:
    claim = grasp_claim(_NeverCloses, AllegroHandRight.sim_freq, 20, Penetration())
    assert claim is not None and not claim.passed
    assert claim.value > 0.01 and "not opposed" in claim.detail


def test_a_power_grasp_is_checked_where_it_is_declared() -> None:
    with pytest.raises(ra.ConfigError, match="cube_edge"):
        ra.PowerGrasp("base_link", (0.04, 0.0, 0.0), -0.05, (1.0, 0.0, 0.0))
    with pytest.raises(ra.ConfigError, match="outward"):
        ra.PowerGrasp("base_link", (0.04, 0.0, 0.0), 0.05, (0.0, 0.0, 0.0))
    with pytest.raises(ra.ConfigError, match="cube_centre"):
        ra.PowerGrasp("base_link", (0.04, 0.0), 0.05, (1.0, 0.0, 0.0))
    assert ra.PowerGrasp("base_link", (0.04, 0.0, 0.0), 0.05, (2.0, 0.0, 0.0)).outward == (1.0, 0.0, 0.0)

    class MisnamedPalm(AllegroHandRight):
        parts = (dataclasses.replace(ALLEGRO_HAND, power_grasp=dataclasses.replace(POWER_GRASP, link="base_lnk")),)

    with pytest.raises(UnknownNameError, match=r"power_grasp\.link.*base_lnk.*base_link"):
        MisnamedPalm.check()


def test_a_mounted_hand_carries_its_power_grasp_with_the_prefix() -> None:
    """The Allegro as a piece on an arm's flange: its power grasp names the prefixed palm."""
    from robot_agents.robots.ufactory.xarm6 import XArm6NoGripper

    class ArmWithHand(XArm6NoGripper):
        uid = "arm_with_allegro_test"
        attachments = (ra.Attachment(AllegroHandRight, at="link_eef", prefix="hand/", pos=(0.0, 0.0, 0.1)),)

    hand = next(p for p in ArmWithHand.check().parts if isinstance(p, ra.Hand))
    assert hand.power_grasp is not None and hand.power_grasp.link == "hand/base_link"
    assert hand.power_grasp.cube_centre == POWER_GRASP.cube_centre


# ---------------------------------------------------------------- finger on finger
def thumb_speed_after_pressing_the_index(cls: type[ra.Agent]) -> float:
    """Random ``pd_joint_target_delta_pos`` actions (seed 2) at 320 Hz leave the thumb's
    target beyond the index finger; held there (the accumulated targets, one hold command
    repeated for 3 s) the thumb tip presses on the finger: the fastest joint over the
    last 0.5 s (rad/s)."""
    scene = after_random_actions(cls, "pd_joint_target_delta_pos", 320, seed=2)
    agent = scene.agents[0]
    hold, fastest = hold_action(agent), 0.0
    for step in range(60):
        agent.set_action(hold)
        scene.step()
        if step >= 50:
            fastest = max(fastest, float(np.abs(agent.qvel[0]).max()))
    scene.close()
    return fastest


def test_a_fingertip_on_another_finger_meets_the_links_contact_and_comes_to_rest(tmp_path: Path) -> None:
    """The thumb tip pressed on the index finger meets MuJoCo's default contact (the links
    take contact priority over the pads, whose contact is MuJoCo's default too) and the
    hand comes to rest; with the pads' former near-rigid contact there (solref 0.01 s,
    impedance 0.9999, the links' priority removed) the tip chatters on the finger, sliding
    and bouncing every 0.24 s, above the sweep's settle bound (as it chattered on a fixed
    block: tests/test_allegro_press.py)."""
    from robot_agents.tuning.claims import SETTLE_SPEED

    path = Path(str(AllegroHandRight.mjcf_path))
    links_first = '<geom group="3" rgba="0.55 0.65 0.8 0.5" priority="2"/>'
    source = path.read_text()
    assert links_first in source
    pads = 'condim="4" priority="1"/>'
    assert source.count(pads) == 1
    near_rigid_pads = 'condim="4" priority="1" solref="0.01 1" solimp="0.9999 0.9999 0.01"/>'
    source = source.replace(pads, near_rigid_pads)
    (tmp_path / path.name).write_text(source.replace(links_first, '<geom group="3" rgba="0.55 0.65 0.8 0.5"/>'))
    pads_everywhere = type("PadsEverywhere", (AllegroHandRight,), {"uid": "", "mjcf_path": tmp_path / path.name})
    assert thumb_speed_after_pressing_the_index(AllegroHandRight) < SETTLE_SPEED / 10
    assert thumb_speed_after_pressing_the_index(pads_everywhere) > SETTLE_SPEED
