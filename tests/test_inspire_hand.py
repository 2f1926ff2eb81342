"""The Inspire RH56DFX hands checked against numbers: the model files are the generator's
output; joint frames against the URDFs' joint origins chained here (right and left, at
random configurations); the couplings' ratios hold in simulation; the URDF's masses and
ranges; keyframes held and random actions in every mode; a cube picked from a pedestal
by the floating hand, palm down, lifted 10 cm and held, the hand's contact forces
carrying its weight; and the power grasp the time-step sweep checks."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions, hold_action
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.robots.inspire import model
from robot_agents.robots.inspire.inspire_hand import (
    CLOSED,
    COUPLED,
    DRIVEN,
    OPEN,
    PALM_UP_MOUNT,
    FixedInspireHandRight,
    hand_part,
)
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform

SIDES = ("right", "left")
FIXED = {side: f"fixed_inspire_hand_{side}" for side in SIDES}
FLOATING = {side: f"floating_inspire_hand_{side}" for side in SIDES}
UIDS = (*FIXED.values(), *FLOATING.values())


# ---------------------------------------------------------------- the generated files
@pytest.mark.parametrize("side", SIDES)
def test_the_model_files_are_the_generators_output(side: str) -> None:
    path = model.ASSETS / f"inspire_hand_{side}.xml"
    assert path.read_text() == model.hand_mjcf(side), "run python -m robot_agents.robots.inspire.model"


def test_an_unknown_side_is_refused() -> None:
    with pytest.raises(ra.UnknownNameError, match="right"):
        model.hand_mjcf("rihgt")


# ---------------------------------------------------------------- independent kinematics
# ManiSkill's inspire_hand_{right,left}.urdf joint origins (xyz, rpy), written out here
# from both files, not read from our model: child link -> (parent, xyz, rpy, joint).
HALF = math.pi / 2
RIGHT_ORIGINS = {
    "wrist_link": ("wrist_base_link", (0.0, 0.0, 0.0785), (HALF, 0.0, HALF), "wrist_pitch_joint"),
    "hand_base_link": ("wrist_link", (0.0, 0.0, 0.0), (0.0, HALF, 0.0), "wrist_yaw_joint"),
    "thumb_metacarpal_base": (
        "hand_base_link",
        (0.02125, 0.0285, 0.01515),
        (-HALF, -0.2617993877991494, 0.0),
        "thumb_CMC_yaw_joint",
    ),
    "thumb_metacarpal": (
        "thumb_metacarpal_base",
        (0.0115, 0.0, -0.00075),
        (-HALF, -0.6831165238198015, 0.0),
        "thumb_CMC_pitch_joint",
    ),
    "thumb_proximal": ("thumb_metacarpal", (0.055852, -0.0040666, 0.0), (0.0, 0.0, -0.0031723), "thumb_MCP_joint"),
    "thumb_distal": ("thumb_proximal", (0.022558, 0.0020717, 0.0), (0.0, 0.0, 0.011853), "thumb_IP_joint"),
    "thumb_tip": ("thumb_distal", (0.024859, -0.000031, 0.0), (0.0, 0.0, 0.0), None),
    "index_proximal": ("hand_base_link", (0.027071, 0.10464, -0.0020953), (-HALF, 0.12457, 1.5359), "index_MCP_joint"),
    "index_middle": ("index_proximal", (0.030445, -0.010275, 0.0), (0.0, 0.0, 0.0016248), "index_PIP_joint"),
    "index_tip": ("index_middle", (0.043944, -0.009147, 0.0), (0.0, 0.0, 0.0), None),
    "middle_proximal": ("hand_base_link", (0.00775, 0.105, -0.0020953), (-HALF, 0.12457, HALF), "middle_MCP_joint"),
    "middle_middle": ("middle_proximal", (0.030445, -0.010275, 0.0), (0.0, 0.0, -0.019795), "middle_PIP_joint"),
    "middle_tip": ("middle_middle", (0.047746, -0.009066, 0.0), (0.0, 0.0, 0.0), None),
    "ring_proximal": ("hand_base_link", (-0.011479, 0.1045, -0.0020953), (-HALF, 0.12457, 1.6232), "ring_MCP_joint"),
    "ring_middle": ("ring_proximal", (0.030445, -0.010275, 0.0), (0.0, 0.0, 0.0016262), "ring_PIP_joint"),
    "ring_tip": ("ring_middle", (0.043944, -0.009147, 0.0), (0.0, 0.0, 0.0), None),
    "pinky_proximal": ("hand_base_link", (-0.030655, 0.10299, -0.0020953), (-HALF, 0.12457, 1.6755), "pinky_MCP_joint"),
    "pinky_middle": ("pinky_proximal", (0.030445, -0.010275, 0.0), (0.0, 0.0, 0.090322), "pinky_PIP_joint"),
    "pinky_tip": ("pinky_middle", (0.035855, -0.009619, 0.0), (0.0, 0.0, 0.0), None),
}
#: The left URDF's origins where they differ from the right's (the rest are equal).
LEFT_CHANGES = {
    "hand_base_link": ((0.0, 0.0, 0.0), (0.0, -HALF, 0.0)),
    "thumb_metacarpal_base": ((0.02125, 0.0285, -0.01515), (HALF, 0.2617993877991494, 0.0)),
    "thumb_metacarpal": ((0.0115, 0.0, 0.00075), (HALF, 0.6831165238198015, 0.0)),
    "thumb_proximal": ((0.055852, -0.0040666, 0.0), (0.0, 0.0, -0.003172)),
    "index_proximal": ((0.027071, 0.10464, 0.0020953), (HALF, -0.12457, 1.5359)),
    "middle_proximal": ((0.00775, 0.105, 0.0020953), (HALF, -0.12457, HALF)),
    "ring_proximal": ((-0.011479, 0.1045, 0.0020953), (HALF, -0.12457, 1.6232)),
    "pinky_proximal": ((-0.030655, 0.10299, 0.0020953), (HALF, -0.12457, 1.6755)),
}
Z = (0.0, 0.0, 1.0)


def origins(side: str) -> dict[str, tuple[str, tuple[float, ...], tuple[float, ...], str | None]]:
    table = dict(RIGHT_ORIGINS)
    if side == "left":
        for link, (xyz, rpy) in LEFT_CHANGES.items():
            table[link] = (table[link][0], xyz, rpy, table[link][3])
    return table


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    rotation: np.ndarray = (
        axis_rotation(Z, yaw) @ axis_rotation((0.0, 1.0, 0.0), pitch) @ axis_rotation((1.0, 0.0, 0.0), roll)
    )
    return rotation


def link_pose(side: str, link: str, q: dict[str, float]) -> np.ndarray:
    """The link's pose (4 x 4) in ``wrist_base_link`` at joint angles ``q`` (by joint name
    without the side's prefix), chained from the URDF's origins."""
    table = origins(side)
    if link == "wrist_base_link":
        return np.eye(4)
    parent, xyz, rpy, joint = table[link]
    pose = link_pose(side, parent, q) @ transform(rpy_matrix(*rpy), np.array(xyz))
    if joint is not None:
        pose = pose @ transform(axis_rotation(Z, q[joint]), np.zeros(3))
    return pose


@pytest.mark.parametrize("side", SIDES)
def test_links_match_the_urdf_chain_at_random_configurations(side: str) -> None:
    scene = ra.Scene(FIXED[side])
    scene.reset()
    agent = scene.agents[0]
    prefix = f"{side}_hand_"
    rng = np.random.default_rng(5)
    low, high = scene.model.jnt_range.T
    for _ in range(5):
        q = rng.uniform(low, high)  # every joint, the coupled ones too: kinematics only
        named = {name.removeprefix(prefix): float(v) for name, v in zip(agent.joint_names, q, strict=True)}
        for link in RIGHT_ORIGINS:
            measured = agent.frame_pose(prefix + link, q, relative_to=prefix + "wrist_base_link")[0]
            expected = link_pose(side, link, named)
            np.testing.assert_allclose(measured[:3], expected[:3, 3], atol=1e-6)
            np.testing.assert_allclose(quat_to_matrix(measured[3:]), expected[:3, :3], atol=1e-5)
    scene.close()


def test_the_left_hand_is_the_right_one_mirrored() -> None:
    """At the same joint angles every left link is the right one reflected through the
    wrist base's y-z plane (x negated)."""
    q = {joint: 0.0 for *_, joint in RIGHT_ORIGINS.values() if joint}
    q |= {"index_MCP_joint": -0.7, "thumb_CMC_yaw_joint": -0.9, "wrist_pitch_joint": 0.2, "wrist_yaw_joint": -0.3}
    for link in RIGHT_ORIGINS:
        right, left = link_pose("right", link, q)[:3, 3], link_pose("left", link, q)[:3, 3]
        np.testing.assert_allclose(left, right * (-1.0, 1.0, 1.0), atol=2e-6)


