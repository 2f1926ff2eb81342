"""Unitree G1, full (ManiSkill's ``unitree_g1`` and ``unitree_g1_simplified_legs``): it
stands on its own legs from ManiSkill's ``standing`` pose, its masses, joint ranges and
kinematics are the URDF's (its leg joint origins chained here; the arms' and hands'
chains and numbers are those of tests/test_unitree_g1.py, the same piece), its actions
follow ManiSkill's order, random actions in every mode stay stable, and the simplified
variant collides only through its shins and feet (numbers, not smoke)."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.robots.unitree.g1_full import (
    G1_FULL_DRIVES,
    LEG_KINDS,
    MANISKILL_JOINTS,
    MANISKILL_STANDING,
    SIMPLIFIED_COLLISION_LINKS,
    STANDING_HEIGHT,
    UnitreeG1,
)
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform
from tests.test_unitree_g1 import (
    ARM_KINDS,
    LEFT_RANGES,
    MIRRORED,
    arm_chain,
    assert_masses_are_the_urdfs,
    body_pose,
    joints,
    mirror,
)

UID = "unitree_g1"
SIMPLIFIED = "unitree_g1_simplified_legs"
X, Y, Z = np.eye(3)

# ---------------------------------------------------------------- the URDF's numbers
# ManiSkill 3.0.1 assets/robots/g1_humanoid/g1.urdf, written out here (left side; the
# right side mirrors y), not read from our model.
#: Leg: (origin in the parent, fixed pitch about y (URDF rpy), axis), from the pelvis.
LEG = (
    ((0.0, 0.06445, -0.1027), -0.34907, Y),  # hip pitch
    ((0.0, 0.0523, 0.0), 0.0, X),  # hip roll
    ((0.01966, -0.0012139, -0.1241), 0.0, Z),  # hip yaw
    ((-0.078292, -0.0017335, -0.177225), 0.5096, Y),  # knee
    ((0.0, 0.0040687, -0.30007), -0.16053, Y),  # ankle pitch
    ((0.0, 0.0, -0.017558), 0.0, X),  # ankle roll
)
#: Leg joint ranges (rad), left side (the right hip roll's is mirrored).
LEG_RANGES = {
    "hip_pitch": (-2.35, 3.05),
    "hip_roll": (-0.26, 2.53),
    "hip_yaw": (-2.75, 2.75),
    "knee": (-0.33489, 2.5449),
    "ankle_pitch": (-0.68, 0.73),
    "ankle_roll": (-0.2618, 0.2618),
}
#: The URDF's (effort N*m, velocity rad/s) per leg joint.
LEG_LIMITS = {
    "hip_pitch": (88.0, 32.0),
    "hip_roll": (88.0, 32.0),
    "hip_yaw": (88.0, 32.0),
    "knee": (139.0, 20.0),
    "ankle_pitch": (40.0, 53.0),
    "ankle_roll": (40.0, 53.0),
}
#: The foot mesh's (ankle_roll_link.STL) bounds in its link (m): x, y, lowest z.
FOOT_X, FOOT_Y, SOLE_Z = (-0.0641, 0.1383), 0.033, -0.034


def leg_chain(pelvis: np.ndarray, q: np.ndarray, side: float) -> np.ndarray:
    """The ankle roll link's pose (4x4) chained from the pelvis and the leg's origins."""
    pose = pelvis
    for (origin, pitch, axis), angle in zip(LEG, q, strict=True):
        pose = pose @ transform(axis_rotation(Y, pitch) @ axis_rotation(axis, float(angle)), mirror(origin, side))
    return pose


def tilt_deg(quat: np.ndarray) -> float:
    """Angle (deg) between the body's up axis and the world's, from a (w, x, y, z) quaternion."""
    _, x, y, _ = quat
    return math.degrees(math.acos(float(np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0))))


def stand(cls: type[ra.Agent] | str, seconds: float = 5.0) -> dict[str, float | bool | set[str]]:
    """Reset to ``standing`` and repeat the default mode's hold action (taken once): the
    last pelvis height, its spread after the first second, the largest tilt and joint
    error, and the bodies touching the floor."""
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


# ---------------------------------------------------------------- data
def test_masses_are_the_urdfs() -> None:
    """The same 32.2389 kg as the upper-body model (the URDFs' links are the same)."""
    assert_masses_are_the_urdfs(UID)


def test_joint_ranges_and_leg_drives_are_the_urdfs() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    limits = dict(zip(agent.joint_names, agent.qpos_limits, strict=True))
    assert len(limits) == 37
    for kind, (low, high) in {**LEG_RANGES, **LEFT_RANGES}.items():
        assert tuple(limits[f"left_{kind}_joint"]) == pytest.approx((low, high)), kind
        right = (-high, -low) if kind in (*MIRRORED, "hip_roll", "hip_yaw") else (low, high)
        assert tuple(limits[f"right_{kind}_joint"]) == pytest.approx(right), kind
    # the URDF's efforts and speeds; kp 1000 N*m/rad, kv 10 N*m*s/rad on every leg joint
    legs = {d.joints[0]: d for d in G1_FULL_DRIVES[: len(LEG_KINDS)]}
    for kind, (effort, speed) in LEG_LIMITS.items():
        drive = legs[f"(left|right)_{kind}_joint"]
        assert (drive.effort_limit, drive.velocity_limit, drive.stiffness, drive.damping) == (
            effort,
            speed,
            1000.0,
            10.0,
        )
        assert drive.armature == 0.01
    scene.close()


# ---------------------------------------------------------------- kinematics
def test_feet_at_standing_lie_level_just_above_the_floor() -> None:
    """ManiSkill's ``standing`` (pelvis 0.755 m, legs straight): the three pitches cancel,
    the feet are level, their soles (the mesh's lowest points) 1.3 mm above the floor, and
    the foot box spans the mesh's bounds."""
    scene = ra.Scene(UID)
    scene.reset(keyframes="standing")
    data, prefix = scene.world.datas[0], scene.agents[0].prefix
    pelvis = transform(np.eye(3), np.array([0.0, 0.0, STANDING_HEIGHT]))
    for side, s in (("left", 1.0), ("right", -1.0)):
        ankle = leg_chain(pelvis, np.zeros(6), s)
        np.testing.assert_allclose(ankle[:3, :3], np.eye(3), atol=1e-5)
        foot = data.geom(prefix + f"{side}_foot")
        np.testing.assert_allclose(foot.xmat.reshape(3, 3), np.eye(3), atol=1e-5)
        half = scene.model.geom(prefix + f"{side}_foot").size
        centre = np.array([0.5 * sum(FOOT_X), 0.0, SOLE_Z + half[2]])
        np.testing.assert_allclose(foot.xpos, ankle[:3, :3] @ centre + ankle[:3, 3], atol=1e-6)
        np.testing.assert_allclose(half[:2], [0.5 * (FOOT_X[1] - FOOT_X[0]), FOOT_Y], atol=1e-4)
        assert foot.xpos[2] - half[2] == pytest.approx(0.0013, abs=1e-4)
    scene.close()


def test_legs_and_arms_follow_the_urdf_joint_origins_at_random_poses() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        at = dict(zip(agent.joint_names, q, strict=True))
        pelvis = body_pose(scene, "pelvis")
        torso = pelvis @ transform(axis_rotation(Z, at["torso_joint"]), np.zeros(3))
        np.testing.assert_allclose(body_pose(scene, "torso_link"), torso, atol=1e-9)
        for side, s in (("left", 1.0), ("right", -1.0)):
            leg_q = np.array([at[j] for j in joints(side, LEG_KINDS)])
            # 1e-8: the model's pitches are the URDF's angles as 10-digit quaternions
            np.testing.assert_allclose(
                body_pose(scene, f"{side}_ankle_roll_link"), leg_chain(pelvis, leg_q, s), atol=1e-8
            )
            palm = arm_chain(torso, np.array([at[j] for j in joints(side, ARM_KINDS)]), s)
            np.testing.assert_allclose(body_pose(scene, f"{side}_palm_link"), palm, atol=1e-9)
    scene.close()


# ---------------------------------------------------------------- keyframes and actions
def test_standing_is_maniskills_keyframe() -> None:
    scene = ra.Scene(UID)
    scene.reset(keyframes="standing")
    agent = scene.agents[0]
    q = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    assert [q[j] for j in MANISKILL_JOINTS] == list(MANISKILL_STANDING)
    assert (q["left_shoulder_roll_joint"], q["right_elbow_pitch_joint"], q["left_two_joint"]) == (0.2, 0.9, 0.92)
    np.testing.assert_allclose(agent.base_pose[0], [0.0, 0.0, STANDING_HEIGHT, 1.0, 0.0, 0.0, 0.0])
    scene.close()
    assert set(UnitreeG1.keyframe_names()) == {"standing", "rest"}


def test_actions_follow_maniskills_joint_order_and_bounds() -> None:
    """One part, ``body``, over ManiSkill's 37 joints in its order: absolute targets within
    the joint limits, deltas of at most 0.2 rad (ManiSkill's, on every joint)."""
    scene = ra.Scene(UID, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert list(agent.controller.parts) == ["body"]
    assert agent.controller.parts["body"].config.joint_names == MANISKILL_JOINTS
    limits = agent.qpos_limits[[agent.joint_names.index(j) for j in MANISKILL_JOINTS]]
    np.testing.assert_allclose(agent.single_action_space.low, limits[:, 0].astype(np.float32))
    np.testing.assert_allclose(agent.single_action_space.high, limits[:, 1].astype(np.float32))
    scene.close()
    delta = ra.Scene(UID, control_modes="pd_joint_delta_pos")
    np.testing.assert_allclose(delta.agents[0].controller.parts["body"].to_raw(np.ones((1, 37)))[0], 0.2)
    delta.close()
    assert UnitreeG1.default_mode() == "pd_joint_pos"  # ManiSkill's first


# ---------------------------------------------------------------- standing
@pytest.mark.parametrize("uid", [UID, SIMPLIFIED])
def test_stands_on_its_feet_for_5_s_from_standing(uid: str) -> None:
    """The default mode's hold action: the pelvis settles 2.1 mm below the keyframe (1.3
    mm of it the drop onto the floor) and stays within 1 mm over the last 4 s, upright
    within 0.5 deg, joints within 0.05 rad (the arms sag under their own weight), the
    feet alone on the floor."""
    result = stand(uid)
    assert result["spread"] < 0.001, result
    assert STANDING_HEIGHT - result["height"] == pytest.approx(0.0021, abs=0.0005), result
    assert result["tilt"] < 0.5, result
    assert result["error"] < 0.05, result
    assert result["touching"] == {"left_ankle_roll_link", "right_ankle_roll_link"}
    assert result["standing"]  # agent.is_standing, not is_fallen


def test_the_simplified_variant_stands_bit_for_bit_as_the_full_robot() -> None:
    """Standing, the links that lost their contacts touch nothing: the same run."""
    assert stand(SIMPLIFIED, seconds=2.0) == stand(UID, seconds=2.0)


class ManiSkillGainsG1(UnitreeG1):
    """ManiSkill's gains (50 N*m/rad, 1 N*m*s/rad) on the legs."""

    actuators: ClassVar = (
        tuple(dataclasses.replace(d, stiffness=50.0, damping=1.0) for d in G1_FULL_DRIVES[: len(LEG_KINDS)])
        + G1_FULL_DRIVES[len(LEG_KINDS) :]
    )


def test_maniskill_leg_gains_let_it_fall_over() -> None:
    """Why the leg gains are not ManiSkill's: at 50 N*m/rad two ankles (100 N*m/rad) are
    softer than gravity's toppling stiffness about them (m g h, about 230 N*m/rad): it
    falls on its face within 2 s."""
    result = stand(ManiSkillGainsG1, seconds=2.0)
    assert result["tilt"] > 60.0
    assert result["height"] < 0.3
    assert not result["standing"]


# ---------------------------------------------------------------- random actions
@pytest.mark.parametrize("mode", list(UnitreeG1.modes()))
def test_random_actions_for_10_s_stay_finite_and_stable(mode: str) -> None:
    """Random targets over the whole range throw it down, but nothing blows up, no joint
    is pressed more than 0.25 rad past its stop, and the same actions replay exactly."""
    scene = ra.Scene(UID, control_modes=mode)
    agent = scene.agents[0]
    space = agent.single_action_space
    limits = agent.qpos_limits
    runs = []
    for _ in range(2):
        scene.reset()
        rng = np.random.default_rng(0)
        worst = 0.0
        for _ in range(10 * scene.control_freq):
            agent.set_action(rng.uniform(space.low, space.high))
            scene.step()
            q = agent.qpos[0]
            worst = max(worst, float(np.max(np.maximum(q - limits[:, 1], limits[:, 0] - q))))
        state = scene.world.get_state()
        assert np.all(np.isfinite(state))
        assert not np.any(scene.world.instability_counts())
        assert worst < 0.25
        runs.append(state)
    np.testing.assert_array_equal(runs[0], runs[1])
    scene.close()


# ---------------------------------------------------------------- the simplified legs
def test_the_simplified_variant_collides_only_through_its_shins_and_feet() -> None:
    """ManiSkill's ``g1_simplified_legs.urdf`` keeps collision shapes on the knee links
    (the URDF's cylinder) and the feet alone; so do we: the variant's collision geoms are
    the full robot's on those links, the masses and drives the full robot's."""

    def colliding(scene: ra.Scene) -> list[tuple[str, tuple[float, ...]]]:
        model, prefix = scene.model, scene.agents[0].prefix
        shapes = []
        for g in range(model.ngeom):
            body = model.body(int(model.geom_bodyid[g])).name
            if body.startswith(prefix) and (model.geom_contype[g] or model.geom_conaffinity[g]):
                shapes.append((body.removeprefix(prefix), tuple(model.geom_size[g])))
        return sorted(shapes)

    full, simple = ra.Scene(UID), ra.Scene(SIMPLIFIED)
    kept = [shape for shape in colliding(full) if shape[0] in SIMPLIFIED_COLLISION_LINKS]
    assert colliding(simple) == kept
    assert {body for body, _ in kept} == set(SIMPLIFIED_COLLISION_LINKS)
    assert {body for body, _ in colliding(full)} > set(SIMPLIFIED_COLLISION_LINKS) | {"pelvis", "left_palm_link"}
    np.testing.assert_array_equal(full.model.body_mass, simple.model.body_mass)
    np.testing.assert_array_equal(full.model.actuator_gainprm, simple.model.actuator_gainprm)
    full.close()
    simple.close()


# ---------------------------------------------------------------- grasp
def test_the_sweeps_grasp_claim_holds_the_declared_power_grasp_standing() -> None:
    """The claim's cube held in the left hand with the robot standing on the floor (a
    robot whose legs carry it grasps standing: in the air it would fall with its hand)."""
    claim = grasp_claim(UnitreeG1, UnitreeG1.sim_freq or 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 0.002 and "not opposed" not in claim.detail


def test_in_the_air_the_grasp_claim_would_lose_the_cube(monkeypatch: pytest.MonkeyPatch) -> None:
    """Why the claim stands a legged robot on the floor: without one (as for a fixed
    robot) the robot falls with its hand while the weightless cube stays: lost."""
    import robot_agents.tuning.grasp_claim as module

    monkeypatch.setattr(module, "standing_leg_joints", lambda cls: ())
    claim = grasp_claim(UnitreeG1, UnitreeG1.sim_freq or 500, 20, Penetration())
    assert claim is not None and not claim.passed
    assert "cube lost" in claim.detail


def test_the_simplified_variant_declares_no_power_grasp() -> None:
    """Its hands have no contacts (ManiSkill's simplified legs model collides only its
    shins and feet): no grasp claim."""
    cls = ra.get_agent(SIMPLIFIED)
    assert grasp_claim(cls, cls.sim_freq or 500, 20, Penetration()) is None
