"""The MuJoCo humanoid (ManiSkill's ``humanoid``): its geometry, masses,
ranges and torque limits are dm_control's model's, its actions follow ManiSkill's
orders, it stands from ``stand`` with our gains and not with ManiSkill's, and ManiSkill's
``squat`` needs more ankle torque than the model's motors give (numbers, not smoke)."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.robots.humanoid.humanoid import (
    DELTA_JOINTS,
    GEAR,
    MANISKILL_JOINTS,
    SQUAT,
    SQUAT_KEYFRAME,
    STAND_HEIGHT,
    Humanoid,
    joint_kind,
)
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.standing_claim import standing_claim
from tests.chain_check import axis_rotation, transform

X, Y, Z = np.eye(3)
DENSITY = 1000.0  # MuJoCo's default, the model's (kg/m^3)

#: dm_control humanoid.xml (ManiSkill 3.0.1's copy): joint ranges (deg).
RANGES_DEG = {
    "abdomen_z": (-45, 45),
    "abdomen_y": (-75, 30),
    "abdomen_x": (-35, 35),
    "right_hip_x": (-25, 5),
    "right_hip_z": (-60, 35),
    "right_hip_y": (-110, 20),
    "left_hip_x": (-25, 5),
    "left_hip_z": (-60, 35),
    "left_hip_y": (-120, 20),
    "right_knee": (-160, 2),
    "left_knee": (-160, 2),
    "right_ankle_y": (-50, 50),
    "right_ankle_x": (-50, 50),
    "left_ankle_y": (-50, 50),
    "left_ankle_x": (-50, 50),
    "right_shoulder1": (-85, 60),
    "right_shoulder2": (-85, 60),
    "left_shoulder1": (-60, 85),
    "left_shoulder2": (-60, 85),
    "right_elbow": (-90, 50),
    "left_elbow": (-90, 50),
}


def capsule(radius: float, length: float) -> float:
    """Volume (m^3) of a capsule: a cylinder of ``length`` and two hemispheres."""
    return math.pi * radius**2 * length + 4.0 / 3.0 * math.pi * radius**3


def sphere(radius: float) -> float:
    return 4.0 / 3.0 * math.pi * radius**3


#: Each body's geoms from the model (radius, segment length from its ``fromto``).
VOLUMES = {
    "torso": capsule(0.07, 0.14) + capsule(0.06, 0.12),
    "head": sphere(0.09),
    "lower_waist": capsule(0.06, 0.12),
    "pelvis": capsule(0.09, 0.14),
    "thigh": capsule(0.06, math.hypot(0.01, 0.34)),
    "shin": capsule(0.049, 0.3),
    "foot": 2 * capsule(0.027, math.hypot(0.21, 0.02)),
    "upper_arm": capsule(0.04, math.sqrt(3) * 0.16),
    "lower_arm": capsule(0.031, math.sqrt(3) * 0.16),
    "hand": sphere(0.04),
}


def unit(*v: float) -> np.ndarray:
    a = np.array(v, dtype=float)
    return a / np.linalg.norm(a)


def body_frame(pos: tuple[float, float, float], quat_y: float = 0.0) -> np.ndarray:
    """A body's frame in its parent: ``pos`` and the model's quaternion ``(1, 0, quat_y, 0)``."""
    angle = 2.0 * math.atan2(quat_y, 1.0)
    return transform(axis_rotation(Y, angle), np.array(pos))


def hinge(anchor: tuple[float, float, float], axis: np.ndarray, angle: float) -> np.ndarray:
    """A hinge at ``anchor`` (in the body's frame) turned by ``angle``: MuJoCo's joint."""
    a = np.array(anchor)
    return transform(np.eye(3), a) @ transform(axis_rotation(axis, angle), np.zeros(3)) @ transform(np.eye(3), -a)


def leg_foot(torso: np.ndarray, q: dict[str, float], side: str) -> np.ndarray:
    """The foot body's pose (4x4) chained from the torso through the model's origins."""
    s = 1.0 if side == "left" else -1.0
    pose = torso @ body_frame((-0.01, 0.0, -0.26), -0.002)
    pose = pose @ hinge((0, 0, 0.065), Z, q["abdomen_z"]) @ hinge((0, 0, 0.065), Y, q["abdomen_y"])
    pose = pose @ body_frame((0.0, 0.0, -0.165), -0.002) @ hinge((0, 0, 0.1), X, q["abdomen_x"])
    pose = pose @ body_frame((0.0, s * 0.1, -0.04))
    pose = pose @ hinge((0, 0, 0), s * -X, q[f"{side}_hip_x"])  # left: (-1, 0, 0)
    pose = pose @ hinge((0, 0, 0), s * -Z, q[f"{side}_hip_z"])  # left: (0, 0, -1)
    pose = pose @ hinge((0, 0, 0), Y, q[f"{side}_hip_y"])
    pose = pose @ body_frame((0.0, -s * 0.01, -0.403)) @ hinge((0, 0, 0.02), -Y, q[f"{side}_knee"])
    pose = pose @ body_frame((0.0, 0.0, -0.39)) @ hinge((0, 0, 0.08), Y, q[f"{side}_ankle_y"])
    return pose @ hinge((0, 0, 0.04), unit(1, 0, 0.5), q[f"{side}_ankle_x"])


def arm_hand(torso: np.ndarray, q: dict[str, float], side: str) -> np.ndarray:
    """The hand body's pose (4x4) chained from the torso through the model's origins."""
    s = 1.0 if side == "left" else -1.0
    pose = torso @ body_frame((0.0, s * 0.17, 0.06))
    pose = pose @ hinge((0, 0, 0), unit(2, -s, 1), q[f"{side}_shoulder1"])
    pose = pose @ hinge((0, 0, 0), unit(0, s, 1), q[f"{side}_shoulder2"])
    pose = pose @ body_frame((0.18, s * 0.18, -0.18)) @ hinge((0, 0, 0), unit(0, -1, -s), q[f"{side}_elbow"])
    return pose @ body_frame((0.18, -s * 0.18, 0.18))


def body_pose(scene: ra.Scene, name: str) -> np.ndarray:
    body = scene.world.datas[0].body(scene.agents[0].prefix + name)
    return transform(body.xmat.reshape(3, 3), body.xpos.copy())


class StandOnly(Humanoid):
    """The humanoid with its ``stand`` keyframe alone."""

    keyframes: ClassVar = {"stand": Humanoid.keyframes["stand"]}


class SquatOnly(Humanoid):
    """The humanoid with ManiSkill's ``squat`` alone."""

    keyframes: ClassVar = {"squat": SQUAT_KEYFRAME}


class ManiSkillGains(StandOnly):
    """ManiSkill's ``pd_joint_pos`` gains (kp 100, kv 10) on every joint."""

    actuators: ClassVar = tuple(dataclasses.replace(d, stiffness=100.0, damping=10.0) for d in Humanoid.actuators)


# ---------------------------------------------------------------- the model's numbers
def test_masses_are_the_capsules_at_the_models_density() -> None:
    scene = ra.Scene(Humanoid)
    model, prefix = scene.model, scene.agents[0].prefix
    total = 0.0
    for name, volume in VOLUMES.items():
        sides = ("",) if name in ("torso", "head", "lower_waist", "pelvis") else ("left_", "right_")
        for side in sides:
            assert model.body(prefix + side + name).mass[0] == pytest.approx(DENSITY * volume, rel=1e-9), side + name
            total += DENSITY * volume
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(prefix)]
    assert len(robot) == 16
    assert float(model.body_mass[robot].sum()) == pytest.approx(total, rel=1e-12)
    assert total == pytest.approx(40.844, abs=5e-4)  # ManiSkill's loaded links: 40.844 kg
    scene.close()


