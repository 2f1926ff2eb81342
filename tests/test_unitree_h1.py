"""Unitree H1: it stands on its own legs from ManiSkill's ``standing`` pose, its masses,
joint ranges and kinematics are the public model's, its actions follow ManiSkill's
order, and random actions in every mode stay stable (numbers, not smoke)."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.robots.unitree.h1 import (
    H1_DRIVES,
    MANISKILL_JOINTS,
    STANDING_HEIGHT,
    STANDING_LEG,
    UnitreeH1,
)
from tests.chain_check import axis_rotation, transform

X, Y, Z = np.eye(3)

#: MuJoCo Menagerie unitree_h1/h1.xml: body masses (kg), one side for the limbs.
MASSES = {
    "pelvis": 5.39,
    "hip_yaw_link": 2.244,
    "hip_roll_link": 2.232,
    "hip_pitch_link": 4.152,
    "knee_link": 1.721,
    "ankle_link": 0.446,
    "torso_link": 17.789,
    "shoulder_pitch_link": 1.033,
    "shoulder_roll_link": 0.793,
    "shoulder_yaw_link": 0.839,
    "elbow_link": 0.669,
}
#: Menagerie's joint ranges (rad), left side; the right side's roll and yaw are mirrored.
RANGES = {
    "hip_yaw": (-0.43, 0.43),
    "hip_roll": (-0.43, 0.43),
    "hip_pitch": (-1.57, 1.57),
    "knee": (-0.26, 2.05),
    "ankle": (-0.87, 0.52),
    "shoulder_pitch": (-2.87, 2.87),
    "shoulder_roll": (-0.34, 3.11),
    "shoulder_yaw": (-1.3, 4.45),
    "elbow": (-1.25, 2.61),
}
MIRRORED = ("shoulder_roll", "shoulder_yaw")
#: Joint origins in the parent link (m) and axes, written out from Menagerie's h1.xml /
#: Unitree's URDF; ``s`` is +1 for the left side, -1 for the right.
LEG = (
    ((0.0, 0.0875, -0.1742), Z),  # hip yaw, on the pelvis
    ((0.039468, 0.0, 0.0), X),  # hip roll
    ((0.0, 0.11536, 0.0), Y),  # hip pitch
    ((0.0, 0.0, -0.4), Y),  # knee
    ((0.0, 0.0, -0.4), Y),  # ankle
)
#: Unitree's URDF foot box: centre in the ankle link (m), half sizes.
FOOT_CENTRE, FOOT_HALF = (0.05, 0.0, -0.05), (0.14, 0.015, 0.012)
#: Arm: (origin, fixed roll about x of the link frame (rad, URDF rpy), joint axis).
ARM = (
    ((0.0055, 0.15535, 0.42999), 0.43633, Y),  # shoulder pitch, on the torso
    ((-0.0055, 0.0565, -0.0165), -0.43633, X),  # shoulder roll
    ((0.0, 0.0, -0.1343), 0.0, Z),  # shoulder yaw
    ((0.0185, 0.0, -0.198), 0.0, Y),  # elbow
)


def mirror(vector: tuple[float, float, float], side: float) -> np.ndarray:
    return np.array([vector[0], side * vector[1], vector[2]])


def leg_chain(pelvis: np.ndarray, q: np.ndarray, side: float) -> np.ndarray:
    """The ankle link's pose (4x4) chained from the pelvis and the leg's joint origins."""
    pose = pelvis
    for (origin, axis), angle in zip(LEG, q, strict=True):
        pose = pose @ transform(axis_rotation(axis, float(angle)), mirror(origin, side))
    return pose


def arm_chain(torso: np.ndarray, q: np.ndarray, side: float) -> np.ndarray:
    """The elbow link's pose (4x4) chained from the torso link and the arm's origins."""
    pose = torso
    for (origin, roll, axis), angle in zip(ARM, q, strict=True):
        fixed = axis_rotation(X, side * roll)
        pose = pose @ transform(fixed @ axis_rotation(axis, float(angle)), mirror(origin, side))
    return pose


def body_pose(scene: ra.Scene, name: str) -> np.ndarray:
    body = scene.world.datas[0].body(scene.agents[0].prefix + name)
    return transform(body.xmat.reshape(3, 3), body.xpos.copy())


def side_joints(side: str, kinds: tuple[str, ...]) -> list[str]:
    return [f"{side}_{kind}_joint" for kind in kinds]


def tilt_deg(quat: np.ndarray) -> float:
    """Angle (deg) between the body's up axis and the world's, from a (w, x, y, z) quaternion."""
    _, x, y, _ = quat
    return math.degrees(math.acos(float(np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0))))


def stand(cls: type[ra.Agent] | str, seconds: float = 5.0) -> dict[str, float | bool | set[str]]:
    """Reset to ``standing`` and repeat the default mode's hold action (taken once);
    the pelvis heights, the largest tilt, joint error and the bodies touching the floor."""
    scene = ra.Scene(cls)
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    model, data = scene.model, scene.world.datas[0]
    keyframe = agent.qpos[0].copy()
    hold = hold_action(agent)
    heights, tilt, error, touching = [], 0.0, 0.0, set()
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(hold)
        scene.step()
        pose = agent.base_pose[0]
        heights.append(float(pose[2]))
        tilt = max(tilt, tilt_deg(pose[3:]))
        error = max(error, float(np.max(np.abs(agent.qpos[0] - keyframe))))
        for contact in data.contact[: data.ncon]:
            bodies = {int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])}
            if 0 in bodies:  # the floor (world body)
                touching |= {model.body(b).name.removeprefix(agent.prefix) for b in bodies - {0}}
    standing = bool(agent.is_standing()[0]) and not bool(agent.is_fallen()[0])
    scene.close()
    last = np.array(heights[round(scene.control_freq) :])
    return {
        "standing": standing,
        "height": heights[-1],
        "spread": float(last.max() - last.min()),
        "tilt": tilt,
        "error": error,
        "touching": touching,
    }


# ---------------------------------------------------------------- standing
def test_stands_on_its_feet_for_5_s_from_standing() -> None:
    """ManiSkill's ``standing``, the default mode's hold action: the pelvis settles 4.2 mm
    below the keyframe (1.9 mm of it the drop onto the floor) and stays within 1 cm over
    the last 4 s, upright within 2 deg, joints within 0.05 rad, the feet alone on the floor."""
    result = stand("unitree_h1")
    assert UnitreeH1.default_mode() == "pd_joint_pos"
    assert result["spread"] < 0.01
    assert STANDING_HEIGHT - result["height"] == pytest.approx(0.0042, abs=0.001)
    assert result["tilt"] < 2.0
    assert result["error"] < 0.05
    assert result["touching"] == {"left_ankle_link", "right_ankle_link"}
    assert result["standing"]  # agent.is_standing, not is_fallen


class ManiSkillGainsH1(UnitreeH1):
    """ManiSkill's gains (1000 N*m/rad, 100 N*m*s/rad) on every joint."""

    actuators: ClassVar = tuple(dataclasses.replace(d, stiffness=1000.0, damping=100.0) for d in H1_DRIVES)