def test_the_chain_check_can_fail() -> None:
    """A 1 mm change in one origin of the chain written here moves the index tip 1 mm."""
    q = {joint: 0.0 for *_, joint in RIGHT_ORIGINS.values() if joint}
    before = link_pose("right", "index_tip", q)[:3, 3]
    saved = RIGHT_ORIGINS["index_middle"]
    RIGHT_ORIGINS["index_middle"] = (saved[0], (0.030445, -0.010275, 0.001), saved[2], saved[3])
    try:
        assert np.linalg.norm(link_pose("right", "index_tip", q)[:3, 3] - before) == pytest.approx(0.001)
    finally:
        RIGHT_ORIGINS["index_middle"] = saved


# ---------------------------------------------------------------- couplings, masses, ranges
#: The URDF's mimic relations: follower -> (leader, multiplier, offset).
COUPLINGS = {
    **{f"{f}_PIP_joint": (f"{f}_MCP_joint", 1.06399, -0.167348) for f in ("index", "middle", "ring", "pinky")},
    "thumb_MCP_joint": ("thumb_CMC_pitch_joint", 4.0 / 3.0, -0.08144869842640205),
    "thumb_IP_joint": ("thumb_CMC_pitch_joint", 2.0 / 3.0, -0.040724349213201026),
}