def test_joint_ranges_torque_limits_and_armature_are_the_models() -> None:
    scene = ra.Scene(Humanoid)
    agent, model = scene.agents[0], scene.model
    limits = dict(zip(agent.joint_names, agent.qpos_limits, strict=True))
    assert set(limits) == set(RANGES_DEG) == set(MANISKILL_JOINTS) == set(DELTA_JOINTS)
    for joint, (low, high) in RANGES_DEG.items():
        np.testing.assert_allclose(limits[joint], np.radians([low, high]), atol=1e-12, err_msg=joint)
        full = agent.prefix + joint
        dof = model.jnt_dofadr[model.joint(full).id]
        assert model.dof_armature[dof] == pytest.approx(0.01)
        assert model.dof_damping[dof] == 0.0 and model.jnt_stiffness[model.joint(full).id] == 0.0
    drives = {d.joint: d for d in Humanoid.check().drives}
    for joint in RANGES_DEG:
        assert drives[joint].effort_limit == GEAR[joint_kind(joint)], joint
    assert sorted({GEAR[joint_kind(j)] for j in RANGES_DEG}) == [20.0, 40.0, 80.0, 120.0]
    for joint in RANGES_DEG:  # our rule: full torque 20 mrad off target; ManiSkill's kv / kp
        assert drives[joint].stiffness == pytest.approx(GEAR[joint_kind(joint)] / 0.02), joint
        assert drives[joint].damping == pytest.approx(drives[joint].stiffness / 10.0), joint
    scene.close()