def test_maniskill_gains_let_the_loaded_legs_give_and_the_pelvis_lean_back() -> None:
    """Why the leg gains are not ManiSkill's: at 1000 N*m/rad the knees bend 0.056 rad under
    the standing load and the pelvis leans back 6.5 deg onto the heels."""
    result = stand(ManiSkillGainsH1)
    assert result["tilt"] > 5.0
    assert result["error"] > 0.05


# ---------------------------------------------------------------- the public model's numbers
def test_masses_are_menageries() -> None:
    scene = ra.Scene("unitree_h1")
    model, prefix = scene.model, scene.agents[0].prefix
    total = 0.0
    for name, mass in MASSES.items():
        sides = ("",) if name in ("pelvis", "torso_link") else ("left_", "right_")
        for side in sides:
            assert model.body(prefix + side + name).mass[0] == pytest.approx(mass, abs=1e-9), side + name
            total += mass
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(prefix)]
    assert float(model.body_mass[robot].sum()) == pytest.approx(total, abs=1e-9)
    assert total == pytest.approx(51.437, abs=1e-9)
    scene.close()


def test_joint_ranges_are_menageries() -> None:
    scene = ra.Scene("unitree_h1")
    agent = scene.agents[0]
    limits = dict(zip(agent.joint_names, agent.qpos_limits, strict=True))
    assert len(limits) == 19
    assert tuple(limits["torso_joint"]) == pytest.approx((-2.35, 2.35))
    for kind, (low, high) in RANGES.items():
        assert tuple(limits[f"left_{kind}_joint"]) == pytest.approx((low, high)), kind
        right = (-high, -low) if kind in MIRRORED else (low, high)
        assert tuple(limits[f"right_{kind}_joint"]) == pytest.approx(right), kind
    scene.close()