@pytest.mark.parametrize("uid", [FIXED["right"], FLOATING["left"]])
def test_coupled_joints_follow_with_the_urdfs_ratios(uid: str) -> None:
    """Closing in ``pd_joint_pos`` (2 s), every coupled joint sits where its mimic
    relation puts it (within 1 mrad), in the keyframe and closed."""
    scene = ra.Scene(uid, control_modes="pd_joint_pos")
    scene.reset()
    agent = scene.agents[0]
    side = "right" if "right" in uid else "left"
    prefix = f"{side}_hand_"
    names = list(agent.joint_names)

    def check() -> None:
        q = agent.qpos[0]
        for follower, (leader, multiplier, offset) in COUPLINGS.items():
            assert q[names.index(prefix + follower)] == pytest.approx(
                offset + multiplier * q[names.index(prefix + leader)], abs=1e-3
            ), follower

    check()
    action = hold_action(agent)
    action[-len(DRIVEN) :] = CLOSED  # the hand's slice comes last (after the mount's)
    for _ in range(2 * scene.control_freq):
        agent.set_action(action)
        scene.step()
    q = agent.qpos[0]
    assert q[names.index(prefix + "index_MCP_joint")] == pytest.approx(-1.34, abs=0.01)
    assert q[names.index(prefix + "index_PIP_joint")] == pytest.approx(1.06399 * -1.34 - 0.167348, abs=0.01)
    check()
    scene.close()