def test_limbs_follow_the_models_joint_origins_at_random_poses() -> None:
    """Feet and hands against the model's body origins, anchors and axes chained here."""
    scene = ra.Scene(Humanoid)
    agent = scene.agents[0]
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
        agent.reset(qpos=q)
        named = dict(zip(agent.joint_names, q, strict=True))
        torso = body_pose(scene, "torso")
        for side in ("left", "right"):
            np.testing.assert_allclose(body_pose(scene, f"{side}_foot"), leg_foot(torso, named, side), atol=1e-9)
            np.testing.assert_allclose(body_pose(scene, f"{side}_hand"), arm_hand(torso, named, side), atol=1e-9)
    scene.close()


def test_the_stand_puts_the_soles_14_5_mm_above_the_floor() -> None:
    """Every joint at 0 and the torso 1.3 m up (ManiSkill's tasks' reset): the chained foot
    origins lie 1.258 m below the torso, the capsules' lowest points 1.2855 m."""
    scene = ra.Scene(Humanoid)
    scene.reset(keyframes="stand")
    torso = transform(np.eye(3), np.array([0.0, 0.0, STAND_HEIGHT]))
    zero = dict.fromkeys(MANISKILL_JOINTS, 0.0)
    data, prefix = scene.world.datas[0], scene.agents[0].prefix
    for side in ("left", "right"):
        foot = leg_foot(torso, zero, side)
        np.testing.assert_allclose(body_pose(scene, f"{side}_foot"), foot, atol=1e-9)
        assert foot[2, 3] == pytest.approx(STAND_HEIGHT - 1.25797, abs=1e-5)
    lowest = min(
        data.geom(prefix + g).xpos[2] - 0.027
        for g in ("left_left_foot", "right_left_foot", "left_right_foot", "right_right_foot")
    )
    assert lowest == pytest.approx(0.0145, abs=1e-3)
    scene.close()