def test_feet_at_standing_match_the_chained_joint_origins() -> None:
    """The soles lie 1.9 mm above the floor, level, 0.4061 m apart, centred 5 cm ahead of
    the ankles directly below the hips (the pose's hip, knee and ankle angles cancel)."""
    scene = ra.Scene("unitree_h1")
    scene.reset(keyframes="standing")
    hip_pitch, knee, ankle = STANDING_LEG
    pelvis = transform(np.eye(3), np.array([0.0, 0.0, STANDING_HEIGHT]))
    for side, s in (("left", 1.0), ("right", -1.0)):
        ankle_pose = leg_chain(pelvis, np.array([0.0, 0.0, hip_pitch, knee, ankle]), s)
        centre = ankle_pose[:3, :3] @ np.array(FOOT_CENTRE) + ankle_pose[:3, 3]
        foot = scene.world.datas[0].geom(scene.agents[0].prefix + f"{side}_foot")
        np.testing.assert_allclose(foot.xpos, centre, atol=1e-3)
        np.testing.assert_allclose(foot.xmat.reshape(3, 3), np.eye(3), atol=1e-9)  # level
        assert foot.xpos[2] - FOOT_HALF[2] == pytest.approx(0.0019, abs=1e-4)
        assert foot.xpos[1] == pytest.approx(s * (0.0875 + 0.11536), abs=1e-9)
    scene.close()


def test_limbs_follow_the_public_joint_origins_at_random_poses() -> None:
    scene = ra.Scene("unitree_h1")
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    legs = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle")
    arms = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow")
    for _ in range(5):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        pelvis = body_pose(scene, "pelvis")
        torso = pelvis @ transform(axis_rotation(Z, q[agent.joint_names.index("torso_joint")]), np.zeros(3))
        np.testing.assert_allclose(body_pose(scene, "torso_link"), torso, atol=1e-9)
        for side, s in (("left", 1.0), ("right", -1.0)):
            leg_q = q[[agent.joint_names.index(j) for j in side_joints(side, legs)]]
            np.testing.assert_allclose(body_pose(scene, f"{side}_ankle_link"), leg_chain(pelvis, leg_q, s), atol=1e-9)
            arm_q = q[[agent.joint_names.index(j) for j in side_joints(side, arms)]]
            # 1e-5: the model's shoulder rotations are Menagerie's 6-digit quaternions of
            # the URDF's 0.43633 rad
            np.testing.assert_allclose(body_pose(scene, f"{side}_elbow_link"), arm_chain(torso, arm_q, s), atol=1e-5)
    scene.close()


# ---------------------------------------------------------------- actions
def test_actions_follow_maniskills_joint_order_and_bounds() -> None:
    """One part, ``body``, over ManiSkill's 19 joints in ManiSkill's order: absolute targets
    within the joint limits, deltas of at most 0.2 rad (ManiSkill's), normalized."""
    scene = ra.Scene("unitree_h1", control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert list(agent.controller.parts) == ["body"]
    assert agent.controller.parts["body"].config.joint_names == MANISKILL_JOINTS
    limits = agent.qpos_limits[[agent.joint_names.index(j) for j in MANISKILL_JOINTS]]
    np.testing.assert_allclose(agent.single_action_space.low, limits[:, 0].astype(np.float32))
    np.testing.assert_allclose(agent.single_action_space.high, limits[:, 1].astype(np.float32))
    scene.close()
    delta = ra.Scene("unitree_h1", control_modes="pd_joint_delta_pos")
    controller = delta.agents[0].controller.parts["body"]
    np.testing.assert_allclose(controller.to_raw(np.ones((1, 19)))[0], 0.2)
    delta.close()


@pytest.mark.parametrize("mode", list(UnitreeH1.modes()))
def test_random_actions_for_10_s_stay_finite_and_stable(mode: str) -> None:
    """It falls over (random targets over the whole range: ``is_fallen``), but nothing blows up, no
    joint is pressed more than 0.15 rad past its stop, and the same actions replay exactly."""
    scene = ra.Scene("unitree_h1", control_modes=mode)
    agent = scene.agents[0]
    space = agent.single_action_space
    limits = agent.qpos_limits
    runs = []
    for _ in range(2):
        scene.reset()
        rng = np.random.default_rng(0)
        worst, fell = 0.0, False
        for _ in range(10 * scene.control_freq):
            agent.set_action(rng.uniform(space.low, space.high))
            scene.step()
            fell = fell or bool(agent.is_fallen()[0])
            q = agent.qpos[0]
            worst = max(worst, float(np.max(np.maximum(q - limits[:, 1], limits[:, 0] - q))))
        state = scene.world.get_state()
        assert np.all(np.isfinite(state))
        assert not np.any(scene.world.instability_counts())
        assert worst < 0.15
        assert fell  # thrown down: a body other than a foot touched the floor
        runs.append(state)
    np.testing.assert_array_equal(runs[0], runs[1])
    scene.close()