#: The URDF's link masses (kg), right hand.
MASSES = {
    "wrist_base_link": 0.065373,
    "wrist_link": 0.00056124,
    "hand_base_link": 0.19286,
    "thumb_metacarpal_base": 0.0015178,
    "thumb_metacarpal": 0.026112,
    "thumb_proximal": 0.0076245,
    "thumb_distal": 0.0032026,
    "index_proximal": 0.0074557,
    "index_middle": 0.0044472,
    "middle_proximal": 0.0074556,
    "middle_middle": 0.0048916,
    "ring_proximal": 0.0074556,
    "ring_middle": 0.0044472,
    "pinky_proximal": 0.0074556,
    "pinky_middle": 0.00358,
}
#: The URDF's ranges (rad), in our qpos order (without the prefix).
RANGES = {
    "wrist_pitch_joint": (-0.39549160850191506, 0.3860668305411457),
    "wrist_yaw_joint": (-0.445058959258554, 0.445058959258554),
    "thumb_CMC_yaw_joint": (-1.3089969389957472, 0.0),
    "thumb_CMC_pitch_joint": (-0.4799655442984406, 0.0),
    "thumb_MCP_joint": (-0.8, 0.0),
    "thumb_IP_joint": (-0.4, 0.0),
    **{
        f"{f}_{j}": r
        for f in ("index", "middle", "ring", "pinky")
        for j, r in (("MCP_joint", (-1.34, 0.0)), ("PIP_joint", (-1.5930946, 0.04545)))
    },
}


@pytest.mark.parametrize("side", SIDES)
def test_masses_ranges_and_drives_match_the_sources(side: str) -> None:
    scene = ra.Scene(FIXED[side])
    m = scene.model
    agent = scene.agents[0]
    prefix = f"{side}_hand_"
    for body, mass in MASSES.items():
        # the index proximal weighs 0.0074557 kg, the others 0.0074556: ours are all the latter
        assert m.body(agent.prefix + prefix + body).mass[0] == pytest.approx(mass, abs=2e-7), body
    assert sum(MASSES.values()) == pytest.approx(0.3444396, abs=1e-6)
    assert [n.removeprefix(prefix) for n in agent.joint_names] == list(RANGES)
    ranges = np.array([m.joint(agent.prefix + name).range for name in agent.joint_names])
    np.testing.assert_allclose(ranges, list(RANGES.values()), atol=1e-8)
    # the six actuators and the wrist are driven (1 N*m, the URDF's effort), the rest follow
    assert list(agent.part_joints["hand"]) == [prefix + j for j in DRIVEN]
    driven = sorted(m.joint(int(m.actuator_trnid[i, 0])).name for i in range(m.nu))
    assert driven == sorted(agent.prefix + prefix + j for j in DRIVEN) and len(COUPLED) == 6
    np.testing.assert_allclose(m.actuator_forcerange, [(-1.0, 1.0)] * len(DRIVEN))
    scene.close()


# ---------------------------------------------------------------- keyframes, stability
@pytest.mark.parametrize("uid", UIDS)
def test_keyframes_hold_and_random_actions_stay_stable(uid: str) -> None:
    held = check_holds(ra.get_agent(uid), seconds=2.0)
    assert held.passed, held.detail
    random = check_random_actions(ra.get_agent(uid), seconds=5.0)
    assert random.passed, random.detail


@pytest.mark.parametrize("side", SIDES)
def test_the_fixed_hand_holds_palm_up_on_its_mount(side: str) -> None:
    scene = ra.Scene(FIXED[side], robot_poses=[PALM_UP_MOUNT])
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    action = hold_action(agent)
    drift = 0.0
    for _ in range(2 * scene.control_freq):
        agent.set_action(action)
        scene.step()
        drift = max(drift, float(np.max(np.abs(agent.qpos[0] - agent.keyframe_qpos("palm_up")))))
    assert drift < 0.01
    # palm up: the palm's face (its frame's +z on the right, -z on the left) faces the sky
    palm = agent.frame_pose(f"{side}_hand_hand_base_link")[0]
    normal = quat_to_matrix(palm[3:])[:, 2] * (1.0 if side == "right" else -1.0)
    assert normal[2] > 0.99
    scene.close()