# ---------------------------------------------------------------- actions
def test_actions_follow_maniskills_orders_and_bounds() -> None:
    scene = ra.Scene(Humanoid, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    assert list(agent.controller.parts) == ["body"]
    assert agent.controller.parts["body"].config.joint_names == MANISKILL_JOINTS
    limits = agent.qpos_limits[[agent.joint_names.index(j) for j in MANISKILL_JOINTS]]
    np.testing.assert_allclose(agent.single_action_space.low, limits[:, 0].astype(np.float32))
    np.testing.assert_allclose(agent.single_action_space.high, limits[:, 1].astype(np.float32))
    scene.close()
    delta = ra.Scene(Humanoid, control_modes="pd_joint_delta_pos")
    controller = delta.agents[0].controller.parts["body"]
    assert controller.config.joint_names == DELTA_JOINTS
    np.testing.assert_allclose(controller.to_raw(np.ones((1, 21)))[0], 2.0)  # ManiSkill's +-2 rad
    delta.close()


def test_squat_keyframe_is_maniskills() -> None:
    assert set(Humanoid.keyframes) == {"stand", "rest"}  # the squat cannot be held: not a keyframe
    assert Humanoid.keyframes["rest"] == Humanoid.keyframes["stand"]
    scene = ra.Scene(SquatOnly)
    scene.reset(keyframes="squat")
    agent = scene.agents[0]
    named = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    assert named == pytest.approx(SQUAT)
    assert SQUAT["abdomen_y"] == 0.12 and SQUAT["right_knee"] == SQUAT["left_knee"] == -1.3
    np.testing.assert_allclose(agent.base_pose[0], [0, 0, 1.13, 1, 0, 0, 0])
    scene.close()


# ---------------------------------------------------------------- standing
def test_stands_from_stand_with_our_gains() -> None:
    result = standing_claim(StandOnly, Humanoid.sim_freq or 500, 20, Penetration())
    assert result is not None
    assert result.passed, result
    assert result.value < 0.005


def test_maniskill_gains_fall_from_the_stand() -> None:
    """Two ankles of kp 100 against the body's toppling stiffness on them, m g h = 299
    N*m/rad (h: the centre of mass 0.745 m above the ankle_y axes)."""
    scene = ra.Scene(StandOnly)
    scene.reset(keyframes="stand")
    model, data, prefix = scene.model, scene.world.datas[0], scene.agents[0].prefix
    torso = model.body(prefix + "torso").id
    height = data.subtree_com[torso][2] - data.joint(prefix + "right_ankle_y").xanchor[2]
    toppling = float(model.body_subtreemass[torso]) * 9.81 * height
    scene.close()
    assert height == pytest.approx(0.745, abs=1e-3)
    assert toppling == pytest.approx(299, abs=1)
    assert toppling > 2 * 100.0
    result = standing_claim(ManiSkillGains, 500, 20, Penetration())
    assert result is not None and not result.passed
    assert result.value > 0.3  # on the floor


def squat_statics(pitch: float) -> dict[str, float]:
    """Torques (N*m) that hold the squat statically on the right leg with the torso
    pitched by ``pitch`` (rad) and each foot's weight share on its inner capsule below
    the centre of mass; also the centre of mass's and the capsule ends' x (m)."""
    scene = ra.Scene(SquatOnly)
    scene.reset(keyframes="squat")
    agent = scene.agents[0]
    model, prefix = scene.model, agent.prefix
    data = mujoco.MjData(model)
    data.qpos[:] = scene.world.datas[0].qpos
    root = model.jnt_qposadr[model.joint(prefix + "root").id]
    data.qpos[root + 3 : root + 7] = [math.cos(pitch / 2), 0.0, math.sin(pitch / 2), 0.0]
    mujoco.mj_forward(model, data)
    com = data.subtree_com[model.body(prefix + "torso").id].copy()
    weight = float(model.body_subtreemass[model.body(prefix + "torso").id]) * 9.81
    geom = data.geom(prefix + "left_right_foot")
    half = model.geom(prefix + "left_right_foot").size[1] * geom.xmat.reshape(3, 3)[:, 2]
    ends = sorted([geom.xpos + half, geom.xpos - half], key=lambda p: p[0])
    t = (com[0] - ends[0][0]) / (ends[1][0] - ends[0][0])
    cop = ends[0] + t * (ends[1] - ends[0])
    out = {"com_x": float(com[0]), "heel_x": float(ends[0][0]), "toe_x": float(ends[1][0])}
    out["slope"] = float(ends[1][2] - ends[0][2])
    for joint in ("right_ankle_y", "right_knee", "right_hip_y"):
        j = model.joint(prefix + joint).id
        axis, anchor = data.xaxis[j], data.xanchor[j]
        torque = axis @ np.cross(cop - anchor, [0.0, 0.0, weight / 2])
        below = [b for b in range(model.nbody) if _descends(model, b, int(model.jnt_bodyid[j]))]
        for b in below:
            torque += axis @ np.cross(data.xipos[b] - anchor, [0.0, 0.0, -model.body_mass[b] * 9.81])
        out[joint] = float(torque)
    scene.close()
    return out


def _descends(model: mujoco.MjModel, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = int(model.body_parentid[body])
    return False


def test_squat_needs_more_ankle_torque_than_the_model_gives() -> None:
    """Level (ManiSkill's), the centre of mass is ahead of the toes; pitched back until
    the inner sole capsules lie flat (4.2 deg), it is 11.5 cm ahead of the ankles and
    each ankle_y must give 22.6 N*m: the model's motor gives 20."""
    level = squat_statics(0.0)
    assert level["com_x"] > level["toe_x"] + 0.027 - 0.002  # at or past the toes' rounded ends
    flat = squat_statics(-0.07335)
    assert abs(flat["slope"]) < 1e-4
    assert flat["heel_x"] < flat["com_x"] < flat["toe_x"]
    assert abs(flat["right_ankle_y"]) == pytest.approx(22.6, abs=0.1)
    assert abs(flat["right_ankle_y"]) > GEAR["ankle_y"]
    assert abs(flat["right_knee"]) < GEAR["knee"] and abs(flat["right_hip_y"]) < GEAR["hip_y"]


def test_falls_from_the_squat() -> None:
    result = standing_claim(SquatOnly, Humanoid.sim_freq or 500, 20, Penetration())
    assert result is not None and not result.passed
    assert result.value > 0.3


# ---------------------------------------------------------------- stability
@pytest.mark.parametrize("mode", list(Humanoid.modes()))
def test_random_actions_stay_finite_and_replay_exactly(mode: str) -> None:
    scene = ra.Scene(StandOnly, control_modes=mode)
    agent = scene.agents[0]
    space = agent.single_action_space
    limits = agent.qpos_limits
    runs = []
    for _ in range(2):
        scene.reset()
        rng = np.random.default_rng(0)
        worst = 0.0
        for _ in range(5 * scene.control_freq):
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


def test_stand_is_held_in_the_default_mode() -> None:
    scene = ra.Scene(StandOnly)
    scene.reset(keyframes="stand")
    agent = scene.agents[0]
    keyframe = agent.qpos[0].copy()
    hold = hold_action(agent)
    errors = []
    for _ in range(3 * scene.control_freq):
        agent.set_action(hold)
        scene.step()
        errors.append(float(np.max(np.abs(agent.qpos[0] - keyframe))))
    scene.close()
    assert max(errors[scene.control_freq :]) < 0.05
    assert max(errors[scene.control_freq :]) - min(errors[scene.control_freq :]) < 0.01