def test_maniskill_keyframe_poses_on_the_floating_mount() -> None:
    """The floating hand's keyframes put its wrist base where ManiSkill's keyframe poses
    do: 0.4 m up, turned -pi/2 about z (palm_side), then pi/2 about x (palm_up)."""
    scene = ra.Scene(FLOATING["right"])
    for key, quat in (("palm_side", (math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))), ("palm_up", (0.5, 0.5, -0.5, -0.5))):
        scene.reset(keyframes=key)
        pose = scene.agents[0].frame_pose("right_hand_wrist_base_link")[0]
        np.testing.assert_allclose(pose[:3], (0.0, 0.0, 0.4), atol=1e-9)
        assert abs(float(np.dot(pose[3:], quat))) == pytest.approx(1.0, abs=1e-9), key
    scene.close()


# ---------------------------------------------------------------- a pick
CUBE_EDGE = 0.04
CUBE_MASS = 0.05
THUMB_LINKS = ("thumb_metacarpal", "thumb_proximal", "thumb_distal")


@pytest.mark.parametrize("side", SIDES)
def test_the_floating_hand_picks_a_cube_palm_down_and_carries_its_weight(side: str) -> None:
    """Palm down over a 4 cm, 50 g cube on a pedestal (the hand open around it), the
    hand closes (2 s), lifts it 10 cm (1 s) and holds it (2 s): the hand's contacts
    carry the cube's weight (within 0.05 N), the thumb and the fingers press on it from
    opposite sides, and the cube stays in the palm; opened, it drops."""
    uid = FLOATING[side]
    # where the palm-down grasp puts the cube: the declared power-grasp cube, palm down
    probe = ra.Scene(uid, control_modes="pd_joint_pos")
    probe.reset(keyframes="palm_up")
    agent = probe.agents[0]
    names = list(agent.joint_names)
    q = agent.qpos[0].copy()
    q[names.index("root_y_rot_joint")] = 0.75 * math.pi  # a half turn about y from palm_up
    grasp = hand_part(side).power_grasp
    assert grasp is not None
    palm = agent.frame_pose(f"{side}_hand_hand_base_link", q)[0]
    centre = palm[:3] + quat_to_matrix(palm[3:]) @ np.array(grasp.cube_centre)
    probe.close()
    half = 0.5 * CUBE_EDGE
    cube = ra.Prop("cube", "box", (half,) * 3, pos=tuple(centre), mass=CUBE_MASS)
    top = float(centre[2]) - half
    pedestal = ra.Prop("pedestal", "box", (0.012, 0.012, 0.5 * top), pos=(centre[0], centre[1], 0.5 * top), mass=None)
    scene = ra.Scene(uid, props=[cube, pedestal], control_modes="pd_joint_pos")
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    hand = [names.index(f"{side}_hand_{j}") for j in DRIVEN]
    q[hand] = OPEN
    agent.reset(qpos=q)
    mount = q[:6].copy()

    def act(hand_target: tuple[float, ...], lift: float = 0.0, steps: int = 1) -> None:
        for _ in range(steps):
            target = mount.copy()
            target[2] += lift
            agent.set_action(np.concatenate([target, hand_target]))
            scene.step()

    act(OPEN, steps=10)
    assert not agent.is_grasping("cube")[0]
    act(CLOSED, steps=2 * scene.control_freq)
    assert agent.is_grasping("cube")[0]
    for i in range(scene.control_freq):  # lift 10 cm over 1 s
        act(CLOSED, lift=0.1 * (i + 1) / scene.control_freq)
    act(CLOSED, lift=0.1, steps=2 * scene.control_freq)
    body = int(scene.model.body("cube").id)
    cube_pose = scene.body_pose("cube")[0]
    assert cube_pose[2] - centre[2] == pytest.approx(0.1, abs=0.01)
    palm = agent.frame_pose(f"{side}_hand_hand_base_link")[0]
    in_palm = quat_to_matrix(palm[3:]).T @ (cube_pose[:3] - palm[:3])
    assert np.linalg.norm(in_palm - np.array(grasp.cube_centre)) < 0.01
    assert agent.is_grasping("cube")[0]
    hand_bodies = [
        i for i in range(scene.model.nbody) if scene.model.body(i).name.startswith(f"{agent.prefix}{side}_hand_")
    ]
    thumb = [int(scene.model.body(f"{agent.prefix}{side}_hand_{link}").id) for link in THUMB_LINKS]
    carried, from_pedestal = scene.world.contact_forces([hand_bodies, [int(scene.model.body("pedestal").id)]], body)[0]
    assert not np.any(from_pedestal)
    np.testing.assert_allclose(carried, (0.0, 0.0, CUBE_MASS * 9.81), atol=0.05)
    # the thumb presses on one side of the cube and the fingers on the other
    by_thumb, by_fingers = scene.world.contact_forces([thumb, [b for b in hand_bodies if b not in thumb]], body)[0]
    assert np.linalg.norm(by_thumb) > 1.0
    assert float(np.dot(by_thumb, by_fingers)) < 0.0
    act(OPEN, lift=0.1, steps=20)
    assert not agent.is_grasping("cube")[0]
    assert scene.body_pose("cube")[0, 2] < cube_pose[2] - 0.05  # it dropped
    scene.close()


# ---------------------------------------------------------------- the sweep's grasp claim
@pytest.mark.parametrize("uid", UIDS)
def test_the_sweeps_grasp_claim_holds_the_declared_power_grasp(uid: str) -> None:
    """The declared 4 cm cube (water's density, 64 g) held against a 1 g pull away from
    the palm at the default step, the finger forces opposed."""
    cls = ra.get_agent(uid)
    claim = grasp_claim(cls, cls.sim_freq or 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.001 and "not opposed" not in claim.detail


class _NeverCloses(FixedInspireHandRight):
    """The right hand whose power grasp is its open pose: the fingers never close."""

    parts = (dataclasses.replace(hand_part("right"), closed=OPEN),)


def test_the_sweeps_grasp_claim_fails_when_the_hand_does_not_close() -> None:
    claim = grasp_claim(_NeverCloses, FixedInspireHandRight.sim_freq or 500, 20, Penetration())
    assert claim is not None and not claim.passed
    assert "not opposed" in claim.detail


def test_a_hand_on_an_arm_takes_absolute_targets_in_the_absolute_modes() -> None:
    """The floating hands' ``pd_joint_pos`` gives the hand absolute targets (as
    ManiSkill's), the delta modes deltas (+-0.1 rad)."""
    modes = ra.get_agent(FLOATING["right"]).modes()
    for mode, delta in (("pd_joint_pos", False), ("pd_ee_pose", False), ("pd_joint_delta_pos", True)):
        config = modes[mode]["hand"]  # type: ignore[index]
        assert config.use_delta is delta, mode
    assert modes["pd_joint_delta_pos"]["hand"].upper == 0.1  # type: ignore[index]


def test_the_hand_mounted_on_an_arm_brings_its_part_drives_and_couplings() -> None:
    """The right hand as a piece on the xArm6's flange: its hand part (power grasp on the
    prefixed palm), its eight drives and six couplings come along, and the arm's absolute
    modes give the hand absolute targets."""
    from robot_agents.robots.inspire.inspire_hand import InspireHandRight
    from robot_agents.robots.ufactory.xarm6 import XArm6NoGripper

    class ArmWithHand(XArm6NoGripper):
        uid = "arm_with_inspire_test"
        attachments = (ra.Attachment(InspireHandRight, at="link_eef", prefix="hand/"),)

    checked = ArmWithHand.check()
    hand = next(p for p in checked.parts if isinstance(p, ra.Hand))
    assert hand.power_grasp is not None and hand.power_grasp.link == "hand/right_hand_hand_base_link"
    modes = ArmWithHand.modes()
    name = hand.name  # the piece's part, named with its prefix
    assert modes["pd_joint_pos"][name].use_delta is False  # type: ignore[index,union-attr]
    assert modes["pd_joint_delta_pos"][name].use_delta is True  # type: ignore[index,union-attr]
    assert modes["pd_joint_pos"][name].joint_names == tuple(f"hand/right_hand_{j}" for j in DRIVEN)  # type: ignore[index,union-attr]
    spec = ArmWithHand.build_spec()
    couplings = [eq for eq in spec.equalities if eq.name1.startswith("hand/")]
    assert len(couplings) == len(COUPLED)
